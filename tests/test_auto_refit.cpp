// `auto`'s refit (docs/auto.md, "Refit"): after the scene's vertices move,
// its rigid parts' keys are fitted again, its trees refitted, and only the
// objects whose choice no longer holds rebuilt. Whatever it did, its hits
// are brute's and a fresh auto build's over the moved scene (random times,
// 0, 1 and every step time), and lastUpdate says what it did.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "auto/auto_plan.h"
#include "auto_scene.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

// New vertex buffers for the meshes and segments of a scene (and of the
// scenes it instances), each vertex `move`d from where the original put it
// at that step; owns them (the scene points at them).
class MovedScene {
 public:
  using Move = std::function<Vec3f(const Scene& scene, uint32_t geomID, uint32_t step, Vec3f p)>;
  void apply(Scene& scene, const Scene& original, const Move& move) {
    for (uint32_t id = 0; id < original.numGeometries(); ++id) {
      const Geometry& g = original.geometry(id);
      if (g.type() == GeometryType::Instance) continue;
      for (uint32_t k = 0; k < g.numSteps(); ++k) {
        auto& v = data_.emplace_back(g.vertices(k).count + 1);  // one more: readable padding
        for (size_t i = 0; i + 1 < v.size(); ++i) v[i] = move(original, id, k, g.vertices(k)[i]);
        VertexBuffer b;
        b.data = v.data();
        b.count = v.size() - 1;
        b.padding = sizeof(Vec3f);
        scene.setVertices(id, k, b);
      }
    }
  }
  // Frees the buffers of the moves before (as a frame sequence does).
  void forgetBefore(size_t keep) { data_.erase(data_.begin(), data_.end() - ptrdiff_t(keep)); }
  size_t size() const { return data_.size(); }

 private:
  std::vector<std::vector<Vec3f>> data_;
};

BuildOptions autoOptions(std::optional<AccelKind> leafKind = std::nullopt) {
  BuildOptions o;
  o.kind = AccelKind::Auto;
  o.autoLeafKind = leafKind;
  o.autoConfirmByTrace = false;  // the model's choice: the same every run
  return o;
}

// The refitted accel agrees with brute and with a fresh auto build over the
// moved scene.
void expectAgreesAfterMove(const ProceduralScene& ps, const Accel& refitted, const BuildOptions& options,
                           const std::string& what) {
  SCOPED_TRACE(what);
  auto oracle = test::buildBrute(*ps.scene);
  auto fresh = Accel::build(*ps.scene, options);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 300), test::scaled(30, 5), 17);
  const auto rep = test::compareWithOracle(*oracle, refitted, rays);
  EXPECT_EQ(rep.wrong, 0u) << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u);
  EXPECT_GT(rep.hits, rep.rays / 5);
  const auto same = test::compareWithOracle(*fresh, refitted, rays);
  EXPECT_EQ(same.wrong, 0u) << "against a fresh build: " << same.firstFailure;
  EXPECT_EQ(same.anyWrong, 0u);
}

// auto's test scene (auto_scene.h) built with a forced leaf kind (the
// decomposition kept), its original beside it to move the vertices from.
struct MovingAutoScene {
  explicit MovingAutoScene(AccelKind leaf)
      : ps(test::autoTestScene()), original(test::autoTestScene()), options(autoOptions(leaf)),
        accel(Accel::build(*ps.scene, options)) {}
  ProceduralScene ps, original;
  BuildOptions options;
  std::unique_ptr<Accel> accel;
  MovedScene moved;
};

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A turn and a shift of everything: rigid parts stay rigid.
Vec3f turned(const Scene&, uint32_t, uint32_t, Vec3f p) {
  return (Affine3f::translate({0.15f, -0.1f, 0.05f}) * Affine3f::rotate(normalize(Vec3f{0.3f, 1.0f, 0.2f}), 0.4f))
      .xfmPoint(p);
}

// A wave along x that grows with the step: what it moves no longer moves rigidly.
Vec3f waved(Vec3f p, uint32_t step) { return p + Vec3f{0.0f, 0.06f * float(step + 1) * std::sin(7.0f * p.x), 0.0f}; }

TEST(AutoRefit, RigidMovesRefitTheInstancesKeysOnly) {
  for (AccelKind leaf : {AccelKind::BvhInterp, AccelKind::Msbvh}) {
    MovingAutoScene m(leaf);
    auto& [ps, original, o, accel, moved] = m;
    EXPECT_EQ(accel->lastUpdate(), "build");
    moved.apply(*ps.scene, *original.scene, turned);
    ASSERT_TRUE(accel->refit()) << accel->lastUpdate();
    const std::string update = accel->lastUpdate();
    EXPECT_TRUE(has(update, "instances' keys")) << update;
    EXPECT_TRUE(has(update, "refitted (" + std::string(toString(leaf)) + ")")) << update;
    EXPECT_FALSE(has(update, "rebuilt")) << update;
    EXPECT_EQ(accel->stats().update, update);
    expectAgreesAfterMove(ps, *accel, o, "rigid move, leaf kind " + std::string(toString(leaf)));
  }
}

TEST(AutoRefit, APartNoLongerRigidIsRebuiltWorldSpaceAlone) {
  MovingAutoScene m(AccelKind::BvhInterp);
  auto& [ps, original, o, accel, moved] = m;
  moved.apply(*ps.scene, *original.scene, [](const Scene&, uint32_t id, uint32_t k, Vec3f p) {
    return id == 0 ? waved(p, k) : p;
  });
  ASSERT_TRUE(accel->refit()) << accel->lastUpdate();
  const std::string update = accel->lastUpdate();
  EXPECT_TRUE(has(update, "1 object rebuilt (no longer rigid)")) << update;
  EXPECT_TRUE(has(update, "instances' keys")) << update << ": the other rigid parts keep their instances";
  EXPECT_TRUE(has(accel->stats().objects, "geometry 0, 360 triangles made world-space by a refit (no longer rigid)"))
      << accel->stats().objects;
  expectAgreesAfterMove(ps, *accel, o, "geometry 0 deformed");
  // The next frame: the same vertices moved rigidly on; the world-space
  // part's tree refits.
  moved.apply(*ps.scene, *original.scene, [](const Scene& s, uint32_t id, uint32_t k, Vec3f p) {
    return turned(s, id, k, id == 0 ? waved(p, k) : p);
  });
  moved.forgetBefore(moved.size() / 2);
  ASSERT_TRUE(accel->refit()) << accel->lastUpdate();
  EXPECT_FALSE(has(accel->lastUpdate(), "rebuilt")) << accel->lastUpdate();
  expectAgreesAfterMove(ps, *accel, o, "the next frame");
}

// Rigid parts moved, one deformed, the deforming and static geometry moved
// too, the user instance's own scene moved: keys, refits and one rebuild
// together, each reported.
TEST(AutoRefit, MixedMovesRefitWhatTheyCanAndRebuildOnlyTheRest) {
  MovingAutoScene m(AccelKind::Msbvh);
  auto& [ps, original, o, accel, moved] = m;
  moved.apply(*ps.scene, *original.scene, [](const Scene& s, uint32_t id, uint32_t k, Vec3f p) {
    return id == 6 ? waved(p, k) : id == 2 ? waved(turned(s, id, k, p), k) : turned(s, id, k, p);
  });
  const Geometry& user = ps.scene->geometry(7);
  Scene& child = const_cast<Scene&>(*user.instancedScene());  // the test owns it
  const ProceduralScene childOriginal = test::autoTestScene();
  moved.apply(child, *childOriginal.scene->geometry(7).instancedScene(), turned);
  ASSERT_TRUE(accel->refit()) << accel->lastUpdate();
  const std::string update = accel->lastUpdate();
  EXPECT_TRUE(has(update, "instances' keys")) << update;
  EXPECT_TRUE(has(update, "refitted (msbvh)")) << update;
  EXPECT_TRUE(has(update, "1 object rebuilt (no longer rigid)")) << update;
  expectAgreesAfterMove(ps, *accel, o, "mixed");
}

// The whole scene as one object (nothing rigid): a kind that cannot refit
// is rebuilt once as the cheapest of its trials that can; then it refits.
TEST(AutoRefit, OneObjectOfAKindThatCannotRefitBecomesOneThatCan) {
  for (const char* name : {"deform", "skinned"}) {
    ProceduralScene ps = makeProceduralScene(name, 0.02, 3);
    const ProceduralScene original = makeProceduralScene(name, 0.02, 3);
    BuildOptions o = autoOptions();
    auto accel = Accel::build(*ps.scene, o);
    MovedScene moved;
    for (int frame = 1; frame <= 2; ++frame) {
      moved.apply(*ps.scene, *original.scene, [frame](const Scene& s, uint32_t id, uint32_t k, Vec3f p) {
        return waved(turned(s, id, k, p), k + uint32_t(frame));
      });
      ASSERT_TRUE(accel->refit()) << name << ": " << accel->lastUpdate();
      const std::string update = accel->lastUpdate();
      if (frame == 2) EXPECT_FALSE(has(update, "cannot refit")) << name << ": " << update;
      EXPECT_TRUE(has(update, "refitted") || has(update, "cannot refit: now")) << name << ": " << update;
      expectAgreesAfterMove(ps, *accel, o, std::string(name) + " frame " + std::to_string(frame));
    }
  }
}

// Objects' lines (mbrt stats) that name a kind which cannot refit.
std::vector<std::string> nonRefittingLines(const std::string& objects) {
  std::vector<std::string> found;
  size_t start = 0;
  while (start < objects.size()) {
    const size_t end = std::min(objects.find('\n', start), objects.size());
    const std::string line = objects.substr(start, end - start);
    if (line.rfind("object", 0) == 0 && (has(line, "stbvh") || has(line, "bvh-segments") || has(line, "cluster")))
      found.push_back(line);
    start = end + 1;
  }
  return found;
}

// For an accel that will be refitted (a frame sequence), auto builds only
// kinds that refit in place and no near-rigid clusters: its first refit
// rebuilds nothing for want of a refit.
TEST(AutoRefit, ForRefitsItBuildsOnlyWhatRefits) {
  EXPECT_FALSE(detail::planDecomposition(*test::bendingTubeScene().scene, 1e-5, true).clusters.empty());
  EXPECT_TRUE(detail::planDecomposition(*test::bendingTubeScene().scene, 1e-5, false).clusters.empty());
  const std::vector<std::pair<const char*, double>> scenes = {{"skinned", 0.02}, {"deform", 0.02}};
  for (const auto& [name, size] : scenes) {
    ProceduralScene ps = makeProceduralScene(name, size, 3);
    const ProceduralScene original = makeProceduralScene(name, size, 3);
    BuildOptions o = autoOptions();
    EXPECT_FALSE(nonRefittingLines(Accel::build(*ps.scene, o)->stats().objects).empty())
        << name << ": without the hint the model picks a kind that cannot refit (else this test proves nothing)";
    o.autoForRefits = true;
    auto accel = Accel::build(*ps.scene, o);
    const std::vector<std::string> lines = nonRefittingLines(accel->stats().objects);
    EXPECT_TRUE(lines.empty()) << name << ": " << lines.front();
    MovedScene moved;
    moved.apply(*ps.scene, *original.scene, [](const Scene& s, uint32_t id, uint32_t k, Vec3f p) {
      return waved(turned(s, id, k, p), k + 1);
    });
    ASSERT_TRUE(accel->refit()) << name << ": " << accel->lastUpdate();
    EXPECT_FALSE(has(accel->lastUpdate(), "cannot refit")) << name << ": " << accel->lastUpdate();
    expectAgreesAfterMove(ps, *accel, o, std::string(name) + " built for refits");
  }
}

TEST(AutoRefit, ANewLayoutRebuildsTheWholeScene) {
  ProceduralScene ps = test::autoTestScene();
  auto accel = Accel::build(*ps.scene, autoOptions(AccelKind::BvhInterp));
  test::MeshParts m;
  test::addBlob(m, {0.0f, 0.9f, 0.0f}, 0.1f, 6, 0.0f);
  ps.scene->addTriangleMesh(m.triangles, std::vector<std::vector<Vec3f>>{m.vertices});
  EXPECT_FALSE(accel->refit());
  EXPECT_EQ(accel->lastUpdate(), "rebuild (the scene's layout changed)");
  expectAgreesAfterMove(ps, *accel, autoOptions(AccelKind::BvhInterp), "a geometry added");
}

TEST(AccelUpdate, SaysWhatTheLastUpdateDid) {
  ProceduralScene ps = makeProceduralScene("deform", 0.01, 3);
  for (AccelKind kind : {AccelKind::BvhInterp, AccelKind::Stbvh}) {
    auto accel = test::buildKind(*ps.scene, kind);
    EXPECT_EQ(accel->lastUpdate(), "build");
    accel->rebuild();
    EXPECT_EQ(accel->lastUpdate(), "rebuild");
    accel->refit();
    EXPECT_EQ(accel->lastUpdate(), kind == AccelKind::BvhInterp ? "refit" : "rebuild (kind cannot refit)");
  }
}

}  // namespace
