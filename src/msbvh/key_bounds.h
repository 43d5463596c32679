// Per-key bounds of MSBVH references (Grünschloß et al. 2011, §3.1, §6.3).
//
// A structure has n + 1 key times t_i = i/n, n a power of two. The steps
// ask for the smallest one with at least (S-1)/|range| segments for every
// geometry, so that mesh steps fall on keys wherever they can (the paper
// resamples children with fewer segments; powers of two make them
// coincide; at most kMaxKeySegments); fitKeySegments then keeps fewer where
// the motion is linear enough that they bound as tightly.
//
// A reference's *piece* is its primitive clipped to the reference's region
// (spatial_split.h) at the build time t = 0.5: a convex polygon in the
// barycentric coordinates of the triangle, or a parameter interval [s0, s1]
// of a segment's axis. The same barycentrics / parameters at time t give the
// piece at time t: the point with barycentrics b moves as sum b_j v_j(t).
// Since the regions of a primitive's references tile space, every point of
// the primitive at 0.5 is in some piece, and so is its image at time t: the
// union of the pieces is the primitive at every time. (Segments: every
// point of the round segment is within the largest radius of an axis point
// c(s), and c(s) lies in some region, so padding the piece's axis by the
// radius covers it. Eq. 1 of the paper — interpolating the clipped box by
// the motion of the whole box — is not used: it fails when the primitive
// turns.) Instances are never clipped: their pieces are the whole instance.
//
// Between keys: the piece's vertices move linearly between the mesh's step
// times; where a step time falls strictly between two keys (step counts that
// are not a power of two, partial time ranges), both key boxes are pushed
// out by the largest violation at that step time (as linearBounds does):
// the interpolation of the keys then contains the piece at every time of the
// interval, because between consecutive break points both are linear.
#pragma once

#include <vector>

#include "bvh/heuristics/spatial_split.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

constexpr uint32_t kMaxKeySegments = 32;
constexpr float kBuildTime = 0.5f;

uint32_t chooseKeySegments(const SceneContext& ctx);

// Fewer keys where they bound as tightly: any n is conservative (the breaks
// below), so where the motion is linear in time over several steps (a
// translation sampled at 6 steps) keys at every step only cost memory and
// cache. Returns the smallest power of two n <= maxSegments whose
// interpolated bounds of a sample of primitives have a mean area within
// kKeyAreaSlack of those with maxSegments; maxSegments where none is.
inline constexpr double kKeyAreaSlack = 0.01;
uint32_t fitKeySegments(const SceneContext& ctx, uint32_t maxSegments);

class KeyBounder final : public RefClipper {
 public:
  KeyBounder(const SceneContext& ctx, uint32_t segments);

  uint32_t segments() const { return n_; }
  // Bounds of the primitive at the build time (t = 0.5, or its nearest
  // alive time).
  Box3f buildBox(PrimRef prim) const;
  // RefClipper: bounds of the primitive's part inside `box` at the build time.
  Box3f clip(PrimRef prim, const Box3f& box) const override;
  // RefClipper: triangles are split plane by plane (geometry/clip.h
  // chopTriangle); other primitives clip each slab.
  void chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes, Box3f* pieces) const override;
  // The n+1 key boxes of the piece of `prim` in `region` (widened); false
  // when the piece is empty (out untouched).
  bool pieceKeys(PrimRef prim, const Box3f& region, Box3f* out) const;

 private:
  struct Break {
    uint32_t interval;  // between keys i and i+1
    float time, fraction;
  };
  template <class At>
  void keysOf(PrimRef prim, Box3f* out, const At& at) const;
  const SceneContext& ctx_;
  uint32_t n_;
  std::vector<std::vector<Break>> breaks_;  // per geometry: step times strictly between keys
};

// The clipper of the SBVH build: KeyBounder's clip and chop with the
// triangles' vertices at the build time evaluated once (the spatial
// binning chops every reference it meets on three axes, at every node; each
// vertexAt interpolates two steps). Same bounds, bit for bit. Lives for the
// build only: a refit moves the vertices.
class BuildTimeClipper final : public RefClipper {
 public:
  BuildTimeClipper(const SceneContext& ctx, const KeyBounder& bounder);
  size_t bytes() const { return bytes_; }
  Box3f clip(PrimRef prim, const Box3f& box) const override;
  void chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes, Box3f* pieces) const override;

 private:
  // The triangle's vertices at the build time; false for other primitives.
  bool corners(PrimRef prim, Vec3f (&v)[3]) const;

  const SceneContext& ctx_;
  const KeyBounder& bounder_;
  std::vector<std::vector<Vec3f>> vertices_;  // per triangle geometry, at kBuildTime
  size_t bytes_ = 0;
};

}  // namespace mbrt::detail
