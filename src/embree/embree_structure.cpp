// `embree`: the same scene fed to Intel Embree 3, as a peer for the oracle
// tests and the benchmark.
//
// Mapping (one Embree geometry per mbrt geometry, attached under the same id):
// - triangle meshes: RTC_GEOMETRY_TYPE_TRIANGLE with one vertex buffer per
//   time step (rtcSetGeometryTimeStepCount). Vertex buffers are SHARED with
//   the scene where Embree's 16-byte load of the last vertex stays inside the
//   caller's memory (stride >= 16, or VertexBuffer::padding >= 4: the scene
//   pads the buffers it owns); other buffers are COPIED into padded arrays
//   (counted in the structure's bytes). The index buffer is always shared.
// - round segments: RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE. Embree wants
//   float4 (x, y, z, radius) vertices and one index per segment naming its
//   first vertex (the second is the next one), so the vertices are always
//   copied: when every mbrt segment is (i, i+1) the scene's vertex order is
//   kept, otherwise each segment gets its own two vertices. A flags buffer of
//   zeros marks every segment as having no neighbours, so each one is the
//   whole capsule (both end spheres), as mbrt defines segments.
// - instances: RTC_GEOMETRY_TYPE_INSTANCE over the Embree scene of the
//   instanced scene's structure (built by the SceneContext with the same
//   kind), one 3x4 column-major transform per step (element-wise
//   interpolation, Embree's default for matrix keys), or for SRT keys one
//   RTCQuaternionDecomposition per step (Embree slerps them). Embree 3 as packaged
//   by Debian supports one instance level only (RTC_MAX_INSTANCE_LEVEL_COUNT):
//   nested instances are refused with an Error.
// - partial time ranges: rtcSetGeometryTimeRange. A static geometry with a
//   partial range is given two identical steps so that Embree culls it
//   outside its range as mbrt does. Embree treats the range ends with a small
//   slack (docs/design.md): compare such geometries away from their ends.
// - masks: rtcSetGeometryMask when the device supports ray masks; otherwise
//   (or when forced, for tests) the masks of the geometry and of the
//   instance are checked in a filter function.
// - intersection filters: an Embree filter function calls the geometry's
//   IntersectFilter with the ray in the geometry's space (tfar = the
//   candidate's distance) and the candidate hit (object-space Ng, no instID).
// Modes (BuildOptions::embreeMode): Robust builds with RTC_SCENE_FLAG_ROBUST
// (watertight, as mbrt's triangle test; what the oracle tests compare with),
// Default with Embree's default flags (what its users run), Static with the
// default flags over the scene frozen at BuildOptions::frozenTime: one time
// step per geometry (vertices and transforms evaluated at that time, always
// copied), geometries not alive then left out, so that Embree builds its
// static BVH (the bound `frozen` is compared with); StaticRobust is that
// static BVH with RTC_SCENE_FLAG_ROBUST (the watertight peer of `frozen`,
// whose slab and triangle tests are always robust). All use medium build
// quality (Embree's default, which is its motion-blur builder with temporal
// splits for moving geometry).
//
// Rays: Embree asserts on origins beyond 1.844e18, which mbrt accepts;
// embree_ray.h moves such origins forward onto a cube around the coordinate
// limit before Embree sees them (or reports the miss without calling it).
//
// Memory: the device's memory monitor callback keeps the current and peak
// bytes. Builds are serialized by a mutex so that the monitor's figures can
// be attributed to one structure: bytes = growth of Embree's memory over the
// build (plus our copies), peak = the largest growth during the build.
#include "embree/embree_structure.h"

#include "embree/embree_device.h"
#include "embree/embree_ray.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace mbrt::detail {
namespace {

bool isFullRange(TimeRange r) { return r.lo == 0.0f && r.hi == 1.0f; }

class EmbreeStructure final : public Structure {
 public:
  explicit EmbreeStructure(const SceneContext& ctx)
      : ctx_(ctx), mode_(ctx.options().embreeMode), frozenTime_(ctx.options().frozenTime) {
    Device& d = device();
    filterMasks_ = !d.rayMask || gForceFilterMasks.load();
    std::lock_guard<std::mutex> lock(d.buildMutex);
    const long long before = d.current.load();
    d.base = before;
    d.peak = before;
    const size_t budget = ctx.options().memoryBudget;
    d.limit = budget == 0 ? 0 : (long long)(budget > ctx.budget().used() ? budget - ctx.budget().used() : 1);
    {
      std::lock_guard<std::mutex> errLock(d.errorMutex);
      d.lastError.clear();
    }
    try {
      buildScene(d, budget);
    } catch (...) {
      d.limit = 0;
      if (scene_) rtcReleaseScene(scene_);
      scene_ = nullptr;
      throw;
    }
    d.limit = 0;
    embreeBytes_ = size_t(std::max(0LL, d.current.load() - before));
    const size_t peak = size_t(std::max(0LL, d.peak.load() - before));
    // Account the build's peak and what stays in the context's budget.
    const size_t kept = embreeBytes_ + copiedBytes_;
    const size_t high = std::max(peak + copiedBytes_, kept);
    ctx.budget().charge(high, "the Embree build");
    ctx.budget().release(high - kept);
  }

  ~EmbreeStructure() override {
    if (scene_) rtcReleaseScene(scene_);
  }

  RTCScene embreeScene() const { return scene_; }

  bool intersect(RayQuery& q, Hit& hit) const override {
    RTCRayHit rh;
    const EmbreeRayClip clip = toEmbree(q, rh.ray);
    if (clip.miss) return false;
    TraceContext ctx = context(q, clip.shift);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar + clip.shift;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.Ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    hit.geomID = rh.hit.geomID;
    hit.primID = rh.hit.primID;
    hit.instID = rh.hit.instID[0];
    if (hit.instID != RTC_INVALID_GEOMETRY_ID) {
      // Embree reports an instanced hit's Ng in object space: to world
      // space with the inverse transpose of the transform at the ray's time
      // (at the frozen time for a static scene).
      const float t = isStatic() ? frozenTime_ : q.time;
      const Affine3f inv = ctx_.geometry(hit.instID).transformAt(t).inverse();
      const Vec3f n = hit.Ng;
      hit.Ng = {dot(inv.vx, n), dot(inv.vy, n), dot(inv.vz, n)};
    } else {
      hit.instID = kInvalidId;
    }
    q.tfar = hit.t;
    return true;
  }

  bool occluded(RayQuery& q) const override {
    RTCRay ray;
    const EmbreeRayClip clip = toEmbree(q, ray);
    if (clip.miss) return false;
    TraceContext ctx = context(q, clip.shift);
    rtcOccluded1(scene_, &ctx.embree, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
  }

  // Embree exposes no traversal counters: this only intersects ("n/a").
  bool intersectCounted(RayQuery& q, Hit& hit, TraversalCounters&) const override { return intersect(q, hit); }

  void fillStats(AccelStats& s) const override {
    s.references = ctx_.numPrimitives();
    s.bytes = embreeBytes_ + copiedBytes_;
    s.sahCost = std::numeric_limits<double>::quiet_NaN();  // no tree to see: n/a
  }

 private:
  bool isStatic() const {
    return mode_ == BuildOptions::EmbreeMode::Static || mode_ == BuildOptions::EmbreeMode::StaticRobust;
  }
  bool isRobust() const {
    return mode_ == BuildOptions::EmbreeMode::Robust || mode_ == BuildOptions::EmbreeMode::StaticRobust;
  }

  void buildScene(Device& d, size_t budget) {
    scene_ = rtcNewScene(d.device);
    rtcSetSceneFlags(scene_, isRobust() ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
    const Scene& scene = ctx_.scene();
    for (uint32_t id = 0; id < scene.numGeometries(); ++id) addGeometry(d, id, ctx_.geometry(id));
    rtcCommitScene(scene_);
    const RTCError err = rtcGetDeviceError(d.device);
    std::string message;
    {
      std::lock_guard<std::mutex> errLock(d.errorMutex);
      message = d.lastError;
    }
    if (err != RTC_ERROR_NONE || !message.empty()) {
      if (err == RTC_ERROR_OUT_OF_MEMORY && budget != 0)
        throw Error("memory budget of " + std::to_string(budget) + " bytes exceeded by the Embree build");
      throw Error("embree: scene build failed (" + (message.empty() ? "error " + std::to_string(int(err)) : message) +
                  ")");
    }
  }

  TraceContext context(const RayQuery& q, float shift) const {
    TraceContext c;
    rtcInitIntersectContext(&c.embree);
    c.root = &ctx_.scene();
    c.mask = q.mask;
    c.filterMasks = filterMasks_;
    c.shift = shift;
    return c;
  }

  static EmbreeRayClip toEmbree(const RayQuery& q, RTCRay& r) {
    const EmbreeRayClip c = clipForEmbree(q.org, q.dir, q.tnear, q.tfar);
    r.org_x = c.org.x;
    r.org_y = c.org.y;
    r.org_z = c.org.z;
    r.tnear = c.tnear;
    r.dir_x = q.dir.x;
    r.dir_y = q.dir.y;
    r.dir_z = q.dir.z;
    r.time = q.time;
    r.tfar = c.tfar;
    r.mask = q.mask;
    r.id = 0;
    r.flags = 0;
    return c;
  }

  void setCommon(Device& d, RTCGeometry geom, const Geometry& g) {
    if (!isStatic() && !isFullRange(g.timeRange()))
      rtcSetGeometryTimeRange(geom, g.timeRange().lo, g.timeRange().hi);
    if (d.rayMask) rtcSetGeometryMask(geom, g.mask());
    if (g.type() != GeometryType::Instance && (g.hasFilter() || filterMasks_)) {
      rtcSetGeometryUserData(geom, const_cast<Geometry*>(&g));
      rtcSetGeometryIntersectFilterFunction(geom, filterFunction);
      rtcSetGeometryOccludedFilterFunction(geom, filterFunction);
    }
  }

  // Embree steps: 1 in the static mode; else S, or 2 identical ones for a
  // static geometry with a partial time range (so that Embree culls it
  // outside the range).
  uint32_t embreeSteps(const Geometry& g) const {
    if (isStatic()) return 1;
    return g.numSteps() == 1 && !isFullRange(g.timeRange()) ? 2 : g.numSteps();
  }
  static uint32_t sourceStep(const Geometry& g, uint32_t k) { return g.numSteps() == 1 ? 0 : k; }

  // Vertex i of Embree step k: the geometry's step, or its position at the
  // frozen time in the static mode.
  Vec3f vertex(const Geometry& g, uint32_t k, uint32_t i) const {
    return isStatic() ? g.vertexAt(frozenTime_, i) : g.vertices(sourceStep(g, k))[i];
  }

  void addGeometry(Device& d, uint32_t id, const Geometry& g) {
    if (isStatic() && !g.timeRange().contains(frozenTime_)) return;  // not there at the frozen time
    RTCGeometry geom = nullptr;
    switch (g.type()) {
      case GeometryType::Triangles:
        geom = newTriangles(d, g);
        break;
      case GeometryType::Segments:
        geom = newSegments(d, g);
        break;
      case GeometryType::Instance:
        geom = newInstance(d, id, g);
        break;
    }
    setCommon(d, geom, g);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, id);
    rtcReleaseGeometry(geom);
  }

  RTCGeometry newTriangles(Device& d, const Geometry& g) {
    const uint32_t steps = embreeSteps(g);
    RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryTimeStepCount(geom, steps);  // before the per-step buffers
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g.triangles().data(), 0,
                               sizeof(Triangle), g.numPrimitives());
    for (uint32_t k = 0; k < steps; ++k) {
      const VertexBuffer& vb = g.vertices(sourceStep(g, k));
      const bool aligned = vb.stride % 4 == 0 && reinterpret_cast<uintptr_t>(vb.data) % 4 == 0;
      if (aligned && (vb.stride >= 16 || vb.padding >= 4) && (!isStatic() || g.numSteps() == 1)) {
        // Shared: the 16-byte load of the last vertex stays in the caller's memory.
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, vb.data, 0, vb.stride,
                                   vb.count);
        continue;
      }
      // Copied: unpadded or misaligned buffer, or the frozen positions, into a padded array.
      std::vector<float>& copy = copies_.emplace_back(vb.count * 3 + 1, 0.0f);
      for (size_t i = 0; i < vb.count; ++i) {
        const Vec3f p = vertex(g, k, uint32_t(i));
        std::memcpy(&copy[3 * i], &p, sizeof(Vec3f));
      }
      copiedBytes_ += copy.size() * sizeof(float);
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, copy.data(), 0,
                                 3 * sizeof(float), vb.count);
    }
    return geom;
  }

  RTCGeometry newSegments(Device& d, const Geometry& g) {
    const uint32_t steps = embreeSteps(g);
    RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetGeometryTimeStepCount(geom, steps);
    const auto segs = g.segments();
    bool chained = true;
    for (const Segment& s : segs) chained &= s.v1 == s.v0 + 1;
    std::vector<uint32_t>& index = indexCopies_.emplace_back(segs.size());
    for (size_t i = 0; i < segs.size(); ++i) index[i] = chained ? segs[i].v0 : uint32_t(2 * i);
    copiedBytes_ += index.size() * sizeof(uint32_t);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, index.data(), 0, sizeof(uint32_t),
                               index.size());
    auto* flags = static_cast<unsigned char*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, segs.size()));
    std::memset(flags, 0, segs.size());  // no neighbours: every segment has both end caps
    const auto radii = g.radii();
    for (uint32_t k = 0; k < steps; ++k) {
      const size_t n = chained ? g.vertices(0).count : 2 * segs.size();
      std::vector<float>& v4 = copies_.emplace_back(4 * n, 0.0f);
      auto put = [&](size_t at, uint32_t i) {
        const Vec3f p = vertex(g, k, i);
        v4[4 * at + 0] = p.x;
        v4[4 * at + 1] = p.y;
        v4[4 * at + 2] = p.z;
        v4[4 * at + 3] = radii[i];
      };
      if (chained) {
        for (size_t i = 0; i < n; ++i) put(i, uint32_t(i));
      } else {
        for (size_t i = 0; i < segs.size(); ++i) {
          put(2 * i, segs[i].v0);
          put(2 * i + 1, segs[i].v1);
        }
      }
      copiedBytes_ += v4.size() * sizeof(float);
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT4, v4.data(), 0,
                                 4 * sizeof(float), n);
    }
    return geom;
  }

  RTCGeometry newInstance(Device& d, uint32_t id, const Geometry& g) {
    const auto* child = dynamic_cast<const EmbreeStructure*>(&ctx_.child(id));
    if (!child) throw Error("embree: instance " + std::to_string(id) + " has no Embree child structure");
    if (RTC_MAX_INSTANCE_LEVEL_COUNT < 2) {
      const Scene& cs = *g.instancedScene();
      for (uint32_t c = 0; c < cs.numGeometries(); ++c)
        if (cs.geometry(c).type() == GeometryType::Instance)
          throw Error("embree: geometry " + std::to_string(id) +
                      " nests instances, but this Embree supports one instance level only "
                      "(RTC_MAX_INSTANCE_LEVEL_COUNT = " +
                      std::to_string(RTC_MAX_INSTANCE_LEVEL_COUNT) + ")");
    }
    const uint32_t steps = embreeSteps(g);
    RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, child->embreeScene());
    rtcSetGeometryTimeStepCount(geom, steps);
    for (uint32_t k = 0; k < steps; ++k) {
      if (g.hasSRTKeys() && !isStatic()) {
        setQuaternionKey(geom, k, g.srtKeys()[sourceStep(g, k)]);
        continue;
      }
      // Affine3f is (vx, vy, vz, p): exactly a column-major 3x4 matrix.
      const Affine3f a = isStatic() ? g.transformAt(frozenTime_) : g.transforms()[sourceStep(g, k)];
      const float m[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z, a.vz.x, a.vz.y, a.vz.z, a.p.x, a.p.y, a.p.z};
      rtcSetGeometryTransform(geom, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
    }
    return geom;
  }

  // SRT keys: Embree lerps scale and translation and slerps the quaternion,
  // as mbrt does (the keys' quaternions are already on one hemisphere, so
  // both take the same arc).
  static void setQuaternionKey(RTCGeometry geom, uint32_t k, const SRTKey& key) {
    RTCQuaternionDecomposition qd;
    rtcInitQuaternionDecomposition(&qd);
    qd.scale_x = key.scale.x;
    qd.scale_y = key.scale.y;
    qd.scale_z = key.scale.z;
    qd.quaternion_r = key.rotation.w;
    qd.quaternion_i = key.rotation.x;
    qd.quaternion_j = key.rotation.y;
    qd.quaternion_k = key.rotation.z;
    qd.translation_x = key.translation.x;
    qd.translation_y = key.translation.y;
    qd.translation_z = key.translation.z;
    rtcSetGeometryTransformQuaternion(geom, k, &qd);
  }

  const SceneContext& ctx_;
  BuildOptions::EmbreeMode mode_;
  float frozenTime_;
  RTCScene scene_ = nullptr;
  bool filterMasks_ = false;
  size_t embreeBytes_ = 0;
  size_t copiedBytes_ = 0;
  std::vector<std::vector<float>> copies_;
  std::vector<std::vector<uint32_t>> indexCopies_;
};

}  // namespace

std::unique_ptr<Structure> makeEmbree(const SceneContext& context) {
  return std::make_unique<EmbreeStructure>(context);
}

EmbreeMemory embreeMemory() {
  Device& d = device();
  return {d.current.load(), d.peak.load()};
}

void embreeForceFilterMasks(bool on) { gForceFilterMasks = on; }

}  // namespace mbrt::detail
