#include "auto/part_fit.h"

#include <algorithm>
#include <cmath>

#include "decompose/affine_fit.h"

namespace mbrt::detail {
namespace {

// |det| of the interpolated key at interior fractions, relative to the ends:
// det(lerp) is a cubic in the fraction, so a few samples show a dip.
bool staysRegular(const Affine3f& a, const Affine3f& b) {
  const float da = a.determinant(), db = b.determinant();
  if (!(da * db > 0.0f)) return false;
  const float least = 1e-2f * std::min(std::fabs(da), std::fabs(db));
  for (float f : {0.25f, 0.5f, 0.75f}) {
    const float d = lerp(a, b, f).determinant();
    if (!(d * da > 0.0f) || !(std::fabs(d) >= least)) return false;
  }
  return true;
}

// The rest pose and the steps of one part, in double.
struct PartPoses {
  std::vector<Vec3d> rest;
  const Geometry& g;
  std::span<const uint32_t> vertices;
  bool restIsStep0;  // step 0's key is then the identity exactly

  Vec3d at(uint32_t step, size_t i) const { return toD(g.vertices(step)[vertices[i]]); }
  Vec3d restMean() const {
    Vec3d m;
    for (const Vec3d& r : rest) m = m + r;
    return m * (1.0 / double(rest.size()));
  }
  Vec3d stepMean(uint32_t step) const {
    Vec3d m;
    for (size_t i = 0; i < rest.size(); ++i) m = m + at(step, i);
    return m * (1.0 / double(rest.size()));
  }
};

// Keys of `form` fitted to the poses; false when the fit has no solution.
bool fitKeys(const PartPoses& p, KeyForm form, std::vector<Affine3f>& keys) {
  const uint32_t steps = p.g.numSteps();
  keys.assign(steps, Affine3f());
  const Vec3d restMean = p.restMean();
  Mat3d common;  // the one linear part of ConstantLinear keys
  if (form == KeyForm::ConstantLinear) {
    // Pooled over every step: with a translation per step, the centred
    // cross-moments of all steps together give the common linear part.
    FitMoments m;
    for (uint32_t k = 0; k < steps; ++k) {
      const Vec3d shift = restMean - p.stepMean(k);
      for (size_t i = 0; i < p.rest.size(); ++i) m.add(p.rest[i], p.at(k, i) + shift);
    }
    Affine3d fit;
    if (!m.solve(fit)) return false;
    common = fit.L;
  }
  for (uint32_t k = 0; k < steps; ++k) {
    if (k == 0 && p.restIsStep0) continue;
    Affine3d key;
    if (form == KeyForm::Affine) {
      FitMoments m;
      for (size_t i = 0; i < p.rest.size(); ++i) m.add(p.rest[i], p.at(k, i));
      if (!m.solve(key)) return false;
    } else {
      if (form == KeyForm::ConstantLinear) key.L = common;
      key.t = p.stepMean(k) - key.L * restMean;
    }
    keys[k] = key.toFloat();
    if (form == KeyForm::Translation) keys[k] = Affine3f::translate(keys[k].p);  // exactly the identity's L
  }
  return true;
}

// The largest distance of a stored (float) key's image of a rest vertex
// from the vertex at that step, measured in double; stops above `limit`.
double residualOf(const PartPoses& p, const std::vector<Affine3f>& keys, double limit) {
  double worst = 0;
  for (uint32_t k = 0; k < keys.size(); ++k) {
    const Affine3d stored = Affine3d::fromFloat(keys[k]);
    for (size_t i = 0; i < p.rest.size(); ++i) {
      worst = std::max(worst, std::sqrt(norm2(stored.apply(p.rest[i]) - p.at(k, i))));
      if (worst > limit) return worst;
    }
  }
  return worst;
}

PartFit fitPoses(const PartPoses& p, double tolerance) {
  PartFit out;
  if (p.g.type() != GeometryType::Triangles || p.rest.empty()) return out;
  Box3f box;
  for (const Vec3d& r : p.rest) box.extend(toF(r));
  out.diagonal = length(box.upper - box.lower);
  if (!(out.diagonal > 0)) return out;
  const double limit = tolerance * out.diagonal;
  for (uint32_t k = 0; k < p.g.numSteps() && !out.moves; ++k)
    for (size_t i = 0; i < p.rest.size() && !out.moves; ++i)
      out.moves = std::sqrt(norm2(p.at(k, i) - p.rest[i])) > limit;
  double leastResidual = 0;
  for (KeyForm form : {KeyForm::Translation, KeyForm::ConstantLinear, KeyForm::Affine}) {
    std::vector<Affine3f> keys;
    if (!fitKeys(p, form, keys)) continue;
    const double residual = residualOf(p, keys, limit);
    leastResidual = form == KeyForm::Translation ? residual : std::min(leastResidual, residual);
    if (residual > limit) continue;
    bool regular = true;
    for (uint32_t k = 0; k + 1 < keys.size(); ++k) regular = regular && staysRegular(keys[k], keys[k + 1]);
    if (!regular) continue;
    out.fits = true;
    out.form = form;
    out.keys = std::move(keys);
    out.maxResidual = residual / out.diagonal;
    return out;
  }
  out.maxResidual = leastResidual / out.diagonal;
  return out;
}

}  // namespace

const char* toString(KeyForm form) {
  switch (form) {
    case KeyForm::Translation: return "translation";
    case KeyForm::ConstantLinear: return "one linear part";
    case KeyForm::Affine: break;
  }
  return "affine";
}

std::vector<uint32_t> usedVertices(const Geometry& g, std::span<const uint32_t> triangles) {
  std::vector<uint32_t> v;
  v.reserve(triangles.size() * 3);
  for (uint32_t t : triangles) {
    const Triangle& tri = g.triangles()[t];
    v.push_back(tri.v0);
    v.push_back(tri.v1);
    v.push_back(tri.v2);
  }
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

PartFit fitPart(const Geometry& g, std::span<const uint32_t> vertices, double tolerance) {
  PartPoses p{{}, g, vertices, true};
  if (g.type() == GeometryType::Triangles)
    for (uint32_t v : vertices) p.rest.push_back(toD(g.vertices(0)[v]));
  return fitPoses(p, tolerance);
}

PartFit refitPart(std::span<const Vec3f> rest, const Geometry& g, std::span<const uint32_t> vertices,
                  double tolerance) {
  PartPoses p{{}, g, vertices, false};
  if (rest.size() != vertices.size()) return {};
  for (const Vec3f& r : rest) p.rest.push_back(toD(r));
  return fitPoses(p, tolerance);
}

}  // namespace mbrt::detail
