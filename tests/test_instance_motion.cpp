// The cheaper ways into an instance (scene/instance_space.h): translation
// keys move the ray's origin only, keys of one linear part reuse its
// inverse made once; both give the general path's local ray (bit for bit
// for translations) and hits the float64 reference accepts. auto fits the
// simplest key form that reproduces a part (auto/part_fit.h).
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "auto/part_fit.h"
#include "auto_scene.h"
#include "oracle.h"
#include "reference64.h"
#include "scene/instance_space.h"
#include "test_util.h"

using namespace mbrt;
using detail::InstanceMotion;

namespace {

std::shared_ptr<Scene> blobScene() {
  test::MeshParts m;
  test::addBlob(m, {0.0f, 0.0f, 0.0f}, 0.5f, 12, 0.2f);
  auto child = std::make_shared<Scene>();
  child->addTriangleMesh(m.triangles, std::vector<std::vector<Vec3f>>{m.vertices});
  return child;
}

std::vector<Affine3f> translationKeys() {
  return {Affine3f::translate({-0.6f, 0.1f, 0.0f}), Affine3f::translate({0.2f, 0.3f, -0.1f}),
          Affine3f::translate({0.7f, -0.2f, 0.1f})};
}
std::vector<Affine3f> constantLinearKeys() {
  const Affine3f l = Affine3f::rotate(normalize(Vec3f{1, 2, 0.5f}), 0.7f) * Affine3f::scale({1.2f, 0.8f, 1.0f});
  std::vector<Affine3f> keys;
  for (const Affine3f& t : translationKeys()) keys.push_back(t * l);
  return keys;
}
std::vector<Affine3f> turningKeys() {
  std::vector<Affine3f> keys;
  for (int k = 0; k < 3; ++k) keys.push_back(Affine3f::translate({0.3f * k, 0, 0}) * Affine3f::rotate({0, 1, 0}, 0.8f * k));
  return keys;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0 || (a == 0.0f && b == 0.0f); }
bool sameBits(Vec3f a, Vec3f b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

TEST(InstanceMotion, KeysAreClassifiedOnce) {
  Scene scene;
  scene.addInstance(blobScene(), translationKeys());
  scene.addInstance(blobScene(), constantLinearKeys());
  scene.addInstance(blobScene(), turningKeys());
  scene.addInstance(blobScene(), std::vector<SRTKey>{SRTKey{}, SRTKey{}});
  scene.addInstance(blobScene(), std::vector<Affine3f>{Affine3f()});
  EXPECT_EQ(InstanceMotion(scene.geometry(0)).kind(), InstanceMotion::Kind::Translation);
  EXPECT_EQ(InstanceMotion(scene.geometry(1)).kind(), InstanceMotion::Kind::ConstantLinear);
  EXPECT_EQ(InstanceMotion(scene.geometry(2)).kind(), InstanceMotion::Kind::General);
  EXPECT_EQ(InstanceMotion(scene.geometry(3)).kind(), InstanceMotion::Kind::General);
  EXPECT_EQ(InstanceMotion(scene.geometry(4)).kind(), InstanceMotion::Kind::Translation);
}

// The local ray against the general path's (the inverse of the
// interpolated key by cofactors): translations bit for bit (up to the sign
// of a zero), a constant linear part within the rounding of the general
// path's own interpolation of it (lerp(L, L, f) is L only up to an ulp).
TEST(InstanceMotion, LocalRaysAreTheGeneralPathsOwn) {
  Scene scene;
  scene.addInstance(blobScene(), translationKeys());
  scene.addInstance(blobScene(), constantLinearKeys());
  scene.addInstance(blobScene(), std::vector<Affine3f>{constantLinearKeys()[1]});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (uint32_t id = 0; id < 3; ++id) {
    const Geometry& g = scene.geometry(id);
    const InstanceMotion motion(g);
    double worst = 0;
    for (int i = 0; i < 5000; ++i) {
      Ray r;
      r.org = Vec3f{u(rng), u(rng), u(rng)} * 5.0f;
      r.dir = Vec3f{u(rng), u(rng), u(rng)};
      r.time = i < 10 ? float(i % 3) * 0.5f : 0.5f * (u(rng) + 1.0f);  // step times, then any
      if (i == 5) r.dir = {0.0f, -0.0f, 1.0f};
      const detail::RayQuery ray(r);
      detail::RayQuery fast, general;
      detail::InstanceFrame fastFrame, generalFrame;
      ASSERT_TRUE(motion.toLocal(g, ray, fast, &fastFrame));
      ASSERT_TRUE(detail::toInstanceSpace(g, ray, general, &generalFrame));
      if (id != 1) {  // translations, and a single key
        EXPECT_TRUE(sameBits(fast.org, general.org)) << id << " ray " << i;
        EXPECT_TRUE(sameBits(fast.dir, general.dir)) << id << " ray " << i;
        EXPECT_TRUE(sameBits(fast.rdir, general.rdir) || (id == 0 && i == 5)) << id << " ray " << i;
        EXPECT_EQ(fast.kz, general.kz);
        EXPECT_TRUE(sameBits(fast.Sx, general.Sx) && sameBits(fast.Sy, general.Sy) && sameBits(fast.Sz, general.Sz));
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(sameBits(fastFrame.cofactor[c], generalFrame.cofactor[c]));
        EXPECT_EQ(fastFrame.invDet, generalFrame.invDet);
      }
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, double(std::fabs(fast.org[c] - general.org[c])) / (1.0 + std::fabs(general.org[c])));
        worst = std::max(worst, double(std::fabs(fast.dir[c] - general.dir[c])) / (1.0 + std::fabs(general.dir[c])));
      }
      EXPECT_EQ(fast.time, ray.time);
      EXPECT_EQ(fast.tfar, ray.tfar);
    }
    EXPECT_LE(worst, id == 1 ? 1e-6 : 0.0) << "instance " << id;
  }
}

// Hits through each kind of keys, judged by the float64 reference (its own
// key interpolation and inverse), for brute and a tree over the instances.
TEST(InstanceMotion, HitsAreTheReferencesThroughEveryKindOfKeys) {
  for (const auto& keys : {translationKeys(), constantLinearKeys(), turningKeys()}) {
    Scene scene;
    scene.addInstance(blobScene(), keys);
    scene.addInstance(blobScene(), std::vector<Affine3f>{Affine3f::translate({0.0f, 0.9f, 0.0f})});
    const ref::Reference reference(scene);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (AccelKind kind : {AccelKind::Brute, AccelKind::BvhInterp}) {
      auto accel = test::buildKind(scene, kind);
      size_t hits = 0;
      for (int i = 0; i < test::scaled(3000, 300); ++i) {
        Ray r;
        r.time = i < 30 ? float(i % 3) * 0.5f : u(rng);
        r.org = Vec3f{u(rng) - 0.5f, u(rng) - 0.5f, -4.0f};
        r.dir = Vec3f{u(rng) - 0.5f, u(rng) - 0.2f, 4.0f} - r.org * 0.1f;
        Hit h;
        hits += accel->intersect(r, h) ? 1 : 0;
        const ref::Verdict v = reference.judgeClosest(r, h);
        ASSERT_TRUE(v.ok) << toString(kind) << " ray " << i << ": " << v.why;
        ASSERT_TRUE(reference.judgeAny(r, accel->occluded(r)).ok) << toString(kind) << " ray " << i;
      }
      EXPECT_GT(hits, test::scaled(3000, 300) / 5) << toString(kind);
    }
  }
}

// auto keeps the simplest form of keys that fits a part: translations for
// a sliding mesh, an affine map per step for a turning one; after a refit
// where the mesh was turned between frames and slides within this one,
// one linear part.
TEST(InstanceMotion, AutoFitsTheSimplestKeys) {
  test::MeshParts m;
  test::addBlob(m, {0.0f, 0.0f, 0.0f}, 0.5f, 12, 0.2f);
  Scene scene;
  scene.addTriangleMesh(m.triangles, test::movedSteps(m.vertices, translationKeys(), ~0u, 0, 1, 1));
  scene.addTriangleMesh(m.triangles, test::movedSteps(m.vertices, turningKeys(), ~0u, 0, 1, 1));
  std::vector<uint32_t> all(m.vertices.size());
  for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
  const detail::PartFit sliding = detail::fitPart(scene.geometry(0), all, 1e-5);
  ASSERT_TRUE(sliding.fits);
  EXPECT_EQ(sliding.form, detail::KeyForm::Translation);
  for (const Affine3f& k : sliding.keys) {
    EXPECT_EQ(k.vx, Vec3f(1, 0, 0));
    EXPECT_EQ(k.vy, Vec3f(0, 1, 0));
    EXPECT_EQ(k.vz, Vec3f(0, 0, 1));
  }
  const detail::PartFit turning = detail::fitPart(scene.geometry(1), all, 1e-5);
  ASSERT_TRUE(turning.fits);
  EXPECT_EQ(turning.form, detail::KeyForm::Affine);
  // The sliding mesh as a later frame shows it: turned, then sliding; its
  // rest pose the first frame's.
  const std::vector<Vec3f> rest(m.vertices.begin(), m.vertices.end());
  Scene later;
  later.addTriangleMesh(m.triangles, test::movedSteps(m.vertices, constantLinearKeys(), ~0u, 0, 1, 1));
  const detail::PartFit refitted = detail::refitPart(rest, later.geometry(0), all, 1e-5);
  ASSERT_TRUE(refitted.fits);
  EXPECT_EQ(refitted.form, detail::KeyForm::ConstantLinear);
  EXPECT_LT(refitted.maxResidual, 1e-5);
}

}  // namespace
