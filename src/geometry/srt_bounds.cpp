#include "geometry/srt_bounds.h"

#include <algorithm>
#include <cmath>

namespace mbrt::detail {

Box3f srtSegmentBounds(const SRTKey& a, const SRTKey& b, const Box3f& box) {
  if (box.empty()) return {};
  Vec3f corners[8];
  for (int c = 0; c < 8; ++c)
    corners[c] = {c & 1 ? box.upper.x : box.lower.x, c & 2 ? box.upper.y : box.lower.y,
                  c & 4 ? box.upper.z : box.lower.z};
  const double w = rotationAngle(a.rotation, b.rotation);
  double g = 0, dg = 0;
  for (const Vec3f& x : corners) {
    g = std::max({g, double(length(a.scale * x)), double(length(b.scale * x))});
    dg = std::max(dg, double(length((b.scale - a.scale) * x)));
  }
  const double k = w * w * g + 2.0 * w * dg;  // bound on |f''| over u in [0,1]

  // The box at the keys gives the size the tolerance is relative to.
  Box3f ends;
  const Affine3f ma = a.toAffine(), mb = b.toAffine();
  for (const Vec3f& x : corners) {
    ends.extend(ma.xfmPoint(x));
    ends.extend(mb.xfmPoint(x));
  }
  const double size = std::max(double(maxComponent(ends.size())), g);
  const double tolerance = std::max(1e-4 * size, 1e-30);
  int n = 1;
  if (k > 0) n = int(std::clamp(std::ceil(std::sqrt(k / (8.0 * tolerance))), 1.0, 256.0));

  Box3f out = ends;
  for (int i = 1; i < n; ++i) {
    const Affine3f m = lerp(a, b, float(i) / float(n)).toAffine();
    for (const Vec3f& x : corners) out.extend(m.xfmPoint(x));
  }
  const double magnitude = g + std::max(length(a.translation), length(b.translation));
  const float pad = float(k / (8.0 * double(n) * double(n)) + 1e-5 * magnitude);
  return {out.lower - Vec3f(pad), out.upper + Vec3f(pad)};
}

}  // namespace mbrt::detail
