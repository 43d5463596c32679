// Reads the scene dump that mbrt's Embree API writes under MBRT_EMBREE_DUMP
// (embree_api/src/scene_dump.cpp) back into mbrt scenes, with what maps an
// Embree answer (geomID, primID, instID, u, v) to the mbrt hit the float64
// reference judges.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt::embree_test {

struct DumpedGeometry {
  uint32_t embreeID = 0;
  bool instance = false, quads = false;
  bool filtered = false;       // filter functions ran on it (not in the dump)
  std::vector<uint32_t> kept;  // mbrt triangle -> Embree primitive (2*quad+half for quads); empty: identity
  uint32_t child = 0;          // instances: the scene index
};

struct DumpedScene {
  std::shared_ptr<Scene> scene;
  std::vector<DumpedGeometry> geometries;  // by mbrt id
  bool filtered = false;                   // some geometry, here or instanced, has filters
};

struct SceneDump {
  std::vector<DumpedScene> scenes;  // the last one is the scene committed last
  // An Embree answer as an mbrt hit of the last scene (invalid when it
  // names nothing there).
  Hit toMbrtHit(uint32_t geomID, uint32_t primID, uint32_t instID, float t, float u, float v) const;
};

// Throws mbrt::Error on an unreadable or malformed file.
SceneDump readSceneDump(const std::string& path);

}  // namespace mbrt::embree_test
