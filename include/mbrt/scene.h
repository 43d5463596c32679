// The scene model: moving triangle meshes, moving round line segments and
// instances of other scenes with per-step transforms.
//
// Motion model. A geometry has S >= 1 equidistant time steps over its own
// time range [lo,hi) inside [0,1] (a range ending at 1 contains 1). Step k
// sits at time lo + k*(hi-lo)/(S-1); between steps, positions (or instance
// matrices, element-wise) are linearly interpolated; instances may instead
// carry SRT keys (scale and translation lerped, rotation slerped). Outside its range a
// geometry does not exist: rays at such times pass through it.
//
// Vertex data. Each step is a VertexBuffer: a pointer, a stride and a count.
// Buffers may be owned by the scene (the add* overloads that take vectors) or
// shared with the caller (the overloads that take VertexBuffer views). Shared
// memory must stay valid and unchanged while any Accel built from the scene
// is used; after changing it, call Accel::rebuild() (or Accel::refit()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbrt/error.h"
#include "mbrt/math.h"
#include "mbrt/quaternion.h"
#include "mbrt/ray.h"

namespace mbrt {

// Coordinates beyond this magnitude are refused: products of two of them must
// stay finite in float.
constexpr float kMaxCoordinate = 1e18f;

enum class GeometryType : uint8_t { Triangles, Segments, Instance };

struct Triangle {
  uint32_t v0, v1, v2;
};

struct Segment {
  uint32_t v0, v1;
};

// A strided view of float xyz positions. A buffer with stride >= 16 is
// taken to span count * stride bytes; `padding` says how many more bytes
// after the last vertex's 12 may be read. Structures that load 16 bytes per
// vertex (Embree) share buffers where stride >= 16 or padding >= 4 and copy
// the others. The leaves that gather vertices at the ray's time read each
// with one 16-byte load where padding >= 4, else with 12-byte loads: give
// the padding a buffer has. Buffers the scene owns are padded.
struct VertexBuffer {
  const void* data = nullptr;
  size_t stride = 3 * sizeof(float);  // bytes between consecutive vertices
  size_t count = 0;
  size_t padding = 0;  // readable bytes after the last vertex's xyz

  Vec3f operator[](size_t i) const {
    Vec3f v;
    std::memcpy(&v, static_cast<const char*>(data) + i * stride, sizeof(Vec3f));
    return v;
  }
};

// Arguments of an intersection filter. Returning false rejects the
// candidate hit and traversal goes on (alpha testing, transparent shadows).
struct FilterArgs {
  const Ray& ray;        // the ray in the geometry's space
  const Hit& candidate;  // the hit that would be accepted
  void* userData;
};
using IntersectFilter = std::function<bool(const FilterArgs&)>;

class Scene;

// One geometry of a scene. Read-only to users; created by Scene::add*.
class Geometry {
 public:
  GeometryType type() const { return type_; }
  uint32_t numPrimitives() const { return numPrimitives_; }
  uint32_t numSteps() const { return numSteps_; }  // S: vertex steps or transform keys
  TimeRange timeRange() const { return range_; }
  uint32_t mask() const { return mask_; }
  bool hasFilter() const { return static_cast<bool>(filter_); }
  const IntersectFilter& filter() const { return filter_; }
  void* userData() const { return userData_; }

  // Triangles / segments.
  std::span<const Triangle> triangles() const { return triangles_; }
  std::span<const Segment> segments() const { return segments_; }
  const VertexBuffer& vertices(uint32_t step) const { return steps_[step]; }
  std::span<const float> radii() const { return radii_; }

  // Instances.
  const Scene* instancedScene() const { return child_.get(); }
  const std::shared_ptr<const Scene>& instancedSceneShared() const { return child_; }
  // The key matrices (for SRT instances: each key composed as T*R*S).
  std::span<const Affine3f> transforms() const { return transforms_; }
  // SRT instances: the keys as given (quaternions normalized, and each on
  // the same hemisphere as the previous one so that slerp takes the
  // shorter arc); empty for matrix keys.
  bool hasSRTKeys() const { return !srtKeys_.empty(); }
  std::span<const SRTKey> srtKeys() const { return srtKeys_; }

  // Maps a time inside the range to a step segment and a fraction in [0,1].
  void segmentAt(float time, uint32_t& segment, float& fraction) const {
    if (numSteps_ == 1) {
      segment = 0;
      fraction = 0.0f;
      return;
    }
    float local = (time - range_.lo) * stepScale_;
    float s = std::floor(local);
    s = std::clamp(s, 0.0f, float(numSteps_ - 2));
    segment = uint32_t(s);
    fraction = std::clamp(local - s, 0.0f, 1.0f);
  }
  // Time of step k.
  float stepTime(uint32_t k) const {
    return numSteps_ == 1 ? range_.lo : range_.lo + range_.size() * float(k) / float(numSteps_ - 1);
  }

  Vec3f vertexAtStep(uint32_t step, uint32_t index) const { return steps_[step][index]; }
  Vec3f vertexAt(float time, uint32_t index) const {
    uint32_t s;
    float f;
    segmentAt(time, s, f);
    return numSteps_ == 1 ? steps_[0][index] : lerp(steps_[s][index], steps_[s + 1][index], f);
  }
  Affine3f transformAt(float time) const {
    uint32_t s;
    float f;
    segmentAt(time, s, f);
    if (numSteps_ == 1) return transforms_[0];
    if (!srtKeys_.empty()) return lerp(srtKeys_[s], srtKeys_[s + 1], f).toAffine();
    return lerp(transforms_[s], transforms_[s + 1], f);
  }

 private:
  friend class Scene;
  void setSteps(uint32_t steps, TimeRange range);

  GeometryType type_ = GeometryType::Triangles;
  uint32_t numPrimitives_ = 0;
  uint32_t numSteps_ = 0;
  TimeRange range_;
  float stepScale_ = 0.0f;
  uint32_t mask_ = 0xFFFFFFFFu;
  IntersectFilter filter_;
  void* userData_ = nullptr;

  std::vector<Triangle> triangles_;
  std::vector<Segment> segments_;
  std::vector<VertexBuffer> steps_;
  std::vector<std::vector<Vec3f>> ownedSteps_;
  std::vector<float> radii_;

  std::shared_ptr<const Scene> child_;
  std::vector<Affine3f> transforms_;
  std::vector<SRTKey> srtKeys_;
};

class Scene {
 public:
  Scene() = default;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  // Moving a scene hands its geometries to the new object; accels built on
  // either object before the move refuse every call afterwards (see
  // lifetime()), as they do after the scene is destroyed.
  Scene(Scene&& other);
  Scene& operator=(Scene&& other);

  // Triangle mesh with S = steps.size() vertex steps, owned by the scene.
  // Returns the geometry id (ids count up from 0 in the order of adding).
  uint32_t addTriangleMesh(std::vector<Triangle> triangles, std::vector<std::vector<Vec3f>> steps,
                           TimeRange range = {});
  // Same, with caller-owned vertex memory (see the lifetime rules above).
  uint32_t addTriangleMesh(std::vector<Triangle> triangles, std::vector<VertexBuffer> steps,
                           TimeRange range = {});

  // Round linear segments (Embree's round linear curves): the union of the
  // spheres at both end points and the cone tangent to both. One radius per
  // vertex, the same at every step.
  uint32_t addSegments(std::vector<Segment> segments, std::vector<std::vector<Vec3f>> steps,
                       std::vector<float> radii, TimeRange range = {});
  uint32_t addSegments(std::vector<Segment> segments, std::vector<VertexBuffer> steps,
                       std::vector<float> radii, TimeRange range = {});

  // An instance of another scene with S = transforms.size() keys
  // (object-to-world), interpolated element-wise between keys.
  uint32_t addInstance(std::shared_ptr<const Scene> scene, std::vector<Affine3f> transforms,
                       TimeRange range = {});
  // An instance with S = keys.size() SRT keys: between keys, scale and
  // translation are interpolated linearly, the rotation by slerp along the
  // shorter arc, composed as T*R*S (see quaternion.h). Quaternions are
  // normalized here; validate() refuses non-finite keys, a zero or
  // non-finite quaternion, a zero scale component and a scale component
  // that changes sign between keys (it would pass through zero).
  uint32_t addInstance(std::shared_ptr<const Scene> scene, std::vector<SRTKey> keys, TimeRange range = {});

  // Replaces the vertex buffer of one step (e.g. for the next frame).
  void setVertices(uint32_t geomID, uint32_t step, VertexBuffer buffer);
  void setMask(uint32_t geomID, uint32_t mask);
  void setFilter(uint32_t geomID, IntersectFilter filter, void* userData = nullptr);

  uint32_t numGeometries() const { return uint32_t(geometries_.size()); }
  const Geometry& geometry(uint32_t geomID) const { return *geometries_.at(geomID); }
  size_t numPrimitives() const;  // triangles + segments + instances at this level

  // Largest S - 1 over the geometries (0 for a static scene).
  uint32_t maxSegments() const;

  // Throws Error with a clear message when the scene cannot be built: empty
  // scene, S = 0, inconsistent step sizes, index out of range, NaN/Inf or
  // huge coordinates, bad radii, bad time ranges, singular or non-finite
  // transforms, instance cycles or nesting deeper than maxInstanceDepth.
  void validate(int maxInstanceDepth = 8) const;

  // Bumped by every change to the scene (geometry added, data replaced), so
  // that a caller can tell whether what it derived from the scene is stale.
  uint64_t version() const { return version_; }

  // Expires when this object is destroyed, moved from or assigned to: what
  // an Accel checks before using the scene it was built on.
  std::weak_ptr<const void> lifetime() const { return lifetime_; }

 private:
  Geometry& add(GeometryType type);
  Geometry& mutableGeometry(uint32_t geomID);
  void validate(int depthLeft, std::vector<const Scene*>& path, int maxDepth) const;

  std::vector<std::unique_ptr<Geometry>> geometries_;
  uint64_t version_ = 0;
  std::shared_ptr<const int> lifetime_ = std::make_shared<const int>(0);
};

// Bounds of a scene over the whole shutter: every vertex at every step
// (segments padded by their radii) and, for instances, the corners of their
// scene's bounds under every key. For camera framing and ray offsets; not
// conservative between rotating instance keys, so not for traversal.
Box3f sceneBounds(const Scene& scene);

}  // namespace mbrt
