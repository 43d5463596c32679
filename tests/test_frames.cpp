// Frame sequences at the library level: a structure refitted after an
// animation's scene moved on to the next frames (mbrt/io/animation.h,
// Accel::refit, MSBVH §5) renders the images a rebuild renders, within the ties tolerance of the
// render tests (test_render.cpp): at most 0.1% of the pixels (and at least
// one) differ by more than 1/255, and only where a primary hit is a tie.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mbrt/frame_renderer.h"
#include "mbrt/render.h"
#include "mbrt/scenes.h"
#include "test_util.h"

namespace mbrt {
namespace {

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

// A built-in scene's frames (mbrt/io/animation.h): each frame's vertices
// replace the last's in place and the structure follows by refitting.
void checkRefitFrames(const std::string& name, double size, AccelKind kind) {
  SCOPED_TRACE(name + " with " + std::string(toString(kind)));
  AnimationOptions ao;
  ao.size = size;
  ao.seed = 7;
  Animation animation(name, ao);
  const FrameClock clock;
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.spp = 2;
  o.integrator = IntegratorKind::Ao;
  o.seed = 5;
  BuildOptions build;
  build.kind = kind;
  AccelUpdater updater(UpdatePolicy::Refit);
  std::unique_ptr<Accel> accel;
  EXPECT_EQ(updater.update(accel, *animation.frame(0, clock).scene, build).what, "build");
  bool instances = false;
  for (uint32_t id = 0; id < animation.current().scene->numGeometries(); ++id)
    instances = instances || animation.current().scene->geometry(id).type() == GeometryType::Instance;
  // Three later frames; one in the sanitizer build (MBRT_TEST_SCALE < 1).
  const std::vector<int64_t> frames = test::testScale() < 1.0 ? std::vector<int64_t>{6} : std::vector<int64_t>{2, 6, 12};
  for (int64_t f : frames) {
    const SceneDescription& scene = animation.frame(f, clock);
    // Instances change the layout (their keys cannot be replaced in place):
    // the structure is built anew, never refitted.
    const AccelUpdate u = updater.update(accel, *scene.scene, build);
    EXPECT_EQ(u.what, instances ? "rebuild (new layout)" : "refit") << "frame " << f;
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
  AnimationOptions ao;
  ao.size = 0.05;
  ao.seed = 3;
  Animation animation("skinned", ao);
  BuildOptions build;
  build.kind = AccelKind::Stbvh;
  AccelUpdater updater(UpdatePolicy::Refit);
  std::unique_ptr<Accel> accel;
  updater.update(accel, *animation.frame(0, FrameClock{}).scene, build);
  const SceneDescription& scene = animation.frame(7, FrameClock{});
  EXPECT_EQ(updater.update(accel, *scene.scene, build).what, "rebuild (kind cannot refit)");
  auto brute = test::buildKind(*scene.scene, AccelKind::Brute);
  RenderOptions o;
  o.width = 32;
  o.height = 24;
  o.spp = 1;
  o.integrator = IntegratorKind::Normals;
  expectSameImage(scene, *accel, *brute, o);
}

// auto across frames: built for the refits its updater will make, each
// update's line is auto's own summary of what it refitted, and its pictures
// are those of a fresh auto build over each frame.
TEST(Frames, AutoRefitsAcrossFramesAndSaysWhatItDid) {
  AnimationOptions ao;
  ao.size = 0.05;
  ao.seed = 7;
  Animation animation("skinned", ao);
  const FrameClock clock;
  BuildOptions build;
  build.kind = AccelKind::Auto;
  build.autoConfirmByTrace = false;  // the model's choice: the same every run
  EXPECT_FALSE(AccelUpdater(UpdatePolicy::Rebuild).buildOptions(build).autoForRefits);
  AccelUpdater updater(UpdatePolicy::Auto);
  EXPECT_TRUE(updater.buildOptions(build).autoForRefits);
  std::unique_ptr<Accel> accel;
  EXPECT_EQ(updater.update(accel, *animation.frame(0, clock).scene, build).what, "build");
  EXPECT_TRUE(accel->options().autoForRefits);
  RenderOptions o;
  o.width = 48;
  o.height = 32;
  o.spp = 2;
  o.integrator = IntegratorKind::Normals;
  const std::vector<int64_t> frames = test::testScale() < 1.0 ? std::vector<int64_t>{6} : std::vector<int64_t>{2, 6, 12};
  for (int64_t f : frames) {
    const SceneDescription& scene = animation.frame(f, clock);
    const AccelUpdate u = updater.update(accel, *scene.scene, build);
    EXPECT_TRUE(u.refitted) << "frame " << f << ": " << u.what;
    EXPECT_EQ(u.what.rfind("refit: ", 0), 0u) << "frame " << f << ": " << u.what;
    EXPECT_EQ(u.what, accel->lastUpdate());
    EXPECT_EQ(u.what.find("cannot refit"), std::string::npos) << "frame " << f << ": " << u.what;
    expectSameImage(scene, *accel, *Accel::build(*scene.scene, updater.buildOptions(build)), o);
    expectSameImage(scene, *accel, *test::buildKind(*scene.scene, AccelKind::Brute), o);
  }
}

// The library's frame renderer: a frame's picture is the render of that
// frame's scene, whatever frames came before it.
TEST(Frames, FrameRendererRendersEachFramesScene) {
  AnimationOptions ao;
  ao.size = 0.03;
  Animation animation("skinned", ao);
  FrameRenderOptions fo;
  fo.render.width = 64;
  fo.render.height = 48;
  fo.render.spp = 1;
  fo.render.integrator = IntegratorKind::Normals;
  fo.build.kind = AccelKind::BvhInterp;
  fo.policy = UpdatePolicy::Refit;
  fo.threads = 2;
  FrameRenderer renderer(animation, fo);
  EXPECT_EQ(renderer.accel(), nullptr);
  Animation reference("skinned", ao);  // its descriptions: each frame's scene made afresh
  for (int64_t f : {3, 12, 21}) {
    FrameRecord record;
    const RenderResult r = renderer.render(f, record);
    EXPECT_EQ(record.frame, f);
    EXPECT_TRUE(record.complete);
    EXPECT_EQ(record.update.what, f == 3 ? "build" : "refit");
    EXPECT_GT(record.rays, 0u);
    const SceneDescription scene = reference.describe(fo.clock.openAt(f), fo.clock.closeAt(f));
    auto rebuilt = test::buildKind(*scene.scene, AccelKind::BvhInterp);
    const RenderResult expected = render(scene, *rebuilt, fo.render);
    size_t differing = 0;
    for (int y = 0; y < fo.render.height; ++y)
      for (int x = 0; x < fo.render.width; ++x)
        differing += maxChannelDiff(r.image.at(x, y), expected.image.at(x, y)) > 1.0f / 255.0f ? 1 : 0;
    EXPECT_LE(differing, 3u) << "frame " << f;  // ties (test_render.cpp's tolerance: 0.1%)
  }
  FrameRecord record;
  EXPECT_THROW(renderer.render(24, record), Error);
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
