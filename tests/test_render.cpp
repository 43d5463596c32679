// The renderer: same picture whatever the structure and the thread count,
// heat maps with their colour bar, EXR output, the thin lens, the shutter.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "mbrt/render.h"
#include "mbrt/scenes.h"
#include "test_util.h"

namespace mbrt {
namespace {

SceneDescription suiteScene(const std::string& name, double size) {
  ProceduralScene p = makeProceduralScene(name, size, 7);
  SceneDescription d;
  d.name = p.name;
  d.scene = p.scene;
  d.camera.keys = {p.camera};
  return d;
}

RenderOptions smallOptions(IntegratorKind kind, int w = 48, int h = 32, int spp = 2) {
  RenderOptions o;
  o.width = w;
  o.height = h;
  o.spp = spp;
  o.integrator = kind;
  o.seed = 11;
  return o;
}

float maxChannelDiff(const Rgb& a, const Rgb& b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

// Two closest hits are the same or a tie: the same distance along the ray
// (a shared edge or vertex hit by both triangles).
bool sameOrTie(const Hit& a, const Hit& b) {
  if (a.valid() != b.valid()) return false;
  if (!a.valid()) return true;
  if (a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID) return true;
  return std::abs(a.t - b.t) <= 1e-4f * std::max(1.0f, std::abs(a.t));
}

// Renders with every available structure (but `frozen`, which sees another
// scene) and compares with brute: at most 0.1% of pixels (and at least one)
// may differ by more than 1/255, and only where a primary hit was a tie.
void expectSameImages(const SceneDescription& scene, const RenderOptions& o) {
  auto brute = test::buildKind(*scene.scene, AccelKind::Brute);
  const RenderResult ref = render(scene, *brute, o);
  const RenderCamera camera(scene, o.width, o.height, o.shutterOpen, o.shutterClose);
  const size_t allowed = std::max<size_t>(1, size_t(o.width) * size_t(o.height) / 1000);
  for (AccelKind kind : availableAccelKinds()) {
    if (kind == AccelKind::Brute || kind == AccelKind::Frozen) continue;
    SCOPED_TRACE(std::string(toString(kind)) + " on " + scene.name + ", " + std::string(toString(o.integrator)));
    auto accel = test::buildKind(*scene.scene, kind);
    const RenderResult img = render(scene, *accel, o);
    ASSERT_EQ(img.image.width(), ref.image.width());
    ASSERT_EQ(img.image.height(), ref.image.height());
    size_t differing = 0;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        if (maxChannelDiff(img.image.at(x, y), ref.image.at(x, y)) <= 1.0f / 255.0f) continue;
        ++differing;
        // Every primary hit of the pixel is the same or a tie; where all are the
        // same, a secondary ray grazed an edge (counted in the same budget).
        for (int s = 0; s < o.spp; ++s) {
          const Ray ray = primaryRay(camera, o, x, y, s);
          Hit a, b;
          brute->intersect(ray, a);
          accel->intersect(ray, b);
          EXPECT_TRUE(sameOrTie(a, b)) << "pixel " << x << "," << y << " sample " << s << ": brute prim "
                                       << a.primID << " t " << a.t << ", got prim " << b.primID << " t " << b.t;
        }
      }
    EXPECT_LE(differing, allowed) << differing << " pixels differ";
  }
}

TEST(Render, EveryStructureGivesTheSameImage) {
  const SceneDescription demo = suiteScene("demo", 0.25);
  expectSameImages(demo, smallOptions(IntegratorKind::Normals));
  expectSameImages(demo, smallOptions(IntegratorKind::Ao));
  RenderOptions path = smallOptions(IntegratorKind::Path, 32, 24, 2);
  path.maxDepth = 2;
  expectSameImages(demo, path);
}

TEST(Render, EveryStructureGivesTheSameImageOnThinGeometry) {
  const SceneDescription hairball = suiteScene("hairball", 0.003);
  expectSameImages(hairball, smallOptions(IntegratorKind::Normals, 40, 40, 2));
  const SceneDescription hair = suiteScene("hair", 0.003);
  expectSameImages(hair, smallOptions(IntegratorKind::Ao, 40, 40, 1));
}

TEST(Render, SameImageWhateverTheThreadsAndTiles) {
  const SceneDescription demo = suiteScene("demo", 0.25);
  auto accel = test::buildKind(*demo.scene, AccelKind::BvhInterp);
  RenderOptions o = smallOptions(IntegratorKind::Path, 40, 30, 3);
  RenderResult one, two, tiles;
  tbb::task_arena(1).execute([&] { one = render(demo, *accel, o); });
  tbb::task_arena(2).execute([&] { two = render(demo, *accel, o); });
  o.tileSize = 7;
  tbb::task_arena(2).execute([&] { tiles = render(demo, *accel, o); });
  ASSERT_EQ(one.rays, two.rays);
  ASSERT_EQ(one.rays, tiles.rays);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      ASSERT_EQ(maxChannelDiff(one.image.at(x, y), two.image.at(x, y)), 0.0f) << x << "," << y;
      ASSERT_EQ(maxChannelDiff(one.image.at(x, y), tiles.image.at(x, y)), 0.0f) << x << "," << y;
    }
  // Another seed gives another picture.
  o.seed = 12;
  const RenderResult other = render(demo, *accel, o);
  double diff = 0.0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) diff += maxChannelDiff(one.image.at(x, y), other.image.at(x, y));
  EXPECT_GT(diff, 0.0);
}

TEST(Render, HeatMapHasItsColorBar) {
  const SceneDescription demo = suiteScene("demo", 0.25);
  auto accel = test::buildKind(*demo.scene, AccelKind::BvhInterp);
  for (IntegratorKind kind : {IntegratorKind::HeatSteps, IntegratorKind::HeatIsects}) {
    RenderOptions o = smallOptions(kind, 64, 48, 1);
    const RenderResult r = render(demo, *accel, o);
    const int bar = r.image.height() - o.height;
    ASSERT_GT(bar, 0);
    ASSERT_EQ(r.heat.size(), size_t(o.width) * size_t(o.height));
    EXPECT_GT(r.heatMean, 0.0f);
    EXPECT_GT(r.heatScale, 0.0f);
    EXPECT_GE(r.heatMaxValue, r.heatScale);
    // The bottom row runs through the colour map: darkest left, brightest right.
    auto luminance = [](const Rgb& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
    const int y = r.image.height() - 1;
    float previous = -1.0f;
    for (int x = 0; x < o.width; ++x) {
      const float l = luminance(r.image.at(x, y));
      EXPECT_GE(l, previous - 1e-6f) << "x " << x;
      previous = l;
    }
    EXPECT_LT(luminance(r.image.at(0, y)), 0.01f);
    EXPECT_GT(luminance(r.image.at(o.width - 1, y)), 0.8f);
    // A fixed scale is kept.
    o.heatMax = 1000.0f;
    EXPECT_EQ(render(demo, *accel, o).heatScale, 1000.0f);
    o.colorBar = false;
    EXPECT_EQ(render(demo, *accel, o).image.height(), o.height);
  }
}

TEST(Render, ExrIsWrittenAndReadable) {
  Image image(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) image.at(x, y) = {float(x) * 0.25f, float(y) * 7.5f, -0.125f + float(x * y)};
  const std::string path = (std::filesystem::temp_directory_path() / "mbrt_test_render.exr").string();
  if (!exrSupported()) {
    try {
      writeExr(path, image);
      FAIL() << "writeExr without OpenEXR should throw";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("not built"), std::string::npos) << e.what();
    }
    GTEST_SKIP() << "OpenEXR is not built in";
  }
  writeExr(path, image);
  const Image back = readExr(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.width(), 5);
  ASSERT_EQ(back.height(), 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_EQ(maxChannelDiff(back.at(x, y), image.at(x, y)), 0.0f);
  EXPECT_THROW(readExr(path + ".missing"), Error);
  EXPECT_THROW(writeExr("/no/such/dir/x.exr", image), Error);
}

// A quad facing the camera at distance `distance`, covering the left half of
// the view.
SceneDescription wallScene(float distance) {
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh({{0, 1, 2}, {0, 2, 3}},
                         std::vector<std::vector<Vec3f>>{{{-10, -10, -distance},
                                                          {0, -10, -distance},
                                                          {0, 10, -distance},
                                                          {-10, 10, -distance}}});
  SceneDescription d;
  d.name = "wall";
  d.scene = scene;
  d.camera.keys = {CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.0f}};
  return d;
}

TEST(Render, ThinLensFocusesAtTheFocusDistance) {
  SceneDescription wall = wallScene(4.0f);
  wall.camera.apertureRadius = 0.3f;
  wall.camera.focusDistance = 4.0f;
  const RenderCamera camera(wall, 64, 64, 0.0f, 1.0f);
  // Every lens sample of a pixel meets the same point on the plane of focus.
  for (float px : {3.5f, 32.0f, 60.25f}) {
    Vec3f first;
    for (int i = 0; i < 16; ++i) {
      const Ray r = camera.generate(px, 20.0f, float(i % 4) / 4.0f + 0.1f, float(i / 4) / 4.0f + 0.05f, 0.5f);
      const float s = (-4.0f - r.org.z) / r.dir.z;
      const Vec3f p = r.org + r.dir * s;
      if (i == 0) first = p;
      EXPECT_LT(length(p - first), 1e-4f) << "pixel x " << px << " lens sample " << i;
      EXPECT_GT(length(r.org), 0.0f);  // rays start on the lens, not all at its centre
    }
  }
  // Rendered: in focus, the wall's edge is as sharp as with a pinhole;
  // focused nearer, it blurs.
  auto accel = test::buildKind(*wall.scene, AccelKind::BvhInterp);
  const RenderOptions o = smallOptions(IntegratorKind::Normals, 64, 16, 16);
  auto blurredPixels = [&](const SceneDescription& d) {
    const RenderResult r = render(d, *accel, o);
    int n = 0;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        const float b = r.image.at(x, y).b;  // 1 on the wall (normal +z), 0 on the background
        n += b > 0.02f && b < 0.98f;
      }
    return n;
  };
  SceneDescription pinhole = wall;
  pinhole.camera.apertureRadius = 0.0f;
  const int sharp = blurredPixels(pinhole);
  EXPECT_LE(blurredPixels(wall), sharp + 2 * o.height);
  SceneDescription near = wall;
  near.camera.focusDistance = 1.0f;
  EXPECT_GT(blurredPixels(near), sharp + 4 * o.height);
}

TEST(Render, CameraTimesAreStratifiedOverTheShutter) {
  const SceneDescription wall = wallScene(2.0f);
  RenderOptions o = smallOptions(IntegratorKind::Normals, 8, 8, 8);
  o.shutterOpen = 0.25f;
  o.shutterClose = 0.75f;
  const RenderCamera camera(wall, o.width, o.height, o.shutterOpen, o.shutterClose);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      // Strata of the shutter, rotated per pixel: one sample in each, so any
      // two samples but neighbours lie more than one stratum apart.
      std::vector<float> u;
      for (int s = 0; s < o.spp; ++s) {
        const float t = primaryRay(camera, o, x, y, s).time;
        ASSERT_GE(t, 0.25f);
        ASSERT_LE(t, 0.75f);
        u.push_back((t - 0.25f) / 0.5f);
      }
      std::sort(u.begin(), u.end());
      for (size_t i = 0; i < u.size(); ++i) {
        const float next2 = i + 2 < u.size() ? u[i + 2] : u[i + 2 - u.size()] + 1.0f;
        EXPECT_GE(next2 - u[i], 1.0f / float(o.spp) - 1e-5f) << "pixel " << x << "," << y;
      }
    }
  EXPECT_THROW(RenderCamera(wall, 8, 8, 0.5f, 0.25f), Error);
  EXPECT_THROW(RenderCamera(wall, 8, 8, -0.1f, 0.5f), Error);
}

TEST(Render, MovingCameraFollowsItsKeys) {
  SceneDescription wall = wallScene(2.0f);
  wall.camera.keys = {CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.0f},
                      CameraSpec{{2, 0, 0}, {2, 0, -1}, {0, 1, 0}, 40.0f}};
  const RenderCamera camera(wall, 8, 8, 0.0f, 1.0f);
  EXPECT_NEAR(camera.generate(4, 4, 0.5f, 0.5f, 0.0f).org.x, 0.0f, 1e-6f);
  EXPECT_NEAR(camera.generate(4, 4, 0.5f, 0.5f, 0.5f).org.x, 1.0f, 1e-6f);
  EXPECT_NEAR(camera.generate(4, 4, 0.5f, 0.5f, 0.999f).org.x, 1.998f, 1e-4f);
}

// A floor seen from above under a uniform sky and a light from straight
// above: every sample sees albedo * (sky + irradiance / pi), exactly.
TEST(Render, IntegratorsGiveTheExpectedRadianceOnAFloor) {
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh({{0, 1, 2}, {0, 2, 3}},
                         std::vector<std::vector<Vec3f>>{{{-100, 0, -100}, {-100, 0, 100}, {100, 0, 100}, {100, 0, -100}}});
  SceneDescription d;
  d.name = "floor";
  d.scene = scene;
  d.camera.keys = {CameraSpec{{0, 5, 0}, {0, 0, 0}, {0, 0, -1}, 40.0f}};
  d.materials = {Material{{0.5f, 0.25f, 0.8f}}};
  d.skyColor = {0.4f, 0.6f, 1.0f};
  d.lights = {DirectionalLight{{0, -2, 0}, {3.0f, 3.0f, 3.0f}}};
  auto accel = test::buildKind(*scene, AccelKind::BvhInterp);
  RenderOptions o = smallOptions(IntegratorKind::Path, 8, 8, 4);
  const float invPi = 1.0f / 3.14159265f;
  const RenderResult path = render(d, *accel, o);
  o.integrator = IntegratorKind::Ao;
  const RenderResult ao = render(d, *accel, o);
  o.integrator = IntegratorKind::Normals;
  const RenderResult normals = render(d, *accel, o);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const Rgb p = path.image.at(x, y);
      EXPECT_NEAR(p.r, 0.5f * (0.4f + 3.0f * invPi), 1e-4f);
      EXPECT_NEAR(p.g, 0.25f * (0.6f + 3.0f * invPi), 1e-4f);
      EXPECT_NEAR(p.b, 0.8f * (1.0f + 3.0f * invPi), 1e-4f);
      const Rgb a = ao.image.at(x, y);
      EXPECT_NEAR(a.r, 0.5f, 1e-6f);
      EXPECT_NEAR(a.g, 0.25f, 1e-6f);
      EXPECT_NEAR(a.b, 0.8f, 1e-6f);
      const Rgb n = normals.image.at(x, y);  // (0,1,0) -> (0.5, 1, 0.5)
      EXPECT_NEAR(n.r, 0.5f, 1e-5f);
      EXPECT_NEAR(n.g, 1.0f, 1e-5f);
      EXPECT_NEAR(n.b, 0.5f, 1e-5f);
    }
  // Per sample: path = camera ray + shadow ray + escaping bounce; ao = 1 + 2.
  EXPECT_EQ(path.rays, uint64_t(8 * 8 * 4 * 3));
  EXPECT_EQ(ao.rays, uint64_t(8 * 8 * 4 * 3));
}

// A wall whose edge moves from x = 0 to x = 8 over the shutter: a pixel
// looking at x is covered for the part 1 - x/8 of the shutter.
TEST(Render, MotionBlurAveragesOverTheShutter) {
  auto scene = std::make_shared<Scene>();
  auto wallAt = [](float edge) {
    return std::vector<Vec3f>{{-30 + edge, -10, -4}, {edge, -10, -4}, {edge, 10, -4}, {-30 + edge, 10, -4}};
  };
  scene->addTriangleMesh({{0, 1, 2}, {0, 2, 3}}, std::vector<std::vector<Vec3f>>{wallAt(0.0f), wallAt(8.0f)});
  SceneDescription d;
  d.name = "moving wall";
  d.scene = scene;
  d.camera.keys = {CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40.0f}};
  auto accel = test::buildKind(*scene, AccelKind::BvhInterp);
  RenderOptions o = smallOptions(IntegratorKind::Normals, 64, 4, 32);
  const RenderCamera camera(d, o.width, o.height, 0.0f, 1.0f);
  auto lookAt = [&](int x) {  // x on the wall's plane seen by the pixel's centre
    const Ray centre = camera.generate(float(x) + 0.5f, 2.0f, 0.5f, 0.5f, 0.5f);
    return centre.dir.x * (-4.0f / centre.dir.z);
  };
  const RenderResult blurred = render(d, *accel, o);
  int partial = 0;
  for (int x = 0; x < o.width; ++x) {
    const float expected = 1.0f - std::clamp(lookAt(x) / 8.0f, 0.0f, 1.0f);
    const float coverage = blurred.image.at(x, 2).b;  // wall normal (0,0,1) -> blue 1, background 0
    EXPECT_NEAR(coverage, expected, 0.1f) << "pixel " << x << " looks at x = " << lookAt(x);
    partial += coverage > 0.1f && coverage < 0.9f;
  }
  EXPECT_GE(partial, 8);
  // A zero-length shutter gives a sharp picture at that instant (edge at x = 4).
  o.shutterOpen = o.shutterClose = 0.5f;
  const RenderResult sharp = render(d, *accel, o);
  for (int x = 0; x < o.width; ++x) {
    const float b = sharp.image.at(x, 2).b;
    if (std::abs(lookAt(x) - 4.0f) < 0.5f) continue;  // the pixel on the edge
    EXPECT_EQ(b, lookAt(x) < 4.0f ? 1.0f : 0.0f) << "pixel " << x;
  }
}

TEST(Render, SceneWithoutCameraIsFramed) {
  SceneDescription mesh = suiteScene("translate", 0.005);
  mesh.camera.keys.clear();
  auto accel = test::buildKind(*mesh.scene, AccelKind::BvhInterp);
  const RenderResult r = render(mesh, *accel, smallOptions(IntegratorKind::Normals, 32, 32, 1));
  // The scene sits in the middle of the picture, with background around it.
  int hits = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) hits += r.image.at(x, y).r + r.image.at(x, y).g + r.image.at(x, y).b > 0.0f;
  EXPECT_GT(hits, 32);
  EXPECT_LT(hits, 32 * 32 - 32);
  const Rgb& centre = r.image.at(16, 16);
  EXPECT_GT(centre.r + centre.g + centre.b, 0.0f);
}

TEST(Render, CancelledRenderKeepsItsSize) {
  const SceneDescription demo = suiteScene("demo", 0.25);
  auto accel = test::buildKind(*demo.scene, AccelKind::BvhInterp);
  std::atomic<bool> cancel{true};
  const RenderResult r = render(demo, *accel, smallOptions(IntegratorKind::Ao), &cancel);
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(r.tilesDone, 0u);
  EXPECT_EQ(r.image.width(), 48);
  EXPECT_EQ(r.image.height(), 32);
  // Cancelled half way through: what was rendered is kept.
  std::atomic<bool> stop{false};
  RenderOptions o = smallOptions(IntegratorKind::Normals);
  o.tileSize = 8;
  const RenderResult half = render(demo, *accel, o, &stop, [&](const RenderProgress& p) {
    if (p.tilesDone * 2 >= p.tilesTotal) stop = true;
  });
  EXPECT_FALSE(half.complete);
  EXPECT_GE(half.tilesDone * 2, half.tilesTotal);
  EXPECT_LT(half.tilesDone, half.tilesTotal);
}

TEST(Render, BadOptionsAreRefused) {
  const SceneDescription demo = suiteScene("demo", 0.25);
  auto accel = test::buildKind(*demo.scene, AccelKind::Brute);
  RenderOptions o = smallOptions(IntegratorKind::Ao);
  o.spp = 0;
  EXPECT_THROW(render(demo, *accel, o), Error);
  o = smallOptions(IntegratorKind::Ao);
  o.shutterClose = 1.5f;
  EXPECT_THROW(render(demo, *accel, o), Error);
  EXPECT_EQ(parseIntegratorKind("heat-steps"), IntegratorKind::HeatSteps);
  EXPECT_FALSE(parseIntegratorKind("nope").has_value());
}

}  // namespace
}  // namespace mbrt
