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

}  // namespace

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
  PartFit out;
  if (g.type() != GeometryType::Triangles || vertices.empty()) return out;
  const VertexBuffer& rest = g.vertices(0);
  Box3f box;
  for (uint32_t v : vertices) box.extend(rest[v]);
  out.diagonal = length(box.upper - box.lower);
  const double limit = tolerance * out.diagonal;
  if (!(out.diagonal > 0)) return out;
  out.keys.resize(g.numSteps());
  double worst = 0;
  for (uint32_t k = 0; k < g.numSteps(); ++k) {
    const VertexBuffer& pose = g.vertices(k);
    FitMoments m;
    for (uint32_t v : vertices) m.add(toD(rest[v]), toD(pose[v]));
    Affine3d fit;
    if (!m.solve(fit)) return out;
    out.keys[k] = k == 0 ? Affine3f() : fit.toFloat();
    // The residual of the key as stored (in float), measured in double.
    const Affine3d stored = Affine3d::fromFloat(out.keys[k]);
    for (uint32_t v : vertices) {
      const Vec3d r = toD(rest[v]);
      const double e = std::sqrt(norm2(stored.apply(r) - toD(pose[v])));
      worst = std::max(worst, e);
      if (e > limit) {
        out.maxResidual = worst / out.diagonal;
        out.moves = true;
        out.keys.clear();
        return out;
      }
      if (!out.moves && std::sqrt(norm2(toD(pose[v]) - r)) > limit) out.moves = true;
    }
  }
  for (uint32_t k = 0; k + 1 < g.numSteps(); ++k)
    if (!staysRegular(out.keys[k], out.keys[k + 1])) {
      out.keys.clear();
      return out;
    }
  out.maxResidual = worst / out.diagonal;
  out.fits = true;
  return out;
}

}  // namespace mbrt::detail
