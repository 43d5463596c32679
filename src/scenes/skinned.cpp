// `skinned`: a procedural articulated character (~100k triangles at size 1:
// torso, neck and head, arms, hands, legs, feet as tessellated ellipsoids and
// cylinders) in one mesh with 17 steps. A bone hierarchy swings the limbs
// about their joints (a walk cycle over the shutter) and vertices near a
// joint are blended between the bone and its parent (linear blend skinning):
// the fuzzy kd-tree paper's case.
#include <array>
#include <cmath>
#include <numbers>

#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"

namespace mbrt::scenes {
namespace {

enum Bone { Pelvis, Spine, Head, UArmL, FArmL, UArmR, FArmR, ThighL, ShinL, ThighR, ShinR, kBones };

struct BoneDef {
  int parent;
  Vec3f joint;  // rest-pose position of the joint the bone turns about
};

// Rest pose: standing, facing +z, arms hanging, feet on y = 0.
constexpr std::array<BoneDef, kBones> kSkeleton{{
    {-1, {0.0f, 0.95f, 0.0f}},     // pelvis (root)
    {Pelvis, {0.0f, 1.05f, 0.0f}},  // spine
    {Spine, {0.0f, 1.58f, 0.0f}},   // head (neck joint)
    {Spine, {0.24f, 1.50f, 0.0f}},  // upper arm L (shoulder)
    {UArmL, {0.28f, 1.20f, 0.0f}},  // forearm L (elbow)
    {Spine, {-0.24f, 1.50f, 0.0f}},
    {UArmR, {-0.28f, 1.20f, 0.0f}},
    {Pelvis, {0.10f, 0.93f, 0.0f}},  // thigh L (hip)
    {ThighL, {0.11f, 0.52f, 0.0f}},  // shin L (knee)
    {Pelvis, {-0.10f, 0.93f, 0.0f}},
    {ThighR, {-0.11f, 0.52f, 0.0f}},
}};

// A vertex follows `bone` with weight w and `other` with 1 - w.
struct Influence {
  uint8_t bone, other;
  float w;
};

struct Part {
  MeshData mesh;
  std::vector<Influence> influences;
};

// Adds a limb cylinder from joint a (of `bone`) to b; vertices within `blend`
// of the joint are blended with the parent bone.
void addLimb(Part& body, size_t tris, int bone, Vec3f a, Vec3f b, float ra, float rb, float blend) {
  const Vec3f axis = normalize(b - a);
  MeshData m = makeCylinder(tris, a - axis * blend, b, ra, rb);
  for (const Vec3f& v : m.vertices) {
    const float s = dot(v - a, axis);
    body.influences.push_back({uint8_t(bone), uint8_t(kSkeleton[bone].parent), smoothstep(-blend, blend, s)});
  }
  body.mesh.append(m);
}

// Adds an ellipsoid rigidly attached to `bone`, or blended with `other` by
// a weight function of the vertex.
template <class WeightFn>
void addEllipsoid(Part& body, size_t tris, Vec3f centre, Vec3f radii, int bone, int other, WeightFn weight) {
  MeshData m = makeSphere(tris, [](Vec3f) { return 1.0f; });
  for (Vec3f& v : m.vertices) v = centre + v * radii;
  for (const Vec3f& v : m.vertices) body.influences.push_back({uint8_t(bone), uint8_t(other), weight(v)});
  body.mesh.append(m);
}

}  // namespace

ProceduralScene makeSkinned(double size, uint64_t seed) {
  Rng rng(seed, 0x736b696eull);
  const double total = 100000.0;
  auto share = [&](double fraction) { return scaledCount(size, total * fraction, 16); };

  Part body;
  // Torso: lower half follows the pelvis, upper half the spine.
  addEllipsoid(body, share(0.22), {0.0f, 1.25f, 0.0f}, {0.21f, 0.38f, 0.13f}, Spine, Pelvis,
               [](Vec3f v) { return smoothstep(0.98f, 1.22f, v.y); });
  addLimb(body, share(0.02), Head, {0.0f, 1.58f, 0.0f}, {0.0f, 1.70f, 0.0f}, 0.05f, 0.05f, 0.04f);  // neck
  addEllipsoid(body, share(0.12), {0.0f, 1.80f, 0.02f}, {0.11f, 0.135f, 0.12f}, Head, Spine,
               [](Vec3f) { return 1.0f; });
  for (int side = 0; side < 2; ++side) {
    const float sx = side == 0 ? 1.0f : -1.0f;
    const int uarm = side == 0 ? UArmL : UArmR, farm = side == 0 ? FArmL : FArmR;
    const int thigh = side == 0 ? ThighL : ThighR, shin = side == 0 ? ShinL : ShinR;
    addLimb(body, share(0.065), uarm, kSkeleton[uarm].joint, kSkeleton[farm].joint, 0.055f, 0.045f, 0.05f);
    const Vec3f wrist{0.30f * sx, 0.94f, 0.0f};
    addLimb(body, share(0.055), farm, kSkeleton[farm].joint, wrist, 0.045f, 0.035f, 0.04f);
    addEllipsoid(body, share(0.02), wrist + Vec3f{0.0f, -0.06f, 0.0f}, {0.035f, 0.07f, 0.045f}, farm, farm,
                 [](Vec3f) { return 1.0f; });  // hand
    const Vec3f ankle{0.12f * sx, 0.09f, 0.0f};
    addLimb(body, share(0.085), thigh, kSkeleton[thigh].joint, kSkeleton[shin].joint, 0.085f, 0.06f, 0.06f);
    addLimb(body, share(0.075), shin, kSkeleton[shin].joint, ankle, 0.06f, 0.045f, 0.05f);
    addEllipsoid(body, share(0.02), ankle + Vec3f{0.0f, -0.045f, 0.06f}, {0.055f, 0.045f, 0.12f}, shin, shin,
                 [](Vec3f) { return 1.0f; });  // foot
  }

  // A walk cycle: one stride over the shutter, with a little per-seed variety.
  const float stride = rng.uniform(0.45f, 0.6f);
  const float armSwing = rng.uniform(0.35f, 0.55f);
  const float phase0 = rng.uniform(0.0f, 0.5f);
  constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
  const Vec3f X{1, 0, 0}, Y{0, 1, 0};

  constexpr int kSteps = 17;
  std::vector<std::vector<Vec3f>> steps;
  for (int k = 0; k < kSteps; ++k) {
    const float t = float(k) / float(kSteps - 1);
    const float ph = kTwoPi * (t + phase0);
    const float sw = std::sin(ph);
    std::array<Affine3f, kBones> local;  // rotation about each bone's rest joint
    auto rot = [&](int b, Vec3f axis, float a) { local[b] = rotateAbout(kSkeleton[b].joint, axis, a); };
    local[Pelvis] = Affine3f::translate({0.0f, 0.03f * std::cos(2.0f * ph), 0.5f * t}) *
                    rotateAbout(kSkeleton[Pelvis].joint, Y, 0.12f * sw);
    rot(Spine, Y, -0.2f * sw);
    rot(Head, normalize(Vec3f{0.2f, 1.0f, 0.0f}), 0.35f * std::sin(ph + 1.0f));
    // Legs: swinging forward is a negative turn about +x for a downward limb.
    rot(ThighL, X, -stride * sw);
    rot(ThighR, X, stride * sw);
    rot(ShinL, X, 0.7f * std::max(0.0f, std::sin(ph + 1.2f)));
    rot(ShinR, X, 0.7f * std::max(0.0f, std::sin(ph + 1.2f + std::numbers::pi_v<float>)));
    // Arms swing against the legs; elbows bend forward.
    rot(UArmL, normalize(Vec3f{1.0f, 0.0f, -0.2f}), armSwing * sw);
    rot(UArmR, normalize(Vec3f{1.0f, 0.0f, 0.2f}), -armSwing * sw);
    rot(FArmL, X, -0.35f - 0.25f * std::max(0.0f, -sw));
    rot(FArmR, X, -0.35f - 0.25f * std::max(0.0f, sw));
    std::array<Affine3f, kBones> world;
    for (int b = 0; b < kBones; ++b)
      world[b] = kSkeleton[b].parent < 0 ? local[b] : world[kSkeleton[b].parent] * local[b];

    std::vector<Vec3f> pos(body.mesh.vertices.size());
    for (size_t i = 0; i < pos.size(); ++i) {
      const Vec3f v = body.mesh.vertices[i];
      const Influence& in = body.influences[i];
      pos[i] = world[in.bone].xfmPoint(v) * in.w + world[in.other].xfmPoint(v) * (1.0f - in.w);
    }
    steps.push_back(std::move(pos));
  }

  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(body.mesh.triangles), std::move(steps));
  ProceduralScene out;
  out.camera.eye = {2.1f, 1.6f, 3.4f};
  out.camera.target = {0.0f, 0.95f, 0.25f};
  out.camera.verticalFovDegrees = 40.0f;
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
