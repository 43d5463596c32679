// Wavefront OBJ: positions and polygon faces of one static mesh.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>

#include "mbrt/io/file_access.h"
#include "mbrt/io/mesh_files.h"

namespace mbrt {
namespace {

class ObjParser {
 public:
  explicit ObjParser(std::string_view name) : name_(name) {}

  ObjMesh run(std::istream& in) {
    std::string line;
    while (std::getline(in, line)) {
      ++lineNo_;
      parseLine(line);
    }
    if (in.bad()) fail("read error");
    if (mesh_.triangles.empty()) throw Error(std::string(name_) + ": no faces (no 'f' statement with 3 or more vertices)");
    if (!anyFaceTexcoords_) mesh_.triangleTexcoords.clear();
    if (mesh_.materialNames.empty()) mesh_.triangleMaterials.clear();
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(std::string(name_) + ":" + std::to_string(lineNo_) + ": " + what);
  }

  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

  // Next whitespace-separated token of `rest`, or empty at the end.
  static std::string_view nextToken(std::string_view& rest) {
    size_t b = 0;
    while (b < rest.size() && isSpace(rest[b])) ++b;
    size_t e = b;
    while (e < rest.size() && !isSpace(rest[e])) ++e;
    std::string_view tok = rest.substr(b, e - b);
    rest.remove_prefix(e);
    return tok;
  }

  float parseFloat(std::string_view tok, const char* what) const {
    float v = 0.0f;
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    if (first != last && *first == '+') ++first;  // from_chars refuses a leading '+'
    auto [ptr, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && ptr == last && !std::isfinite(v)))
      fail(std::string("number out of range '") + std::string(tok) + "' in " + what);
    if (ec != std::errc() || ptr != last || first == last)
      fail(std::string("bad number '") + std::string(tok) + "' in " + what);
    if (std::fabs(v) > kMaxCoordinate) fail(std::string("coordinate too large '") + std::string(tok) + "' in " + what);
    return v;
  }

  // Resolves a 1-based or negative index against `count` elements so far.
  uint32_t parseIndex(std::string_view tok, size_t count, const char* what) const {
    long long v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size() || tok.empty())
      fail(std::string("bad ") + what + " index '" + std::string(tok) + "'");
    long long resolved = v > 0 ? v - 1 : (v < 0 ? (long long)count + v : -1);
    if (v == 0 || resolved < 0 || resolved >= (long long)count)
      fail(std::string(what) + " index " + std::string(tok) + " out of range (" + std::to_string(count) + " " +
           what + "s defined so far)");
    return uint32_t(resolved);
  }

  struct FaceVertex {
    uint32_t position, texcoord = kInvalidId;
  };

  FaceVertex parseFaceVertex(std::string_view tok) const {
    // v | v/vt | v/vt/vn | v//vn
    size_t s1 = tok.find('/');
    std::string_view v = tok.substr(0, s1);
    FaceVertex index{parseIndex(v, mesh_.positions.size(), "vertex")};
    if (s1 == std::string_view::npos) return index;
    std::string_view rest = tok.substr(s1 + 1);
    size_t s2 = rest.find('/');
    std::string_view vt = rest.substr(0, s2);
    if (!vt.empty()) index.texcoord = parseIndex(vt, mesh_.texcoords.size(), "texture coordinate");
    else if (s2 == std::string_view::npos) fail("bad face vertex '" + std::string(tok) + "'");
    if (s2 != std::string_view::npos) {
      std::string_view vn = rest.substr(s2 + 1);
      if (vn.empty() || vn.find('/') != std::string_view::npos) fail("bad face vertex '" + std::string(tok) + "'");
      parseIndex(vn, numNormals_, "normal");
    }
    return index;
  }

  void parseLine(std::string_view line) {
    if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::string_view rest = line;
    std::string_view keyword = nextToken(rest);
    if (keyword.empty()) return;
    if (keyword == "v") {
      Vec3f p;
      int n = 0;
      for (std::string_view tok = nextToken(rest); !tok.empty(); tok = nextToken(rest), ++n) {
        const float x = parseFloat(tok, "'v' statement");
        if (n < 3) p[n] = x;  // a 4th (w) or colour values are read and dropped
      }
      if (n < 3) fail("'v' needs 3 coordinates, got " + std::to_string(n));
      if (mesh_.positions.size() >= size_t(kInvalidId) - 1) fail("too many vertices");
      mesh_.positions.push_back(p);
    } else if (keyword == "vt" || keyword == "vn") {
      int n = 0;
      std::array<float, 2> uv{0.0f, 0.0f};
      for (std::string_view tok = nextToken(rest); !tok.empty(); tok = nextToken(rest), ++n) {
        const float x = parseFloat(tok, keyword == "vt" ? "'vt' statement" : "'vn' statement");
        if (n < 2) uv[size_t(n)] = x;
      }
      if (keyword == "vt") {
        if (n < 1) fail("'vt' needs at least 1 coordinate");
        if (mesh_.texcoords.size() >= size_t(kInvalidId) - 1) fail("too many texture coordinates");
        mesh_.texcoords.push_back(uv);
      } else {
        if (n != 3) fail("'vn' needs 3 coordinates, got " + std::to_string(n));
        ++numNormals_;
      }
    } else if (keyword == "f" || keyword == "fo") {
      face_.clear();
      for (std::string_view tok = nextToken(rest); !tok.empty(); tok = nextToken(rest))
        face_.push_back(parseFaceVertex(tok));
      if (face_.size() < 3) fail("a face needs at least 3 vertices, got " + std::to_string(face_.size()));
      for (size_t i = 1; i + 1 < face_.size(); ++i) {
        const FaceVertex& a = face_[0], &b = face_[i], &c = face_[i + 1];
        mesh_.triangles.push_back({a.position, b.position, c.position});
        const bool textured = a.texcoord != kInvalidId && b.texcoord != kInvalidId && c.texcoord != kInvalidId;
        anyFaceTexcoords_ |= textured;
        mesh_.triangleTexcoords.push_back(textured ? std::array<uint32_t, 3>{a.texcoord, b.texcoord, c.texcoord}
                                                   : std::array<uint32_t, 3>{kInvalidId, kInvalidId, kInvalidId});
        mesh_.triangleMaterials.push_back(material_);
      }
    } else if (keyword == "usemtl") {
      const std::string name = restOfLine(rest);
      if (name.empty()) fail("'usemtl' needs a material name");
      const auto found = std::find(mesh_.materialNames.begin(), mesh_.materialNames.end(), name);
      material_ = uint32_t(found - mesh_.materialNames.begin());
      if (found == mesh_.materialNames.end()) mesh_.materialNames.push_back(name);
    } else if (keyword == "mtllib") {
      const std::string name = restOfLine(rest);
      if (name.empty()) fail("'mtllib' needs a file name");
      mesh_.materialLibraries.push_back(name);
    }
    // Everything else (o, g, s, l, p, vp, ...) does not matter here.
  }

  // The rest of a statement without surrounding blanks (names may hold spaces).
  static std::string restOfLine(std::string_view rest) {
    while (!rest.empty() && isSpace(rest.front())) rest.remove_prefix(1);
    while (!rest.empty() && isSpace(rest.back())) rest.remove_suffix(1);
    return std::string(rest);
  }

  std::string_view name_;
  size_t lineNo_ = 0;
  size_t numNormals_ = 0;
  bool anyFaceTexcoords_ = false;
  uint32_t material_ = kInvalidId;
  std::vector<FaceVertex> face_;
  ObjMesh mesh_;
};

}  // namespace

ObjMesh readObj(std::istream& in, std::string_view name) { return ObjParser(name).run(in); }

ObjMesh readObj(const std::string& path) {
  const std::string bytes = io::readInputFile(path);
  io::MemoryInput in(bytes);
  return readObj(in, path);
}

std::shared_ptr<Scene> loadObjScene(const std::string& path) {
  ObjMesh mesh = readObj(path);
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::vector<std::vector<Vec3f>>{std::move(mesh.positions)});
  return scene;
}

}  // namespace mbrt
