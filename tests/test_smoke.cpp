#include <gtest/gtest.h>

#include "mbrt/accel.h"

using namespace mbrt;

TEST(Smoke, BruteHitsATriangle) {
  Scene scene;
  scene.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                                     {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}});
  BuildOptions opt;
  opt.kind = AccelKind::Brute;
  auto accel = Accel::build(scene, opt);
  Ray ray{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, kInf, 0.5f};
  Hit hit;
  ASSERT_TRUE(accel->intersect(ray, hit));
  EXPECT_NEAR(hit.t, 1.5f, 1e-6f);
  EXPECT_EQ(hit.geomID, 0u);
  EXPECT_EQ(hit.primID, 0u);
}
