#include "scenes/strands.h"

#include <cmath>

#include "scenes/mesh_builders.h"
#include "scenes/rng.h"

namespace mbrt::scenes {

std::vector<Vec3f> wanderingStrand(uint64_t seed, uint64_t stream, int points, float segmentLength,
                                   float ballRadius) {
  Rng rng(seed, stream);
  std::vector<Vec3f> pts;
  pts.reserve(size_t(points));
  Vec3f p = rng.inUnitBall() * (0.95f * ballRadius);
  Vec3f dir = rng.unitVector();
  for (int j = 0; j < points; ++j) {
    pts.push_back(p);
    dir = normalize(dir + rng.unitVector() * 0.35f);
    Vec3f q = p + dir * segmentLength;
    const float r = length(q);
    if (r > ballRadius) {  // turn back inwards and stay inside
      dir = normalize(dir - q * (1.2f / r));
      q = p + dir * segmentLength;
      const float r2 = length(q);
      if (r2 > ballRadius) q = q * (ballRadius / r2);
    }
    p = q;
  }
  return pts;
}

std::vector<Vec3f> rootedStrand(uint64_t seed, uint64_t stream, int points, float segmentLength,
                                float rootRadius) {
  Rng rng(seed, stream);
  std::vector<Vec3f> pts;
  pts.reserve(size_t(points));
  Vec3f n = rng.unitVector();
  if (n.y < -0.4f) n.y = -n.y;  // mostly the upper part of the head
  Vec3f p = n * rootRadius;
  Vec3f dir = normalize(n + rng.unitVector() * 0.3f);
  const Vec3f gravity{0.0f, -0.12f, 0.0f};
  for (int j = 0; j < points; ++j) {
    pts.push_back(p);
    dir = normalize(dir + gravity + rng.unitVector() * 0.2f);
    if (dot(dir, p) < 0.0f) dir = normalize(dir + normalize(p) * 0.5f);  // do not grow into the head
    p = p + dir * segmentLength;
  }
  return pts;
}

StrandMotion strandMotion(uint64_t seed, uint64_t stream, float distance, float bend) {
  Rng rng(seed, stream);
  const Vec3f d = rng.unitVector() * distance;
  const Vec3f side = normalize(cross(d, rng.unitVector()));
  const float sign = rng.uniform() < 0.5f ? -1.0f : 1.0f;
  StrandMotion m;
  m.offset[0] = {};
  m.offset[1] = d * 0.5f + side * (sign * bend * distance);
  m.offset[2] = d;
  return m;
}

}  // namespace mbrt::scenes
