// OBJ materials: .mtl files (newmtl, Kd, map_Kd) and the vertex split that
// gives every (v, vt) pair of the faces a vertex of its own.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>

#include "mbrt/io/file_access.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/texture.h"

namespace mbrt {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

std::string_view token(std::string_view& rest) {
  rest = trim(rest);
  size_t e = 0;
  while (e < rest.size() && !isBlank(rest[e])) ++e;
  const std::string_view t = rest.substr(0, e);
  rest.remove_prefix(e);
  return t;
}

bool isNumber(std::string_view t) {
  float v;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size() && !t.empty();
}

// The file of a map_Kd statement: options (-o u v w, -s, -mm base gain,
// -blendu on, ...) skipped; backslashes read as folder separators.
std::string mapFile(std::string_view rest) {
  static const std::map<std::string_view, int> kArgs = {{"-blendu", 1}, {"-blendv", 1}, {"-boost", 1}, {"-mm", 2},
                                                        {"-o", 3},      {"-s", 3},      {"-t", 3},     {"-texres", 1},
                                                        {"-clamp", 1},  {"-bm", 1},     {"-imfchan", 1}, {"-type", 1}};
  for (;;) {
    std::string_view probe = rest;
    const std::string_view t = token(probe);
    const auto opt = kArgs.find(t);
    if (opt == kArgs.end()) break;
    rest = probe;
    for (int i = 0; i < opt->second; ++i) {
      std::string_view next = rest;
      const std::string_view arg = token(next);
      // -o, -s and -t take one to three numbers.
      if (arg.empty() || (opt->second == 3 && i > 0 && !isNumber(arg))) break;
      rest = next;
    }
  }
  std::string file(trim(rest));
  std::replace(file.begin(), file.end(), '\\', '/');
  return file;
}

}  // namespace

std::vector<ObjMaterial> readMtl(std::istream& in, std::string_view name, const std::string& folder) {
  std::vector<ObjMaterial> out;
  std::string line;
  size_t lineNo = 0;
  auto fail = [&](const std::string& what) { throw Error(std::string(name) + ":" + std::to_string(lineNo) + ": " + what); };
  while (std::getline(in, line)) {
    ++lineNo;
    std::string_view rest = line;
    if (const size_t hash = rest.find('#'); hash != std::string_view::npos) rest = rest.substr(0, hash);
    const std::string_view keyword = token(rest);
    if (keyword == "newmtl") {
      out.emplace_back();
      out.back().name = std::string(trim(rest));
      if (out.back().name.empty()) fail("'newmtl' needs a name");
    } else if (keyword == "Kd" || keyword == "map_Kd") {
      if (out.empty()) fail("'" + std::string(keyword) + "' before the first 'newmtl'");
      if (keyword == "map_Kd") {
        const std::string file = mapFile(rest);
        if (file.empty()) fail("'map_Kd' needs a file name");
        const std::filesystem::path p(file);
        out.back().diffuseMap = p.is_absolute() ? file : (std::filesystem::path(folder) / p).string();
        continue;
      }
      float c[3];
      int n = 0;
      for (std::string_view t = token(rest); !t.empty(); t = token(rest), ++n) {
        float v = 0;
        const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || p != t.data() + t.size()) fail("bad number '" + std::string(t) + "' in 'Kd'");
        if (n < 3) c[n] = v;
      }
      if (n == 1) c[1] = c[2] = c[0];  // "Kd r" is grey
      if (n != 1 && n != 3) fail("'Kd' needs 1 or 3 numbers, got " + std::to_string(n));
      for (float v : c)
        if (!(v >= 0.0f && v <= 1.0f)) fail("'Kd' values must be in [0, 1]");
      out.back().diffuse = {c[0], c[1], c[2]};
    }
  }
  if (in.bad()) fail("read error");
  return out;
}

std::vector<ObjMaterial> readMtl(const std::string& path) {
  const std::string bytes = io::readInputFile(path);
  io::MemoryInput in(bytes);
  return readMtl(in, path, std::filesystem::path(path).parent_path().string());
}

namespace {

// Every (v, vt) pair of the faces as a vertex of its own, with its texture
// coordinates (v flipped: OBJ's v = 0 is the image's bottom row).
std::vector<TexCoord> splitVertices(ObjMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> index;
  std::vector<Vec3f> positions;
  std::vector<TexCoord> uvs;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    uint32_t* corners[3] = {&mesh.triangles[t].v0, &mesh.triangles[t].v1, &mesh.triangles[t].v2};
    for (int c = 0; c < 3; ++c) {
      const uint32_t vt = mesh.triangleTexcoords[t][size_t(c)];
      const auto [it, added] = index.try_emplace({*corners[c], vt}, uint32_t(positions.size()));
      if (added) {
        positions.push_back(mesh.positions[*corners[c]]);
        uvs.push_back(vt == kInvalidId ? TexCoord{} : TexCoord{mesh.texcoords[vt][0], 1.0f - mesh.texcoords[vt][1]});
      }
      *corners[c] = it->second;
    }
  }
  mesh.positions = std::move(positions);
  return uvs;
}

}  // namespace

ObjSurface loadObjSurface(const std::string& objPath, ObjMesh& mesh) {
  ObjSurface out;
  if (mesh.triangleMaterials.empty()) return out;
  std::vector<ObjMaterial> library;
  const std::filesystem::path folder = std::filesystem::path(objPath).parent_path();
  for (const std::string& lib : mesh.materialLibraries) {
    std::string file = lib;
    std::replace(file.begin(), file.end(), '\\', '/');
    for (ObjMaterial& m : readMtl((folder / file).string())) library.push_back(std::move(m));
  }
  GeometrySurface& s = out.surface;
  std::map<std::string, int32_t> textureOf;  // map_Kd file -> texture
  for (const std::string& name : mesh.materialNames) {
    const auto found = std::find_if(library.rbegin(), library.rend(), [&](const ObjMaterial& m) { return m.name == name; });
    if (found == library.rend())
      throw Error(objPath + ": usemtl '" + name + "' is not defined by " +
                  (mesh.materialLibraries.empty() ? std::string("any mtllib (there is none)") : "its mtllib files"));
    Material m;
    m.diffuse = found->diffuse;
    if (!found->diffuseMap.empty()) {
      auto [it, added] = textureOf.try_emplace(found->diffuseMap, int32_t(out.textures.size()));
      if (added) out.textures.push_back(readTexture(found->diffuseMap));
      m.texture = it->second;
    }
    s.materials.push_back(m);
  }
  // Faces before the first usemtl get the default material.
  const uint32_t fallback = uint32_t(s.materials.size());
  s.materials.push_back(Material{});
  s.faceMaterials.resize(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    s.faceMaterials[t] = mesh.triangleMaterials[t] == kInvalidId ? fallback : mesh.triangleMaterials[t];
  if (out.textures.empty() || mesh.triangleTexcoords.empty()) {
    for (Material& m : s.materials) m.texture = -1;  // no texture coordinates to look one up with
    out.textures.clear();
    return out;
  }
  // A textured face without texture coordinates gets its material untextured.
  std::map<uint32_t, uint32_t> untextured;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t m = s.faceMaterials[t];
    if (s.materials[m].texture < 0 || mesh.triangleTexcoords[t][0] != kInvalidId) continue;
    auto [it, added] = untextured.try_emplace(m, uint32_t(s.materials.size()));
    if (added) {
      Material plain = s.materials[m];
      plain.texture = -1;
      s.materials.push_back(plain);
    }
    s.faceMaterials[t] = it->second;
  }
  s.texcoords = splitVertices(mesh);
  return out;
}

}  // namespace mbrt
