// SRT instance keys: interpolation, validation, conservative bounds of the
// curved paths, and every structure against brute on a propeller.
#include <gtest/gtest.h>

#include <random>

#include "accel/structure_factory.h"
#include "scene/scene_context.h"
#include "scene/primitive_bounds.h"
#include "geometry/srt_bounds.h"
#include "mbrt/accel.h"
#include "mbrt/quaternion.h"
#include "oracle.h"
#include "test_util.h"

namespace mbrt {
namespace {

constexpr float kPi = 3.14159265358979f;

void expectNear(Vec3f a, Vec3f b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(Srt, QuaternionBasics) {
  const Quaternion q = Quaternion::fromAxisAngle({0, 0, 1}, 0.5f * kPi);
  expectNear(q.rotate({1, 0, 0}), {0, 1, 0}, 1e-6f);
  Vec3f cx, cy, cz;
  q.toMatrix(cx, cy, cz);
  expectNear(cx, {0, 1, 0}, 1e-6f);
  const Quaternion back = Quaternion::fromRotationMatrix(cx, cy, cz);
  EXPECT_NEAR(std::fabs(dot(back, q)), 1.0f, 1e-6f);
  // slerp halfway = half the angle, also across the hemisphere flip.
  const Quaternion a = Quaternion::identity(), b = Quaternion::fromAxisAngle({0, 0, 1}, 0.8f * kPi);
  expectNear(slerp(a, -b, 0.5f).rotate({1, 0, 0}), {std::cos(0.4f * kPi), std::sin(0.4f * kPi), 0}, 1e-5f);
  EXPECT_NEAR(rotationAngle(a, b), 0.8f * kPi, 1e-5f);
  // T*R*S: scale first, then rotate, then translate.
  const SRTKey k{{2, 1, 1}, q, {0, 0, 3}};
  expectNear(k.toAffine().xfmPoint({1, 0, 0}), {0, 2, 3}, 1e-6f);
  SRTKey d;
  ASSERT_TRUE(decomposeSRT(k.toAffine(), d));
  expectNear(d.scale, k.scale, 1e-5f);
  expectNear(d.translation, k.translation, 1e-6f);
  EXPECT_NEAR(std::fabs(dot(d.rotation, q)), 1.0f, 1e-6f);
}

std::shared_ptr<Scene> blade() {
  auto s = std::make_shared<Scene>();
  // Two long thin blades along x and a hub.
  s->addTriangleMesh({{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}},
                     std::vector<std::vector<Vec3f>>{{{-1.0f, -0.08f, 0},
                                                      {1.0f, -0.08f, 0},
                                                      {1.0f, 0.08f, 0},
                                                      {-1.0f, 0.08f, 0},
                                                      {-0.1f, -0.1f, 0.05f},
                                                      {0.1f, -0.1f, 0.05f},
                                                      {0.1f, 0.1f, 0.05f},
                                                      {-0.1f, 0.1f, 0.05f}}});
  return s;
}

TEST(Srt, TransformAtKeepsTheShapeBetweenKeys) {
  Scene scene;
  const SRTKey k0{{1, 1, 1}, Quaternion::identity(), {0, 0, 0}};
  const SRTKey k1{{1, 1, 1}, Quaternion::fromAxisAngle({0, 0, 1}, 0.5f * kPi), {2, 0, 0}};
  scene.addInstance(blade(), std::vector<SRTKey>{k0, k1});
  scene.addInstance(blade(), std::vector<Affine3f>{k0.toAffine(), k1.toAffine()});
  scene.validate();
  const Affine3f srt = scene.geometry(0).transformAt(0.5f), matrix = scene.geometry(1).transformAt(0.5f);
  EXPECT_NEAR(srt.determinant(), 1.0f, 1e-5f);      // a rigid turn
  EXPECT_NEAR(matrix.determinant(), 0.5f, 1e-5f);   // element-wise lerp shrinks it
  expectNear(srt.xfmPoint({1, 0, 0}), {1 + std::cos(0.25f * kPi), std::sin(0.25f * kPi), 0}, 1e-5f);
  expectNear(scene.geometry(0).transformAt(1.0f).xfmPoint({1, 0, 0}), {2, 1, 0}, 1e-5f);
}

TEST(Srt, ValidationNamesTheProblem) {
  auto expectError = [](std::vector<SRTKey> keys, const std::string& what) {
    Scene scene;
    scene.addInstance(blade(), std::move(keys));
    try {
      scene.validate();
      ADD_FAILURE() << "no error for " << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  SRTKey ok;
  SRTKey nan = ok;
  nan.translation.y = std::nanf("");
  expectError({ok, nan}, "SRT key 1 has a non-finite");
  SRTKey zero = ok;
  zero.scale.z = 0;
  expectError({zero}, "zero scale on axis z");
  SRTKey flip = ok;
  flip.scale.x = -1;
  expectError({ok, flip}, "changes sign");
  SRTKey noRotation = ok;
  noRotation.rotation = {0, 0, 0, 0};
  expectError({noRotation}, "zero or non-finite rotation");
  // A non-unit quaternion is normalized.
  Scene scene;
  SRTKey big = ok;
  big.rotation = {2, 0, 0, 2};
  scene.addInstance(blade(), std::vector<SRTKey>{big});
  EXPECT_NO_THROW(scene.validate());
  EXPECT_NEAR(scene.geometry(0).srtKeys()[0].rotation.norm(), 1.0f, 1e-6f);
}

// Random SRT keys with large turns, scale changes and a moving child: the
// key boxes (interpolated) and linear bounds over random ranges contain
// every vertex at many sampled times.
TEST(Srt, BoundsAreConservativeForTheCurvedPath) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  size_t checks = 0, violations = 0;
  double worstSlack = 0;
  for (int trial = 0; trial < 12; ++trial) {
    auto child = std::make_shared<Scene>();
    test::addRandomMovingTriangles(*child, rng, 30, 1 + trial % 3, 0.3f, 0.2f);
    const uint32_t keys = 2 + trial % 4;
    std::vector<SRTKey> srt;
    for (uint32_t k = 0; k < keys; ++k) {
      SRTKey key;
      key.scale = {1.0f + 0.5f * u(rng), 1.0f + 0.5f * u(rng), 1.0f + 0.5f * u(rng)};
      // Up to ~170 degrees between keys about a random axis.
      key.rotation = (k == 0 ? Quaternion::identity() : srt.back().rotation) *
                     Quaternion::fromAxisAngle({u(rng), u(rng), u(rng) + 0.01f}, 2.95f * (0.5f + 0.5f * u(rng)));
      key.translation = Vec3f{u(rng), u(rng), u(rng)} * 2.0f;
      srt.push_back(key);
    }
    Scene scene;
    scene.addInstance(child, srt);
    scene.validate();
    BuildOptions o;
    o.kind = AccelKind::Brute;
    detail::BuildBudget budget;
    detail::SceneContext ctx(scene, o, budget, detail::makeStructure);
    const Geometry& g = scene.geometry(0);
    const detail::PrimRef ref{0, 0};
    const TimeRange range{0.1f + 0.05f * u(rng), 0.8f + 0.1f * u(rng)};
    const LBounds lb = detail::linearBounds(ctx, ref, range);
    for (int i = 0; i <= 4000; ++i) {
      const float t = float(i) / 4000.0f;
      const Affine3f m = g.transformAt(t);
      const Box3f box = detail::boxAt(ctx, ref, t);
      const bool inRange = t >= range.lo && t <= range.hi;
      const Box3f lin = lb.at((t - range.lo) / range.size());
      for (uint32_t c = 0; c < child->numGeometries(); ++c) {
        const Geometry& cg = child->geometry(c);
        for (size_t v = 0; v < cg.vertices(0).count; ++v) {
          const Vec3f p = m.xfmPoint(cg.vertexAt(t, uint32_t(v)));
          ++checks;
          if (!box.contains(p) || (inRange && !lin.contains(p))) ++violations;
          for (int a = 0; a < 3; ++a)
            worstSlack = std::max(worstSlack, double(std::min(p[a] - box.lower[a], box.upper[a] - p[a])));
        }
      }
    }
  }
  EXPECT_EQ(violations, 0u) << "of " << checks;
  EXPECT_GT(checks, 100000u);
}

// The segment bound alone, on a half turn of a far-off box: a sampled path
// must stay inside, and the bound must not be much larger than the path.
TEST(Srt, SegmentBoundsAreTight) {
  const SRTKey a{{1, 1, 1}, Quaternion::identity(), {0, 0, 0}};
  const SRTKey b{{1.5f, 1, 1}, Quaternion::fromAxisAngle({0, 0, 1}, 0.9f * kPi), {1, 0, 0}};
  const Box3f box({2, -0.1f, -0.1f}, {3, 0.1f, 0.1f});
  const Box3f bound = detail::srtSegmentBounds(a, b, box);
  Box3f path;
  for (int i = 0; i <= 10000; ++i) {
    const Affine3f m = lerp(a, b, float(i) / 10000.0f).toAffine();
    for (int c = 0; c < 8; ++c)
      path.extend(m.xfmPoint({c & 1 ? box.upper.x : box.lower.x, c & 2 ? box.upper.y : box.lower.y,
                              c & 4 ? box.upper.z : box.lower.z}));
  }
  EXPECT_TRUE(bound.contains(path));
  for (int ax = 0; ax < 3; ++ax) {
    EXPECT_LT(path.lower[ax] - bound.lower[ax], 0.01f * maxComponent(path.size()));
    EXPECT_LT(bound.upper[ax] - path.upper[ax], 0.01f * maxComponent(path.size()));
  }
}

// A propeller turning 3/4 of a turn (3 SRT keys) over a floor, with a
// second, scaled and moved copy over half of the shutter: every structure
// agrees with brute.
TEST(Srt, EveryStructureAgreesWithBruteOnAPropeller) {
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh({{0, 1, 2}, {0, 2, 3}},
                         std::vector<std::vector<Vec3f>>{{{-3, -1.5f, -1}, {3, -1.5f, -1}, {3, 1.5f, -1}, {-3, 1.5f, -1}}});
  auto prop = blade();
  std::vector<SRTKey> keys;
  for (int k = 0; k < 3; ++k)
    keys.push_back({{1, 1, 1}, Quaternion::fromAxisAngle({0, 0, 1}, 0.75f * kPi * float(k)), {-1, 0, 0}});
  scene->addInstance(prop, keys);
  std::vector<SRTKey> keys2;
  for (int k = 0; k < 4; ++k)
    keys2.push_back({{0.6f + 0.1f * float(k), 0.6f, 0.6f},
                     Quaternion::fromAxisAngle({0.2f, 0.3f, 1}, -0.9f * kPi * float(k)),
                     {1.2f, 0.2f * float(k), 0.3f}});
  scene->addInstance(prop, keys2, {0.25f, 0.75f});
  ProceduralScene ps{"propeller", scene, CameraSpec{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 50.0f}};
  const auto rays = test::oracleRays(ps, 3000, 100, 3);
  BuildOptions o;
  o.kind = AccelKind::Brute;
  const auto brute = Accel::build(*scene, o);
  size_t hits = 0;
  for (AccelKind kind : availableAccelKinds()) {
    if (kind == AccelKind::Brute) continue;
    if (kind == AccelKind::Frozen) {
      // `frozen` holds the geometry at its build time: compare there.
      BuildOptions f;
      f.kind = kind;
      f.frozenTime = 0.3f;
      const auto frozen = Accel::build(*scene, f);
      const test::OracleReport rep =
          test::compareWithOracle(*brute, *frozen, test::oracleRays(ps, 2000, 0, 5, 0.3f));
      EXPECT_EQ(rep.wrong, 0u) << "frozen: " << rep.firstFailure;
      EXPECT_EQ(rep.anyWrong, 0u) << "frozen";
      continue;
    }
    const float tolerance = kind == AccelKind::Embree ? 2e-4f : 1e-5f;
    for (int width : {2, 8}) {
      const auto accel = test::buildKind(*scene, kind, width);
      const test::OracleReport rep = test::compareWithOracle(*brute, *accel, rays, tolerance);
      EXPECT_EQ(rep.wrong, 0u) << toString(kind) << " width " << width << ": " << rep.firstFailure;
      EXPECT_EQ(rep.anyWrong, 0u) << toString(kind);
      hits = rep.hits;
    }
  }
  EXPECT_GT(hits, rays.size() / 4);
}

}  // namespace
}  // namespace mbrt
