// A scene described once and built three ways by the Embree API's tests:
// through the real libembree3, through mbrt's Embree API (both by
// embree_side.inl) and directly as an mbrt::Scene (toMbrtScene, for the
// float64 reference and for mbrt's brute oracle). Geometry ids are the
// same everywhere: meshes first, then instances, in order.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt::embree_test {

struct TestMesh {
  bool quads = false;
  std::vector<uint32_t> indices;           // 3 or 4 per primitive
  std::vector<std::vector<Vec3f>> steps;   // vertex positions per time step
  bool hasRange = false;
  float t0 = 0.0f, t1 = 1.0f;
  uint32_t mask = 0xFFFFFFFFu;
  bool filter = false;  // the geometry filter of filterRule runs on it
};

struct TestInstance {
  int child = 0;                                   // index into TestWorld::children
  std::vector<Affine3f> matrices;                  // one per step, or
  std::vector<RTCQuaternionDecomposition> quats;   // one per step
  uint32_t mask = 0xFFFFFFFFu;
};

struct TestScene {
  std::vector<TestMesh> meshes;
  std::vector<TestInstance> instances;
};

struct TestWorld {
  std::vector<TestScene> children;
  TestScene top;
  bool contextFilter = false;  // RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION and contextRule
};

struct TestRay {
  Vec3f org, dir;
  float tnear = 0.0f, tfar = kInf, time = 0.0f;
  uint32_t mask = 0xFFFFFFFFu;
};

// One ray's answers as Embree writes them.
struct TestAnswer {
  bool hit = false;
  float t = 0, u = 0, v = 0;
  Vec3f Ng;
  uint32_t geomID = RTC_INVALID_GEOMETRY_ID, primID = RTC_INVALID_GEOMETRY_ID, instID = RTC_INVALID_GEOMETRY_ID;
  bool occluded = false;
};

// The filter rules (Embree's ids, u of the quad for quads): the geometry
// filter rejects (geomID + primID) % 3 == 1, the context filter u < 0.2.
inline bool filterRule(uint32_t geomID, uint32_t primID) { return (geomID + primID) % 3 != 1; }
inline bool contextRule(float u) { return u >= 0.2f; }

// A world with moving and static triangle and quad meshes (a partial time
// range on a moving and on a static one), masks, filters, and instances
// with matrix keys, quaternion keys and quaternion keys with skew and
// shift (pivot), static and moving.
TestWorld randomWorld(uint32_t seed, bool contextFilter);

// Rays aimed into the world; times random and at 0, 1 and the step times.
std::vector<TestRay> randomRays(uint32_t seed, size_t count);

// The world as an mbrt scene with the same ids and motion; filters apply
// the rules above to mbrt's candidate (quads: two triangles 2p, 2p+1).
std::shared_ptr<Scene> toMbrtScene(const TestWorld& world);

// Whether an answer's primitive is a quad.
bool meshIsQuads(const TestWorld& world, const TestAnswer& a);

// Embree's answer as an mbrt hit of toMbrtScene's scene.
Hit toMbrtHit(const TestWorld& world, const TestAnswer& a);

}  // namespace mbrt::embree_test
