// The C API's kinds, build options, accels, statistics and tracing
// (mbrt/mbrt.h).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "c/handles.h"

namespace {

// The leaf kind of `auto`: a name in the C struct (NULL: none), a kind in C++.
void copyLeafKind(const std::optional<mbrt::AccelKind>& from, const char*& to) {
  to = nullptr;
  if (!from) return;
  for (const std::string& name : mbrt::capi::kindNames())
    if (mbrt::parseAccelKind(name) == from) to = name.c_str();
}

void copyLeafKind(const char* from, std::optional<mbrt::AccelKind>& to) {
  to.reset();
  if (!from) return;
  to = mbrt::parseAccelKind(from);
  if (!to) mbrt::capi::fail(MBRT_ERROR_INVALID_ARGUMENT, std::string("unknown autoLeafKind \"") + from + "\"");
}

// The build options the C struct mirrors (the fields share their names), in
// one list for both directions.
template <class From, class To>
void copyBuildOptions(const From& from, To& to) {
  to.branching = from.branching;
  to.maxLeafSize = from.maxLeafSize;
  to.sahBins = from.sahBins;
  to.traversalCost = from.traversalCost;
  to.frozenTime = from.frozenTime;
  to.memoryBudget = from.memoryBudget;
  to.maxInstanceDepth = from.maxInstanceDepth;
  to.autoFitTolerance = from.autoFitTolerance;
  copyLeafKind(from.autoLeafKind, to.autoLeafKind);
}

}  // namespace

using namespace mbrt::capi;

extern "C" {

uint32_t mbrtGetKindCount(void) {
  return guarded<uint32_t>(nullptr, 0, "mbrtGetKindCount", [] { return uint32_t(kindNames().size()); });
}

const char* mbrtGetKindName(uint32_t index) {
  return guarded<const char*>(nullptr, nullptr, "mbrtGetKindName", [&]() -> const char* {
    const auto& names = kindNames();
    if (index >= names.size())
      fail(MBRT_ERROR_INVALID_ARGUMENT, "kind index " + std::to_string(index) + " out of range (" +
                                            std::to_string(names.size()) + " kinds)");
    return names[index].c_str();
  });
}

void mbrtDefaultBuildOptions(MBRTBuildOptions* options) {
  guarded(nullptr, 0, "mbrtDefaultBuildOptions", [&] {
    require(options != nullptr, "options is NULL");
    copyBuildOptions(mbrt::BuildOptions{}, *options);
    return 0;
  });
}

MBRTAccel mbrtNewAccel(MBRTScene scene, const char* kind, const MBRTBuildOptions* options) {
  return guarded<MBRTAccel>(deviceOf(scene), nullptr, "mbrtNewAccel", [&] {
    checkScene(scene);
    require(kind != nullptr, "kind is NULL");
    auto parsed = mbrt::parseAccelKind(kind);
    if (!parsed) {
      std::string names;
      for (const auto& k : kindNames()) names += (names.empty() ? "" : ", ") + k;
      fail(MBRT_ERROR_INVALID_ARGUMENT, std::string("unknown kind \"") + kind + "\" (kinds: " + names + ")");
    }
    mbrt::BuildOptions o;
    o.kind = *parsed;
    if (options) copyBuildOptions(*options, o);
    auto a = std::make_unique<MBRTAccelT>();
    a->scene = scene;
    a->options = o;
    a->accel = mbrt::Accel::build(*scene->data->scene, o);
    a->sceneVersion = scene->data->scene->version();
    scene->liveAccels.fetch_add(1);
    addUsers(*scene->data, 1);
    return a.release();
  });
}

void mbrtReleaseAccel(MBRTAccel accel) {
  guarded(deviceOf(accel), 0, "mbrtReleaseAccel", [&] {
    checkAccel(accel);
    accel->scene->liveAccels.fetch_sub(1);
    addUsers(*accel->scene->data, -1);
    accel->tag = 0;
    delete accel;
    return 0;
  });
}

int mbrtGetAccelStats(MBRTAccel accel, MBRTAccelStats* stats) {
  return guarded(deviceOf(accel), 0, "mbrtGetAccelStats", [&] {
    const mbrt::Accel& a = traced(accel);
    require(stats != nullptr, "stats is NULL");
    mbrt::AccelStats s = a.stats();
    std::memset(stats, 0, sizeof(*stats));
    std::strncpy(stats->kind, s.kind.c_str(), sizeof(stats->kind) - 1);
    stats->primitives = s.primitives;
    stats->references = s.references;
    stats->innerNodes = s.innerNodes;
    stats->leafNodes = s.leafNodes;
    stats->maxDepth = s.maxDepth;
    stats->bytes = s.bytes;
    stats->peakBuildBytes = s.peakBuildBytes;
    stats->sahCost = s.sahCost;
    stats->buildSeconds = s.buildSeconds;
    stats->invalidRays = s.invalidRays;
    return 1;
  });
}

int mbrtIntersect1(MBRTAccel accel, const MBRTRay* ray, MBRTHit* hit) {
  return guarded(deviceOf(accel), (missHit(hit), 0), "mbrtIntersect1", [&] {
    const mbrt::Accel& a = traced(accel);
    require(ray != nullptr, "ray is NULL");
    require(hit != nullptr, "hit is NULL");
    mbrt::Hit h;
    bool found = a.intersect(toRay(*ray), h);
    toHit(h, *hit);
    return found ? 1 : 0;
  });
}

int mbrtOccluded1(MBRTAccel accel, const MBRTRay* ray) {
  return guarded(deviceOf(accel), 0, "mbrtOccluded1", [&] {
    const mbrt::Accel& a = traced(accel);
    require(ray != nullptr, "ray is NULL");
    return a.occluded(toRay(*ray)) ? 1 : 0;
  });
}

int mbrtIntersectM(MBRTAccel accel, const MBRTRay* rays, MBRTHit* hits, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtIntersectM", [&] {
    const mbrt::Accel& a = traced(accel);
    require(count == 0 || (rays && hits), "rays or hits is NULL");
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        mbrt::Hit h;
        a.intersect(toRay(rays[i]), h);
        toHit(h, hits[i]);
      }
    });
    return 1;
  });
}

int mbrtOccludedM(MBRTAccel accel, const MBRTRay* rays, uint8_t* occluded, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtOccludedM", [&] {
    const mbrt::Accel& a = traced(accel);
    require(count == 0 || (rays && occluded), "rays or occluded is NULL");
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) occluded[i] = a.occluded(toRay(rays[i])) ? 1 : 0;
    });
    return 1;
  });
}

namespace {
void checkSoA(const MBRTRaySoA* r, size_t count) {
  require(r != nullptr, "rays is NULL");
  require(count == 0 || (r->orgX && r->orgY && r->orgZ && r->dirX && r->dirY && r->dirZ),
          "rays: orgX, orgY, orgZ, dirX, dirY and dirZ must not be NULL");
}

mbrt::Ray soaRay(const MBRTRaySoA& r, size_t i) {
  mbrt::Ray ray;
  ray.org = {r.orgX[i], r.orgY[i], r.orgZ[i]};
  ray.dir = {r.dirX[i], r.dirY[i], r.dirZ[i]};
  if (r.tnear) ray.tnear = r.tnear[i];
  if (r.tfar) ray.tfar = r.tfar[i];
  if (r.time) ray.time = r.time[i];
  if (r.mask) ray.mask = r.mask[i];
  return ray;
}

void storeSoA(const mbrt::Hit& h, const MBRTHitSoA& o, size_t i) {
  o.t[i] = h.t;
  o.geomID[i] = h.geomID;
  o.primID[i] = h.primID;
  if (o.u) o.u[i] = h.u;
  if (o.v) o.v[i] = h.v;
  if (o.ngX) o.ngX[i] = h.Ng.x;
  if (o.ngY) o.ngY[i] = h.Ng.y;
  if (o.ngZ) o.ngZ[i] = h.Ng.z;
  if (o.instID) o.instID[i] = h.instID;
}
}  // namespace

int mbrtIntersectSoA(MBRTAccel accel, const MBRTRaySoA* rays, const MBRTHitSoA* hits, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtIntersectSoA", [&] {
    const mbrt::Accel& a = traced(accel);
    checkSoA(rays, count);
    require(hits != nullptr, "hits is NULL");
    require(count == 0 || (hits->t && hits->geomID && hits->primID), "hits: t, geomID and primID must not be NULL");
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        mbrt::Hit h;
        a.intersect(soaRay(*rays, i), h);
        storeSoA(h, *hits, i);
      }
    });
    return 1;
  });
}

int mbrtOccludedSoA(MBRTAccel accel, const MBRTRaySoA* rays, uint8_t* occluded, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtOccludedSoA", [&] {
    const mbrt::Accel& a = traced(accel);
    checkSoA(rays, count);
    require(count == 0 || occluded, "occluded is NULL");
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) occluded[i] = a.occluded(soaRay(*rays, i)) ? 1 : 0;
    });
    return 1;
  });
}

}  // extern "C"
