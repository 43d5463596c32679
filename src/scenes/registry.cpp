// Scene names -> makers, argument checks, and camera framing.
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "scenes/scene_makers.h"

namespace mbrt {
namespace {

struct Entry {
  const char* name;
  ProceduralScene (*make)(double, uint64_t);
};

constexpr std::array<Entry, 10> kScenes{{
    {"translate", scenes::makeTranslate},
    {"rotate", scenes::makeRotate},
    {"crowd", scenes::makeCrowd},
    {"hairball", scenes::makeHairball},
    {"hair", scenes::makeHair},
    {"deform", scenes::makeDeform},
    {"skinned", scenes::makeSkinned},
    {"demo", scenes::makeDemo},
    {"slide", scenes::makeSlide},
    {"ribbons", scenes::makeRibbons},
}};

constexpr double kMaxSize = 100.0;

std::string joinedNames() {
  std::string s;
  for (const Entry& e : kScenes) {
    if (!s.empty()) s += ", ";
    s += e.name;
  }
  return s;
}

}  // namespace

std::vector<std::string> proceduralSceneNames() {
  std::vector<std::string> names;
  for (const Entry& e : kScenes) names.emplace_back(e.name);
  return names;
}

ProceduralScene makeProceduralScene(std::string_view name, double size, uint64_t seed) {
  const Entry* entry = nullptr;
  for (const Entry& e : kScenes)
    if (name == e.name) entry = &e;
  if (!entry)
    throw Error("unknown procedural scene '" + std::string(name) + "' (valid names: " + joinedNames() + ")");
  if (!(size > 0.0 && size <= kMaxSize))  // also refuses NaN
    throw Error("procedural scene '" + std::string(name) + "': size " + std::to_string(size) +
                " is out of range (0, " + std::to_string(int(kMaxSize)) + "]; 1 gives the default sizes");
  ProceduralScene s = entry->make(size, seed);
  s.name = entry->name;
  return s;
}

CameraSpec frameBox(const Box3f& box) {
  if (box.empty() || !isFinite(box.lower) || !isFinite(box.upper)) return CameraSpec{};
  // Look along -z from the front of the box.
  CameraSpec cam = scenes::viewFrom(box, {0, 0, 1}, 40.0f, 1.05f);
  return cam;
}

namespace scenes {

CameraSpec viewFrom(const Box3f& box, Vec3f direction, float verticalFovDegrees, float margin) {
  CameraSpec cam;
  cam.verticalFovDegrees = verticalFovDegrees;
  const Vec3f c = box.center();
  float radius = 0.5f * length(box.size()) * margin;
  if (!(radius > 0.0f)) radius = 1.0f;
  const float halfFov = 0.5f * verticalFovDegrees * std::numbers::pi_v<float> / 180.0f;
  const float dist = radius / std::sin(halfFov);
  cam.target = c;
  cam.eye = c + normalize(direction) * dist;
  cam.up = {0, 1, 0};
  return cam;
}

}  // namespace scenes
}  // namespace mbrt
