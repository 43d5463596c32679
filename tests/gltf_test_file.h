// A tiny hand-made glTF file for the loader and animation tests, and the
// writer that makes such files (.gltf + .bin).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace mbrt::test {

// Writes a .gltf + .bin pair, one buffer view per accessor.
class GltfWriter {
 public:
  int floats(const std::vector<float>& v, const char* type) { return add(v.data(), v.size() * 4, 5126, v.size() / width(type), type); }
  int bytes(const std::vector<uint8_t>& v, const char* type) { return add(v.data(), v.size(), 5121, v.size() / width(type), type); }

  // `rest`: the JSON members after "accessors" and "bufferViews".
  std::string write(const std::filesystem::path& dir, const std::string& name, const std::string& rest) {
    std::filesystem::create_directories(dir);
    std::ofstream(dir / (name + ".bin"), std::ios::binary).write(reinterpret_cast<const char*>(bin_.data()), std::streamsize(bin_.size()));
    const std::string json = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"" + name + ".bin\",\"byteLength\":" +
                             std::to_string(bin_.size()) + "}],\"bufferViews\":[" + views_ + "],\"accessors\":[" +
                             accessors_ + "]," + rest + "}";
    const std::filesystem::path p = dir / (name + ".gltf");
    std::ofstream(p) << json;
    return p.string();
  }

 private:
  static size_t width(const char* type) {
    return std::strcmp(type, "SCALAR") == 0 ? 1 : std::strcmp(type, "VEC3") == 0 ? 3 : std::strcmp(type, "VEC4") == 0 ? 4 : 16;
  }
  int add(const void* data, size_t size, int componentType, size_t count, const char* type) {
    while (bin_.size() % 4) bin_.push_back(0);
    const size_t offset = bin_.size();
    bin_.insert(bin_.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + size);
    if (!views_.empty()) views_ += ",", accessors_ += ",";
    views_ += "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) + ",\"byteLength\":" + std::to_string(size) + "}";
    accessors_ += "{\"bufferView\":" + std::to_string(n_) + ",\"componentType\":" + std::to_string(componentType) +
                  ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"}";
    return n_++;
  }
  std::vector<uint8_t> bin_;
  std::string views_, accessors_;
  int n_ = 0;
};

// Node 0: a triangle skinned to joints 1 and 2; joint 2 (child of 1, rest
// at x = 1) moves up by 2 over [0,1] (LINEAR).
// Node 3 (at x = 5): a triangle with one morph target whose weight goes 0 -> 1
// (CUBICSPLINE, zero tangents: w(s) = 3s^2 - 2s^3).
// Node 4: a triangle turning 90 degrees about z (LINEAR), translated by a
// STEP channel: (10,0,0) until 0.75 s, then (10,0,3).
inline std::string writeTinyGltf(const std::filesystem::path& dir, const std::string& name, bool nanPosition = false) {
  GltfWriter w;
  const float n = nanPosition ? std::nanf("") : 0.0f;
  const int pos0 = w.floats({0, 0, n, 1, 0, 0, 1, 1, 0}, "VEC3");
  const int joints = w.bytes({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}, "VEC4");
  const int weights = w.floats({1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0}, "VEC4");
  const int ibm = w.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1},
                           "MAT4");
  const int pos1 = w.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  const int target = w.floats({0, 0, 1, 0, 0, 2, 0, 0, 0}, "VEC3");
  const int times = w.floats({0, 1}, "SCALAR");
  const int moves = w.floats({1, 0, 0, 1, 2, 0}, "VEC3");
  const int cubic = w.floats({0, 0, 0, 0, 1, 0}, "SCALAR");  // (in, value, out) per key
  const float h = std::sqrt(0.5f);
  const int turns = w.floats({0, 0, 0, 1, 0, 0, h, h}, "VEC4");
  const int stepTimes = w.floats({0, 0.75f}, "SCALAR");
  const int stepValues = w.floats({10, 0, 0, 10, 0, 3}, "VEC3");
  auto s = [](int i) { return std::to_string(i); };
  const std::string rest =
      "\"scene\":0,\"scenes\":[{\"nodes\":[0,1,3,4]}],"
      "\"nodes\":[{\"name\":\"skinned\",\"mesh\":0,\"skin\":0},{\"name\":\"j0\",\"children\":[2]},"
      "{\"name\":\"j1\",\"translation\":[1,0,0]},{\"name\":\"morphed\",\"mesh\":1,\"translation\":[5,0,0]},"
      "{\"name\":\"spinner\",\"mesh\":2}],"
      "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":" + s(ibm) + "}],"
      "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.2,0.4,0.6,1]}}],"
      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + s(pos0) + ",\"JOINTS_0\":" + s(joints) +
      ",\"WEIGHTS_0\":" + s(weights) + "}}]},"
      "{\"weights\":[0],\"primitives\":[{\"attributes\":{\"POSITION\":" + s(pos1) + "},\"material\":0,\"targets\":[{\"POSITION\":" +
      s(target) + "}]}]},"
      "{\"primitives\":[{\"attributes\":{\"POSITION\":" + s(pos1) + "}}]}],"
      "\"animations\":[{\"name\":\"move\",\"samplers\":["
      "{\"input\":" + s(times) + ",\"output\":" + s(moves) + "},"
      "{\"input\":" + s(times) + ",\"output\":" + s(cubic) + ",\"interpolation\":\"CUBICSPLINE\"},"
      "{\"input\":" + s(times) + ",\"output\":" + s(turns) + "},"
      "{\"input\":" + s(stepTimes) + ",\"output\":" + s(stepValues) + ",\"interpolation\":\"STEP\"}],"
      "\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"translation\"}},"
      "{\"sampler\":1,\"target\":{\"node\":3,\"path\":\"weights\"}},"
      "{\"sampler\":2,\"target\":{\"node\":4,\"path\":\"rotation\"}},"
      "{\"sampler\":3,\"target\":{\"node\":4,\"path\":\"translation\"}}]},"
      "{\"name\":\"other\",\"samplers\":[{\"input\":" + s(times) + ",\"output\":" + s(moves) + "}],"
      "\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"translation\"}}]}]";
  return w.write(dir, name, rest);
}

}  // namespace mbrt::test
