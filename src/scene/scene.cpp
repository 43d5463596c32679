// Scene construction and validation.
#include "mbrt/scene.h"

#include <algorithm>
#include <string>

namespace mbrt {
namespace {

std::string where(uint32_t geomID) { return "geometry " + std::to_string(geomID); }

// Views of owned steps, each padded by one vertex so that 16-byte loads of
// the last vertex stay inside the allocation (Embree shares such buffers).
std::vector<VertexBuffer> viewsOf(std::vector<std::vector<Vec3f>>& steps) {
  std::vector<VertexBuffer> views;
  views.reserve(steps.size());
  for (auto& s : steps) {
    const size_t n = s.size();
    s.push_back(Vec3f(0.0f));
    views.push_back({s.data(), sizeof(Vec3f), n, sizeof(Vec3f)});
  }
  return views;
}

void checkRange(TimeRange range, uint32_t geomID) {
  if (!(range.lo >= 0.0f && range.hi <= 1.0f && range.lo < range.hi))
    throw Error(where(geomID) + ": time range [" + std::to_string(range.lo) + ", " +
                std::to_string(range.hi) + ") must satisfy 0 <= lo < hi <= 1");
}

void checkVertex(Vec3f v, uint32_t geomID, uint32_t step, size_t index) {
  auto bad = [](float c) { return !std::isfinite(c) || std::fabs(c) > kMaxCoordinate; };
  if (bad(v.x) || bad(v.y) || bad(v.z))
    throw Error(where(geomID) + ": vertex " + std::to_string(index) + " of step " + std::to_string(step) +
                " is NaN, infinite or beyond 1e18 in magnitude (" + std::to_string(v.x) + ", " +
                std::to_string(v.y) + ", " + std::to_string(v.z) + ")");
}

}  // namespace

void Geometry::setSteps(uint32_t steps, TimeRange range) {
  numSteps_ = steps;
  range_ = range;
  stepScale_ = steps > 1 ? float(steps - 1) / range.size() : 0.0f;
}

// Both objects get fresh lifetimes: accels on either one expire (scene.h).
Scene::Scene(Scene&& other) : geometries_(std::move(other.geometries_)), version_(other.version_ + 1) {
  other.geometries_.clear();
  other.lifetime_ = std::make_shared<const int>(0);
  ++other.version_;
}

Scene& Scene::operator=(Scene&& other) {
  if (this == &other) return *this;
  geometries_ = std::move(other.geometries_);
  version_ = std::max(version_, other.version_) + 1;
  lifetime_ = std::make_shared<const int>(0);
  other.geometries_.clear();
  other.lifetime_ = std::make_shared<const int>(0);
  ++other.version_;
  return *this;
}

Geometry& Scene::add(GeometryType type) {
  geometries_.push_back(std::make_unique<Geometry>());
  geometries_.back()->type_ = type;
  ++version_;
  return *geometries_.back();
}

Geometry& Scene::mutableGeometry(uint32_t geomID) {
  if (geomID >= geometries_.size())
    throw Error("no " + where(geomID) + " (the scene has " + std::to_string(geometries_.size()) + ")");
  ++version_;
  return *geometries_[geomID];
}

uint32_t Scene::addTriangleMesh(std::vector<Triangle> triangles, std::vector<std::vector<Vec3f>> steps,
                                TimeRange range) {
  const uint32_t id = addTriangleMesh(std::move(triangles), viewsOf(steps), range);
  geometries_[id]->ownedSteps_ = std::move(steps);  // moving keeps the data pointers
  return id;
}

uint32_t Scene::addTriangleMesh(std::vector<Triangle> triangles, std::vector<VertexBuffer> steps,
                                TimeRange range) {
  Geometry& g = add(GeometryType::Triangles);
  g.numPrimitives_ = uint32_t(triangles.size());
  g.triangles_ = std::move(triangles);
  g.steps_ = std::move(steps);
  g.setSteps(uint32_t(g.steps_.size()), range);
  return numGeometries() - 1;
}

uint32_t Scene::addSegments(std::vector<Segment> segments, std::vector<std::vector<Vec3f>> steps,
                            std::vector<float> radii, TimeRange range) {
  const uint32_t id = addSegments(std::move(segments), viewsOf(steps), std::move(radii), range);
  geometries_[id]->ownedSteps_ = std::move(steps);
  return id;
}

uint32_t Scene::addSegments(std::vector<Segment> segments, std::vector<VertexBuffer> steps,
                            std::vector<float> radii, TimeRange range) {
  Geometry& g = add(GeometryType::Segments);
  g.numPrimitives_ = uint32_t(segments.size());
  g.segments_ = std::move(segments);
  g.steps_ = std::move(steps);
  g.radii_ = std::move(radii);
  g.setSteps(uint32_t(g.steps_.size()), range);
  return numGeometries() - 1;
}

uint32_t Scene::addInstance(std::shared_ptr<const Scene> scene, std::vector<Affine3f> transforms,
                            TimeRange range) {
  Geometry& g = add(GeometryType::Instance);
  g.numPrimitives_ = 1;
  g.child_ = std::move(scene);
  g.transforms_ = std::move(transforms);
  g.setSteps(uint32_t(g.transforms_.size()), range);
  return numGeometries() - 1;
}

uint32_t Scene::addInstance(std::shared_ptr<const Scene> scene, std::vector<SRTKey> keys, TimeRange range) {
  Geometry& g = add(GeometryType::Instance);
  g.numPrimitives_ = 1;
  g.child_ = std::move(scene);
  for (size_t k = 0; k < keys.size(); ++k) {
    Quaternion& q = keys[k].rotation;
    const float n = q.norm();
    if (q.isFinite() && n > 0 && std::isfinite(n)) q = q.normalized();
    if (k > 0 && dot(keys[k - 1].rotation, q) < 0) q = -q;  // same rotation, shorter arc
  }
  g.srtKeys_ = std::move(keys);
  g.transforms_.reserve(g.srtKeys_.size());
  for (const SRTKey& k : g.srtKeys_) g.transforms_.push_back(k.toAffine());
  g.setSteps(uint32_t(g.srtKeys_.size()), range);
  return numGeometries() - 1;
}

void Scene::setVertices(uint32_t geomID, uint32_t step, VertexBuffer buffer) {
  Geometry& g = mutableGeometry(geomID);
  if (g.type_ == GeometryType::Instance) throw Error(where(geomID) + " is an instance: it has no vertices");
  if (step >= g.steps_.size())
    throw Error(where(geomID) + " has " + std::to_string(g.steps_.size()) + " steps; no step " +
                std::to_string(step));
  g.steps_[step] = buffer;
}

void Scene::setMask(uint32_t geomID, uint32_t mask) { mutableGeometry(geomID).mask_ = mask; }

void Scene::setFilter(uint32_t geomID, IntersectFilter filter, void* userData) {
  Geometry& g = mutableGeometry(geomID);
  g.filter_ = std::move(filter);
  g.userData_ = userData;
}

size_t Scene::numPrimitives() const {
  size_t n = 0;
  for (const auto& g : geometries_) n += g->numPrimitives();
  return n;
}

uint32_t Scene::maxSegments() const {
  uint32_t s = 0;
  for (const auto& g : geometries_) s = std::max(s, g->numSteps() > 0 ? g->numSteps() - 1 : 0u);
  return s;
}

void Scene::validate(int maxInstanceDepth) const {
  std::vector<const Scene*> path;
  validate(maxInstanceDepth, path, maxInstanceDepth);
}

void Scene::validate(int depthLeft, std::vector<const Scene*>& path, int maxDepth) const {
  if (std::find(path.begin(), path.end(), this) != path.end())
    throw Error("instance cycle: a scene instances itself through " + std::to_string(path.size()) +
                " level(s)");
  if (depthLeft < 0)
    throw Error("instances nested deeper than the limit of " + std::to_string(maxDepth) + " levels");
  if (geometries_.empty())
    throw Error(path.empty() ? "scene is empty: add at least one geometry before building"
                             : "an instanced scene is empty");
  path.push_back(this);
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry& g = *geometries_[id];
    checkRange(g.range_, id);
    if (g.numSteps_ == 0)
      throw Error(where(id) + ": needs at least one time step (S >= 1), got S = 0");
    if (g.type_ == GeometryType::Instance) {
      if (!g.child_) throw Error(where(id) + ": instance of a null scene");
      for (size_t k = 0; k < g.srtKeys_.size(); ++k) {
        const SRTKey& key = g.srtKeys_[k];
        const std::string at = where(id) + ": SRT key " + std::to_string(k);
        if (!isFinite(key.scale) || !isFinite(key.translation))
          throw Error(at + " has a non-finite scale or translation");
        if (!key.rotation.isFinite() || !(key.rotation.norm() > 0.5f))
          throw Error(at + " has a zero or non-finite rotation quaternion");
        for (int a = 0; a < 3; ++a) {
          if (key.scale[a] == 0.0f) throw Error(at + " has a zero scale on axis " + "xyz"[a]);
          if (k > 0 && (key.scale[a] > 0) != (g.srtKeys_[k - 1].scale[a] > 0))
            throw Error(at + ": scale on axis " + std::string(1, "xyz"[a]) +
                        " changes sign from the previous key (it would pass through zero)");
        }
      }
      for (size_t k = 0; k < g.transforms_.size(); ++k) {
        const Affine3f& m = g.transforms_[k];
        if (!m.isFinite()) throw Error(where(id) + ": transform key " + std::to_string(k) + " is not finite");
        if (!(std::fabs(m.determinant()) > 1e-30f))
          throw Error(where(id) + ": transform key " + std::to_string(k) + " is singular");
      }
      g.child_->validate(depthLeft - 1, path, maxDepth);
      continue;
    }
    const size_t count = g.steps_[0].count;
    for (uint32_t s = 0; s < g.numSteps_; ++s) {
      const VertexBuffer& b = g.steps_[s];
      if (b.count != count)
        throw Error(where(id) + ": step " + std::to_string(s) + " has " + std::to_string(b.count) +
                    " vertices but step 0 has " + std::to_string(count) + " (all steps must match)");
      if (b.count > 0 && !b.data) throw Error(where(id) + ": step " + std::to_string(s) + " has no data");
      if (b.stride < sizeof(Vec3f))
        throw Error(where(id) + ": vertex stride " + std::to_string(b.stride) + " is below 12 bytes");
      for (size_t i = 0; i < b.count; ++i) checkVertex(b[i], id, s, i);
    }
    auto checkIndex = [&](uint32_t v, size_t prim) {
      if (v >= count)
        throw Error(where(id) + ": primitive " + std::to_string(prim) + " uses vertex " + std::to_string(v) +
                    " but there are " + std::to_string(count) + " vertices");
    };
    if (g.type_ == GeometryType::Triangles) {
      for (size_t p = 0; p < g.triangles_.size(); ++p) {
        checkIndex(g.triangles_[p].v0, p);
        checkIndex(g.triangles_[p].v1, p);
        checkIndex(g.triangles_[p].v2, p);
      }
    } else {
      if (g.radii_.size() != count)
        throw Error(where(id) + ": " + std::to_string(g.radii_.size()) + " radii for " + std::to_string(count) +
                    " vertices (one radius per vertex)");
      for (size_t i = 0; i < g.radii_.size(); ++i)
        if (!(g.radii_[i] >= 0.0f && g.radii_[i] <= kMaxCoordinate))
          throw Error(where(id) + ": radius " + std::to_string(i) + " is negative, NaN or infinite");
      for (size_t p = 0; p < g.segments_.size(); ++p) {
        checkIndex(g.segments_[p].v0, p);
        checkIndex(g.segments_[p].v1, p);
      }
    }
  }
  path.pop_back();
}

}  // namespace mbrt
