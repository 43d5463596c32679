// OBJ keyframe sequences: one file per key, the same faces in every file.
#include <glob.h>

#include <algorithm>
#include <filesystem>

#include "mbrt/io/mesh_files.h"

namespace mbrt {
namespace {

bool hasObjExtension(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".obj";
}

std::string triangleText(const Triangle& t) {
  return "(" + std::to_string(t.v0 + 1) + " " + std::to_string(t.v1 + 1) + " " + std::to_string(t.v2 + 1) + ")";
}

}  // namespace

bool isObjSequenceSpec(const std::string& spec) {
  std::error_code ec;
  if (std::filesystem::is_directory(spec, ec)) return true;
  return spec.find_first_of("*?[") != std::string::npos;
}

std::vector<std::string> listObjSequence(const std::string& spec) {
  std::vector<std::string> files;
  std::error_code ec;
  if (std::filesystem::is_directory(spec, ec)) {
    for (const auto& entry : std::filesystem::directory_iterator(spec, ec))
      if (entry.is_regular_file() && hasObjExtension(entry.path())) files.push_back(entry.path().string());
    if (ec) throw Error("cannot list folder '" + spec + "': " + ec.message());
    if (files.empty()) throw Error("folder '" + spec + "' has no .obj files");
  } else {
    glob_t g{};
    const int rc = ::glob(spec.c_str(), 0, nullptr, &g);
    if (rc == 0)
      for (size_t i = 0; i < g.gl_pathc; ++i) files.push_back(g.gl_pathv[i]);
    globfree(&g);
    if (rc == GLOB_NOMATCH || files.empty()) throw Error("no file matches '" + spec + "'");
    if (rc != 0) throw Error("cannot expand '" + spec + "' (glob error " + std::to_string(rc) + ")");
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::shared_ptr<Scene> loadObjSequence(const std::vector<std::string>& files) {
  if (files.empty()) throw Error("OBJ sequence: no files");
  ObjMesh first = readObj(files[0]);
  std::vector<std::vector<Vec3f>> steps;
  steps.reserve(files.size());
  steps.push_back(std::move(first.positions));
  for (size_t k = 1; k < files.size(); ++k) {
    ObjMesh m = readObj(files[k]);
    const std::string differs = files[k] + ": not the same mesh as " + files[0] + " (an OBJ sequence needs ";
    if (m.positions.size() != steps[0].size())
      throw Error(differs + "the same vertices in every file): " + std::to_string(m.positions.size()) +
                  " vertices, the first file has " + std::to_string(steps[0].size()));
    if (m.triangles.size() != first.triangles.size())
      throw Error(differs + "the same faces in every file): " + std::to_string(m.triangles.size()) +
                  " triangles after fanning, the first file has " + std::to_string(first.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const Triangle &a = m.triangles[i], &b = first.triangles[i];
      if (a.v0 != b.v0 || a.v1 != b.v1 || a.v2 != b.v2)
        throw Error(differs + "the same faces in every file): triangle " + std::to_string(i) + " is " +
                    triangleText(a) + ", in the first file " + triangleText(b) + " (1-based vertex numbers)");
    }
    steps.push_back(std::move(m.positions));
  }
  auto scene = std::make_shared<Scene>();
  scene->addTriangleMesh(std::move(first.triangles), std::move(steps));
  return scene;
}

}  // namespace mbrt
