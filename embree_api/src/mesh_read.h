// A triangle or quad mesh of the Embree API read into what
// mbrt::Scene::addTriangleMesh takes. Quads become two triangles each,
// (v0, v1, v3) and (v2, v3, v1), Embree's own split. Primitives Embree
// would leave out of its BVH are left out (an index beyond the vertex
// count; a vertex that is NaN, infinite or beyond 1e18 at any step, the
// largest coordinate mbrt takes), and the primitive map says which
// Embree primitive each mbrt triangle is.
#pragma once

#include <string>
#include <vector>

#include "geometry.h"
#include "mbrt/scene.h"
#include "snapshot.h"

namespace mbrt::embree_api {

struct MeshData {
  std::vector<Triangle> triangles;
  PrimitiveMap prims;
  // The vertex steps: views of the caller's buffers, or (when a vertex is
  // invalid) copies with the invalid vertices zeroed.
  std::vector<VertexBuffer> views;
  std::vector<std::vector<Vec3f>> copies;
  TimeRange range;
  std::vector<Ref<Buffer>> buffers;
};

// False, with the reason in `error`, when the mesh cannot be read (no
// vertex buffer for a step, steps of different sizes).
bool readMesh(const Geometry& g, MeshData& out, std::string& error);

// The vertex steps of g as views of its buffers (for a refit).
std::vector<VertexBuffer> vertexViews(const Geometry& g);

}  // namespace mbrt::embree_api
