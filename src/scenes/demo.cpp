// `demo`: small and pretty (a few thousand triangles at size 1). A static
// floor with a post (S = 1), a three-bladed propeller on the post (an
// instance of its own scene with 33 matrix keys, a quarter turn over the
// shutter), a bouncing and squashing ball (9 steps), and a tuft of grass as
// round segments swaying in the wind (3 steps).
#include <cmath>
#include <numbers>

#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;

// Hub plus three twisted blades, spinning about the local z axis.
std::shared_ptr<Scene> makePropeller(double size) {
  MeshData prop = makeSphere(scaledCount(size, 200, 32), [](Vec3f d) { return d.z > 0 ? 0.12f : 0.1f; });
  transformInPlace(prop.vertices, Affine3f::scale({1.0f, 1.0f, 1.4f}));
  const size_t bladeTris = scaledCount(size, 500, 32);
  for (int b = 0; b < 3; ++b) {
    // A flat, tapered blade along +x, pitched by 25 degrees, then placed around the hub.
    MeshData blade = makeSphere(bladeTris, [](Vec3f) { return 1.0f; });
    for (Vec3f& v : blade.vertices) {
      const float x = 0.5f * (v.x + 1.0f);  // 0 at the root, 1 at the tip
      const float chord = 0.11f * (1.0f - 0.4f * x);
      v = {0.06f + 0.64f * x, v.y * chord, v.z * 0.012f};
      const float twist = 0.45f - 0.25f * x;  // less pitch towards the tip
      v = Affine3f::rotate({1, 0, 0}, twist).xfmPoint(v);
    }
    transformInPlace(blade.vertices, Affine3f::rotate({0, 0, 1}, 2.0f * kPi * float(b) / 3.0f));
    prop.append(blade);
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(prop.triangles), std::vector<std::vector<Vec3f>>{std::move(prop.vertices)});
  return scene;
}

}  // namespace

ProceduralScene makeDemo(double size, uint64_t seed) {
  Rng rng(seed, 0x64656d6full);
  auto scene = std::make_shared<Scene>();

  // Static floor and the propeller's post (one mesh, S = 1).
  const int cells = int(scaledCount(std::sqrt(size), 28, 4));
  MeshData stage = makeGrid(cells, cells, 14.0f, 14.0f);
  const Vec3f hubPos{-1.0f, 1.45f, -0.6f};
  stage.append(makeCylinder(scaledCount(size, 300, 24), {hubPos.x, 0.0f, hubPos.z - 0.05f},
                            {hubPos.x, hubPos.y - 0.02f, hubPos.z - 0.05f}, 0.07f, 0.05f));
  stage.append(makeSphere(scaledCount(size, 200, 16), [](Vec3f) { return 0.18f; }, {hubPos.x, 0.0f, hubPos.z - 0.05f}));
  scene->addTriangleMesh(std::move(stage.triangles), std::vector<std::vector<Vec3f>>{std::move(stage.vertices)});

  // The propeller: faces the camera side, a quarter turn over the shutter.
  auto propeller = makePropeller(size);
  // SRT keys: the blades keep their shape between keys (slerp), where
  // element-wise matrix keys would shrink them.
  const Quaternion mount = Quaternion::fromAxisAngle({0, 1, 0}, 0.45f);
  const float spin = (rng.uniform() < 0.5f ? -0.5f : 0.5f) * kPi;
  const float spin0 = rng.uniform(0.0f, 2.0f * kPi);
  constexpr int kKeys = 33;
  std::vector<SRTKey> keys;
  for (int k = 0; k < kKeys; ++k)
    keys.push_back({Vec3f(1.0f),
                    mount * Quaternion::fromAxisAngle({0, 0, 1}, spin0 + spin * float(k) / float(kKeys - 1)),
                    hubPos + Vec3f{0.0f, 0.0f, 0.12f}});
  scene->addInstance(std::move(propeller), std::move(keys));

  // The ball: falls, squashes on the floor at t = 0.5, bounces up again,
  // rolling as it goes.
  constexpr float kR = 0.38f;
  MeshData ball = makeSphere(scaledCount(size, 1200, 48), [](Vec3f) { return kR; });
  constexpr int kBallSteps = 9;
  std::vector<std::vector<Vec3f>> ballSteps;
  const Vec3f from{0.1f, 0.0f, 0.9f}, to{1.9f, 0.0f, 0.2f};
  const float height = rng.uniform(1.0f, 1.4f);
  for (int k = 0; k < kBallSteps; ++k) {
    const float t = float(k) / float(kBallSteps - 1);
    const float u = 2.0f * t - 1.0f;
    const float squash = 1.0f - 0.22f * std::exp(-40.0f * u * u);  // y scale, 0.78 at contact
    const float bulge = 1.0f / std::sqrt(squash);                   // keeps the volume
    Vec3f c = lerp(from, to, t);
    c.y = kR * squash + height * u * u;
    const Affine3f m = Affine3f::translate(c) * Affine3f::scale({bulge, squash, bulge}) *
                       Affine3f::rotate(normalize(cross({0, 1, 0}, to - from)), 3.0f * t);
    ballSteps.push_back(transformed(ball.vertices, m));
  }
  scene->addTriangleMesh(std::move(ball.triangles), std::move(ballSteps));

  // A tuft of grass: round segments, swaying (3 steps).
  const size_t blades = scaledCount(size, 60, 12);
  constexpr int kPts = 6;
  std::vector<Segment> segs;
  std::vector<float> radii;
  std::vector<std::vector<Vec3f>> grassSteps(3);
  const Vec3f tuft{-0.2f, 0.0f, 1.1f};
  const Vec3f wind = normalize(Vec3f{1.0f, 0.0f, 0.3f});
  for (size_t i = 0; i < blades; ++i) {
    Rng g(seed, 0x67726173ull + i);
    const float a = g.uniform(0.0f, 2.0f * kPi), r = 0.25f * std::sqrt(g.uniform());
    const Vec3f root = tuft + Vec3f{r * std::cos(a), 0.0f, r * std::sin(a)};
    const float h = g.uniform(0.35f, 0.7f);
    const Vec3f lean{g.uniform(-0.25f, 0.25f), 0.0f, g.uniform(-0.25f, 0.25f)};
    const float sway = g.uniform(0.08f, 0.2f);
    const uint32_t first = uint32_t(radii.size());
    for (int j = 0; j < kPts; ++j) {
      const float f = float(j) / float(kPts - 1);
      const Vec3f p = root + Vec3f{0.0f, h * f, 0.0f} + lean * (h * f * f);
      radii.push_back(0.012f * (1.0f - 0.8f * f));
      for (int k = 0; k < 3; ++k) {
        const float w = (k == 1 ? 1.0f : (k == 0 ? -0.3f : 0.4f)) * sway;
        grassSteps[k].push_back(p + wind * (w * h * f * f));
      }
      if (j + 1 < kPts) segs.push_back({first + uint32_t(j), first + uint32_t(j) + 1});
    }
  }
  scene->addSegments(std::move(segs), std::move(grassSteps), std::move(radii));

  ProceduralScene out;
  out.camera.eye = {2.9f, 2.6f, 4.9f};
  out.camera.target = {0.45f, 0.65f, 0.05f};
  out.camera.verticalFovDegrees = 38.0f;
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
