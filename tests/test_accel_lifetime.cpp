// An Accel whose scene was destroyed, moved from or moved into refuses every
// call with an Error (accel.h, "Lifetime"), instead of reading freed memory.
#include <gtest/gtest.h>

#include "error_of.h"
#include "test_util.h"

namespace mbrt {
namespace {

Ray rayAtTheScene() {
  Ray r;
  r.org = {0, 0, -5};
  r.dir = {0, 0, 1};
  r.time = 0.5f;
  return r;
}

void expectRefused(const Accel& accel) {
  const Ray ray = rayAtTheScene();
  Hit hit;
  std::vector<Ray> rays(4, ray);
  std::vector<Hit> hits(4);
  std::vector<uint8_t> any(4);
  TraversalCounters counters;
  const std::string expected = "the scene this accel was built on was destroyed or moved";
  EXPECT_THROW(accel.intersect(ray, hit), Error);
  EXPECT_THROW(accel.occluded(ray), Error);
  EXPECT_THROW(accel.intersect(ray, hit, counters), Error);
  EXPECT_THROW(accel.intersect(rays, hits), Error);
  EXPECT_THROW(accel.occluded(rays, any), Error);
  EXPECT_THROW(accel.stats(), Error);
  EXPECT_THROW(accel.scene(), Error);
  EXPECT_THROW(accel.clusterOf(0, 0), Error);
  EXPECT_NE(test::errorOf([&] { accel.stats(); }).find(expected), std::string::npos);
}

std::unique_ptr<Scene> denseScene() {
  auto scene = std::make_unique<Scene>();
  std::mt19937 rng(3);
  test::addRandomMovingTriangles(*scene, rng, 300, 2, 0.4f, 0.1f);
  return scene;
}

TEST(AccelLifetime, DestroyedSceneIsRefused) {
  for (AccelKind kind : availableAccelKinds()) {
    auto scene = denseScene();
    auto accel = test::buildKind(*scene, kind);
    std::vector<Hit> hits(1);
    const Ray ray = rayAtTheScene();
    accel->intersect(std::span(&ray, 1), hits);  // fine while the scene lives
    scene.reset();
    SCOPED_TRACE(std::string(toString(kind)));
    expectRefused(*accel);
    EXPECT_THROW(accel->rebuild(), Error);
    EXPECT_THROW(accel->refit(), Error);
  }
}

TEST(AccelLifetime, MovedSceneIsRefusedOnBothSides) {
  auto source = denseScene();
  auto onSource = test::buildKind(*source, AccelKind::Stbvh);
  Scene moved(std::move(*source));
  expectRefused(*onSource);
  // The geometry went with the move: an accel on the new object works, and
  // the moved-from object is empty.
  Hit hit;
  auto onMoved = test::buildKind(moved, AccelKind::Stbvh);
  EXPECT_TRUE(onMoved->intersect(rayAtTheScene(), hit));
  EXPECT_EQ(source->numGeometries(), 0u);

  // Assigning over a scene expires the accels built on it, too.
  Scene other;
  std::mt19937 rng(4);
  test::addRandomMovingTriangles(other, rng, 20, 1);
  moved = std::move(other);
  expectRefused(*onMoved);
}

TEST(AccelLifetime, LiveSceneIsNotRefused) {
  auto scene = denseScene();
  auto accel = test::buildKind(*scene, AccelKind::BvhInterp);
  Hit hit;
  EXPECT_TRUE(accel->intersect(rayAtTheScene(), hit));
  EXPECT_NO_THROW(accel->rebuild());
  EXPECT_EQ(&accel->scene(), scene.get());
}

}  // namespace
}  // namespace mbrt
