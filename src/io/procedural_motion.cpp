// A procedural motion (translate / rotate) for static meshes, for experiments.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "mbrt/io/mesh_files.h"

namespace mbrt {
namespace {

// A step count for a message: as an integer, whatever its size (a double
// beyond 2^64 has no unsigned integer to convert to).
std::string stepCount(double steps) {
  char buf[400];
  std::snprintf(buf, sizeof buf, "%.0f", steps);
  return buf;
}

std::vector<float> parseFloats(const std::string& s, const std::string& spec) {
  std::vector<float> out;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) {
    float v = 0;
    auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size() || !std::isfinite(v))
      throw Error("motion '" + spec + "': bad number '" + tok + "'");
    out.push_back(v);
  }
  return out;
}

}  // namespace

ProceduralMotion parseProceduralMotion(const std::string& spec) {
  ProceduralMotion m;
  std::stringstream ss(spec);
  std::string part;
  while (std::getline(ss, part, ';')) {
    if (part.empty()) continue;
    const size_t colon = part.find(':');
    const std::string kind = part.substr(0, colon);
    const std::string args = colon == std::string::npos ? "" : part.substr(colon + 1);
    if (kind == "translate") {
      const auto v = parseFloats(args, spec);
      if (v.size() != 3) throw Error("motion '" + spec + "': translate needs X,Y,Z");
      m.translate = {v[0], v[1], v[2]};
    } else if (kind == "rotate") {
      const size_t c2 = args.find(':');
      const auto deg = parseFloats(args.substr(0, c2), spec);
      if (deg.size() != 1) throw Error("motion '" + spec + "': rotate needs DEGREES");
      m.rotateDegrees = deg[0];
      if (c2 != std::string::npos) {
        const auto a = parseFloats(args.substr(c2 + 1), spec);
        if (a.size() != 3 || (a[0] == 0 && a[1] == 0 && a[2] == 0))
          throw Error("motion '" + spec + "': the rotation axis needs 3 numbers, not all zero");
        m.axis = {a[0], a[1], a[2]};
      }
      // Enough steps that linear interpolation of the arc stays close: about
      // one step per 10 degrees.
      // The count is capped: every step is a copy of the mesh.
      const double steps = 1.0 + std::ceil(std::fabs(double(m.rotateDegrees)) / 10.0);
      if (steps > double(kMaxProceduralMotionSteps))
        throw Error("motion '" + spec + "': rotating by " + args.substr(0, c2) + " degrees needs " +
                    stepCount(steps) + " steps (one per 10 degrees), more than the limit of " +
                    std::to_string(kMaxProceduralMotionSteps) + ": rotate by at most " +
                    std::to_string((kMaxProceduralMotionSteps - 1) * 10) + " degrees");
      m.steps = std::max<uint32_t>(m.steps, uint32_t(steps));
    } else {
      throw Error("motion '" + spec + "': unknown part '" + part + "' (translate:X,Y,Z or rotate:DEG[:AX,AY,AZ])");
    }
  }
  return m;
}

std::shared_ptr<Scene> makeMovingMeshScene(ObjMesh mesh, const ProceduralMotion& motion) {
  auto scene = std::make_shared<Scene>();
  if (!motion.any()) {
    scene->addTriangleMesh(std::move(mesh.triangles), std::vector<std::vector<Vec3f>>{std::move(mesh.positions)});
    return scene;
  }
  Box3f box;
  for (const Vec3f& p : mesh.positions) box.extend(p);
  const Vec3f centre = box.center();
  const uint32_t steps = std::max<uint32_t>(2, motion.steps);
  std::vector<std::vector<Vec3f>> keys(steps);
  for (uint32_t k = 0; k < steps; ++k) {
    const float t = float(k) / float(steps - 1);
    const Affine3f m = Affine3f::translate(centre + motion.translate * t) *
                       Affine3f::rotate(motion.axis, motion.rotateDegrees * t * 3.14159265f / 180.0f) *
                       Affine3f::translate(-centre);
    keys[k].reserve(mesh.positions.size());
    for (const Vec3f& p : mesh.positions) keys[k].push_back(m.xfmPoint(p));
  }
  scene->addTriangleMesh(std::move(mesh.triangles), std::move(keys));
  return scene;
}

}  // namespace mbrt
