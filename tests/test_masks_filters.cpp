// Masks and intersection filters with every kind (not only the BVH family):
// layered meshes whose front layer's filter rejects most first candidates,
// so that traversal must go on behind them; masked and filtered meshes and
// segments inside a (masked) instance. Brute is judged by the float64
// reference (which applies masks and filters itself); every other kind must
// give brute's answers, `frozen` at its build time.
#include <gtest/gtest.h>

#include "oracle.h"
#include "reference_check.h"
#include "test_util.h"

using namespace mbrt;

namespace {

// A grid of n x n quads (two triangles each) in the plane z = z0 (+ motion
// over `steps` steps), over [-1,1]^2.
uint32_t addLayer(Scene& scene, float z0, uint32_t steps, float motion, uint32_t n = 6) {
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> pos(steps);
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      const float x0 = -1 + 2.0f * float(i) / float(n), x1 = -1 + 2.0f * float(i + 1) / float(n);
      const float y0 = -1 + 2.0f * float(j) / float(n), y1 = -1 + 2.0f * float(j + 1) / float(n);
      const uint32_t b = uint32_t(pos[0].size());
      for (uint32_t k = 0; k < steps; ++k) {
        const float z = z0 + motion * float(k) * (float(i + j) * 0.05f + 0.1f);
        pos[k].insert(pos[k].end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
      }
      tris.push_back({b, b + 1, b + 2});
      tris.push_back({b, b + 2, b + 3});
    }
  return scene.addTriangleMesh(std::move(tris), std::move(pos));
}

uint32_t addStrands(Scene& scene, float z, uint32_t steps) {
  std::vector<Segment> segs;
  std::vector<std::vector<Vec3f>> pos(steps);
  std::vector<float> radii;
  for (uint32_t i = 0; i < 12; ++i) {
    const float x = -0.9f + 0.15f * float(i);
    for (uint32_t k = 0; k < steps; ++k) {
      const float dz = 0.1f * float(k);
      pos[k].push_back({x, -1, z + dz});
      pos[k].push_back({x, 1, z + dz});
    }
    radii.push_back(0.04f);
    radii.push_back(0.02f);
    segs.push_back({2 * i, 2 * i + 1});
  }
  return scene.addSegments(std::move(segs), std::move(pos), std::move(radii));
}

ProceduralScene maskedFilteredScene(bool filters = true) {
  auto child = std::make_shared<Scene>();
  addLayer(*child, 0.0f, 2, 0.3f, 4);
  addStrands(*child, -0.2f, 2);
  child->setMask(0, 0x2);
  if (filters) child->setFilter(1, [](const FilterArgs& a) { return a.candidate.primID % 2 == 0; });
  auto top = std::make_shared<Scene>();
  // Front layer: the filter rejects two thirds of its triangles, so most
  // rays' first candidate is rejected and the layers behind must be found.
  const uint32_t front = addLayer(*top, -1.0f, 3, 0.2f);
  if (filters) top->setFilter(front, [](const FilterArgs& a) { return a.candidate.primID % 3 == 0; });
  const uint32_t masked = addLayer(*top, -0.5f, 2, 0.2f);
  top->setMask(masked, 0x4);
  const uint32_t strands = addStrands(*top, -0.7f, 3);
  if (filters) top->setFilter(strands, [](const FilterArgs& a) { return a.candidate.primID % 3 != 1; });
  top->setMask(strands, 0x1 | 0x4);
  const uint32_t inst =
      top->addInstance(child, {Affine3f::translate({0, 0, 0.5f}), Affine3f::translate({0.1f, 0, 0.6f}) *
                                                                      Affine3f::rotate({0, 0, 1}, 0.3f)});
  top->setMask(inst, 0x1 | 0x2);
  addLayer(*top, 1.5f, 1, 0.0f, 2);  // the back wall: every ray ends somewhere
  ProceduralScene ps;
  ps.scene = top;
  ps.camera.eye = {0.3f, 0.2f, -4.0f};
  ps.camera.target = {0, 0, 0};
  ps.camera.up = {0, 1, 0};
  ps.camera.verticalFovDegrees = 30.0f;
  return ps;
}

TEST(MasksAndFilters, EveryKindAgreesWithBruteAndBruteWithTheReference) {
  const ProceduralScene ps = maskedFilteredScene();
  std::vector<Ray> rays = test::oracleRays(ps, test::scaled(4000, 400), test::scaled(100, 10), 61);
  const uint32_t masks[] = {~0u, 0x1, 0x2, 0x4, 0x6};
  for (size_t i = 0; i < rays.size(); ++i) rays[i].mask = masks[i % 5];
  const ref::Reference reference(*ps.scene);
  auto brute = test::buildKind(*ps.scene, AccelKind::Brute);
  const ref::RefReport b = test::judgeWithReference(reference, *brute, rays);
  EXPECT_EQ(b.wrong + b.anyWrong, 0u) << b.firstFailure;
  // The filters matter: the same scene without them gives other closest
  // hits on many rays (those whose first candidate is rejected).
  {
    const ProceduralScene unfiltered = maskedFilteredScene(false);
    auto plain = test::buildKind(*unfiltered.scene, AccelKind::Brute);
    std::vector<Hit> a(rays.size()), c(rays.size());
    brute->intersect(rays, a);
    plain->intersect(rays, c);
    size_t differ = 0;
    for (size_t i = 0; i < rays.size(); ++i) differ += a[i].geomID != c[i].geomID || a[i].primID != c[i].primID;
    EXPECT_GT(differ, rays.size() / 5) << "too few rays pass a rejected first candidate";
  }
  for (AccelKind kind : availableAccelKinds()) {
    if (kind == AccelKind::Brute) continue;
    BuildOptions o;
    o.kind = kind;
    o.frozenTime = 0.5f;
    auto accel = Accel::build(*ps.scene, o);
    std::vector<Ray> own = rays;
    if (kind == AccelKind::Frozen)
      for (Ray& r : own) r.time = o.frozenTime;
    if (kind == AccelKind::Embree) {
      // Embree: its own arithmetic; where it differs the reference decides.
      const test::Settlement s = test::settleWithReference(reference, *brute, *accel, own, 2e-4f, "embree");
      EXPECT_EQ(s.bruteWrong + s.peerWrong, 0u) << (s.listed.empty() ? "" : s.listed[0]);
      continue;
    }
    const test::OracleReport rep = test::compareWithOracle(*brute, *accel, own);
    EXPECT_EQ(rep.wrong, 0u) << toString(kind) << ": " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << toString(kind);
    EXPECT_GT(rep.hits, rep.rays / 2) << toString(kind);
  }
}

}  // namespace
