// mbrt's Embree API against the real libembree3, side by side in one
// process (the renamed build, src/renames.h): the same world built through
// both, the same rays (random times and 0, 1 and step times) traced
// through both. Where they differ, the float64 reference (tests/
// reference64.h) decides, and mbrt must be the one it accepts; Embree's
// wrong answers are counted and must stay rare (a semantic difference
// would show as many). mbrt's brute oracle traced directly on the same
// scene must give bit for bit the answers the API gives with kind brute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "answers.h"
#include "embree_side.h"
#include "mbrt/accel.h"
#include "test_util.h"

namespace mbrt::embree_test {
namespace {

struct Tally {
  size_t rays = 0, hits = 0, differing = 0, embreeWrong = 0, mbrtWrong = 0;
  std::string firstMbrtWrong, firstDifference;
};

Tally compareSides(const TestWorld& world, const std::vector<TestRay>& rays, TraceMode mode, const char* kind) {
  const std::string config = std::string("mbrt.kind=") + kind + ",threads=0";
  void* real = realEmbree().build(world, nullptr, RTC_SCENE_FLAG_ROBUST);
  void* ours = mbrtEmbree().build(world, config.c_str(), RTC_SCENE_FLAG_ROBUST);
  std::vector<TestAnswer> a, b;
  realEmbree().trace(real, rays, a, mode);
  mbrtEmbree().trace(ours, rays, b, mode);
  realEmbree().release(real);
  mbrtEmbree().release(ours);
  const auto scene = toMbrtScene(world);
  const ref::Reference reference(*scene);
  Tally t;
  t.rays = rays.size();
  for (size_t i = 0; i < rays.size(); ++i) {
    t.hits += b[i].hit ? 1 : 0;
    std::string why;
    if (sameAnswer(a[i], b[i], why)) continue;
    ++t.differing;
    if (t.firstDifference.empty()) t.firstDifference = why + " for " + ref::describe(toMbrtRay(rays[i]));
    std::string embreeWhy, mbrtWhy;
    if (!referenceAccepts(reference, world, rays[i], a[i], embreeWhy)) ++t.embreeWrong;
    if (!referenceAccepts(reference, world, rays[i], b[i], mbrtWhy)) {
      if (t.mbrtWrong++ == 0) t.firstMbrtWrong = why + ": " + mbrtWhy;
    }
  }
  std::printf("%-16s %-6s %5zu rays, %5zu hits: differ on %3zu, Embree wrong on %3zu, mbrt wrong on %zu\n",
              modeName(mode), kind, t.rays, t.hits, t.differing, t.embreeWrong, t.mbrtWrong);
  if (t.differing) std::printf("  first difference: %s\n", t.firstDifference.c_str());
  return t;
}

void expectAgreement(const Tally& t) {
  EXPECT_EQ(t.mbrtWrong, 0u) << t.firstMbrtWrong;
  // A difference the reference does not settle for mbrt is a failure
  // above; many settled ones would still mean a semantic difference.
  EXPECT_LE(t.differing, t.rays / 100 + 2) << t.firstDifference;
  EXPECT_GT(t.hits, t.rays / 4) << "too few hits to mean anything";
}

TEST(EmbreeApiCompare, SameHitsAsEmbree) {
  for (bool contextFilter : {false, true}) {
    const TestWorld world = randomWorld(7, contextFilter);
    const std::vector<TestRay> rays = randomRays(11, test::scaled(6000, 600));
    for (const char* kind : {"auto", "stbvh"}) expectAgreement(compareSides(world, rays, TraceMode::Single, kind));
  }
}

TEST(EmbreeApiCompare, PacketsAndStreamsAsEmbree) {
  const TestWorld world = randomWorld(13, true);
  const std::vector<TestRay> rays = randomRays(17, test::scaled(1500, 300));
  for (TraceMode mode : {TraceMode::Packet4, TraceMode::Packet8, TraceMode::Packet16, TraceMode::Stream1M,
                         TraceMode::Stream1Mp, TraceMode::StreamNM, TraceMode::StreamNp})
    expectAgreement(compareSides(world, rays, mode, "auto"));
}

bool identical(const TestAnswer& a, const TestAnswer& b) {
  return a.hit == b.hit && a.occluded == b.occluded &&
         (!a.hit || (a.t == b.t && a.u == b.u && a.v == b.v && a.Ng == b.Ng && a.geomID == b.geomID &&
                     a.primID == b.primID && a.instID == b.instID));
}

// Every packet and stream form gives the single-ray answers exactly.
TEST(EmbreeApiCompare, PacketsAndStreamsGiveTheSingleRayAnswers) {
  const TestWorld world = randomWorld(19, true);
  const std::vector<TestRay> rays = randomRays(23, test::scaled(1000, 200));
  void* ours = mbrtEmbree().build(world, "mbrt.kind=stbvh", 0);
  std::vector<TestAnswer> single, other;
  mbrtEmbree().trace(ours, rays, single, TraceMode::Single);
  for (TraceMode mode : {TraceMode::Packet4, TraceMode::Packet8, TraceMode::Packet16, TraceMode::Stream1M,
                         TraceMode::Stream1Mp, TraceMode::StreamNM, TraceMode::StreamNp}) {
    mbrtEmbree().trace(ours, rays, other, mode);
    size_t differ = 0;
    for (size_t i = 0; i < rays.size(); ++i)
      differ += identical(single[i], other[i]) ? 0 : 1;
    EXPECT_EQ(differ, 0u) << modeName(mode);
  }
  mbrtEmbree().release(ours);
}

// The object-space normal of an instanced hit, from the instanced mesh.
Vec3f instancedNormal(const Scene& top, const Hit& h, float time) {
  const Scene* s = top.geometry(h.instID).instancedScene();
  if (s->geometry(0).type() == GeometryType::Instance) s = s->geometry(0).instancedScene();  // pivot: S inside
  const Geometry& g = s->geometry(h.geomID);
  const Triangle& t = g.triangles()[h.primID];
  const Vec3f v0 = g.vertexAt(time, t.v0), v1 = g.vertexAt(time, t.v1), v2 = g.vertexAt(time, t.v2);
  return cross(v1 - v0, v2 - v0);
}

TEST(EmbreeApiCompare, BruteThroughTheApiIsBruteOnTheScene) {
  const TestWorld world = randomWorld(29, true);
  const std::vector<TestRay> rays = randomRays(31, test::scaled(3000, 300));
  void* ours = mbrtEmbree().build(world, "mbrt.kind=brute", 0);
  std::vector<TestAnswer> api;
  mbrtEmbree().trace(ours, rays, api, TraceMode::Single);
  mbrtEmbree().release(ours);
  const auto scene = toMbrtScene(world);
  const auto brute = test::buildKind(*scene, AccelKind::Brute);
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray r = toMbrtRay(rays[i]);
    Hit h;
    const bool found = brute->intersect(r, h);
    ASSERT_EQ(found, api[i].hit) << ref::describe(r);
    ASSERT_EQ(brute->occluded(r), api[i].occluded) << ref::describe(r);
    if (!found) continue;
    ++hits;
    const Hit a = toMbrtHit(world, api[i]);
    EXPECT_EQ(h.t, a.t);
    EXPECT_EQ(h.geomID, a.geomID);
    EXPECT_EQ(h.primID, a.primID);
    EXPECT_EQ(h.instID, a.instID);
    const bool secondHalf = meshIsQuads(world, api[i]) && (h.primID & 1);
    EXPECT_EQ(secondHalf ? 1.0f - h.u : h.u, a.u);
    EXPECT_EQ(secondHalf ? 1.0f - h.v : h.v, a.v);
    const Vec3f ng = h.instID == kInvalidId ? h.Ng : instancedNormal(*scene, h, std::clamp(r.time, 0.0f, 1.0f));
    EXPECT_TRUE(ng == a.Ng) << ref::describe(r);
  }
  EXPECT_GT(hits, rays.size() / 4);
}

// Every kind through the API gives brute's answers (mbrt's oracle test).
TEST(EmbreeApiCompare, EveryKindThroughTheApiAgreesWithBrute) {
  const TestWorld world = randomWorld(37, false);
  const std::vector<TestRay> rays = randomRays(41, test::scaled(2000, 200));
  std::vector<TestAnswer> brute, other;
  void* b = mbrtEmbree().build(world, "mbrt.kind=brute", 0);
  mbrtEmbree().trace(b, rays, brute, TraceMode::Single);
  mbrtEmbree().release(b);
  for (AccelKind kind : availableAccelKinds()) {
    if (kind == AccelKind::Frozen) continue;  // the scene frozen at one time: not the same answers
    const std::string config = "mbrt.kind=" + std::string(toString(kind));
    void* k = mbrtEmbree().build(world, config.c_str(), 0);
    mbrtEmbree().trace(k, rays, other, TraceMode::Single);
    mbrtEmbree().release(k);
    size_t wrong = 0;
    std::string first;
    for (size_t i = 0; i < rays.size(); ++i) {
      std::string why;
      const bool tie = brute[i].hit && other[i].hit && brute[i].occluded == other[i].occluded &&
                       std::fabs(brute[i].t - other[i].t) <= 1e-4f * std::max(1.0f, brute[i].t);
      if (!sameAnswer(brute[i], other[i], why) && !tie && wrong++ == 0) first = why;
    }
    EXPECT_EQ(wrong, 0u) << toString(kind) << ": " << first;
  }
}

}  // namespace
}  // namespace mbrt::embree_test
