// Clipping of primitives against axis-aligned boxes (MSBVH paper §3.1):
// triangles with Sutherland-Hodgman, keeping each polygon vertex's
// barycentric coordinates in the unclipped triangle so that the same piece
// can be re-evaluated with the triangle's vertices at any other time; line
// segments as a parameter interval [s0, s1] of their axis.
#pragma once

#include <span>

#include "mbrt/math.h"

namespace mbrt::detail {

// A convex polygon that is a piece of a triangle (v0, v1, v2): each vertex
// has its position (where it was clipped) and its barycentric weights
// (w0, w1, w2) with position = w0*v0 + w1*v1 + w2*v2.
struct ClippedPolygon {
  static constexpr int kMaxVertices = 9;  // 3 + one per clipping plane
  Vec3f pos[kMaxVertices];
  Vec3f bary[kMaxVertices];
  int count = 0;

  Box3f bounds() const {
    Box3f b;
    for (int i = 0; i < count; ++i) b.extend(pos[i]);
    return b;
  }
};

// The part of triangle (v0, v1, v2) inside `box` (closed). Box planes may be
// infinite (no clipping on that side). Empty polygon: count == 0.
ClippedPolygon clipTriangle(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box);

// clipTriangle(v0, v1, v2, box).bounds(), without the barycentrics.
Box3f clipTriangleBounds(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box);

// Bounds of the part of triangle (v0, v1, v2) inside `box` between
// consecutive planes x[axis] = planes[k] (increasing): pieces[0] below
// planes[0], ..., pieces[planes.size()] above the last; conservative, not
// tight. Each plane splits the triangle's bounds by its vertices and edge
// crossings on either side, intersected with `box` narrowed by the planes
// before (SBVH §4.2 chopping, as Embree's spatial binning splits
// references): three edges per plane, no polygon.
void chopTriangle(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box, int axis, std::span<const float> planes,
                  Box3f* pieces);

// Position of barycentric weights in another pose of the triangle.
inline Vec3f evalBary(Vec3f bary, Vec3f v0, Vec3f v1, Vec3f v2) { return v0 * bary.x + v1 * bary.y + v2 * bary.z; }

// The parameter interval [s0, s1] of the line segment a + s*(b - a),
// s in [0, 1], inside `box` (closed, planes may be infinite) by slab
// clipping (Liang-Barsky). False when the segment misses the box.
bool clipSegment(Vec3f a, Vec3f b, const Box3f& box, float& s0, float& s1);

// The box grown on every side by `margin` (infinite planes stay infinite).
inline Box3f grow(const Box3f& box, Vec3f margin) { return {box.lower - margin, box.upper + margin}; }

}  // namespace mbrt::detail
