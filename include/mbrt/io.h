// Scene files. For now: one static Wavefront OBJ file (positions and faces).
#pragma once

#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt {

// Geometry read from an OBJ file: positions and triangles (polygons fanned
// (a,b,c), (a,c,d), ...). Texture coordinates and normals are checked
// (their indices must exist) but not kept.
struct ObjMesh {
  std::vector<Vec3f> positions;
  std::vector<Triangle> triangles;
};

// Reads `v` and `f`/`fo` statements with vertex references v, v/vt,
// v/vt/vn or v//vn, positive (1-based) or negative (relative) indices.
// Other statements (vt, vn, o, g, s, usemtl, mtllib, l, ...) are skipped.
// Throws Error as "name:line: what" for bad numbers, indices out of range,
// faces with fewer than 3 vertices, and for a file without faces.
ObjMesh readObj(std::istream& in, std::string_view name);
ObjMesh readObj(const std::string& path);

// A scene with the file's triangles as one static mesh (S = 1).
std::shared_ptr<Scene> loadObjScene(const std::string& path);

}  // namespace mbrt
