// Frame sequences at the library level: a structure refitted after the
// scene's vertices moved on to the next frames (Accel::refit, MSBVH §5)
// renders the images a rebuild renders, within the ties tolerance of the
// render tests (test_render.cpp): at most 0.1% of the pixels (and at least
// one) differ by more than 1/255, and only where a primary hit is a tie.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mbrt/render.h"
#include "mbrt/scenes.h"
#include "test_util.h"

namespace mbrt {
namespace {

// The scene's motion over [a, a + 0.5] on its steps: what a frame later in a
// sequence shows. Owns the vertices the scene is pointed at.
class MovedVertices {
 public:
  void moveTo(Scene& scene, const Scene& original, float a) {
    data_.clear();
    for (uint32_t id = 0; id < original.numGeometries(); ++id) {
      const Geometry& g = original.geometry(id);
      if (g.type() == GeometryType::Instance || g.numSteps() < 2) continue;
      for (uint32_t k = 0; k < g.numSteps(); ++k) {
        const float t = std::min(1.0f, a + 0.5f * g.stepTime(k));
        auto& v = data_.emplace_back(g.vertices(0).count + 1);  // one more: readable padding
        for (size_t i = 0; i + 1 < v.size(); ++i) v[i] = g.vertexAt(t, uint32_t(i));
        VertexBuffer b;
        b.data = v.data();
        b.count = v.size() - 1;
        b.padding = sizeof(Vec3f);
        scene.setVertices(id, k, b);
      }
    }
  }

 private:
  std::vector<std::vector<Vec3f>> data_;
};

bool sameOrTie(const Hit& a, const Hit& b) {
  if (a.valid() != b.valid()) return false;
  if (!a.valid()) return true;
  if (a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID) return true;
  return std::abs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::abs(a.t));
}

float maxChannelDiff(const Rgb& a, const Rgb& b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

void expectSameImage(const SceneDescription& scene, const Accel& refitted, const Accel& rebuilt,
                     const RenderOptions& o) {
  const RenderResult a = render(scene, refitted, o), b = render(scene, rebuilt, o);
  const RenderCamera camera(scene, o.width, o.height, o.shutterOpen, o.shutterClose);
  size_t differing = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      if (maxChannelDiff(a.image.at(x, y), b.image.at(x, y)) <= 1.0f / 255.0f) continue;
      ++differing;
      for (int s = 0; s < o.spp; ++s) {
        const Ray ray = primaryRay(camera, o, x, y, s);
        Hit ha, hb;
        refitted.intersect(ray, ha);
        rebuilt.intersect(ray, hb);
        EXPECT_TRUE(sameOrTie(ha, hb)) << "pixel " << x << "," << y << ": refit prim " << ha.primID << " t " << ha.t
                                       << ", rebuild prim " << hb.primID << " t " << hb.t;
      }
    }
  EXPECT_LE(differing, std::max<size_t>(1, size_t(o.width) * size_t(o.height) / 1000)) << differing << " pixels";
}

void checkRefitFrames(const std::string& name, double size, AccelKind kind) {
  SCOPED_TRACE(name + " with " + std::string(toString(kind)));
  ProceduralScene p = makeProceduralScene(name, size, 7);
  ProceduralScene original = makeProceduralScene(name, size, 7);
  SceneDescription scene;
  scene.name = p.name;
  scene.scene = p.scene;
  scene.camera.keys = {p.camera};
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.spp = 2;
  o.integrator = IntegratorKind::Ao;
  o.seed = 5;
  bool instances = false;
  for (uint32_t id = 0; id < scene.scene->numGeometries(); ++id)
    instances = instances || scene.scene->geometry(id).type() == GeometryType::Instance;
  auto accel = test::buildKind(*scene.scene, kind);
  MovedVertices moved;
  // Three later frames; one in the sanitizer build (MBRT_TEST_SCALE < 1).
  const std::vector<float> frames =
      test::testScale() < 1.0 ? std::vector<float>{0.25f} : std::vector<float>{0.1f, 0.25f, 0.5f};
  for (float a : frames) {
    moved.moveTo(*scene.scene, *original.scene, a);
    // Instances are rebuilt, never refitted (their key boxes are made once).
    EXPECT_EQ(accel->refit(), !instances) << "frame at " << a;
    auto rebuilt = test::buildKind(*scene.scene, kind);
    expectSameImage(scene, *accel, *rebuilt, o);
  }
}

TEST(Frames, RefitRendersWhatARebuildRendersOnTheSuite) {
  for (AccelKind kind : {AccelKind::BvhInterp, AccelKind::Msbvh}) {
    checkRefitFrames("skinned", 0.05, kind);
    checkRefitFrames("demo", 0.25, kind);
    checkRefitFrames("hair", 0.003, kind);
  }
}

TEST(Frames, KindsWithoutRefitRebuildAndStayCorrect) {
  ProceduralScene p = makeProceduralScene("skinned", 0.05, 3);
  ProceduralScene original = makeProceduralScene("skinned", 0.05, 3);
  auto accel = test::buildKind(*p.scene, AccelKind::Stbvh);
  MovedVertices moved;
  moved.moveTo(*p.scene, *original.scene, 0.3f);
  EXPECT_FALSE(accel->refit());  // rebuilt instead
  auto brute = test::buildKind(*p.scene, AccelKind::Brute);
  SceneDescription scene;
  scene.scene = p.scene;
  scene.camera.keys = {p.camera};
  RenderOptions o;
  o.width = 32;
  o.height = 24;
  o.spp = 1;
  o.integrator = IntegratorKind::Normals;
  expectSameImage(scene, *accel, *brute, o);
}

// One picture split over processes (mpirun, tools/mpi_frames.h) renders
// ranges of tiles: put together they are the one-process picture exactly.
TEST(Frames, TileRangesMakeTheWholePicture) {
  ProceduralScene p = makeProceduralScene("demo", 0.1, 3);
  SceneDescription scene;
  scene.scene = p.scene;
  scene.camera.keys = {p.camera};
  auto accel = test::buildKind(*p.scene, AccelKind::BvhInterp);
  RenderOptions o;
  o.width = 37;
  o.height = 21;
  o.spp = 2;
  o.tileSize = 8;
  o.integrator = IntegratorKind::Ao;
  const RenderResult whole = render(scene, *accel, o);
  const size_t tiles = whole.tilesTotal;  // 5 x 3
  ASSERT_EQ(tiles, 15u);
  Image joined(o.width, o.height);
  for (size_t begin : {size_t(0), size_t(4), size_t(11)}) {
    RenderOptions part = o;
    part.tileBegin = begin;
    part.tileEnd = begin == 0 ? 4 : begin == 4 ? 11 : 99;  // past the end: clamped
    const RenderResult r = render(scene, *accel, part);
    EXPECT_TRUE(r.complete);
    EXPECT_EQ(r.tilesTotal, std::min<size_t>(part.tileEnd, tiles) - begin);
    for (size_t t = begin; t < std::min<size_t>(part.tileEnd, tiles); ++t) {
      const int x0 = int(t % 5) * 8, y0 = int(t / 5) * 8;
      for (int y = y0; y < std::min(o.height, y0 + 8); ++y)
        for (int x = x0; x < std::min(o.width, x0 + 8); ++x) joined.at(x, y) = r.image.at(x, y);
    }
  }
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      EXPECT_EQ(joined.at(x, y).r, whole.image.at(x, y).r) << x << "," << y;
      EXPECT_EQ(joined.at(x, y).g, whole.image.at(x, y).g) << x << "," << y;
      EXPECT_EQ(joined.at(x, y).b, whole.image.at(x, y).b) << x << "," << y;
    }
  RenderOptions none = o;
  none.tileBegin = 20;  // past the last tile: nothing to render
  EXPECT_EQ(render(scene, *accel, none).tilesTotal, 0u);
}

}  // namespace
}  // namespace mbrt
