// Primitive tests: watertight triangles, round segments, linear bounds.
#include <gtest/gtest.h>

#include <random>

#include "scene/scene_context.h"
#include "scene/primitive_bounds.h"
#include "geometry/segment_intersect.h"
#include "geometry/triangle_intersect.h"
#include "test_util.h"

using namespace mbrt;
using namespace mbrt::detail;

namespace {

// A closed octahedron-like mesh: a subdivided sphere made of shared vertices.
void addClosedSphere(Scene& scene, int rings, int sectors) {
  std::vector<Vec3f> v;
  std::vector<Triangle> t;
  v.push_back({0, 1, 0});
  for (int r = 1; r < rings; ++r) {
    const float th = 3.14159265f * r / rings;
    for (int s = 0; s < sectors; ++s) {
      const float ph = 2 * 3.14159265f * s / sectors;
      v.push_back({std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)});
    }
  }
  v.push_back({0, -1, 0});
  auto idx = [&](int r, int s) { return uint32_t(1 + (r - 1) * sectors + (s % sectors)); };
  const uint32_t bottom = uint32_t(v.size() - 1);
  for (int s = 0; s < sectors; ++s) t.push_back({0, idx(1, s + 1), idx(1, s)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      t.push_back({idx(r, s), idx(r, s + 1), idx(r + 1, s + 1)});
      t.push_back({idx(r, s), idx(r + 1, s + 1), idx(r + 1, s)});
    }
  for (int s = 0; s < sectors; ++s) t.push_back({idx(rings - 1, s), idx(rings - 1, s + 1), bottom});
  scene.addTriangleMesh(std::move(t), std::vector<std::vector<Vec3f>>{v});
}

}  // namespace

TEST(Watertight, RaysThroughSharedEdgesAndVerticesNeverSlipThrough) {
  Scene scene;
  addClosedSphere(scene, 12, 16);
  auto accel = test::buildKind(scene, AccelKind::Brute);
  const Geometry& g = scene.geometry(0);
  // Aim from outside at every vertex and every edge midpoint: the ray must hit.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int rays = 0, misses = 0;
  for (const Triangle& tri : g.triangles()) {
    const uint32_t ids[3] = {tri.v0, tri.v1, tri.v2};
    for (int e = 0; e < 3; ++e) {
      const Vec3f a = g.vertexAtStep(0, ids[e]), b = g.vertexAtStep(0, ids[(e + 1) % 3]);
      for (Vec3f target : {a, (a + b) * 0.5f, lerp(a, b, 0.3f)}) {
        Ray r;
        r.org = Vec3f{u(rng), u(rng), u(rng)} * 0.05f;  // from inside: must hit the shell
        r.dir = target - r.org;
        Hit h;
        ++rays;
        misses += accel->intersect(r, h) ? 0 : 1;
      }
    }
  }
  EXPECT_EQ(misses, 0) << "of " << rays << " rays";
}

TEST(Watertight, BarycentricsAndNormal) {
  RayQuery q(Ray{{0.2f, 0.3f, -1.0f}, 0.0f, {0, 0, 1}, kInf, 0.0f});
  TriangleHit h;
  ASSERT_TRUE(intersectTriangle(q, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, h));
  EXPECT_NEAR(h.t, 1.0f, 1e-6f);
  EXPECT_NEAR(h.u, 0.2f, 1e-6f);
  EXPECT_NEAR(h.v, 0.3f, 1e-6f);
  // Outside the [tnear, tfar] interval: no hit.
  RayQuery shortRay(Ray{{0.2f, 0.3f, -1.0f}, 0.0f, {0, 0, 1}, 0.5f, 0.0f});
  EXPECT_FALSE(intersectTriangle(shortRay, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, h));
  // Degenerate triangle: never hit.
  EXPECT_FALSE(intersectTriangle(q, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, h));
}

// Brute-force distance to a round segment: the hit t is where the ray first
// comes within the interpolated radius of the axis.
TEST(RoundSegment, MatchesSampledDistanceField) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), ur(0.05f, 0.4f);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3f p0{u(rng), u(rng), u(rng)}, p1{u(rng), u(rng), u(rng)};
    const float r0 = ur(rng), r1 = ur(rng);
    Ray ray;
    ray.org = Vec3f{u(rng), u(rng), u(rng)} * 4.0f;
    ray.dir = (p0 + p1) * 0.5f + Vec3f{u(rng), u(rng), u(rng)} * 0.5f - ray.org;
    RayQuery q(ray);
    SegmentHit sh;
    const bool hit = intersectSegment(q, p0, p1, r0, r1, sh);
    // Inside test of the solid (union of spheres along the segment).
    auto inside = [&](Vec3f x, float slack) {
      for (int k = 0; k <= 2000; ++k) {
        const float s = k / 2000.0f;
        const Vec3f c = lerp(p0, p1, s);
        const float r = r0 + (r1 - r0) * s;
        if (length(x - c) <= r + slack) return true;
      }
      return false;
    };
    const float len = length(ray.dir);
    if (hit) {
      ++hits;
      const Vec3f x = ray.org + ray.dir * sh.t;
      EXPECT_TRUE(inside(x, 2e-3f)) << "hit point is not on the solid, case " << i;
      EXPECT_FALSE(inside(ray.org + ray.dir * (sh.t - 0.01f / len), -2e-3f)) << "not the first hit, case " << i;
    } else {
      for (int k = 0; k <= 400; ++k) {
        const Vec3f x = ray.org + ray.dir * (k / 400.0f * 2.0f);
        ASSERT_FALSE(inside(x, -0.01f)) << "missed a hit, case " << i;
      }
    }
  }
  EXPECT_GT(hits, 50);
}

TEST(LinearBounds, ContainPrimitiveAtEveryTimeOfTheRange) {
  std::mt19937 rng(11);
  for (uint32_t steps : {1u, 2u, 3u, 7u}) {
    Scene scene;
    test::addRandomMovingTriangles(scene, rng, 50, steps, 0.2f, 0.5f);
    test::addRandomMovingTriangles(scene, rng, 20, steps, 0.2f, 0.5f, {0.3f, 0.8f});
    BuildOptions opt;
    opt.kind = AccelKind::Brute;
    BuildBudget budget;
    SceneContext ctx(scene, opt, budget);
    for (const PrimRef& ref : ctx.primitives()) {
      const Geometry& g = ctx.geometry(ref.geomID);
      for (TimeRange range : {TimeRange{0, 1}, TimeRange{0.1f, 0.35f}, TimeRange{0.5f, 1.0f}}) {
        const LBounds local = linearBounds(ctx, ref, range);
        const LBounds global = toGlobal(local, range);
        for (int k = 0; k <= 64; ++k) {
          const float t = range.lo + range.size() * k / 64.0f;
          const float tc = std::clamp(t, g.timeRange().lo, g.timeRange().hi);
          const Triangle& tri = g.triangles()[ref.primID];
          const Box3f lb = local.at((t - range.lo) / range.size()), gb = global.at(t);
          for (uint32_t v : {tri.v0, tri.v1, tri.v2}) {
            const Vec3f p = g.vertexAt(tc, v);
            ASSERT_TRUE(lb.contains(p)) << "local bounds, steps " << steps << " t " << t;
            ASSERT_TRUE(gb.contains(p)) << "global bounds, steps " << steps << " t " << t;
          }
        }
      }
    }
  }
}
