// Geometry files: Wavefront OBJ (one static mesh, or a keyframe sequence of
// files with the same faces), PLY (static), and a procedural motion for
// static meshes. glTF is in gltf.h, JSON scene files in loaders.h; the
// formats are described in docs/input.md.
#pragma once

#include <array>
#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/io/scene_description.h"
#include "mbrt/scene.h"

namespace mbrt {

// Geometry read from an OBJ file: positions and triangles (polygons fanned
// (a,b,c), (a,c,d), ...), texture coordinates and material names. Normals
// are checked (their indices must exist) but not kept.
struct ObjMesh {
  std::vector<Vec3f> positions;
  std::vector<Triangle> triangles;
  // `vt` statements (u, v as in the file: v = 0 at the image's bottom) and,
  // per triangle, the `vt` of its corners (kInvalidId where a face has
  // none); triangleTexcoords is empty when no face has any.
  std::vector<std::array<float, 2>> texcoords;
  std::vector<std::array<uint32_t, 3>> triangleTexcoords;
  // `usemtl` names in order of first use and, per triangle, the one in
  // effect (kInvalidId before the first); triangleMaterials is empty when
  // there is no usemtl.
  std::vector<std::string> materialNames;
  std::vector<uint32_t> triangleMaterials;
  std::vector<std::string> materialLibraries;  // `mtllib` files, relative to the OBJ's folder
};

// Reads `v`, `vt`, `f`/`fo`, `usemtl` and `mtllib` statements; faces with
// vertex references v, v/vt, v/vt/vn or v//vn, positive (1-based) or
// negative (relative) indices. Other statements (vn, o, g, s, l, ...) are
// skipped.
// Throws Error as "name:line: what" for bad numbers, indices out of range,
// faces with fewer than 3 vertices, and for a file without faces.
ObjMesh readObj(std::istream& in, std::string_view name);
ObjMesh readObj(const std::string& path);

// ---- OBJ materials (.mtl) ----

struct ObjMaterial {
  std::string name;
  Vec3f diffuse{0.7f, 0.7f, 0.7f};  // Kd
  std::string diffuseMap;           // map_Kd, resolved against the .mtl's folder; empty: none
};

// Reads `newmtl`, `Kd` and `map_Kd` (options such as -s or -o skipped, the
// rest of the line is the file); other statements are skipped. Throws Error
// as "name:line: what" for bad numbers, Kd outside [0,1] or a statement
// before the first newmtl.
std::vector<ObjMaterial> readMtl(std::istream& in, std::string_view name, const std::string& folder);
std::vector<ObjMaterial> readMtl(const std::string& path);

// The render-side data of geometry 0 of a scene made from `mesh`: per
// triangle its usemtl material (Kd, and map_Kd as a texture), from the
// mtllib files beside `objPath`. When a material has a texture, vertices
// are split in place so that every (v, vt) pair of the faces becomes a
// vertex with its texture coordinates (v flipped to glTF's convention).
// Without usemtl: an empty surface. Throws Error naming the file for a
// missing or bad .mtl or texture and for a usemtl no mtllib defines.
struct ObjSurface {
  GeometrySurface surface;
  std::vector<Texture> textures;
};
ObjSurface loadObjSurface(const std::string& objPath, ObjMesh& mesh);

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
