// The BVH family (bvh-interp, bvh-segments, frozen, stbvh) against the brute-force
// oracle, plus invariants: conservative bounds, determinism, budgets, refit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "build_in_arena.h"
#include "bvh/build/build_wide.h"
#include "bvh/kinds/bvh_structure.h"
#include "bvh/inspect.h"
#include "bvh/traverse.h"
#include "accel/structure_factory.h"
#include "scene/scene_context.h"
#include "scene/primitive_bounds.h"
#include "mbrt/accel.h"
#include "test_util.h"

using namespace mbrt;

namespace {

using Rng = std::mt19937;
float uni(Rng& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
Vec3f uniVec(Rng& rng, float lo, float hi) { return {uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)}; }

// `count` small triangles in [-1,1]^3, each vertex moving its own way over S steps.
void addRandomTriangles(Scene& scene, Rng& rng, int count, int steps, TimeRange range = {}, float motion = 0.3f) {
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> pos(static_cast<size_t>(steps));
  for (int i = 0; i < count; ++i) {
    const Vec3f c = uniVec(rng, -1.0f, 1.0f);
    const Vec3f drift = uniVec(rng, -motion, motion);
    const uint32_t base = uint32_t(pos[0].size());
    for (int v = 0; v < 3; ++v) {
      const Vec3f p = c + uniVec(rng, -0.15f, 0.15f);
      for (int s = 0; s < steps; ++s)
        pos[size_t(s)].push_back(p + drift * (float(s) / float(std::max(1, steps - 1))) +
                                 uniVec(rng, -0.05f, 0.05f) * float(s > 0));
    }
    tris.push_back({base, base + 1, base + 2});
  }
  scene.addTriangleMesh(std::move(tris), std::move(pos), range);
}

void addRandomSegments(Scene& scene, Rng& rng, int count, int steps) {
  std::vector<Segment> segs;
  std::vector<std::vector<Vec3f>> pos(static_cast<size_t>(steps));
  std::vector<float> radii;
  for (int i = 0; i < count; ++i) {
    const Vec3f c = uniVec(rng, -1.0f, 1.0f);
    const uint32_t base = uint32_t(radii.size());
    for (int v = 0; v < 2; ++v) {
      const Vec3f p = c + uniVec(rng, -0.2f, 0.2f);
      for (int s = 0; s < steps; ++s) pos[size_t(s)].push_back(p + uniVec(rng, -0.1f, 0.1f) * float(s));
      radii.push_back(uni(rng, 0.01f, 0.04f));
    }
    segs.push_back({base, base + 1});
  }
  scene.addSegments(std::move(segs), std::move(pos), std::move(radii));
}

// Axis-aligned grid of triangles in the plane z = 0 (grazing slab tests).
void addGrid(Scene& scene, int n) {
  std::vector<Triangle> tris;
  std::vector<Vec3f> pos;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) pos.push_back({-1.0f + 2.0f * x / n, -1.0f + 2.0f * y / n, 0.0f});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      tris.push_back({a, b, d});
      tris.push_back({a, d, c});
    }
  scene.addTriangleMesh(std::move(tris), std::vector<std::vector<Vec3f>>{pos});
}

struct TestScene {
  std::string name;
  std::shared_ptr<Scene> scene;
  std::vector<float> specialTimes;  // step boundaries etc.
};

TestScene movingTriangles(int steps) {
  Rng rng(uint32_t(100 + steps));
  auto s = std::make_shared<Scene>();
  addRandomTriangles(*s, rng, 300, steps);
  TestScene t{"triangles S=" + std::to_string(steps), s, {0.0f, 1.0f}};
  for (int k = 0; k < steps; ++k) t.specialTimes.push_back(steps == 1 ? 0.0f : float(k) / float(steps - 1));
  return t;
}

TestScene mixedScene() {
  Rng rng(7);
  auto child = std::make_shared<Scene>();
  addRandomTriangles(*child, rng, 40, 2);
  auto s = std::make_shared<Scene>();
  addRandomTriangles(*s, rng, 80, 1);
  addRandomTriangles(*s, rng, 80, 5);
  addRandomTriangles(*s, rng, 60, 3, {0.2f, 0.7f});  // partial time range
  addRandomSegments(*s, rng, 60, 2);
  std::vector<Affine3f> keys = {Affine3f::translate({0.5f, 0, 0}) * Affine3f::scale(Vec3f(0.5f)),
                                Affine3f::translate({0, 0.4f, 0}) * Affine3f::rotate({0, 0, 1}, 0.8f) *
                                    Affine3f::scale(Vec3f(0.5f)),
                                Affine3f::translate({-0.5f, 0, 0.2f}) * Affine3f::rotate({1, 1, 0}, 1.6f) *
                                    Affine3f::scale(Vec3f(0.4f))};
  s->addInstance(child, keys);
  addGrid(*s, 6);
  return {"mixed", s, {0.0f, 1.0f, 0.25f, 0.5f, 0.75f, 0.2f, 0.45f, 0.7f}};
}

std::vector<Ray> makeRays(const TestScene& ts, int count, uint32_t seed, const float* fixedTime = nullptr) {
  Rng rng(seed);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray r;
    r.org = uniVec(rng, -2.5f, 2.5f);
    const Vec3f target = uniVec(rng, -1.0f, 1.0f);
    r.dir = target - r.org;
    if (i % 10 == 0) {  // axis-aligned rays onto grid vertices/edges: grazing slabs, zero components
      const int k = int(rng() % 3);
      const float gx = -1.0f + float(rng() % 13) / 6.0f, gy = -1.0f + float(rng() % 13) / 6.0f;
      r.org = k == 0 ? Vec3f{gx, gy, -2.0f} : (k == 1 ? Vec3f{gx, -2.0f, 0.0f} : Vec3f{-2.0f, gy, 0.0f});
      r.dir = k == 0 ? Vec3f{0, 0, 1} : (k == 1 ? Vec3f{0, 1, 0} : Vec3f{1, 0, 0});
    }
    if (i % 7 == 0) r.tnear = uni(rng, 0.0f, 0.5f);
    if (i % 5 == 0) r.tfar = uni(rng, 0.5f, 1.5f);
    if (fixedTime)
      r.time = *fixedTime;
    else if (i % 3 == 0)
      r.time = ts.specialTimes[rng() % ts.specialTimes.size()];
    else
      r.time = uni(rng, 0.0f, 1.0f);
    rays.push_back(r);
  }
  return rays;
}

// Same closest hit (ids, or t within 1e-4 relative for ties) and the same
// any-hit answer as brute; the counted path agrees with the fast path.
void expectAgreement(const Accel& accel, const Accel& brute, const std::vector<Ray>& rays, const std::string& what) {
  int failures = 0;
  TraversalCounters counters;
  for (const Ray& r : rays) {
    Hit h, hb, hc;
    const bool f = accel.intersect(r, h), fb = brute.intersect(r, hb);
    const bool fc = accel.intersect(r, hc, counters);
    bool ok = f == fb && fc == f && accel.occluded(r) == brute.occluded(r);
    if (ok && f) {
      const bool same = h.geomID == hb.geomID && h.primID == hb.primID && h.instID == hb.instID;
      ok = same || std::fabs(h.t - hb.t) <= 1e-4f * std::max(1.0f, std::fabs(hb.t));
      ok = ok && hc.geomID == h.geomID && hc.primID == h.primID && hc.t == h.t;
    }
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << what << ": ray org (" << r.org.x << "," << r.org.y << "," << r.org.z << ") dir (" << r.dir.x
                    << "," << r.dir.y << "," << r.dir.z << ") time " << r.time << ": hit " << f << " t " << h.t
                    << " prim " << h.geomID << "/" << h.primID << " vs brute " << fb << " t " << hb.t << " prim "
                    << hb.geomID << "/" << hb.primID;
  }
  EXPECT_EQ(failures, 0) << what;
  EXPECT_GT(counters.nodesVisited, 0u) << what;
}

std::vector<TestScene> allScenes() {
  return {movingTriangles(1), movingTriangles(2), movingTriangles(5), mixedScene()};
}

const AccelKind kKinds[] = {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Frozen, AccelKind::Stbvh};

}  // namespace

TEST(Bvh, AgreesWithBrute) {
  for (const TestScene& ts : allScenes()) {
    BuildOptions bo;
    bo.kind = AccelKind::Brute;
    bo.frozenTime = 0.45f;
    auto brute = Accel::build(*ts.scene, bo);
    const std::vector<Ray> rays = makeRays(ts, test::scaled(3000, 300), 11);
    const std::vector<Ray> frozenRays = makeRays(ts, test::scaled(1500, 150), 12, &bo.frozenTime);
    for (AccelKind kind : kKinds)
      for (int width : {2, 4, 8}) {
        BuildOptions o = bo;
        o.kind = kind;
        o.branching = width;
        o.maxLeafSize = width == 2 ? 2 : 6;
        auto accel = Accel::build(*ts.scene, o);
        const std::string what = ts.name + " " + std::string(toString(kind)) + " N=" + std::to_string(width);
        expectAgreement(*accel, *brute, kind == AccelKind::Frozen ? frozenRays : rays, what);
        const AccelStats s = accel->stats();
        EXPECT_GT(s.innerNodes, 0u) << what;
        EXPECT_GT(s.sahCost, 0.0) << what;
        EXPECT_GT(s.bytes, 0u) << what;
      }
  }
}

TEST(Bvh, BoundsAreConservative) {
  for (const TestScene& ts : allScenes())
    for (AccelKind kind : kKinds)
      for (int width : {2, 8}) {
        BuildOptions o;
        o.kind = kind;
        o.branching = width;
        o.frozenTime = 0.7f;
        detail::BuildBudget budget;
        detail::SceneContext ctx(*ts.scene, o, budget, detail::makeStructure);
        auto structure = detail::makeStructure(ctx);
        const detail::Inspect* inspect = &detail::inspect(*structure);
        std::vector<float> times = ts.specialTimes;
        for (int k = 0; k <= 16; ++k) times.push_back(float(k) / 16.0f);
        times.push_back(o.frozenTime);
        for (uint32_t g = 0; g < ts.scene->numGeometries(); ++g)
          for (uint32_t k = 0; k < ts.scene->geometry(g).numSteps(); ++k) times.push_back(ts.scene->geometry(g).stepTime(k));
        size_t violations = 0, checks = 0;
        std::set<std::pair<uint32_t, uint32_t>> reached;
        inspect->forEachLane([&](const detail::LaneView& lane) {
          for (const detail::PrimRef& p : lane.below) reached.insert({p.geomID, p.primID});
          for (float t : times) {
            if (kind == AccelKind::Frozen ? t != o.frozenTime : (t < lane.range.lo || t > lane.range.hi)) continue;
            const Box3f box = lane.box(t);
            for (const detail::PrimRef& p : lane.below) {
              const Geometry& geo = ctx.geometry(p.geomID);
              if (!geo.timeRange().contains(t)) continue;
              ++checks;
              bool inside = box.contains(detail::boxAt(ctx, p, t));
              if (geo.type() == GeometryType::Triangles) {
                const Triangle& tri = geo.triangles()[p.primID];
                for (uint32_t v : {tri.v0, tri.v1, tri.v2}) inside = inside && box.contains(geo.vertexAt(t, v));
              }
              if (!inside) ++violations;
            }
          }
        });
        const std::string what = ts.name + " " + std::string(toString(kind)) + " N=" + std::to_string(width);
        EXPECT_EQ(violations, 0u) << what;
        EXPECT_GT(checks, 0u) << what;
        if (kind == AccelKind::BvhInterp) EXPECT_EQ(reached.size(), ctx.numPrimitives()) << what;
      }
}

TEST(Bvh, DeterministicWhateverTheThreadCount) {
  Rng rng(3);
  Scene scene;
  addRandomTriangles(scene, rng, uint32_t(test::scaled(12000, 3000)), 3);
  addRandomTriangles(scene, rng, uint32_t(test::scaled(8000, 2000)), 1);
  for (AccelKind kind : kKinds)
    for (int width : {2, 8}) {
      BuildOptions o;
      o.kind = kind;
      o.branching = width;
      const test::BuiltInArena one = test::buildInArena(scene, o, 1), two = test::buildInArena(scene, o, 2);
      EXPECT_EQ(one.bytes, two.bytes) << toString(kind) << " N=" << width;
      EXPECT_EQ(one.stats.sahCost, two.stats.sahCost) << toString(kind) << " N=" << width;
    }
}

TEST(Bvh, MemoryBudgetStopsTheBuild) {
  const TestScene ts = mixedScene();
  for (AccelKind kind : kKinds) {
    BuildOptions o;
    o.kind = kind;
    const AccelStats stats = Accel::build(*ts.scene, o)->stats();
    const size_t peak = stats.peakBuildBytes;
    EXPECT_GT(peak, stats.bytes);
    if (kind != AccelKind::BvhSegments) {  // segments builds its trees concurrently: peak varies
      o.memoryBudget = peak;
      EXPECT_NO_THROW(Accel::build(*ts.scene, o)) << toString(kind);
      o.memoryBudget = peak - 1;
      EXPECT_THROW(Accel::build(*ts.scene, o), Error) << toString(kind);
    }
    o.memoryBudget = stats.bytes;  // the result alone, no room for scratch
    EXPECT_THROW(Accel::build(*ts.scene, o), Error) << toString(kind);
    o.memoryBudget = 2000;
    EXPECT_THROW(Accel::build(*ts.scene, o), Error) << toString(kind);
  }
}

TEST(Bvh, RefitFollowsMovedVertices) {
  Rng rng(5);
  const int count = 400, steps = 3;
  std::vector<std::vector<Vec3f>> pos(steps);
  std::vector<Triangle> tris;
  for (int i = 0; i < count; ++i) {
    const Vec3f c = uniVec(rng, -1.0f, 1.0f);
    for (int v = 0; v < 3; ++v) {
      const Vec3f p = c + uniVec(rng, -0.1f, 0.1f);
      for (int s = 0; s < steps; ++s) pos[size_t(s)].push_back(p + Vec3f(0.1f * float(s), 0, 0));
    }
    tris.push_back({uint32_t(3 * i), uint32_t(3 * i + 1), uint32_t(3 * i + 2)});
  }
  Scene scene;
  std::vector<VertexBuffer> buffers;
  for (auto& p : pos) buffers.push_back(VertexBuffer{p.data(), sizeof(Vec3f), p.size()});
  scene.addTriangleMesh(tris, buffers);
  TestScene ts{"refit", nullptr, {0.0f, 0.5f, 1.0f}};
  for (int width : {2, 4, 8}) {
    BuildOptions o;
    o.kind = AccelKind::BvhInterp;
    o.branching = width;
    auto accel = Accel::build(scene, o);
    const double before = accel->stats().sahCost;
    // Move every vertex: a swirl plus noise, different per step.
    for (int s = 0; s < steps; ++s)
      for (Vec3f& p : pos[size_t(s)]) p = Vec3f(p.y, -p.x, p.z + 0.3f * float(s)) + uniVec(rng, -0.05f, 0.05f);
    EXPECT_TRUE(accel->refit());
    BuildOptions bo;
    bo.kind = AccelKind::Brute;
    auto brute = Accel::build(scene, bo);
    expectAgreement(*accel, *brute, makeRays(ts, 2000, 21), "refit N=" + std::to_string(width));
    EXPECT_NE(accel->stats().sahCost, before);
  }
}

TEST(Bvh, RefitOfInstancesRebuilds) {
  const TestScene ts = mixedScene();
  BuildOptions o;
  o.kind = AccelKind::BvhInterp;
  auto accel = Accel::build(*ts.scene, o);
  EXPECT_FALSE(accel->refit());  // instanced bounds are not refitted: rebuilt instead
  BuildOptions bo;
  bo.kind = AccelKind::Brute;
  auto brute = Accel::build(*ts.scene, bo);
  expectAgreement(*accel, *brute, makeRays(ts, 500, 31), "refit with instances");
}

// The scalar pack and the SIMD pack of this build agree on random nodes.
TEST(Bvh, ScalarAndSimdNodeTestsAgree) {
  Rng rng(9);
  for (int trial = 0; trial < 2000; ++trial) {
    detail::WideNode<8, true> node;
    node.clear();
    LBounds lanes[8];
    uint32_t present = 0;
    for (int l = 0; l < 8; ++l) {
      if (rng() % 5 == 0) continue;  // empty lane
      Box3f b0(uniVec(rng, -1, 1)), b1(uniVec(rng, -1, 1));
      b0.extend(b0.lower + uniVec(rng, 0, 0.5f));
      b1.extend(b1.lower + uniVec(rng, 0, 0.5f));
      lanes[l] = LBounds(b0, b1);
      present |= 1u << l;
    }
    node.encode(lanes, present);
    Ray ray{uniVec(rng, -2, 2), 0.0f, uniVec(rng, -1, 1), uni(rng, 0.5f, 5.0f), uni(rng, 0, 1)};
    if (trial % 4 == 0) ray.dir[int(rng() % 3)] = 0.0f;
    detail::RayQuery q(ray);
    alignas(32) float d1[8], dw[8];
    const uint32_t m1 = detail::intersectNode<1>(node, detail::NodeRay<1>(q, ray.time), q.tfar, d1);
    constexpr int W = detail::packWidth<8>();
    const uint32_t mw = detail::intersectNode<W>(node, detail::NodeRay<W>(q, ray.time), q.tfar, dw);
    ASSERT_EQ(m1, mw) << "trial " << trial;
    for (int l = 0; l < 8; ++l)
      if (m1 >> l & 1) ASSERT_EQ(d1[l], dw[l]);
    for (int l = 0; l < 8; ++l)
      if (node.isEmpty(l)) ASSERT_FALSE(m1 >> l & 1);
  }
}

TEST(Bvh, EmptyAndTinyScenes) {
  Scene scene;
  scene.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                                     {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}});
  for (AccelKind kind : kKinds) {
    BuildOptions o;
    o.kind = kind;
    auto accel = Accel::build(scene, o);
    Ray ray{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, kInf, 0.5f};
    Hit hit;
    ASSERT_TRUE(accel->intersect(ray, hit)) << toString(kind);
    EXPECT_NEAR(hit.t, 1.5f, 1e-5f);
    EXPECT_EQ(accel->stats().references, 1u);
  }
}

// Leaves test one geometry's run at a time (scene/leaf_intersect.h): leaves
// mixing many small meshes and segments, some masked, some filtered, some
// alive only part of the shutter, must answer exactly as brute force.
TEST(Bvh, LeavesMixingGeometriesHonourMasksAndFilters) {
  Rng rng(31);
  auto s = std::make_shared<Scene>();
  for (int g = 0; g < 12; ++g) {
    if (g % 4 == 3)
      addRandomSegments(*s, rng, 6, 1 + g % 3);
    else
      addRandomTriangles(*s, rng, 8, 1 + g % 4, g % 5 == 4 ? TimeRange{0.1f, 0.6f} : TimeRange{});
  }
  s->setMask(1, 0x2);
  s->setMask(6, 0x4);
  s->setFilter(2, [](const FilterArgs& a) { return a.candidate.primID % 2 == 1; });
  s->setFilter(7, [](const FilterArgs& a) { return a.candidate.u < 0.5f; });
  TestScene ts{"mixed leaves", s, {0.0f, 0.1f, 0.6f, 1.0f, 1.0f / 3.0f, 0.5f}};
  std::vector<Ray> rays = makeRays(ts, test::scaled(3000, 300), 17);
  for (size_t i = 0; i < rays.size(); ++i) rays[i].mask = i % 3 == 0 ? 0x1u : (i % 3 == 1 ? 0x6u : ~0u);
  BuildOptions bo;
  bo.kind = AccelKind::Brute;
  auto brute = Accel::build(*s, bo);
  // Leaves of one reference are kept in their node (wide_node.h,
  // kInlineLeaf) when of the node's most common geometry: with leaf size 1
  // most leaves are, across geometries, masks, filters and instances.
  for (AccelKind kind : {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Stbvh, AccelKind::Frozen})
    for (int width : {4, 8})
      for (int leafSize : {1, 8}) {
        BuildOptions o;
        o.kind = kind;
        o.branching = width;
        o.maxLeafSize = leafSize;
        o.frozenTime = 0.6f;
        std::vector<Ray> at = rays;
        if (kind == AccelKind::Frozen)
          for (Ray& r : at) r.time = o.frozenTime;
        auto accel = Accel::build(*s, o);
        expectAgreement(*accel, *brute, at,
                        ts.name + " " + std::string(toString(kind)) + " N=" + std::to_string(width) +
                            " leaf " + std::to_string(leafSize));
      }
}

// One-reference leaves live in their node (kInlineLeaf): the layout keeps
// those of the node's most common geometry there, the others in the table,
// and every primitive is still referenced exactly once (bvh-interp).
template <int N, bool Motion>
void checkInlineLeaves(const detail::WideBvh<N, Motion>& bvh, size_t numPrimitives, bool oneGeometry,
                       const std::string& what) {
  std::multiset<std::pair<uint32_t, uint32_t>> refs;
  for (const detail::PrimRef& p : bvh.prims) refs.insert({p.geomID, p.primID});
  size_t inlined = 0, geometriesMixed = 0;
  for (const auto& node : bvh.nodes) {
    std::set<uint32_t> singles;
    for (int l = 0; l < N; ++l) {
      if (node.count[l] == detail::kInlineLeaf) {
        ++inlined;
        refs.insert({node.leafGeom, node.child[l]});
        ASSERT_TRUE(node.isLeaf(l)) << what;
        ASSERT_FALSE(node.isEmpty(l)) << what;
      } else if (node.isLeaf(l) && node.count[l] == 1) {
        // Left in the table only when of another geometry than the inline ones.
        ASSERT_NE(bvh.prims[node.child[l]].geomID, node.leafGeom) << what;
        ++geometriesMixed;
      }
    }
  }
  EXPECT_EQ(inlined, bvh.inlineRefs) << what;
  EXPECT_EQ(bvh.numReferences(), numPrimitives) << what;
  EXPECT_EQ(refs.size(), numPrimitives) << what;
  const std::set<std::pair<uint32_t, uint32_t>> distinct(refs.begin(), refs.end());
  EXPECT_EQ(distinct.size(), numPrimitives) << what;
  if (oneGeometry) {
    EXPECT_EQ(inlined, numPrimitives) << what;
  } else {
    EXPECT_GT(inlined, numPrimitives / 5) << what;
    EXPECT_GT(geometriesMixed, 0u) << what;
  }
}

TEST(Bvh, OneReferenceLeavesLiveInTheirNode) {
  for (int meshes : {1, 40}) {
    // Many small meshes: nodes meet single leaves of several geometries.
    Rng rng(5);
    Scene scene;
    for (int g = 0; g < meshes; ++g) addRandomTriangles(scene, rng, 400 / meshes, 1 + g % 3);
    BuildOptions o;
    o.kind = AccelKind::BvhInterp;
    o.maxLeafSize = 1;
    detail::BuildBudget budget;
    detail::SceneContext ctx(scene, o, budget);
    const std::vector<detail::PrimRef> prims = ctx.primitives();
    const std::string what = std::to_string(meshes) + " meshes, N=";
    detail::WideBvh<8, true> motion8;
    detail::buildWideBvh(ctx, prims, detail::ShutterRefs(ctx), motion8);
    checkInlineLeaves(motion8, ctx.numPrimitives(), meshes == 1, what + "8");
    detail::WideBvh<4, true> motion4;
    detail::buildWideBvh(ctx, prims, detail::ShutterRefs(ctx), motion4);
    checkInlineLeaves(motion4, ctx.numPrimitives(), meshes == 1, what + "4");
  }
}
