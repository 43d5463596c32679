// The Embree API tests' world (test_world.h).
#include "test_world.h"

#include <cmath>

#include "instance_keys.h"  // scaleSkewShift, the S of T R S

namespace mbrt::embree_test {
namespace {

using Rng = std::mt19937;

float uniform(Rng& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

Vec3f randomPoint(Rng& rng, float r) { return {uniform(rng, -r, r), uniform(rng, -r, r), uniform(rng, -r, r)}; }

// `count` triangles or quads of size ~`size` in [-1,1]^3, moving by up to
// `motion` per step.
TestMesh randomMesh(Rng& rng, bool quads, uint32_t count, uint32_t steps, float size, float motion) {
  TestMesh m;
  m.quads = quads;
  m.steps.resize(steps);
  const uint32_t corners = quads ? 4 : 3;
  for (uint32_t p = 0; p < count; ++p) {
    const Vec3f c = randomPoint(rng, 1.0f);
    Vec3f v[4];
    const Vec3f a = randomPoint(rng, size), b = randomPoint(rng, size);
    v[0] = c;
    v[1] = c + a;
    v[2] = quads ? c + a + b + randomPoint(rng, 0.2f * size) : c + b;  // quads: nearly planar
    v[3] = c + b;
    Vec3f offset{0.0f};
    const Vec3f move = randomPoint(rng, motion);
    for (uint32_t s = 0; s < steps; ++s) {
      for (uint32_t k = 0; k < corners; ++k) m.steps[s].push_back(v[k] + offset + randomPoint(rng, 0.1f * motion));
      offset += move;
    }
    for (uint32_t k = 0; k < corners; ++k) m.indices.push_back(corners * p + k);
  }
  return m;
}

RTCQuaternionDecomposition decomposition(Quaternion q, Vec3f scale, Vec3f translation) {
  RTCQuaternionDecomposition d;
  rtcInitQuaternionDecomposition(&d);
  rtcQuaternionDecompositionSetQuaternion(&d, q.w, q.x, q.y, q.z);
  rtcQuaternionDecompositionSetScale(&d, scale.x, scale.y, scale.z);
  rtcQuaternionDecompositionSetTranslation(&d, translation.x, translation.y, translation.z);
  return d;
}

bool plainDecompositions(const std::vector<RTCQuaternionDecomposition>& keys) {
  for (size_t k = 0; k < keys.size(); ++k) {
    const auto& d = keys[k];
    if (d.skew_xy != 0 || d.skew_xz != 0 || d.skew_yz != 0 || d.shift_x != 0 || d.shift_y != 0 || d.shift_z != 0)
      return false;
    if (k > 0 && ((d.scale_x > 0) != (keys[k - 1].scale_x > 0) || (d.scale_y > 0) != (keys[k - 1].scale_y > 0) ||
                  (d.scale_z > 0) != (keys[k - 1].scale_z > 0)))
      return false;
  }
  return true;
}

const TestMesh& meshOf(const TestWorld& w, uint32_t geomID, uint32_t instID) {
  if (instID == RTC_INVALID_GEOMETRY_ID) return w.top.meshes[geomID];
  const TestInstance& inst = w.top.instances[instID - w.top.meshes.size()];
  return w.children[inst.child].meshes[geomID];
}

void addMeshes(Scene& scene, const TestScene& ts, bool contextFilter) {
  for (uint32_t id = 0; id < ts.meshes.size(); ++id) {
    const TestMesh& m = ts.meshes[id];
    std::vector<Triangle> tris;
    const size_t prims = m.indices.size() / (m.quads ? 4 : 3);
    for (size_t p = 0; p < prims; ++p) {
      const uint32_t* i = &m.indices[p * (m.quads ? 4 : 3)];
      if (m.quads) {
        tris.push_back({i[0], i[1], i[3]});
        tris.push_back({i[2], i[3], i[1]});
      } else {
        tris.push_back({i[0], i[1], i[2]});
      }
    }
    const TimeRange range = m.hasRange && m.steps.size() > 1 ? TimeRange{m.t0, m.t1} : TimeRange{};
    const uint32_t got = scene.addTriangleMesh(std::move(tris), m.steps, range);
    scene.setMask(got, m.mask);
    if (m.filter || contextFilter) {
      const bool quads = m.quads, own = m.filter;
      scene.setFilter(got, [id, quads, own, contextFilter](const FilterArgs& a) {
        const uint32_t prim = quads ? a.candidate.primID / 2 : a.candidate.primID;
        const float u = quads && (a.candidate.primID & 1) ? 1.0f - a.candidate.u : a.candidate.u;
        return (!own || filterRule(id, prim)) && (!contextFilter || contextRule(u));
      });
    }
  }
}

}  // namespace

TestWorld randomWorld(uint32_t seed, bool contextFilter) {
  Rng rng(seed);
  TestWorld w;
  w.contextFilter = contextFilter;
  w.children.resize(2);
  w.children[0].meshes.push_back(randomMesh(rng, false, 30, 2, 0.3f, 0.2f));
  w.children[0].meshes.push_back(randomMesh(rng, true, 12, 1, 0.3f, 0.0f));
  w.children[0].meshes.back().filter = true;
  w.children[1].meshes.push_back(randomMesh(rng, false, 25, 1, 0.3f, 0.0f));

  TestScene& t = w.top;
  t.meshes.push_back(randomMesh(rng, false, 60, 1, 0.25f, 0.0f));
  t.meshes.push_back(randomMesh(rng, false, 40, 3, 0.25f, 0.3f));
  t.meshes.back().mask = 0x2;
  t.meshes.push_back(randomMesh(rng, true, 25, 2, 0.25f, 0.3f));
  t.meshes.back().filter = true;
  t.meshes.push_back(randomMesh(rng, false, 20, 2, 0.25f, 0.3f));
  t.meshes.back().hasRange = true;
  t.meshes.back().t0 = 0.25f;
  t.meshes.back().t1 = 0.75f;
  t.meshes.push_back(randomMesh(rng, true, 10, 1, 0.25f, 0.0f));  // static: its time range changes nothing
  t.meshes.back().hasRange = true;
  t.meshes.back().t0 = 0.3f;
  t.meshes.back().t1 = 0.6f;

  TestInstance moving;  // matrix keys
  moving.child = 0;
  moving.matrices = {Affine3f::translate({0.3f, -0.2f, 0.1f}) * Affine3f::rotate({0, 1, 0}, 0.3f) *
                         Affine3f::scale({0.5f, 0.5f, 0.5f}),
                     Affine3f::translate({0.6f, 0.1f, 0.0f}) * Affine3f::rotate({0, 1, 0}, 0.9f) *
                         Affine3f::scale({0.5f, 0.6f, 0.5f})};
  t.instances.push_back(moving);
  TestInstance spinning;  // quaternion keys, three steps
  spinning.child = 1;
  for (int k = 0; k < 3; ++k)
    spinning.quats.push_back(decomposition(Quaternion::fromAxisAngle({0.2f, 1, 0.1f}, 1.2f * float(k)),
                                           {0.6f, 0.6f, 0.7f}, {-0.4f, 0.1f * float(k), 0.3f}));
  t.instances.push_back(spinning);
  TestInstance pivoting;  // quaternion keys with skew and shift
  pivoting.child = 0;
  for (int k = 0; k < 2; ++k) {
    RTCQuaternionDecomposition d =
        decomposition(Quaternion::fromAxisAngle({1, 0.3f, 0}, 0.8f * float(k)), {0.5f, 0.4f, 0.5f}, {0, -0.5f, -0.3f});
    rtcQuaternionDecompositionSetShift(&d, 0.3f, 0.0f, -0.2f * float(k));
    rtcQuaternionDecompositionSetSkew(&d, 0.1f * float(k), 0.0f, 0.05f);
    pivoting.quats.push_back(d);
  }
  t.instances.push_back(pivoting);
  TestInstance still;  // one matrix key, a mask
  still.child = 1;
  still.matrices = {Affine3f::translate({-0.5f, 0.5f, -0.4f}) * Affine3f::scale({0.4f, 0.4f, 0.4f})};
  still.mask = 0x4;
  t.instances.push_back(still);
  return w;
}

std::vector<TestRay> randomRays(uint32_t seed, size_t count) {
  Rng rng(seed);
  const float special[] = {0.0f, 1.0f, 0.5f, 0.25f, 0.75f, 0.3f, 0.6f};
  const uint32_t masks[] = {0xFFFFFFFFu, 0x1u, 0x2u, 0x4u, 0x5u, 0xFFFFFFFFu};
  std::vector<TestRay> rays(count);
  for (size_t i = 0; i < count; ++i) {
    TestRay& r = rays[i];
    Vec3f o = randomPoint(rng, 1.0f);
    o = o * (3.0f / std::max(length(o), 1e-3f));
    r.org = o;
    r.dir = randomPoint(rng, 0.9f) - o;
    r.time = i % 2 ? uniform(rng, 0.0f, 1.0f) : special[(i / 2) % 7];
    r.mask = masks[i % 6];
    if (i % 5 == 0) r.tnear = 1.0f;  // starts inside the world
  }
  return rays;
}

std::shared_ptr<Scene> toMbrtScene(const TestWorld& w) {
  std::vector<std::shared_ptr<Scene>> children;
  for (const TestScene& c : w.children) {
    children.push_back(std::make_shared<Scene>());
    addMeshes(*children.back(), c, w.contextFilter);
  }
  auto top = std::make_shared<Scene>();
  addMeshes(*top, w.top, w.contextFilter);
  for (const TestInstance& inst : w.top.instances) {
    uint32_t id;
    if (!inst.matrices.empty()) {
      id = top->addInstance(children[inst.child], inst.matrices);
    } else {
      const bool plain = plainDecompositions(inst.quats);
      std::vector<SRTKey> keys;
      for (const auto& d : inst.quats)
        keys.push_back({plain ? Vec3f{d.scale_x, d.scale_y, d.scale_z} : Vec3f{1, 1, 1},
                        {d.quaternion_r, d.quaternion_i, d.quaternion_j, d.quaternion_k},
                        {d.translation_x, d.translation_y, d.translation_z}});
      if (plain) {
        id = top->addInstance(children[inst.child], keys);
      } else {
        // T R S = (T R) after S: the S matrices as an inner instance.
        auto inner = std::make_shared<Scene>();
        std::vector<Affine3f> s;
        for (const auto& d : inst.quats) s.push_back(embree_api::scaleSkewShift(d));
        inner->addInstance(children[inst.child], s);
        id = top->addInstance(inner, keys);
      }
    }
    top->setMask(id, inst.mask);
  }
  return top;
}

bool meshIsQuads(const TestWorld& w, const TestAnswer& a) { return a.hit && meshOf(w, a.geomID, a.instID).quads; }

Hit toMbrtHit(const TestWorld& w, const TestAnswer& a) {
  Hit h;
  if (!a.hit) return h;
  const TestMesh& m = meshOf(w, a.geomID, a.instID);
  h.t = a.t;
  h.u = a.u;
  h.v = a.v;
  h.Ng = a.Ng;
  h.geomID = a.geomID;
  h.primID = m.quads ? 2 * a.primID + (a.u + a.v > 1.0f ? 1 : 0) : a.primID;
  h.instID = a.instID == RTC_INVALID_GEOMETRY_ID ? kInvalidId : a.instID;
  return h;
}

}  // namespace mbrt::embree_test
