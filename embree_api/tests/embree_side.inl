// The tests' Embree calls, compiled once per side (side_real.cpp,
// side_mbrt.cpp) with MBRT_EMBREE_SIDE naming its namespace: builds a
// TestWorld with Embree's API and traces rays in every packet and stream
// form. Included after <embree3/rtcore.h> (or its renamed form).
#include <cmath>
#include <cstring>
#include <memory>

#include "embree_side.h"

namespace mbrt::embree_test {
namespace MBRT_EMBREE_SIDE {
namespace {

struct Built {
  RTCDevice device = nullptr;
  std::vector<RTCScene> children;
  RTCScene top = nullptr;
  bool contextFilter = false;
};

// The audit's log of the ray being traced (one thread traces).
thread_local std::vector<FilterCall>* tLog = nullptr;

void geometryFilter(const RTCFilterFunctionNArguments* a) {
  for (unsigned i = 0; i < a->N; ++i)
    if (a->valid[i] && !filterRule(RTCHitN_geomID(a->hit, a->N, i), RTCHitN_primID(a->hit, a->N, i))) a->valid[i] = 0;
}

void contextFilter(const RTCFilterFunctionNArguments* a) {
  for (unsigned i = 0; i < a->N; ++i)
    if (a->valid[i] && !contextRule(RTCHitN_u(a->hit, a->N, i))) a->valid[i] = 0;
}

void record(const RTCFilterFunctionNArguments* a, bool context) {
  for (unsigned i = 0; i < a->N; ++i) {
    if (!a->valid[i]) continue;
    FilterCall c;
    c.context = context;
    c.N = a->N;
    RTCHitN* h = a->hit;
    RTCRayN* r = a->ray;
    c.geomID = RTCHitN_geomID(h, a->N, i);
    c.primID = RTCHitN_primID(h, a->N, i);
    c.instID = RTCHitN_instID(h, a->N, i, 0);
    c.contextInstID = a->context->instID[0];
    c.u = RTCHitN_u(h, a->N, i);
    c.v = RTCHitN_v(h, a->N, i);
    c.Ng = {RTCHitN_Ng_x(h, a->N, i), RTCHitN_Ng_y(h, a->N, i), RTCHitN_Ng_z(h, a->N, i)};
    c.tfar = RTCRayN_tfar(r, a->N, i);
    c.org = {RTCRayN_org_x(r, a->N, i), RTCRayN_org_y(r, a->N, i), RTCRayN_org_z(r, a->N, i)};
    c.dir = {RTCRayN_dir_x(r, a->N, i), RTCRayN_dir_y(r, a->N, i), RTCRayN_dir_z(r, a->N, i)};
    if (tLog) tLog->push_back(c);
    if (context) a->valid[i] = 0;
  }
}
void recordGeometry(const RTCFilterFunctionNArguments* a) { record(a, false); }
void recordContext(const RTCFilterFunctionNArguments* a) { record(a, true); }

RTCGeometry newMesh(RTCDevice d, const TestMesh& m, bool audit) {
  RTCGeometry g = rtcNewGeometry(d, m.quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
  const uint32_t steps = uint32_t(m.steps.size());
  rtcSetGeometryTimeStepCount(g, steps);
  if (m.hasRange) rtcSetGeometryTimeRange(g, m.t0, m.t1);
  const unsigned corners = m.quads ? 4 : 3;
  // The index buffer shared, the vertex buffers owned (rtcSetNewGeometryBuffer).
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, m.quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                             m.indices.data(), 0, corners * sizeof(uint32_t), m.indices.size() / corners);
  for (uint32_t s = 0; s < steps; ++s) {
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, s, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.steps[s].size()));
    std::memcpy(v, m.steps[s].data(), m.steps[s].size() * sizeof(Vec3f));
  }
  rtcSetGeometryMask(g, m.mask);
  if (audit) {
    rtcSetGeometryIntersectFilterFunction(g, recordGeometry);
    rtcSetGeometryOccludedFilterFunction(g, recordGeometry);
  } else if (m.filter) {
    rtcSetGeometryIntersectFilterFunction(g, geometryFilter);
    rtcSetGeometryOccludedFilterFunction(g, geometryFilter);
  }
  rtcCommitGeometry(g);
  return g;
}

RTCScene newScene(RTCDevice d, const TestScene& ts, const std::vector<RTCScene>& children, unsigned flags, bool audit) {
  RTCScene s = rtcNewScene(d);
  rtcSetSceneFlags(s, RTCSceneFlags(flags));
  for (const TestMesh& m : ts.meshes) {
    RTCGeometry g = newMesh(d, m, audit);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
  }
  for (const TestInstance& inst : ts.instances) {
    RTCGeometry g = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, children[inst.child]);
    const size_t steps = inst.matrices.empty() ? inst.quats.size() : inst.matrices.size();
    rtcSetGeometryTimeStepCount(g, unsigned(steps));
    for (unsigned k = 0; k < steps; ++k) {
      if (inst.matrices.empty()) {
        rtcSetGeometryTransformQuaternion(g, k, &inst.quats[k]);
      } else {
        const Affine3f& a = inst.matrices[k];
        const float m[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z, a.vz.x, a.vz.y, a.vz.z, a.p.x, a.p.y, a.p.z};
        rtcSetGeometryTransform(g, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
      }
    }
    rtcSetGeometryMask(g, inst.mask);
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(s);
  return s;
}

Built* buildWorld(const TestWorld& w, const char* config, unsigned flags, bool audit) {
  auto* b = new Built;
  b->device = rtcNewDevice(config);
  b->contextFilter = w.contextFilter || audit;
  const unsigned ctxFlag = b->contextFilter ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : 0;
  for (const TestScene& c : w.children) b->children.push_back(newScene(b->device, c, {}, ctxFlag | flags, audit));
  b->top = newScene(b->device, w.top, b->children, ctxFlag | flags, audit);
  return b;
}

void* build(const TestWorld& w, const char* config, unsigned flags) { return buildWorld(w, config, flags, false); }

void release(void* p) {
  auto* b = static_cast<Built*>(p);
  rtcReleaseScene(b->top);
  for (RTCScene s : b->children) rtcReleaseScene(s);
  rtcReleaseDevice(b->device);
  delete b;
}

#include "embree_side_trace.inl"
#include "mistakes.inl"
#include "scenarios.inl"

std::vector<std::vector<FilterCall>> filterAudit(const TestWorld& w, const std::vector<TestRay>& rays, TraceMode mode) {
  Built* b = buildWorld(w, nullptr, RTC_SCENE_FLAG_ROBUST, true);
  std::vector<std::vector<FilterCall>> logs(rays.size());
  std::vector<TestAnswer> answers;
  for (size_t i = 0; i < rays.size(); ++i) {
    tLog = &logs[i];
    traceWith(*b, {rays[i]}, answers, mode, recordContext);
  }
  tLog = nullptr;
  release(b);
  return logs;
}

void trace(void* p, const std::vector<TestRay>& rays, std::vector<TestAnswer>& out, TraceMode mode) {
  const Built& b = *static_cast<Built*>(p);
  traceWith(b, rays, out, mode, b.contextFilter ? contextFilter : nullptr);
}

}  // namespace
}  // namespace MBRT_EMBREE_SIDE

const Side& MBRT_EMBREE_SIDE_GETTER() {
  static const Side side{MBRT_EMBREE_SIDE_NAME, MBRT_EMBREE_SIDE::build, MBRT_EMBREE_SIDE::trace,
                         MBRT_EMBREE_SIDE::release, MBRT_EMBREE_SIDE::filterAudit,
                         MBRT_EMBREE_SIDE::mistakes, MBRT_EMBREE_SIDE::scenarios};
  return side;
}

}  // namespace mbrt::embree_test
