// Scene bounds from mbrt's scene model (bounds.h).
#include "bounds.h"

#include <unordered_map>
#include <vector>

#include "device.h"
#include "errors.h"
#include "scene.h"

namespace mbrt::embree_api {
namespace {

// Linear bounds over [0, 1] containing box k at time t[k] (Embree's fit).
LBounds fit(const std::vector<Box3f>& boxes, const std::vector<float>& times) {
  if (boxes.size() == 1 || times.front() == times.back()) {
    Box3f all;
    for (const Box3f& b : boxes) all.extend(b);
    return LBounds(all);
  }
  const float t0 = times.front(), t1 = times.back();
  const Box3f& a = boxes.front();
  const Box3f& b = boxes.back();
  auto line = [&](float t) { return lerp(a, b, (t - t0) / (t1 - t0)); };
  Vec3f dlo(0.0f), dhi(0.0f);
  for (size_t k = 1; k + 1 < boxes.size(); ++k) {
    const Box3f l = line(times[k]);
    dlo = min(dlo, boxes[k].lower - l.lower);
    dhi = max(dhi, boxes[k].upper - l.upper);
  }
  Box3f b0 = line(0.0f), b1 = line(1.0f);
  b0.lower += dlo;
  b1.lower += dlo;
  b0.upper += dhi;
  b1.upper += dhi;
  return {b0, b1};
}

Box3f transformed(const Box3f& b, const Affine3f& m) {
  Box3f out;
  for (int c = 0; c < 8; ++c)
    out.extend(m.xfmPoint({c & 1 ? b.upper.x : b.lower.x, c & 2 ? b.upper.y : b.lower.y,
                           c & 4 ? b.upper.z : b.lower.z}));
  return out;
}

class BoundsMaker {
 public:
  SceneBounds of(const mbrt::Scene& scene) {
    auto it = done_.find(&scene);
    if (it != done_.end()) return it->second;
    SceneBounds s;
    for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
      const mbrt::Geometry& g = scene.geometry(id);
      std::vector<Box3f> boxes(g.numSteps());
      std::vector<float> times(g.numSteps());
      for (uint32_t k = 0; k < g.numSteps(); ++k) times[k] = g.stepTime(k);
      if (g.type() == GeometryType::Instance) {
        const Box3f child = of(*g.instancedScene()).box;
        if (child.empty()) continue;
        for (uint32_t k = 0; k < g.numSteps(); ++k) boxes[k] = transformed(child, g.transforms()[k]);
      } else {
        for (const Triangle& t : g.triangles())
          for (uint32_t k = 0; k < g.numSteps(); ++k) {
            const VertexBuffer& v = g.vertices(k);
            boxes[k].extend(v[t.v0]);
            boxes[k].extend(v[t.v1]);
            boxes[k].extend(v[t.v2]);
          }
      }
      for (const Box3f& b : boxes) s.box.extend(b);
      const LBounds l = fit(boxes, times);
      s.linear.b0.extend(l.b0);
      s.linear.b1.extend(l.b1);
    }
    done_[&scene] = s;
    return s;
  }

 private:
  std::unordered_map<const mbrt::Scene*, SceneBounds> done_;
};

void store(const Box3f& b, RTCBounds& out) {
  out = RTCBounds{b.lower.x, b.lower.y, b.lower.z, 0.0f, b.upper.x, b.upper.y, b.upper.z, 0.0f};
}

const Snapshot& committedSnapshot(RTCScene scene) {
  Scene& s = require<Scene>(scene, "RTCScene");
  if (s.modifiedSinceCommit()) fail(RTC_ERROR_INVALID_OPERATION, "scene not committed");
  return *s.committed()->snapshot;
}

}  // namespace

SceneBounds boundsOf(const mbrt::Scene& scene) { return BoundsMaker().of(scene); }

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

RTC_API void rtcGetSceneBounds(RTCScene scene, RTCBounds* bounds) {
  guarded("rtcGetSceneBounds", scene, [&] {
    const Snapshot& s = committedSnapshot(scene);
    if (!bounds) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid destination pointer");
    store(s.bounds, *bounds);
  });
}

RTC_API void rtcGetSceneLinearBounds(RTCScene scene, RTCLinearBounds* bounds) {
  guarded("rtcGetSceneLinearBounds", scene, [&] {
    if (!bounds) fail(RTC_ERROR_INVALID_OPERATION, "invalid destination pointer");
    const Snapshot& s = committedSnapshot(scene);
    store(s.linearBounds.b0, bounds->bounds0);
    store(s.linearBounds.b1, bounds->bounds1);
  });
}
