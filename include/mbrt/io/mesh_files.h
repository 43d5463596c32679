// Geometry files: Wavefront OBJ (one static mesh, or a keyframe sequence of
// files with the same faces), PLY (static), and a procedural motion for
// static meshes. glTF is in gltf.h, JSON scene files in loaders.h; the
// formats are described in docs/input.md.
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

// ---- OBJ keyframe sequences (the Utah animation repository's format) ----

// The files of a sequence: `spec` is a folder (every *.obj in it) or a glob
// pattern (e.g. "frames/doll_*.obj"), sorted by name. Throws Error when
// nothing matches.
std::vector<std::string> listObjSequence(const std::string& spec);
// True when `spec` looks like a sequence: an existing folder or a pattern
// with * ? or [.
bool isObjSequenceSpec(const std::string& spec);

// One mesh (geometry id 0) with one key per file, key i of K at time
// i/(K-1) (K = 1 gives a static mesh). Every file must have the same vertex
// count and the same faces as the first; the Error names the file that
// differs and the first difference.
std::shared_ptr<Scene> loadObjSequence(const std::vector<std::string>& files);

// ---- PLY ----

// Reads vertex x/y/z and face vertex_indices (or vertex_index) of an ascii
// or binary little-endian PLY file; other elements and properties are
// skipped. Polygons are fanned like OBJ faces. Errors name the file and,
// for ascii, the line.
ObjMesh readPly(const std::string& path);
std::shared_ptr<Scene> loadPlyScene(const std::string& path);

// ---- procedural motion for static meshes (experiments) ----

// Over the shutter [0,1] the mesh moves by `translate` and turns by
// `rotateDegrees` about `axis` through its bounding box's centre, sampled
// into `steps` equidistant vertex steps (at least 2 when there is motion).
struct ProceduralMotion {
  Vec3f translate{0, 0, 0};
  Vec3f axis{0, 1, 0};
  float rotateDegrees = 0.0f;
  uint32_t steps = 2;
  bool any() const { return rotateDegrees != 0.0f || !(translate == Vec3f(0.0f)); }
};
// The most steps a procedural motion may have (each is a copy of the mesh).
constexpr uint32_t kMaxProceduralMotionSteps = 1024;
// Parses "translate:X,Y,Z", "rotate:DEG" or "rotate:DEG:AX,AY,AZ", joined
// with ';' (e.g. "translate:0.5,0,0;rotate:90"). Throws Error when bad,
// and when the rotation would need more than kMaxProceduralMotionSteps steps
// (one per 10 degrees: at most 10230 degrees).
ProceduralMotion parseProceduralMotion(const std::string& spec);
// A scene with the mesh as one triangle mesh moving as `motion` says.
std::shared_ptr<Scene> makeMovingMeshScene(ObjMesh mesh, const ProceduralMotion& motion);

}  // namespace mbrt
