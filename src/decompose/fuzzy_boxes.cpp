#include "decompose/fuzzy_boxes.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "decompose/affine_fit.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

constexpr uint32_t kMaxSubdivisions = 16;
constexpr double kNumericPad = 2e-5;
// Sub-sampling refines while the largest pad exceeds this share of the
// cluster's extent; a pad above kMaxPad of it sends the cluster to the
// world tree.
constexpr double kRefinePad = 0.01, kMaxPad = 0.25;

// One sub-segment [a, b] of a key segment: inverse maps at both ends, the
// change D of the linear part and the bound beta on |L(f)^-1|.
struct SubSegment {
  Affine3d inva, invb;
  Mat3d D;
  double beta;
};

// The n sub-segments of every key segment of the maps W; false when a map
// is singular or |L^-1 D| >= 1/2 at both ends of one. invNorm: the largest
// |L^-1|_inf.
bool subSegments(const std::vector<Affine3d>& W, uint32_t n, std::vector<SubSegment>& subs, double& invNorm) {
  const uint32_t segs = uint32_t(W.size()) - 1;
  subs.assign(size_t(segs) * n, SubSegment{});
  invNorm = 0;
  for (uint32_t k = 0; k < segs; ++k)
    for (uint32_t j = 0; j < n; ++j) {
      const Affine3d A = lerp(W[k], W[k + 1], double(j) / n), B = lerp(W[k], W[k + 1], double(j + 1) / n);
      SubSegment& s = subs[size_t(k) * n + j];
      if (!A.inverse(s.inva) || !B.inverse(s.invb)) return false;
      s.D = B.L - A.L;
      const double ra = (s.inva.L * s.D).normInf(), rb = (s.invb.L * s.D).normInf();
      double beta = 1e300;
      if (ra < 0.5) beta = std::min(beta, s.inva.L.normInf() / (1.0 - ra));
      if (rb < 0.5) beta = std::min(beta, s.invb.L.normInf() / (1.0 - rb));
      if (!(beta < 1e300)) return false;
      s.beta = beta;
      invNorm = std::max({invNorm, s.inva.L.normInf(), s.invb.L.normInf()});
    }
  return true;
}

// Per triangle: the box of its local sub-sample positions and its bound pad.
void sampledBoxes(const Geometry& geo, std::span<const PrimRef> prims, const std::vector<SubSegment>& subs,
                  uint32_t n, std::vector<Box3f>& boxes, std::vector<double>& pad) {
  const uint32_t segs = uint32_t(subs.size() / n);
  boxes.assign(prims.size(), Box3f{});
  pad.assign(prims.size(), 0.0);
  const auto tris = geo.triangles();
  tbb::parallel_for(size_t(0), prims.size(), [&](size_t i) {
    const Triangle& t = tris[prims[i].primID];
    Box3f b;
    double p = 0;
    for (uint32_t k = 0; k < segs; ++k)
      for (uint32_t v : {t.v0, t.v1, t.v2}) {
        const Vec3d x0 = toD(geo.vertexAtStep(k, v)), x1 = toD(geo.vertexAtStep(k + 1, v));
        for (uint32_t j = 0; j < n; ++j) {
          const SubSegment& s = subs[size_t(k) * n + j];
          const Vec3d qa = s.inva.apply(lerp(x0, x1, double(j) / n));
          const Vec3d qb = s.invb.apply(lerp(x0, x1, double(j + 1) / n));
          b.extend(Vec3f(float(qa.x), float(qa.y), float(qa.z)));
          b.extend(Vec3f(float(qb.x), float(qb.y), float(qb.z)));
          p = std::max(p, 0.25 * s.beta * normInf(s.D * (qb - qa)));
        }
      }
    boxes[i] = b;
    pad[i] = p;
  });
}

}  // namespace

bool fuzzyBoxes(const Geometry& geo, std::span<const Affine3f> maps, std::span<const PrimRef> prims,
                double worldMag, FuzzyBoxes& out) {
  std::vector<Affine3d> W;  // the float maps, as traversal uses them
  for (const Affine3f& m : maps) W.push_back(Affine3d::fromFloat(m));
  std::vector<SubSegment> subs;
  std::vector<double> pad;
  for (uint32_t n = 1; n <= kMaxSubdivisions; n *= 2) {
    double invNorm;
    if (!subSegments(W, n, subs, invNorm)) continue;
    sampledBoxes(geo, prims, subs, n, out.boxes, pad);
    Box3f all;
    for (const Box3f& b : out.boxes) all.extend(b);
    const double localMag = std::max(normInf(toD(all.lower)), normInf(toD(all.upper)));
    const double extent = normInf(toD(all.upper - all.lower));
    const double maxPad = *std::max_element(pad.begin(), pad.end());
    if (maxPad > kRefinePad * extent && n < kMaxSubdivisions) continue;
    if (maxPad > kMaxPad * extent) return false;
    const double num = kNumericPad * (localMag + invNorm * worldMag) + 1e-30;
    for (size_t i = 0; i < out.boxes.size(); ++i) {
      const float e = float((pad[i] + num) * (1.0 + 1e-6));
      Box3f& b = out.boxes[i];
      b.lower = b.lower - Vec3f(e);
      b.upper = b.upper + Vec3f(e);
      b = widen(b);
    }
    out.subdivisions = n;
    return true;
  }
  return false;
}

}  // namespace mbrt::detail
