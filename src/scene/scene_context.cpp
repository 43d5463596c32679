#include "scene/scene_context.h"

#include <algorithm>
#include <set>

#include "scene/primitive_bounds.h"
#include "geometry/srt_bounds.h"

namespace mbrt::detail {

SceneContext::SceneContext(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
                           const StructureFactory& makeChild)
    : scene_(&scene), options_(options), budget_(&budget), makeChild_(makeChild) {
  const uint32_t n = scene.numGeometries();
  geometries_.resize(n);
  childOf_.assign(n, nullptr);
  childContextOf_.assign(n, nullptr);
  instanceKeyBoxes_.resize(n);
  stepTimes_.resize(n);
  for (uint32_t id = 0; id < n; ++id) {
    geometries_[id] = &scene.geometry(id);
    for (uint32_t k = 0; k < geometries_[id]->numSteps(); ++k)
      stepTimes_[id].push_back(geometries_[id]->stepTime(k));
    numPrimitives_ += geometries_[id]->numPrimitives();
    if (geometries_[id]->type() != GeometryType::Instance) continue;
    const Scene* childScene = geometries_[id]->instancedScene();
    auto it = children_.find(childScene);
    if (it == children_.end()) {
      if (!makeChild) throw Error("scene context: a scene with instances needs a structure factory");
      Child child;
      child.context = std::make_unique<SceneContext>(*childScene, options, budget, makeChild);
      child.context->computeGeometryKeyBoxes();
      child.structure = makeChild(*child.context);
      it = children_.emplace(childScene, std::move(child)).first;
    }
    childOf_[id] = it->second.structure.get();
    childContextOf_[id] = it->second.context.get();
    instanceMotions_.resize(n);
    instanceMotions_[id] = InstanceMotion(*geometries_[id]);
  }
  computeInstanceKeyBoxes();
}

bool SceneContext::refitChildren() {
  for (auto& [scene, child] : children_) {
    if (!child.context->refitChildren() || !child.structure->refit()) return false;
    child.context->computeGeometryKeyBoxes();
  }
  computeInstanceKeyBoxes();
  return true;
}

SceneContext::~SceneContext() = default;

std::vector<PrimRef> SceneContext::primitives() const {
  std::vector<PrimRef> refs;
  refs.reserve(numPrimitives_);
  for (uint32_t g = 0; g < geometries_.size(); ++g)
    for (uint32_t p = 0; p < geometries_[g]->numPrimitives(); ++p) refs.push_back({g, p});
  return refs;
}

size_t SceneContext::totalPrimitives() const {
  size_t n = numPrimitives_;
  for (const auto& [scene, child] : children_) n += child.context->totalPrimitives();
  return n;
}

void SceneContext::addChildStats(AccelStats& stats) const {
  for (const auto& [scene, child] : children_) {
    AccelStats s;
    child.structure->fillStats(s);
    child.context->addChildStats(s);
    stats.bytes += s.bytes;
    stats.leafBlockBytes += s.leafBlockBytes;
    stats.references += s.references;
    stats.innerNodes += s.innerNodes;
    stats.leafNodes += s.leafNodes;
  }
}

Box3f SceneContext::boundsOver(TimeRange range) const {
  Box3f box;
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry& g = *geometries_[id];
    const TimeRange r = g.timeRange();
    if (r.lo > range.hi || range.lo > r.hi) continue;
    const float a = std::max(range.lo, r.lo), b = std::min(range.hi, r.hi);
    const std::vector<Box3f>& keys = geometryKeyBoxes_[id];
    auto at = [&](float t) {
      uint32_t s;
      float f;
      g.segmentAt(t, s, f);
      return g.numSteps() == 1 ? keys[0] : lerp(keys[s], keys[s + 1], f);
    };
    box.extend(at(a));
    box.extend(at(b));
    for (uint32_t k = 0; k < g.numSteps(); ++k)
      if (g.stepTime(k) > a && g.stepTime(k) < b) box.extend(keys[k]);
  }
  return box;
}

void SceneContext::setInstanceKeyBoxes(uint32_t geomID, std::vector<Box3f> boxes) {
  const Geometry& g = *geometries_[geomID];
  if (g.type() != GeometryType::Instance || boxes.size() != g.numSteps())
    throw Error("scene context: instance key boxes need an instance and one box per key");
  instanceKeyBoxes_[geomID] = std::move(boxes);
}

void SceneContext::computeGeometryKeyBoxes() {
  geometryKeyBoxes_.resize(geometries_.size());
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry& g = *geometries_[id];
    std::vector<Box3f>& keys = geometryKeyBoxes_[id];
    keys.assign(g.numSteps(), Box3f());
    for (uint32_t k = 0; k < g.numSteps(); ++k)
      for (uint32_t p = 0; p < g.numPrimitives(); ++p) keys[k].extend(keyBox({id, p}, k));
    // A key with nothing in it would poison interpolation; use the union.
    Box3f all;
    for (const Box3f& b : keys) all.extend(b);
    for (Box3f& b : keys)
      if (b.empty()) b = all;
  }
}

// Instance bounds (MSBVH paper §3.3): between keys j and j+1 the matrix is
// the element-wise lerp of M_j and M_j+1, so M(t)x is a convex combination of
// M_j x and M_j+1 x, and x lies in the child's bounds over that interval:
// the corners of that box under both matrices bound the instance there.
// SRT keys move points on curves; srtSegmentBounds bounds them (srt_bounds.h).
void SceneContext::computeInstanceKeyBoxes() {
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry& g = *geometries_[id];
    if (g.type() != GeometryType::Instance) continue;
    const SceneContext& child = *childContextOf_[id];
    const auto keys = g.transforms();
    std::vector<Box3f>& out = instanceKeyBoxes_[id];
    out.assign(keys.size(), Box3f());
    if (keys.size() == 1) {
      out[0] = transformBox(keys[0], child.boundsOver(g.timeRange()));
    } else if (g.hasSRTKeys()) {
      const auto srt = g.srtKeys();
      for (uint32_t j = 0; j + 1 < keys.size(); ++j) {
        const Box3f c = child.boundsOver({g.stepTime(j), g.stepTime(j + 1)});
        const Box3f seg = srtSegmentBounds(srt[j], srt[j + 1], c);
        out[j].extend(seg);
        out[j + 1].extend(seg);
      }
    } else {
      // Matrix keys interpolate element-wise: at a time f into segment j a
      // point x of the child is at lerp(A_j x, A_j+1 x, f), inside the lerp
      // of the boxes of the child's bounds under A_j and under A_j+1. Each
      // key's box covers the child's bounds over both its segments.
      for (uint32_t j = 0; j + 1 < keys.size(); ++j) {
        const Box3f c = child.boundsOver({g.stepTime(j), g.stepTime(j + 1)});
        out[j].extend(transformBox(keys[j], c));
        out[j + 1].extend(transformBox(keys[j + 1], c));
      }
    }
    Box3f all;
    for (const Box3f& b : out) all.extend(b);
    for (Box3f& b : out)
      if (b.empty()) b = all;
  }
}

}  // namespace mbrt::detail
