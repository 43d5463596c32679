// PLY (ascii and binary little-endian): vertex positions and polygon faces.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

#include "mbrt/io/file_access.h"
#include "mbrt/io/mesh_files.h"

namespace mbrt {
namespace {

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

struct Property {
  std::string name;
  Type type = Type::F32;
  bool isList = false;
  Type countType = Type::U8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> props;
};

size_t sizeOf(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 0;
}

bool parseType(const std::string& s, Type& t) {
  static const struct { const char* name; Type type; } names[] = {
      {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},  {"uint8", Type::U8},
      {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
      {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},  {"uint32", Type::U32},
      {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
  for (const auto& n : names)
    if (s == n.name) {
      t = n.type;
      return true;
    }
  return false;
}

class PlyReader {
 public:
  PlyReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  ObjMesh run() {
    readHeader();
    for (const Element& e : elements_) {
      if (binary_) readBinary(e);
      else readAscii(e);
    }
    if (mesh_.positions.empty()) fail("no vertices (no 'vertex' element with x, y, z)");
    if (mesh_.triangles.empty()) fail("no faces (no 'face' element with vertex_indices)");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(name_ + (line_ > 0 && !binary_ ? ":" + std::to_string(line_) : std::string()) + ": " + what);
  }

  void readHeader() {
    std::string line;
    if (!std::getline(in_, line) || line.substr(0, 3) != "ply") fail("not a PLY file (no 'ply' magic line)");
    line_ = 1;
    bool formatSeen = false;
    while (true) {
      if (!std::getline(in_, line)) fail("header ends without 'end_header'");
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream ls(line);
      std::string kw;
      ls >> kw;
      if (kw == "end_header") break;
      if (kw == "comment" || kw == "obj_info" || kw.empty()) continue;
      if (kw == "format") {
        std::string fmt;
        ls >> fmt;
        if (fmt == "ascii") binary_ = false;
        else if (fmt == "binary_little_endian") binary_ = true;
        else if (fmt == "binary_big_endian") fail("binary_big_endian PLY is not supported (use ascii or little-endian)");
        else fail("unknown PLY format '" + fmt + "'");
        formatSeen = true;
      } else if (kw == "element") {
        Element e;
        long long count = -1;
        ls >> e.name >> count;
        if (e.name.empty() || count < 0 || !ls) fail("bad element line '" + line + "'");
        e.count = size_t(count);
        elements_.push_back(std::move(e));
      } else if (kw == "property") {
        if (elements_.empty()) fail("property before any element");
        Property p;
        std::string t;
        ls >> t;
        if (t == "list") {
          std::string ct, it;
          ls >> ct >> it >> p.name;
          if (!parseType(ct, p.countType) || !parseType(it, p.type)) fail("bad list property '" + line + "'");
          p.isList = true;
        } else {
          ls >> p.name;
          if (!parseType(t, p.type)) fail("unknown property type '" + t + "'");
        }
        if (p.name.empty()) fail("property without a name");
        elements_.back().props.push_back(p);
      } else {
        fail("unknown header keyword '" + kw + "'");
      }
    }
    if (!formatSeen) fail("header has no 'format' line");
    for (const Element& e : elements_) {
      if (e.name != "vertex") continue;
      const std::vector<int> r = roles(e);
      for (int axis = 0; axis < 3; ++axis)
        if (std::find(r.begin(), r.end(), axis) == r.end())
          fail(std::string("element 'vertex' has no property '") + "xyz"[axis] + "'");
    }
    if (binary_ && std::endian::native != std::endian::little) fail("binary PLY needs a little-endian machine");
  }

  // What each property of an element is for: 0..2 x/y/z, 3 face indices, -1 skip.
  std::vector<int> roles(const Element& e) const {
    std::vector<int> r(e.props.size(), -1);
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      if (e.name == "vertex" && !p.isList) {
        if (p.name == "x") r[i] = 0;
        if (p.name == "y") r[i] = 1;
        if (p.name == "z") r[i] = 2;
      }
      if (e.name == "face" && p.isList && (p.name == "vertex_indices" || p.name == "vertex_index")) r[i] = 3;
    }
    return r;
  }

  void addFace(const std::vector<long long>& face, size_t index) {
    if (face.size() < 3) fail("face " + std::to_string(index) + " has " + std::to_string(face.size()) + " vertices (at least 3 needed)");
    for (long long v : face)
      if (v < 0 || size_t(v) >= mesh_.positions.size())
        fail("face " + std::to_string(index) + " uses vertex " + std::to_string(v) + " of " +
             std::to_string(mesh_.positions.size()));
    for (size_t i = 1; i + 1 < face.size(); ++i)
      mesh_.triangles.push_back({uint32_t(face[0]), uint32_t(face[i]), uint32_t(face[i + 1])});
  }

  // A list count or vertex index read as a double: a whole number in range
  // (NaN, infinities, fractions and huge values are refused before any
  // conversion to an integer, which would be undefined for them).
  long long integral(double v, const Element& e, const char* what) const {
    if (!(v >= -2147483648.0 && v <= 4294967295.0) || v != std::floor(v))
      fail(std::string("bad ") + what + " in element '" + e.name + "'");
    return (long long)v;
  }

  void checkCoordinate(float v, size_t index) {
    if (!std::isfinite(v) || std::fabs(v) > kMaxCoordinate)
      fail("vertex " + std::to_string(index) + " has a non-finite or huge coordinate (" + std::to_string(v) + ")");
  }

  void readAscii(const Element& e) {
    const std::vector<int> role = roles(e);
    std::string line;
    std::vector<long long> face;
    for (size_t i = 0; i < e.count; ++i) {
      if (!std::getline(in_, line)) fail("file ends in element '" + e.name + "' (" + std::to_string(i) + " of " + std::to_string(e.count) + " read)");
      ++line_;
      std::string_view rest = line;
      auto next = [&]() -> std::string_view {
        size_t b = rest.find_first_not_of(" \t\r");
        if (b == std::string_view::npos) fail("too few values for element '" + e.name + "'");
        size_t end = rest.find_first_of(" \t\r", b);
        std::string_view tok = rest.substr(b, end == std::string_view::npos ? rest.size() - b : end - b);
        rest.remove_prefix(end == std::string_view::npos ? rest.size() : end);
        return tok;
      };
      auto number = [&]() -> double {
        std::string_view tok = next();
        double v = 0;
        auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (ec != std::errc() || ptr != tok.data() + tok.size()) {
          if (tok == "nan" || tok == "NaN" || tok == "-nan" || tok == "inf" || tok == "-inf") return std::nan("");
          fail("bad number '" + std::string(tok) + "'");
        }
        return v;
      };
      Vec3f p;
      for (size_t k = 0; k < e.props.size(); ++k) {
        const Property& prop = e.props[k];
        if (prop.isList) {
          const long long n = integral(number(), e, "list count");
          if (n < 0) fail("bad list count in element '" + e.name + "'");
          face.clear();
          for (long long j = 0; j < n; ++j) face.push_back(integral(number(), e, "list value"));
          if (role[k] == 3) addFace(face, i);
        } else {
          const double v = number();
          if (role[k] >= 0) p[role[k]] = float(v);
        }
      }
      if (e.name == "vertex") {
        checkCoordinate(p.x, i), checkCoordinate(p.y, i), checkCoordinate(p.z, i);
        mesh_.positions.push_back(p);
      }
    }
  }

  double readValue(Type t, const Element& e) {
    char buf[8];
    if (!in_.read(buf, std::streamsize(sizeOf(t)))) fail("file ends in element '" + e.name + "' (truncated binary data)");
    switch (t) {
      case Type::I8: return double(int8_t(buf[0]));
      case Type::U8: return double(uint8_t(buf[0]));
      case Type::I16: { int16_t v; std::memcpy(&v, buf, 2); return v; }
      case Type::U16: { uint16_t v; std::memcpy(&v, buf, 2); return v; }
      case Type::I32: { int32_t v; std::memcpy(&v, buf, 4); return v; }
      case Type::U32: { uint32_t v; std::memcpy(&v, buf, 4); return v; }
      case Type::F32: { float v; std::memcpy(&v, buf, 4); return v; }
      case Type::F64: { double v; std::memcpy(&v, buf, 8); return v; }
    }
    return 0;
  }

  void readBinary(const Element& e) {
    if (e.props.empty()) return;  // nothing to read, whatever the count
    const std::vector<int> role = roles(e);
    std::vector<long long> face;
    for (size_t i = 0; i < e.count; ++i) {
      Vec3f p;
      for (size_t k = 0; k < e.props.size(); ++k) {
        const Property& prop = e.props[k];
        if (prop.isList) {
          const long long n = integral(readValue(prop.countType, e), e, "list count");
          if (n < 0) fail("negative list count in element '" + e.name + "'");
          face.clear();
          for (long long j = 0; j < n; ++j) face.push_back(integral(readValue(prop.type, e), e, "list value"));
          if (role[k] == 3) addFace(face, i);
        } else {
          const double v = readValue(prop.type, e);
          if (role[k] >= 0) p[role[k]] = float(v);
        }
      }
      if (e.name == "vertex") {
        checkCoordinate(p.x, i), checkCoordinate(p.y, i), checkCoordinate(p.z, i);
        mesh_.positions.push_back(p);
      }
    }
  }

  std::istream& in_;
  std::string name_;
  size_t line_ = 0;
  bool binary_ = false;
  std::vector<Element> elements_;
  ObjMesh mesh_;
};

}  // namespace

ObjMesh readPly(const std::string& path) {
  const std::string bytes = io::readInputFile(path);
  io::MemoryInput in(bytes);
  return PlyReader(in, path).run();
}

std::shared_ptr<Scene> loadPlyScene(const std::string& path) {
  ObjMesh mesh = readPly(path);
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(mesh.triangles), std::vector<std::vector<Vec3f>>{std::move(mesh.positions)});
  return scene;
}

}  // namespace mbrt
