// The scene model: time conventions, masks, filters, instances, shared
// buffers, and bad input (clear errors, never crashes).
#include <gtest/gtest.h>

#include <random>

#include "reference64.h"
#include "test_util.h"

using namespace mbrt;

namespace {

// A unit quad in the z = z0 + z1*t plane... as two triangles, moving along z.
uint32_t addMovingQuad(Scene& scene, std::vector<float> zs, TimeRange range = {}) {
  std::vector<std::vector<Vec3f>> steps;
  for (float z : zs) steps.push_back({{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}});
  return scene.addTriangleMesh({{0, 1, 2}, {0, 2, 3}}, std::move(steps), range);
}

Ray downZ(float time, float x = 0.1f, float y = 0.2f) { return Ray{{x, y, -10.0f}, 0.0f, {0, 0, 1}, kInf, time}; }

std::unique_ptr<Accel> brute(const Scene& s) { return test::buildKind(s, AccelKind::Brute); }

}  // namespace

TEST(Motion, VerticesInterpolateBetweenEquidistantSteps) {
  Scene scene;
  addMovingQuad(scene, {0.0f, 1.0f, 5.0f});  // steps at t = 0, 0.5, 1
  auto accel = brute(scene);
  for (auto [time, z] : {std::pair{0.0f, 0.0f}, {0.25f, 0.5f}, {0.5f, 1.0f}, {0.75f, 3.0f}, {1.0f, 5.0f}}) {
    Hit h;
    ASSERT_TRUE(accel->intersect(downZ(time), h)) << time;
    EXPECT_NEAR(h.t, 10.0f + z, 1e-4f) << time;
  }
}

TEST(Motion, TimeRangesAreHalfOpenExceptAtOne) {
  Scene scene;
  addMovingQuad(scene, {0.0f, 1.0f}, {0.25f, 0.75f});
  addMovingQuad(scene, {2.0f, 3.0f}, {0.75f, 1.0f});
  auto accel = brute(scene);
  Hit h;
  EXPECT_FALSE(accel->intersect(downZ(0.2f), h));
  ASSERT_TRUE(accel->intersect(downZ(0.25f), h));  // lo is inside
  EXPECT_EQ(h.geomID, 0u);
  EXPECT_NEAR(h.t, 10.0f, 1e-4f);
  ASSERT_TRUE(accel->intersect(downZ(0.75f), h));  // hi is outside for geometry 0
  EXPECT_EQ(h.geomID, 1u);
  ASSERT_TRUE(accel->intersect(downZ(1.0f), h));  // 1 is inside a range ending at 1
  EXPECT_EQ(h.geomID, 1u);
  EXPECT_NEAR(h.t, 13.0f, 1e-4f);
}

TEST(Rays, InvalidRaysMissAndAreCounted) {
  Scene scene;
  addMovingQuad(scene, {0.0f});
  auto accel = brute(scene);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> bad = {downZ(-0.1f), downZ(1.5f), downZ(nan), Ray{{0, 0, -1}, 0, {0, 0, 0}, kInf, 0.5f},
                          Ray{{nan, 0, -1}, 0, {0, 0, 1}, kInf, 0.5f}, Ray{{0, 0, -1}, 0, {0, kInf, 1}, kInf, 0.5f},
                          Ray{{0, 0, -1}, 5.0f, {0, 0, 1}, 1.0f, 0.5f}, Ray{{0, 0, -1}, 0, {0, 0, 1}, nan, 0.5f}};
  for (const Ray& r : bad) {
    Hit h;
    EXPECT_FALSE(accel->intersect(r, h));
    EXPECT_FALSE(h.valid());
    EXPECT_FALSE(accel->occluded(r));
  }
  EXPECT_EQ(accel->stats().invalidRays, 2 * bad.size());
  Hit h;
  EXPECT_TRUE(accel->intersect(downZ(0.5f), h));
  EXPECT_EQ(accel->stats().invalidRays, 2 * bad.size());
}

TEST(Rays, MasksAndFilters) {
  Scene scene;
  addMovingQuad(scene, {0.0f});
  addMovingQuad(scene, {1.0f});
  scene.setMask(0, 0x2);
  int calls = 0;
  scene.setFilter(1, [&](const FilterArgs& a) {
    ++calls;
    return a.candidate.primID == 0;  // an "alpha test": triangle 1 is transparent
  });
  auto accel = brute(scene);
  Hit h;
  Ray r = downZ(0.5f, 0.5f, -0.5f);  // through triangle 0 of both quads
  r.mask = 0x1;                      // geometry 0 is invisible to this ray
  ASSERT_TRUE(accel->intersect(r, h));
  EXPECT_EQ(h.geomID, 1u);
  r.mask = 0x3;
  ASSERT_TRUE(accel->intersect(r, h));
  EXPECT_EQ(h.geomID, 0u);
  // Through triangle 1 of geometry 1, which the filter rejects: a miss.
  Ray through = downZ(0.5f, -0.5f, 0.5f);
  through.mask = 0x1;
  EXPECT_FALSE(accel->intersect(through, h));
  EXPECT_FALSE(accel->occluded(through));
  EXPECT_TRUE(accel->occluded(r));
  EXPECT_GT(calls, 0);
}

TEST(Instances, MatchTheTransformedMeshAtEveryTime) {
  auto child = std::make_shared<Scene>();
  addMovingQuad(*child, {0.0f, 0.5f});
  Scene scene;
  const std::vector<Affine3f> keys = {Affine3f::translate({0, 0, 1}),
                                      Affine3f::translate({0, 0, 2}) * Affine3f::rotate({0, 0, 1}, 0.5f),
                                      Affine3f::translate({0, 0, 4}) * Affine3f::scale({2, 2, 2})};
  scene.addInstance(child, keys);
  auto accel = brute(scene);
  const ref::Reference reference(scene);
  for (float time : {0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
    Hit h;
    ASSERT_TRUE(accel->intersect(downZ(time), h)) << time;
    EXPECT_EQ(h.instID, 0u);
    EXPECT_EQ(h.geomID, 0u);
    // Expected: the float64 reference's own key interpolation and
    // intersection (it does not use transformAt, the function under test).
    std::vector<ref::Candidate> c;
    reference.candidates(downZ(time), c, false);
    ASSERT_EQ(c.size(), 1u) << time;
    EXPECT_FALSE(c[0].ambiguous);
    EXPECT_NEAR(h.t, c[0].t, c[0].tBound) << time;
    const ref::Verdict v = reference.judgeClosest(downZ(time), h);
    EXPECT_TRUE(v.ok) << v.why;
  }
  // And rays off the axis, at random times.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    Ray r = downZ(u(rng));
    r.org.x = 2.4f * u(rng) - 1.2f;
    r.org.y = 2.4f * u(rng) - 1.2f;
    Hit h;
    accel->intersect(r, h);
    const ref::Verdict v = reference.judgeClosest(r, h);
    EXPECT_TRUE(v.ok) << v.why;
    if (!v.ok) break;
  }
}

TEST(SharedBuffers, UpdateAndRebuild) {
  std::vector<float> data = {-1, -1, 0, 9, 1, -1, 0, 9, 1, 1, 0, 9, -1, 1, 0, 9};  // stride 16
  Scene scene;
  scene.addTriangleMesh({{0, 1, 2}, {0, 2, 3}}, std::vector<VertexBuffer>{{data.data(), 16, 4}});
  auto accel = brute(scene);
  Hit h;
  ASSERT_TRUE(accel->intersect(downZ(0.0f), h));
  EXPECT_NEAR(h.t, 10.0f, 1e-5f);
  for (int i = 0; i < 4; ++i) data[4 * i + 2] = 3.0f;
  accel->rebuild();
  ASSERT_TRUE(accel->intersect(downZ(0.0f), h));
  EXPECT_NEAR(h.t, 13.0f, 1e-5f);
}

TEST(BadInput, ClearErrorsNeverCrashes) {
  auto expectError = [](const Scene& s, const char* needle) {
    try {
      brute(s);
      ADD_FAILURE() << "no error, expected one mentioning '" << needle << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  {
    Scene empty;
    expectError(empty, "empty");
  }
  {
    Scene s;
    addMovingQuad(s, {0.0f, std::numeric_limits<float>::quiet_NaN()});
    expectError(s, "NaN");
  }
  {
    Scene s;
    addMovingQuad(s, {0.0f, kInf});
    expectError(s, "infinite");
  }
  {
    Scene s;
    addMovingQuad(s, {0.0f, 2e19f});
    expectError(s, "magnitude");
  }
  {
    Scene s;
    s.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{});
    expectError(s, "S = 0");
  }
  {
    Scene s;
    s.addTriangleMesh({{0, 1, 7}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
    expectError(s, "vertex 7");
  }
  {
    Scene s;
    s.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                                   {{0, 0, 0}, {1, 0, 0}}});
    expectError(s, "all steps must match");
  }
  {
    Scene s;
    addMovingQuad(s, {0.0f}, {0.5f, 0.2f});
    expectError(s, "time range");
  }
  {
    Scene s;
    s.addSegments({{0, 1}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}}}, {0.1f, -1.0f});
    expectError(s, "radius");
  }
  {
    // b is owned by this scope (a refers to it without owning it), so the
    // cycle a -> b -> a frees itself when the scope ends.
    Scene bStorage;
    const std::shared_ptr<Scene> b(&bStorage, [](Scene*) {});
    auto a = std::make_shared<Scene>();
    addMovingQuad(*a, {0.0f});
    a->addInstance(b, {Affine3f::identity()});
    b->addInstance(a, {Affine3f::identity()});
    expectError(*a, "cycle");
  }
  {
    auto child = std::make_shared<Scene>();
    addMovingQuad(*child, {0.0f});
    Scene s;
    s.addInstance(child, {Affine3f::scale({1, 0, 1})});
    expectError(s, "singular");
  }
  {
    Scene s;
    addMovingQuad(s, {0.0f});
    BuildOptions o;
    o.branching = 3;
    EXPECT_THROW(Accel::build(s, o), Error);
  }
}

TEST(BadInput, DegenerateTrianglesAreKeptAndNeverHit) {
  Scene s;
  // Degenerate at step 0 only (all three on a line), fine at step 1.
  s.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}},
                                                                 {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}});
  auto accel = brute(s);
  Hit h;
  EXPECT_FALSE(accel->intersect(downZ(0.0f, 0.0f, 0.0f), h));
  EXPECT_TRUE(accel->intersect(downZ(1.0f, 0.0f, 0.0f), h));
  EXPECT_TRUE(accel->intersect(downZ(0.75f, 0.0f, 0.0f), h));
}
