// Animations (mbrt/io/animation.h): an input loaded once and its scene frame
// by frame, updated in place; the update policies that make an Accel follow
// it (mbrt/accel_update.h), checked against the loader's own scenes, the
// whole-timeline motion and the brute-force oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "error_of.h"
#include "gltf_test_file.h"
#include "mbrt/accel_update.h"
#include "mbrt/io/animation.h"
#include "mbrt/io/loaders.h"
#include "mbrt/scenes.h"
#include "oracle.h"
#include "temp_dir.h"

namespace mbrt {
namespace {

namespace fs = std::filesystem;
using test::errorOf;

const fs::path kDir = test::freshProcessDir("mbrt_test_animation_");
const std::string kKeys = std::string(MBRT_SOURCE_DIR) + "/tests/data/keys";

// Every vertex of every step, every instance key, time range and mask equal.
void expectSameScene(const Scene& a, const Scene& b, const std::string& what) {
  ASSERT_EQ(a.numGeometries(), b.numGeometries()) << what;
  for (uint32_t id = 0; id < a.numGeometries(); ++id) {
    const Geometry &x = a.geometry(id), &y = b.geometry(id);
    ASSERT_EQ(x.type(), y.type()) << what << " geometry " << id;
    ASSERT_EQ(x.numSteps(), y.numSteps()) << what << " geometry " << id;
    EXPECT_EQ(x.mask(), y.mask()) << what;
    EXPECT_TRUE(x.timeRange() == y.timeRange()) << what;
    for (uint32_t k = 0; k < x.numSteps(); ++k) {
      if (x.type() == GeometryType::Instance) {
        const SRTKey &p = x.srtKeys()[k], &q = y.srtKeys()[k];
        EXPECT_TRUE(p.translation == q.translation && p.scale == q.scale) << what << " geometry " << id;
        continue;
      }
      ASSERT_EQ(x.vertices(k).count, y.vertices(k).count);
      for (uint32_t i = 0; i < x.vertices(k).count; ++i)
        ASSERT_TRUE(x.vertexAtStep(k, i) == y.vertexAtStep(k, i)) << what << " geometry " << id << " step " << k;
    }
  }
}

// Rays from outside the scene's bounds through random points inside, at
// random times.
std::vector<Ray> raysThrough(const Scene& scene, size_t n, uint32_t seed) {
  const Box3f b = sceneBounds(scene);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float reach = 2.0f * length(b.size()) + 1.0f;
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const Vec3f target{b.lower.x + u(rng) * b.size().x, b.lower.y + u(rng) * b.size().y,
                       b.lower.z + u(rng) * b.size().z};
    const Vec3f away = normalize(Vec3f{u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f} + Vec3f(1e-3f));
    r.org = target + away * reach;
    r.dir = target - r.org;
    r.time = u(rng);
  }
  return rays;
}

void expectOracle(const Scene& scene, const Accel& accel, const std::string& what) {
  const test::OracleReport rep = test::compareWithOracle(*test::buildBrute(scene), accel, raysThrough(scene, 600, 7));
  EXPECT_EQ(rep.wrong, 0u) << what << ": " << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u) << what;
  EXPECT_GT(rep.hits, 0u) << what;
}

TEST(Animation, GltfFramesAreTheLoadersScenes) {
  const std::string path = test::writeTinyGltf(kDir, "frames");
  Animation a(path);
  EXPECT_EQ(a.timeline().what, "clip 0 'move'");
  EXPECT_EQ(a.timeline().end, 1.0);
  const FrameClock clock;
  for (int64_t f : {0, 5, 17, 23}) {
    GltfOptions o;
    o.shutterOpen = clock.openAt(f);
    o.shutterClose = clock.closeAt(f);
    const SceneDescription loaded = loadGltf(path, o);
    const SceneDescription& frame = a.frame(f, clock);
    expectSameScene(*frame.scene, *loaded.scene, "frame " + std::to_string(f));
    EXPECT_EQ(frame.shutterClose, *o.shutterClose);
    EXPECT_EQ(frame.materials.size(), loaded.materials.size());
    expectSameScene(*a.describe(*o.shutterOpen, *o.shutterClose).scene, *loaded.scene, "describe");
  }
}

TEST(Animation, ReadsItsFileOnce) {
  const fs::path dir = kDir / "once";
  const std::string path = test::writeTinyGltf(dir, "once");
  Animation a(path);
  fs::remove_all(dir);  // what the frames need was read at the construction
  EXPECT_NE(errorOf([&] { loadGltf(path); }), "(no error)");
  for (int64_t f = 0; f < 4; ++f) EXPECT_EQ(a.frame(f, FrameClock{}).scene->numGeometries(), 3u);
}

// Clip 'other' moves one joint only: with fixed steps, every frame has the
// layout of the last, and its vertices replace the last's in place.
TEST(Animation, SceneUpdatedInPlaceAndAccelsRefit) {
  const std::string path = test::writeTinyGltf(kDir, "in_place");
  AnimationOptions o;
  o.clip = "other";
  o.steps.steps = 3;
  Animation a(path, o);
  EXPECT_EQ(a.change(), SceneChange::None);
  EXPECT_EQ(a.current().scene->numGeometries(), 0u);
  const Scene* scene = a.current().scene.get();
  const FrameClock clock{24.0, 360.0};
  a.frame(0, clock);
  EXPECT_EQ(a.change(), SceneChange::Layout);
  std::unique_ptr<Accel> accel;
  AccelUpdater refit(UpdatePolicy::Refit);
  BuildOptions bvh;
  bvh.kind = AccelKind::BvhInterp;
  EXPECT_EQ(refit.update(accel, *scene, bvh).what, "build");
  for (int64_t f : {6, 12, 23}) {
    SceneDescription& d = a.frame(f, clock);
    EXPECT_EQ(d.scene.get(), scene);
    EXPECT_EQ(a.change(), SceneChange::Vertices);
    GltfOptions g;
    g.clip = "other";
    g.steps.steps = 3;
    g.shutterOpen = clock.openAt(f);
    g.shutterClose = clock.closeAt(f);
    expectSameScene(*scene, *loadGltf(path, g).scene, "frame " + std::to_string(f));
    const AccelUpdate u = refit.update(accel, *scene, bvh);
    EXPECT_EQ(u.what, "refit");
    EXPECT_TRUE(u.refitted);
    expectOracle(*scene, *accel, "refitted frame " + std::to_string(f));
  }
  // Clip 'move' turns an instance: its keys cannot be replaced in place, so
  // every frame replaces the geometries and expires the accels over them.
  Animation turning(path);
  turning.frame(0, clock);
  std::unique_ptr<Accel> built;
  EXPECT_EQ(refit.update(built, *turning.current().scene, bvh).what, "build");
  const Accel* before = built.get();
  turning.frame(1, clock);
  EXPECT_EQ(turning.change(), SceneChange::Layout);
  EXPECT_FALSE(before->sceneAlive());
  EXPECT_NE(errorOf([&] { before->stats(); }), "(no error)");
  EXPECT_EQ(refit.update(built, *turning.current().scene, bvh).what, "rebuild (new layout)");
  expectOracle(*turning.current().scene, *built, "new layout");
}

TEST(Animation, TimelinesFrameRangesAndBadInput) {
  Animation skinned("skinned", AnimationOptions{{}, {}, 24.0, {}, 0.02, 1, false});
  EXPECT_EQ(skinned.timeline().what, "motion over one second");
  const FrameRange r = skinned.frames(FrameClock{});
  EXPECT_EQ(r.first, 0);
  EXPECT_EQ(r.count, 24);  // frame 23 closes at 23/24 + 1/48 s
  EXPECT_NO_THROW(skinned.checkFrame(23, FrameClock{}));
  const std::string outside = errorOf([&] { skinned.checkFrame(24, FrameClock{}); });
  EXPECT_NE(outside.find("frame 24's shutter [1, 1.02083] s lies outside the timeline of 'skinned'"),
            std::string::npos)
      << outside;
  EXPECT_NE(outside.find("frames 0 to 23 at 24 fps with a 180 degree shutter"), std::string::npos) << outside;
  EXPECT_NE(errorOf([&] { skinned.checkFrame(-1, FrameClock{}); }), "(no error)");
  EXPECT_NE(errorOf([&] { skinned.frame(30, FrameClock{}); }).find("outside the timeline"), std::string::npos);
  EXPECT_NE(errorOf([&] { skinned.frames({0.0, 180.0}); }).find("frame rate"), std::string::npos);
  EXPECT_NE(errorOf([&] { skinned.frames({24.0, 400.0}); }).find("shutter angle"), std::string::npos);
  EXPECT_NE(errorOf([&] { skinned.sceneOver(0.5, 0.25); }).find("open <= close"), std::string::npos);
  EXPECT_NE(errorOf([&] { skinned.sceneOver(0.5, 1.5); }).find("outside the timeline"), std::string::npos);
  EXPECT_EQ(skinned.pictureShutter(24.0), std::make_pair(0.0, 1.0));

  AnimationOptions keys;
  keys.keysPerSecond = 4.0;
  Animation sequence(kKeys, keys);
  EXPECT_EQ(sequence.timeline().what, "2 keys at 4 fps");
  EXPECT_DOUBLE_EQ(sequence.timeline().end, 0.25);
  EXPECT_EQ(sequence.frames({4.0, 180.0}).count, 1);

  const std::string json = errorOf([] { Animation(std::string(MBRT_SOURCE_DIR) + "/tests/data/cube_scene.json"); });
  EXPECT_NE(json.find("JSON scene file"), std::string::npos) << json;
  EXPECT_FALSE(canAnimate("scene.json"));
  EXPECT_TRUE(canAnimate("skinned"));
  EXPECT_NE(errorOf([] { Animation("no_such_scene"); }), "(no error)");
  EXPECT_NE(errorOf([] { Animation((kDir / "missing.glb").string()); }).find("missing.glb"), std::string::npos);
  AnimationOptions badClip;
  badClip.clip = "walk";
  EXPECT_NE(errorOf([&] { Animation(test::writeTinyGltf(kDir, "clip"), badClip); }).find("no animation clip 'walk'"),
            std::string::npos);
}

// Inputs without a clip are sliced: each frame's steps are the whole
// timeline's motion at their times.
TEST(Animation, SlicedFramesFollowTheWholeMotion) {
  AnimationOptions o;
  o.size = 0.02;
  o.seed = 3;
  Animation a("skinned", o);
  const ProceduralScene whole = makeProceduralScene("skinned", 0.02, 3);
  const FrameClock clock;
  for (int64_t f : {0, 7, 23}) {
    const Scene& s = *a.frame(f, clock).scene;
    ASSERT_EQ(s.numGeometries(), whole.scene->numGeometries());
    for (uint32_t id = 0; id < s.numGeometries(); ++id) {
      const Geometry &g = s.geometry(id), &w = whole.scene->geometry(id);
      if (g.type() == GeometryType::Instance) continue;
      for (uint32_t k = 0; k < g.numSteps(); ++k) {
        const double u = g.numSteps() == 1 ? 0.0 : double(k) / double(g.numSteps() - 1);
        const float t = float(clock.openAt(f) + u * (clock.closeAt(f) - clock.openAt(f)));
        for (uint32_t i = 0; i < g.vertices(k).count; i += 17) {
          const Vec3f p = g.vertexAtStep(k, i), q = w.vertexAt(t, i);
          EXPECT_NEAR(p.x, q.x, 1e-4f) << "frame " << f << " geometry " << id;
          EXPECT_NEAR(p.y, q.y, 1e-4f) << "frame " << f << " geometry " << id;
          EXPECT_NEAR(p.z, q.z, 1e-4f) << "frame " << f << " geometry " << id;
        }
      }
    }
  }
}

// The stage stands where the first instant puts it, in every frame, with
// one ground texture however many frames are sampled.
TEST(Animation, StageStandsStill) {
  AnimationOptions o;
  o.keysPerSecond = 4.0;
  o.stage = true;
  Animation a(kKeys, o);
  Animation plain(kKeys, AnimationOptions{{}, {}, 4.0, {}, 1.0, 1, false});
  const Scene& first = *a.sceneOver(0.0, 0.0).scene;
  const uint32_t ground = plain.sceneOver(0.0, 0.0).scene->numGeometries();
  ASSERT_EQ(first.numGeometries(), ground + 1);
  const std::vector<Vec3f> corners = {first.geometry(ground).vertexAtStep(0, 0), first.geometry(ground).vertexAtStep(0, 2)};
  for (double t : {0.1, 0.2}) {
    const SceneDescription& d = a.sceneOver(t, t + 0.05);
    EXPECT_TRUE(d.scene->geometry(ground).vertexAtStep(0, 0) == corners[0]);
    EXPECT_TRUE(d.scene->geometry(ground).vertexAtStep(0, 2) == corners[1]);
    EXPECT_EQ(d.textures.size(), 1u);
    ASSERT_EQ(d.surfaces.size(), ground + 1);
    EXPECT_EQ(d.surfaces[ground].materials.at(0).texture, 0);
  }
  // A built-in scene brings its own surroundings: no stage.
  AnimationOptions builtIn;
  builtIn.size = 0.02;
  builtIn.stage = true;
  Animation demo("skinned", builtIn);
  EXPECT_EQ(demo.frame(0, FrameClock{}).scene->numGeometries(), makeProceduralScene("skinned", 0.02, 1).scene->numGeometries());
}

TEST(AccelUpdater, PoliciesAgreeWithTheOracle) {
  AnimationOptions o;
  o.size = 0.02;
  Animation a("skinned", o);
  const FrameClock clock;
  struct Case {
    UpdatePolicy policy;
    AccelKind kind;
    double factor;
    const char* what;  // of the frames after the first
  };
  for (const Case& c : {Case{UpdatePolicy::Refit, AccelKind::Msbvh, 1.5, "refit"},
                        Case{UpdatePolicy::Refit, AccelKind::Stbvh, 1.5, "rebuild (kind cannot refit)"},
                        Case{UpdatePolicy::Rebuild, AccelKind::BvhInterp, 1.5, "rebuild"},
                        Case{UpdatePolicy::Auto, AccelKind::BvhInterp, 1e6, "refit"}}) {
    SCOPED_TRACE(std::string(toString(c.policy)) + " " + std::string(toString(c.kind)));
    AccelUpdater updater(c.policy, c.factor);
    BuildOptions b;
    b.kind = c.kind;
    std::unique_ptr<Accel> accel;
    a.frame(0, clock);
    EXPECT_EQ(updater.update(accel, *a.current().scene, b).what, "build");
    for (int64_t f : {4, 9}) {
      a.frame(f, clock);
      const AccelUpdate u = updater.update(accel, *a.current().scene, b);
      EXPECT_EQ(u.what, c.what);
      EXPECT_EQ(u.refitted, u.what == "refit");
      EXPECT_EQ(u.sah > 0.0, c.policy == UpdatePolicy::Auto);
      expectOracle(*a.current().scene, *accel, "frame " + std::to_string(f));
    }
  }
  // Auto rebuilds once the refitted tree costs more than the factor allows:
  // with a factor of 1, as soon as it costs more at all.
  AccelUpdater strict(UpdatePolicy::Auto, 1.0);
  BuildOptions b;
  b.kind = AccelKind::BvhInterp;
  std::unique_ptr<Accel> accel;
  a.frame(0, clock);
  const double built = strict.update(accel, *a.current().scene, b).sah;
  bool rebuilt = false;
  for (int64_t f = 1; f < 24 && !rebuilt; ++f) {
    a.frame(f, clock);
    const AccelUpdate u = strict.update(accel, *a.current().scene, b);
    rebuilt = u.what.rfind("rebuild (SAH x", 0) == 0;
    if (!rebuilt) EXPECT_LE(u.sah, built * (1.0 + 1e-9));
  }
  EXPECT_TRUE(rebuilt);
  expectOracle(*a.current().scene, *accel, "after the SAH rebuild");
  EXPECT_NE(errorOf([] { AccelUpdater(UpdatePolicy::Auto, 0.5); }).find("rebuild factor"), std::string::npos);
  EXPECT_EQ(parseUpdatePolicy("refit"), UpdatePolicy::Refit);
  EXPECT_FALSE(parseUpdatePolicy("sometimes"));
}

}  // namespace
}  // namespace mbrt
