// `auto`: rigid motion extraction (whole meshes and connected pieces), hits
// that name the original scene's ids, agreement with brute (exact at the
// default tolerance; near edges only, and vanishing, at coarse tolerances),
// filters that see original ids, conservative instance bounds, options.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include "accel/structure_factory.h"
#include "auto/auto_plan.h"
#include "auto/part_bounds.h"
#include "auto_scene.h"
#include "mixed_scene.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

const detail::RigidPart* rigidPartOf(const detail::AutoPlan& plan, uint32_t geomID) {
  for (const auto& r : plan.rigid)
    if (r.geomID == geomID) return &r;
  return nullptr;
}

TEST(AutoExtraction, RigidMeshIsFoundRigidDeformingIsNotMixedMeshSplits) {
  const ProceduralScene ps = test::autoTestScene();
  ps.scene->setFilter(6, [](const FilterArgs&) { return true; });
  const detail::AutoPlan plan = detail::planDecomposition(*ps.scene, 1e-5);
  const detail::RigidPart* whole = rigidPartOf(plan, 0);
  ASSERT_NE(whole, nullptr) << "a rigidly turning mesh is rigid";
  EXPECT_TRUE(whole->prims.empty()) << "the whole mesh is one part";
  EXPECT_EQ(whole->fit.keys.size(), 9u);
  EXPECT_LT(whole->fit.maxResidual, 1e-5);
  EXPECT_EQ(rigidPartOf(plan, 2), nullptr) << "a deforming mesh is not rigid";
  EXPECT_EQ(rigidPartOf(plan, 3), nullptr) << "a static mesh is left as it is";
  EXPECT_EQ(rigidPartOf(plan, 6), nullptr) << "a mesh with a filter stays world-space";
  // Geometry 1: a rigid piece and a deforming piece.
  const detail::RigidPart* piece = rigidPartOf(plan, 1);
  ASSERT_NE(piece, nullptr);
  const uint32_t half = ps.scene->geometry(1).numPrimitives() / 2;
  ASSERT_EQ(piece->prims.size(), half);
  for (uint32_t p : piece->prims) EXPECT_LT(p, half) << "the rigid piece is the first blob";
  bool restOfMesh = false;
  for (const auto& w : plan.world)
    if (w.geomID == 1) {
      restOfMesh = true;
      EXPECT_EQ(w.prims.size(), half);
      for (uint32_t p : w.prims) EXPECT_GE(p, half);
    }
  EXPECT_TRUE(restOfMesh) << "the deforming piece stays world-space";
  EXPECT_EQ(plan.userInstances, std::vector<uint32_t>{7});
}

TEST(AutoExtraction, ToleranceDecidesNearlyRigidMeshes) {
  const ProceduralScene noisy = test::autoTestScene(1e-4f);
  EXPECT_EQ(rigidPartOf(detail::planDecomposition(*noisy.scene, 1e-5), 4), nullptr);
  const detail::AutoPlan coarsePlan = detail::planDecomposition(*noisy.scene, 1e-3);  // outlives `coarse`
  const detail::RigidPart* coarse = rigidPartOf(coarsePlan, 4);
  ASSERT_NE(coarse, nullptr);
  EXPECT_GT(coarse->fit.maxResidual, 1e-5);
  EXPECT_LE(coarse->fit.maxResidual, 1e-3);
  EXPECT_EQ(rigidPartOf(detail::planDecomposition(*noisy.scene, 0.0), 0), nullptr)
      << "tolerance 0 extracts only exact fits, and float rotations are not exact";
}

// A rigid part as a scene of one instance: the part's triangles at the
// rest pose (step 0) under the fit's keys.
struct PartAsInstance {
  std::vector<Triangle> tris;
  Scene top;
  PartAsInstance(const Geometry& g, const detail::RigidPart& part) {
    if (part.prims.empty()) tris.assign(g.triangles().begin(), g.triangles().end());
    for (uint32_t p : part.prims) tris.push_back(g.triangles()[p]);
    auto child = std::make_shared<Scene>();
    child->addTriangleMesh(tris, std::vector<VertexBuffer>{g.vertices(0)});
    top.addInstance(child, part.fit.keys, g.timeRange());
  }
};

// Every affine key lerped and applied to the rest pose stays inside the
// instance's linear bounds, and so does the original mesh (within the fit).
TEST(AutoBounds, InstanceBoundsAreConservativeAtSampledTimes) {
  const ProceduralScene ps = test::autoTestScene();
  const detail::AutoPlan plan = detail::planDecomposition(*ps.scene, 1e-5);
  for (const detail::RigidPart& part : plan.rigid) {
    const Geometry& g = ps.scene->geometry(part.geomID);
    const PartAsInstance asInstance(g, part);
    const std::vector<Triangle>& tris = asInstance.tris;
    const Scene& top = asInstance.top;
    BuildOptions o;
    o.kind = AccelKind::Brute;
    detail::BuildBudget budget(0);
    detail::SceneContext ctx(top, o, budget, detail::makeStructure);
    const detail::PrimKeys keys = ctx.keys({0, 0});
    const float slack = float(1e-5 * part.fit.diagonal) + 1e-6f;
    const Geometry& inst = top.geometry(0);
    for (int i = 0; i <= 200; ++i) {
      const float t = g.timeRange().lo + g.timeRange().size() * float(i) / 200.0f;
      uint32_t s;
      float f;
      inst.segmentAt(t, s, f);
      const Box3f box = lerp(keys(s), keys(std::min(s + 1, inst.numSteps() - 1)), f);
      const Affine3f m = inst.transformAt(t);
      for (const Triangle& tri : tris)
        for (uint32_t v : {tri.v0, tri.v1, tri.v2}) {
          const Vec3f p = m.xfmPoint(g.vertices(0)[v]);
          ASSERT_TRUE(box.contains(p)) << "geometry " << part.geomID << " time " << t;
          const Vec3f q = g.vertexAt(t, v);
          for (int a = 0; a < 3; ++a) {
            ASSERT_GE(q[a], box.lower[a] - slack) << "geometry " << part.geomID << " time " << t;
            ASSERT_LE(q[a], box.upper[a] + slack) << "geometry " << part.geomID << " time " << t;
          }
        }
    }
  }
}

std::unique_ptr<Accel> buildAuto(const Scene& scene, float tolerance = 1e-5f, int branching = 8,
                                 std::optional<AccelKind> leafKind = std::nullopt) {
  BuildOptions o;
  o.kind = AccelKind::Auto;
  o.autoFitTolerance = tolerance;
  o.branching = branching;
  o.autoLeafKind = leafKind;
  return Accel::build(scene, o);
}

// The top level's boxes of a rigid part (auto/part_bounds.h): at sampled
// times the lerp of consecutive boxes holds the instance's vertices and the
// mesh's own; they are never looser than the corner bounds of the rest pose
// under the keys, and tighter where a part turns.
TEST(AutoBounds, PartKeyBoxesHoldTheInstanceAndBeatCornerBounds) {
  const ProceduralScene ps = test::autoTestScene();
  const detail::AutoPlan plan = detail::planDecomposition(*ps.scene, 1e-5);
  ASSERT_FALSE(plan.rigid.empty());
  double tightest = 1.0;
  for (const detail::RigidPart& part : plan.rigid) {
    const Geometry& g = ps.scene->geometry(part.geomID);
    const std::vector<Box3f> boxes = detail::partKeyBoxes(g, part);
    ASSERT_EQ(boxes.size(), g.numSteps());
    const PartAsInstance asInstance(g, part);
    const std::vector<Triangle>& tris = asInstance.tris;
    const Scene& top = asInstance.top;
    BuildOptions o;
    o.kind = AccelKind::Brute;
    detail::BuildBudget budget(0);
    detail::SceneContext ctx(top, o, budget, detail::makeStructure);
    const Geometry& inst = top.geometry(0);
    for (int i = 0; i <= 200; ++i) {
      const float t = g.timeRange().lo + g.timeRange().size() * float(i) / 200.0f;
      uint32_t s;
      float f;
      inst.segmentAt(t, s, f);
      const Box3f box = lerp(boxes[s], boxes[std::min(s + 1, inst.numSteps() - 1)], f);
      const Affine3f m = inst.transformAt(t);
      for (const Triangle& tri : tris)
        for (uint32_t v : {tri.v0, tri.v1, tri.v2}) {
          ASSERT_TRUE(box.contains(m.xfmPoint(g.vertices(0)[v]))) << "geometry " << part.geomID << " time " << t;
          ASSERT_TRUE(box.contains(g.vertexAt(t, v))) << "geometry " << part.geomID << " time " << t;
        }
    }
    auto area = [](const Box3f& b) {
      const Vec3f d = b.upper - b.lower;
      return double(d.x) * d.y + double(d.y) * d.z + double(d.z) * d.x;
    };
    double ours = 0, corners = 0;
    for (uint32_t k = 0; k < g.numSteps(); ++k) {
      ours += area(boxes[k]);
      corners += area(ctx.keyBox({0, 0}, k));
    }
    EXPECT_LE(ours, corners * (1.0 + 1e-4)) << "geometry " << part.geomID;
    tightest = std::min(tightest, ours / corners);
  }
  EXPECT_LT(tightest, 0.99) << "a turning part's boxes are tighter than its corner bounds";
}

// Matrix keys interpolate element-wise, so each key's box is the child's
// bounds under that key alone: a translating instance's boxes move with it
// (the union of neighbouring keys' boxes would hold it still).
TEST(AutoBounds, MatrixKeyBoxesFollowTheirKeys) {
  auto child = std::make_shared<Scene>();
  child->addTriangleMesh({{0, 1, 2}, {1, 3, 2}},
                         std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {1, 1, 1}}});
  Scene top;
  top.addInstance(child, {Affine3f(), Affine3f::translate({10, 0, 0}), Affine3f::translate({10, 10, 0})});
  BuildOptions o;
  o.kind = AccelKind::Brute;
  detail::BuildBudget budget(0);
  detail::SceneContext ctx(top, o, budget, detail::makeStructure);
  const Vec3f shift[3] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}};
  for (uint32_t k = 0; k < 3; ++k) {
    const Box3f box = ctx.keyBox({0, 0}, k);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(box.lower[a], shift[k][a], 1e-4f) << "key " << k << " axis " << a;  // widened by ulps
      EXPECT_NEAR(box.upper[a], shift[k][a] + 1.0f, 1e-4f) << "key " << k << " axis " << a;
    }
  }
}

TEST(AutoOracle, AgreesWithBruteOnRigidDeformingFilteredAndInstancedGeometry) {
  const ProceduralScene ps = test::autoTestScene(0.0f, 10);
  std::atomic<int> badIds{0};
  const uint32_t prims3 = ps.scene->geometry(3).numPrimitives(), prims6 = ps.scene->geometry(6).numPrimitives();
  ps.scene->setFilter(3, [&](const FilterArgs& a) {
    if (a.candidate.geomID != 3 || a.candidate.primID >= prims3 || a.candidate.instID != kInvalidId) ++badIds;
    return a.candidate.primID % 3 != 1;
  });
  ps.scene->setFilter(6, [&](const FilterArgs& a) {
    if (a.candidate.geomID != 6 || a.candidate.primID >= prims6) ++badIds;
    return a.candidate.primID % 2 == 0;
  });
  auto oracle = test::buildBrute(*ps.scene);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2500, 300), test::scaled(40, 5), 11);
  // As auto chooses (the scene is small: the whole scene as one object may
  // win its trial), and with the decomposition kept (a forced leaf kind
  // skips the flat trial): instances, the world object and user instances.
  const std::pair<std::optional<AccelKind>, int> builds[] = {
      {std::nullopt, 2}, {std::nullopt, 8}, {AccelKind::Stbvh, 2}, {AccelKind::Stbvh, 8}};
  for (const auto& [leafKind, branching] : builds) {
    auto tested = buildAuto(*ps.scene, 1e-5f, branching, leafKind);
    if (leafKind) EXPECT_NE(tested->stats().objects.find("rigid"), std::string::npos) << tested->stats().objects;
    badIds = 0;
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u);
    EXPECT_GT(rep.hits, rep.rays / 4);
    EXPECT_EQ(badIds.load(), 0) << "filters see the original ids";
    // Masks: geometry 0 carries mask 1 only.
    const auto maskedRep = test::compareMasked(*oracle, *tested, rays, 2u);
    EXPECT_EQ(maskedRep.wrong, 0u) << maskedRep.firstFailure;
    EXPECT_EQ(maskedRep.anyWrong, 0u);
  }
}

TEST(AutoOracle, AgreesWithBruteOnTheMixedScene) {
  const ProceduralScene ps = test::mixedScene();
  auto oracle = test::buildBrute(*ps.scene);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 300), test::scaled(30, 5), 5);
  for (AccelKind leaf : {AccelKind::BvhInterp, AccelKind::Stbvh, AccelKind::Msbvh}) {
    BuildOptions o;
    o.kind = AccelKind::Auto;
    o.autoLeafKind = leaf;
    auto tested = Accel::build(*ps.scene, o);
    EXPECT_NE(tested->stats().objects.find("forced"), std::string::npos);
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << toString(leaf) << ": " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << toString(leaf);
  }
}

// Hits on an extracted rigid part: grazing ones (|cos| between the ray and
// the normal below 0.1) are the original triangle's own world-space test,
// t, u and v bit for bit as brute's; steeper ones keep the instance's, within
// 5e-6 of brute's t (measured at most 2.6e-6 on rotate and crowd; grazing
// ones off by up to 5e-5 without the world test).
TEST(AutoOracle, GrazingRigidHitsAreBrutesOwnSteepOnesWithinRounding) {
  const ProceduralScene ps = makeProceduralScene("rotate", 0.02, 3);
  auto oracle = test::buildBrute(*ps.scene);
  BuildOptions o;
  o.kind = AccelKind::Auto;
  o.autoLeafKind = AccelKind::BvhInterp;  // the decomposition, not the flat trial
  auto tested = Accel::build(*ps.scene, o);
  ASSERT_NE(tested->stats().objects.find("rigid"), std::string::npos) << tested->stats().objects;
  size_t grazing = 0, steep = 0;
  double worst = 0;
  for (const Ray& r : test::oracleRays(ps, test::scaled(20000, 4000), test::scaled(100, 20), 29)) {
    Hit a, b;
    if (!oracle->intersect(r, a) || !tested->intersect(r, b) || a.primID != b.primID) continue;
    const float c = std::fabs(dot(a.Ng, r.dir)) / std::sqrt(dot(a.Ng, a.Ng) * dot(r.dir, r.dir));
    if (c < 0.09f) {  // clear of the threshold: the tested side's normal differs by rounding
      ++grazing;
      EXPECT_EQ(a.t, b.t) << "grazing hit at |cos| " << c;
      EXPECT_EQ(a.u, b.u);
      EXPECT_EQ(a.v, b.v);
    } else if (c > 0.11f) {
      ++steep;
      worst = std::max(worst, std::fabs(double(a.t) - double(b.t)) / std::max(1.0, std::fabs(double(a.t))));
    }
  }
  EXPECT_GT(grazing, test::scaled(200, 40)) << "too few grazing hits to mean anything";
  EXPECT_GT(steep, test::scaled(4000, 800));
  EXPECT_LE(worst, 5e-6);
}

// A scene of one rigid mesh: its one instance is tested without a tree
// over it (one_instance.h); hits, any-hits and the mesh's mask agree with
// brute.
TEST(AutoOracle, OneInstanceIsTestedWithoutATopLevel) {
  const ProceduralScene ps = makeProceduralScene("rotate", 0.02, 5);
  ps.scene->setMask(0, 1u);
  auto oracle = test::buildBrute(*ps.scene);
  // The leaf kind forced: the decomposition kept (no flat trial).
  auto tested = buildAuto(*ps.scene, 1e-5f, 8, AccelKind::BvhInterp);
  const AccelStats s = tested->stats();
  EXPECT_NE(s.objects.find(": rigid,"), std::string::npos) << s.objects;
  EXPECT_NE(s.objects.find("top level: none, its one instance tested directly"), std::string::npos) << s.objects;
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 300), test::scaled(30, 5), 13);
  const auto rep = test::compareWithOracle(*oracle, *tested, rays);
  EXPECT_EQ(rep.wrong, 0u) << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u);
  EXPECT_GT(rep.hits, rep.rays / 10);
  const auto maskedRep = test::compareMasked(*oracle, *tested, rays, 2u);
  EXPECT_EQ(maskedRep.hits, 0u);
  EXPECT_EQ(maskedRep.wrong + maskedRep.anyWrong, 0u) << maskedRep.firstFailure;
}

// Where nothing is extracted, the chosen kind is built over the scene
// itself (not the oracle that stands in below user instances).
TEST(AutoChoice, DeformingScenesGetARealStructure) {
  for (const char* name : {"deform", "hair", "hairball"}) {
    const ProceduralScene ps = makeProceduralScene(name, 0.01, 3);
    auto accel = buildAuto(*ps.scene);
    const AccelStats s = accel->stats();
    EXPECT_GT(s.innerNodes, 0u) << name << ": " << s.objects;
    EXPECT_EQ(s.objects.find("kind brute"), std::string::npos) << name << ": " << s.objects;
  }
}

}  // namespace
