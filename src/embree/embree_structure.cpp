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
//   slack (DESIGN.md): compare such geometries away from their ends.
// - masks: rtcSetGeometryMask when the device supports ray masks; otherwise
//   (or when forced, for tests) the masks of the geometry and of the
//   instance are checked in a filter function.
// - intersection filters: an Embree filter function calls the geometry's
//   IntersectFilter with the ray in the geometry's space (tfar = the
//   candidate's distance) and the candidate hit (object-space Ng, no instID).
// Scenes are built with RTC_SCENE_FLAG_ROBUST (watertight, as mbrt's
// triangle test) and medium build quality (Embree's default, which is its
// motion-blur builder with temporal splits).
//
// Memory: the device's memory monitor callback keeps the current and peak
// bytes. Builds are serialized by a mutex so that the monitor's figures can
// be attributed to one structure: bytes = growth of Embree's memory over the
// build (plus our copies), peak = the largest growth during the build.
#include "embree/embree_structure.h"

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

struct Device {
  RTCDevice device = nullptr;
  bool rayMask = false;
  std::atomic<long long> current{0};
  std::atomic<long long> peak{0};
  std::atomic<long long> base{0};   // memory at the start of the current build
  std::atomic<long long> limit{0};  // growth allowed during the current build; 0 = unlimited
  std::mutex buildMutex;
  std::mutex errorMutex;
  std::string lastError;
};

std::atomic<bool> gForceFilterMasks{false};

bool memoryMonitor(void* user, ssize_t bytes, bool /*post*/) {
  Device& d = *static_cast<Device*>(user);
  const long long now = d.current.fetch_add(bytes) + bytes;
  const long long limit = d.limit.load();
  if (bytes > 0 && limit > 0 && now - d.base.load() > limit) {
    d.current.fetch_sub(bytes);
    return false;  // Embree fails the operation with RTC_ERROR_OUT_OF_MEMORY
  }
  long long peak = d.peak.load();
  while (now > peak && !d.peak.compare_exchange_weak(peak, now)) {
  }
  return true;
}

void errorHandler(void* user, RTCError code, const char* message) {
  Device& d = *static_cast<Device*>(user);
  std::lock_guard<std::mutex> lock(d.errorMutex);
  d.lastError = "Embree error " + std::to_string(int(code)) + (message ? std::string(": ") + message : "");
}

// The process-wide device, created on first use (thread-safe static).
Device& device() {
  static Device* d = [] {
    auto* dev = new Device();  // never freed: Embree may be used until exit
    dev->device = rtcNewDevice(nullptr);
    if (!dev->device) throw Error("could not create the Embree device");
    rtcSetDeviceErrorFunction(dev->device, errorHandler, dev);
    rtcSetDeviceMemoryMonitorFunction(dev->device, memoryMonitor, dev);
    dev->rayMask = rtcGetDeviceProperty(dev->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) != 0;
    return dev;
  }();
  return *d;
}

// What we pass to rtcIntersect1/rtcOccluded1: Embree hands it to filters.
struct TraceContext {
  RTCIntersectContext embree;
  const Scene* root;
  uint32_t mask;
  bool filterMasks;
};

void filterFunction(const RTCFilterFunctionNArguments* args) {
  const auto* g = static_cast<const Geometry*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const TraceContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    RTCRayN* r = args->ray;
    RTCHitN* h = args->hit;
    const unsigned N = args->N;
    if (ctx->filterMasks) {
      bool visible = (g->mask() & ctx->mask) != 0;
      const unsigned inst = RTCHitN_instID(h, N, i, 0);
      if (visible && inst != RTC_INVALID_GEOMETRY_ID) visible = (ctx->root->geometry(inst).mask() & ctx->mask) != 0;
      if (!visible) {
        args->valid[i] = 0;
        continue;
      }
    }
    if (!g->hasFilter()) continue;
    Ray ray;
    ray.org = {RTCRayN_org_x(r, N, i), RTCRayN_org_y(r, N, i), RTCRayN_org_z(r, N, i)};
    ray.dir = {RTCRayN_dir_x(r, N, i), RTCRayN_dir_y(r, N, i), RTCRayN_dir_z(r, N, i)};
    ray.tnear = RTCRayN_tnear(r, N, i);
    ray.tfar = RTCRayN_tfar(r, N, i);
    ray.time = RTCRayN_time(r, N, i);
    ray.mask = ctx->mask;
    Hit hit;
    hit.t = ray.tfar;
    hit.u = RTCHitN_u(h, N, i);
    hit.v = RTCHitN_v(h, N, i);
    hit.Ng = {RTCHitN_Ng_x(h, N, i), RTCHitN_Ng_y(h, N, i), RTCHitN_Ng_z(h, N, i)};
    hit.geomID = RTCHitN_geomID(h, N, i);
    hit.primID = RTCHitN_primID(h, N, i);
    hit.instID = kInvalidId;
    if (!g->filter()(FilterArgs{ray, hit, g->userData()})) args->valid[i] = 0;
  }
}

bool isFullRange(TimeRange r) { return r.lo == 0.0f && r.hi == 1.0f; }

class EmbreeStructure final : public Structure {
 public:
  explicit EmbreeStructure(const SceneContext& ctx) : ctx_(ctx) {
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
      scene_ = rtcNewScene(d.device);
      rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
      rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
      const Scene& scene = ctx.scene();
      for (uint32_t id = 0; id < scene.numGeometries(); ++id) addGeometry(d, id, ctx.geometry(id));
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
    TraceContext ctx = context(q);
    RTCRayHit rh;
    toEmbree(q, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.Ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    hit.geomID = rh.hit.geomID;
    hit.primID = rh.hit.primID;
    hit.instID = rh.hit.instID[0];
    if (hit.instID != RTC_INVALID_GEOMETRY_ID) {
      // Embree reports an instanced hit's Ng in object space: to world
      // space with the inverse transpose of the transform at the ray's time.
      const Affine3f inv = ctx_.geometry(hit.instID).transformAt(q.time).inverse();
      const Vec3f n = hit.Ng;
      hit.Ng = {dot(inv.vx, n), dot(inv.vy, n), dot(inv.vz, n)};
    } else {
      hit.instID = kInvalidId;
    }
    q.tfar = hit.t;
    return true;
  }

  bool occluded(RayQuery& q) const override {
    TraceContext ctx = context(q);
    RTCRay ray;
    toEmbree(q, ray);
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
  TraceContext context(const RayQuery& q) const {
    TraceContext c;
    rtcInitIntersectContext(&c.embree);
    c.root = &ctx_.scene();
    c.mask = q.mask;
    c.filterMasks = filterMasks_;
    return c;
  }

  static void toEmbree(const RayQuery& q, RTCRay& r) {
    r.org_x = q.org.x;
    r.org_y = q.org.y;
    r.org_z = q.org.z;
    r.tnear = std::max(q.tnear, 0.0f);  // Embree never traces behind the origin (it asserts tnear >= 0)
    r.dir_x = q.dir.x;
    r.dir_y = q.dir.y;
    r.dir_z = q.dir.z;
    r.time = q.time;
    r.tfar = q.tfar;
    r.mask = q.mask;
    r.id = 0;
    r.flags = 0;
  }

  void setCommon(Device& d, RTCGeometry geom, const Geometry& g) {
    if (!isFullRange(g.timeRange())) rtcSetGeometryTimeRange(geom, g.timeRange().lo, g.timeRange().hi);
    if (d.rayMask) rtcSetGeometryMask(geom, g.mask());
    if (g.type() != GeometryType::Instance && (g.hasFilter() || filterMasks_)) {
      rtcSetGeometryUserData(geom, const_cast<Geometry*>(&g));
      rtcSetGeometryIntersectFilterFunction(geom, filterFunction);
      rtcSetGeometryOccludedFilterFunction(geom, filterFunction);
    }
  }

  // Embree steps: S, or 2 identical ones for a static geometry with a
  // partial time range (so that Embree culls it outside the range).
  static uint32_t embreeSteps(const Geometry& g) {
    return g.numSteps() == 1 && !isFullRange(g.timeRange()) ? 2 : g.numSteps();
  }
  static uint32_t sourceStep(const Geometry& g, uint32_t k) { return g.numSteps() == 1 ? 0 : k; }

  void addGeometry(Device& d, uint32_t id, const Geometry& g) {
    RTCGeometry geom = nullptr;
    const uint32_t steps = embreeSteps(g);
    switch (g.type()) {
      case GeometryType::Triangles: {
        geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryTimeStepCount(geom, steps);  // before the per-step buffers
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g.triangles().data(), 0,
                                   sizeof(Triangle), g.numPrimitives());
        for (uint32_t k = 0; k < steps; ++k) {
          const VertexBuffer& vb = g.vertices(sourceStep(g, k));
          const bool aligned = vb.stride % 4 == 0 && reinterpret_cast<uintptr_t>(vb.data) % 4 == 0;
          if (aligned && (vb.stride >= 16 || vb.padding >= 4)) {
            // Shared: the 16-byte load of the last vertex stays in the caller's memory.
            rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, vb.data, 0, vb.stride,
                                       vb.count);
          } else {
            // Copied: unpadded or misaligned buffer, into a padded array.
            std::vector<float>& copy = copies_.emplace_back(vb.count * 3 + 1, 0.0f);
            for (size_t i = 0; i < vb.count; ++i) {
              const Vec3f p = vb[i];
              std::memcpy(&copy[3 * i], &p, sizeof(Vec3f));
            }
            copiedBytes_ += copy.size() * sizeof(float);
            rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, copy.data(), 0,
                                       3 * sizeof(float), vb.count);
          }
        }
        break;
      }
      case GeometryType::Segments: {
        geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
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
          const VertexBuffer& vb = g.vertices(sourceStep(g, k));
          const size_t n = chained ? vb.count : 2 * segs.size();
          std::vector<float>& v4 = copies_.emplace_back(4 * n, 0.0f);
          auto put = [&](size_t at, uint32_t vertex) {
            const Vec3f p = vb[vertex];
            v4[4 * at + 0] = p.x;
            v4[4 * at + 1] = p.y;
            v4[4 * at + 2] = p.z;
            v4[4 * at + 3] = radii[vertex];
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
        break;
      }
      case GeometryType::Instance: {
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
        geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, child->embreeScene());
        rtcSetGeometryTimeStepCount(geom, steps);
        for (uint32_t k = 0; k < steps; ++k) {
          if (g.hasSRTKeys()) {
            // SRT keys: Embree lerps scale and translation and slerps the
            // quaternion, as mbrt does (the keys' quaternions are already on
            // one hemisphere, so both take the same arc).
            const SRTKey& key = g.srtKeys()[sourceStep(g, k)];
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
            continue;
          }
          // Affine3f is (vx, vy, vz, p): exactly a column-major 3x4 matrix.
          const Affine3f& a = g.transforms()[sourceStep(g, k)];
          const float m[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z,
                               a.vz.x, a.vz.y, a.vz.z, a.p.x,  a.p.y,  a.p.z};
          rtcSetGeometryTransform(geom, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
        }
        break;
      }
    }
    setCommon(d, geom, g);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, id);
    rtcReleaseGeometry(geom);
  }

  const SceneContext& ctx_;
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
