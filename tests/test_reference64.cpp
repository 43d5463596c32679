// The float64 reference (reference64.h): its own answers on hand-computed
// cases, then `brute` judged by it on every suite scene and time class and
// on scenes from 1e-6 to the coordinate limit. Brute shares the triangle and
// segment arithmetic with every structure, so these are the tests that see
// an error they all make.
#include <gtest/gtest.h>

#include <cstdio>

#include "mixed_scene.h"
#include "reference_check.h"
#include "test_util.h"

using namespace mbrt;

namespace {

std::vector<ref::Candidate> candidatesOf(const Scene& scene, const Ray& ray) {
  const ref::Reference r(scene);
  std::vector<ref::Candidate> c;
  r.candidates(ray, c, false);
  return c;
}

Ray rayAt(Vec3f org, Vec3f dir, float time = 0.0f) {
  Ray r;
  r.org = org;
  r.dir = dir;
  r.time = time;
  return r;
}

std::shared_ptr<Scene> oneTriangle(float z0, float z1, TimeRange range = {}) {
  auto s = std::make_shared<Scene>();
  s->addTriangleMesh({{0, 1, 2}}, {{{0, 0, z0}, {1, 0, z0}, {0, 1, z0}}, {{0, 0, z1}, {1, 0, z1}, {0, 1, z1}}},
                     range);
  return s;
}

TEST(Reference64, HandComputedTriangles) {
  auto s = oneTriangle(5, 7);
  // Moving from z = 5 to z = 7: at time 0.5 the plane is at z = 6.
  auto c = candidatesOf(*s, rayAt({0.2f, 0.2f, 0}, {0, 0, 2}, 0.5f));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FALSE(c[0].ambiguous);
  EXPECT_NEAR(c[0].t, 3.0, 1e-12);
  EXPECT_LT(c[0].tBound, 3.0 * 1e-5);
  EXPECT_TRUE(candidatesOf(*s, rayAt({0.6f, 0.6f, 0}, {0, 0, 1}, 0.5f)).empty());
  // Through the hypotenuse exactly: ambiguous, either answer is right.
  c = candidatesOf(*s, rayAt({0.5f, 0.5f, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].ambiguous);
  // Just inside the hypotenuse by far more than the band: definite.
  c = candidatesOf(*s, rayAt({0.499f, 0.499f, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FALSE(c[0].ambiguous);
  // From behind (both-sided) and outside [tnear, tfar].
  EXPECT_EQ(candidatesOf(*s, rayAt({0.2f, 0.2f, 10}, {0, 0, -1})).size(), 1u);
  Ray shortRay = rayAt({0.2f, 0.2f, 0}, {0, 0, 1});
  shortRay.tfar = 4.0f;
  EXPECT_TRUE(candidatesOf(*s, shortRay).empty());
}

TEST(Reference64, HandComputedTimeRangesAndMasks) {
  Scene s;
  s.addTriangleMesh({{0, 1, 2}}, {{{0, 0, 5}, {1, 0, 5}, {0, 1, 5}}}, {0.25f, 0.75f});
  s.setMask(0, 0x2);
  Ray r = rayAt({0.2f, 0.2f, 0}, {0, 0, 1}, 0.5f);
  EXPECT_EQ(candidatesOf(s, r).size(), 1u);
  r.time = 0.75f;  // [lo, hi): the end is outside
  EXPECT_TRUE(candidatesOf(s, r).empty());
  r.time = std::nextafter(0.25f, 0.0f);
  EXPECT_TRUE(candidatesOf(s, r).empty());
  r.time = 0.25f;
  EXPECT_EQ(candidatesOf(s, r).size(), 1u);
  r.mask = 0x1;
  EXPECT_TRUE(candidatesOf(s, r).empty());
}

using Steps = std::vector<std::vector<Vec3f>>;

TEST(Reference64, HandComputedSegments) {
  // A sphere (zero-length segment) of radius 1 at z = 10.
  Scene sphere;
  sphere.addSegments({{0, 1}}, Steps{{{0, 0, 10}, {0, 0, 10}}}, {1.0f, 1.0f});
  auto c = candidatesOf(sphere, rayAt({0, 0, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 9.0, 1e-9);
  EXPECT_FALSE(c[0].ambiguous);
  // Starting inside: the exit.
  Ray inside = rayAt({0, 0, 0}, {0, 0, 1});
  inside.tnear = 9.5f;
  c = candidatesOf(sphere, inside);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 11.0, 1e-9);
  // Off-centre: t = 10 - sqrt(1 - 0.6^2).
  c = candidatesOf(sphere, rayAt({0.6f, 0, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 10.0 - 0.8, 1e-6);
  EXPECT_TRUE(candidatesOf(sphere, rayAt({1.01f, 0, 0}, {0, 0, 1})).empty());
  // A cylinder side (equal radii 0.5) along x.
  Scene cyl;
  cyl.addSegments({{0, 1}}, Steps{{{-2, 0, 10}, {2, 0, 10}}}, {0.5f, 0.5f});
  c = candidatesOf(cyl, rayAt({1, 0.3f, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 10.0 - 0.4, 1e-6);
  // A cone from radius 1 at x = 0 to radius 0 at x = 4: the hull's side is
  // the tangent from the apex (4, 0) to the unit circle, with half-angle
  // asin(1/4), touching it at x = 1/4; at x = 2 it is 2 tan(asin(1/4)) high.
  Scene cone;
  cone.addSegments({{0, 1}}, Steps{{{0, 0, 10}, {4, 0, 10}}}, {1.0f, 0.0f});
  const double h = 2.0 * std::tan(std::asin(0.25));
  c = candidatesOf(cone, rayAt({2, 0, 0}, {0, 0, 1}));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].t, 10.0 - h, 1e-6);
}

TEST(Reference64, HandComputedSlerpedAndNestedInstances) {
  // A small triangle around (1, 0, 5), instanced with SRT keys rotating it
  // by 90 degrees about z: at time 0.5 it sits around (cos 45, sin 45).
  // Element-wise matrix interpolation would put it at (0.5, 0.5).
  auto child = std::make_shared<Scene>();
  child->addTriangleMesh({{0, 1, 2}}, {{{0.95f, -0.05f, 5}, {1.05f, -0.05f, 5}, {0.95f, 0.05f, 5}}});
  Scene top;
  SRTKey k0, k1;
  k1.rotation = Quaternion::fromAxisAngle({0, 0, 1}, 1.5707963f);
  top.addInstance(child, std::vector<SRTKey>{k0, k1});
  const float c45 = 0.70710678f;
  auto c = candidatesOf(top, rayAt({c45 - 0.02f, c45, 0}, {0, 0, 1}, 0.5f));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].instID, 0u);
  EXPECT_NEAR(c[0].t, 5.0, 1e-9);
  EXPECT_TRUE(candidatesOf(top, rayAt({0.5f, 0.5f, 0}, {0, 0, 1}, 0.5f)).empty());
  // Nested: the SRT instance inside a matrix-key instance translating by
  // (0, 0, 0) -> (0, 0, 2): instID names the outer one.
  auto middle = std::make_shared<Scene>();
  middle->addInstance(child, std::vector<SRTKey>{k0, k1});
  Scene outer;
  outer.addTriangleMesh({{0, 1, 2}}, {{{10, 10, 0}, {11, 10, 0}, {10, 11, 0}}});
  outer.addInstance(middle, {Affine3f::identity(), Affine3f::translate({0, 0, 2})});
  c = candidatesOf(outer, rayAt({c45 - 0.02f, c45, 0}, {0, 0, 1}, 0.5f));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].instID, 1u);
  EXPECT_EQ(c[0].geomID, 0u);
  EXPECT_NEAR(c[0].t, 6.0, 1e-9);
}

TEST(Reference64, JudgesRejectWrongAnswers) {
  auto s = oneTriangle(5, 5);
  const ref::Reference r(*s);
  const Ray ray = rayAt({0.2f, 0.2f, 0}, {0, 0, 1});
  Hit right;
  right.t = 5.0f;
  right.geomID = 0, right.primID = 0;
  EXPECT_TRUE(r.judgeClosest(ray, right).ok);
  Hit off = right;
  off.t = 5.0f * (1 + 1e-4f);  // far beyond the t bound
  EXPECT_FALSE(r.judgeClosest(ray, off).ok);
  EXPECT_FALSE(r.judgeClosest(ray, Hit{}).ok);  // a missed hit
  Hit other = right;
  other.primID = 1;
  EXPECT_FALSE(r.judgeClosest(ray, other).ok);
  EXPECT_TRUE(r.judgeAny(ray, true).ok);
  EXPECT_FALSE(r.judgeAny(ray, false).ok);
  const Ray miss = rayAt({0.8f, 0.8f, 0}, {0, 0, 1});
  EXPECT_FALSE(r.judgeAny(miss, true).ok);
  EXPECT_FALSE(r.judgeClosest(miss, right).ok);
}

void expectBruteRight(const ProceduralScene& ps, const std::vector<Ray>& rays, const std::string& what) {
  const ref::Reference reference(*ps.scene);
  auto brute = test::buildKind(*ps.scene, AccelKind::Brute);
  const ref::RefReport rep = test::judgeWithReference(reference, *brute, rays);
  EXPECT_EQ(rep.wrong, 0u) << what << ": " << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u) << what << ": " << rep.firstFailure;
  EXPECT_GT(rep.hits, rep.rays / 5) << what << ": too few hits to mean anything";
  std::printf("reference64 %-28s %7zu rays, %6zu hits, %5zu ambiguous\n", what.c_str(), rep.rays, rep.hits,
              rep.ambiguous);
}

// Every suite scene at a small size; random times, 0, 1, every step time and
// range end (oracleRays), and one float step around every partial range end.
TEST(Reference64, BruteOnEverySuiteSceneAndTimeClass) {
  for (const std::string& name : proceduralSceneNames()) {
    const ProceduralScene ps = makeProceduralScene(name, name == "demo" ? 0.3 : 0.0015, 3);
    std::vector<Ray> rays = test::oracleRays(ps, test::scaled(4000, 200), test::scaled(20, 2), 17);
    for (const Ray& r : test::rangeEndRays(ps, test::scaled(50, 5), 5)) rays.push_back(r);
    expectBruteRight(ps, rays, name);
  }
  const ProceduralScene mixed = test::mixedScene();
  std::vector<Ray> rays = test::oracleRays(mixed, test::scaled(4000, 200), test::scaled(20, 2), 19);
  for (const Ray& r : test::rangeEndRays(mixed, test::scaled(50, 5), 7)) rays.push_back(r);
  expectBruteRight(mixed, rays, "mixed");
}

// Moving triangles and round segments scaled to `scale`, with a camera
// framing them (coordinates up to about `scale`).
ProceduralScene scaledScene(float scale, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto s = std::make_shared<Scene>();
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> tsteps(2);
  for (uint32_t i = 0; i < 150; ++i) {
    const Vec3f c{u(rng) * 0.6f, u(rng) * 0.6f, u(rng) * 0.6f}, m = Vec3f{u(rng), u(rng), u(rng)} * 0.1f;
    for (int k = 0; k < 3; ++k) {
      const Vec3f v = c + Vec3f{u(rng), u(rng), u(rng)} * 0.25f;
      tsteps[0].push_back(v * scale);
      tsteps[1].push_back((v + m) * scale);
    }
    tris.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  s->addTriangleMesh(std::move(tris), std::move(tsteps));
  std::vector<Segment> segs;
  std::vector<std::vector<Vec3f>> ssteps(2);
  std::vector<float> radii;
  for (uint32_t i = 0; i < 60; ++i) {
    const Vec3f a{u(rng) * 0.6f, u(rng) * 0.6f, u(rng) * 0.6f}, b = a + Vec3f{u(rng), u(rng), u(rng)} * 0.3f;
    const Vec3f m = Vec3f{u(rng), u(rng), u(rng)} * 0.1f;
    for (const Vec3f& p : {a, b}) {
      ssteps[0].push_back(p * scale);
      ssteps[1].push_back((p + m) * scale);
      radii.push_back((0.01f + 0.03f * std::fabs(u(rng))) * scale);
    }
    segs.push_back({2 * i, 2 * i + 1});
  }
  s->addSegments(std::move(segs), std::move(ssteps), std::move(radii));
  ProceduralScene ps;
  ps.scene = s;
  ps.camera = frameBox(Box3f(Vec3f(-scale), Vec3f(scale)));
  return ps;
}

// From 1e-6 up to the coordinate limit (kMaxCoordinate): the largest scene
// has coordinates near 1e18 (and its camera beyond). Beyond the limit the scene is refused.
TEST(Reference64, BruteOnTinyAndHugeScenes) {
  for (float scale : {1e-6f, 1e-3f, 1e3f, 1e6f, 1e9f, 1e12f, 1e13f, 1e15f, 1e17f, kMaxCoordinate}) {
    const ProceduralScene ps = scaledScene(scale, 9);
    std::vector<Ray> rays = test::oracleRays(ps, test::scaled(3000, 200), 0, 23);
    char what[64];
    std::snprintf(what, sizeof what, "scale %g", scale);
    expectBruteRight(ps, rays, what);
  }
  const ProceduralScene beyond = scaledScene(2.5f * kMaxCoordinate, 9);
  EXPECT_THROW(test::buildKind(*beyond.scene, AccelKind::Brute), Error);
}

}  // namespace
