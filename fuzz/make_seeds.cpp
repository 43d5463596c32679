// Writes the fuzzers' seed corpus: small valid files of every format the
// targets read, one folder per target. Usage: fuzz_make_seeds OUT_DIR
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "mbrt/io/ray_file.h"

namespace fs = std::filesystem;

namespace {

void put(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
  }
  if (i < in.size()) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <class T>
void append(std::string& s, std::initializer_list<T> values) {
  for (T v : values) s.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// A glTF document over one binary buffer `bin`; `body` holds the members
// after "buffers" (bufferViews, accessors, meshes, nodes, ...).
std::string gltfJson(const std::string& bin, const std::string& body, bool embedded) {
  const std::string buffer = embedded ? "{\"uri\":\"data:application/octet-stream;base64," + base64(bin) +
                                            "\",\"byteLength\":" + std::to_string(bin.size()) + "}"
                                      : "{\"byteLength\":" + std::to_string(bin.size()) + "}";
  return "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"buffers\":[" + buffer + "]," + body + "}";
}

std::string glb(const std::string& json, std::string bin) {
  std::string j = json;
  while (j.size() % 4) j += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string out = "glTF";
  append<uint32_t>(out, {2u, uint32_t(12 + 8 + j.size() + 8 + bin.size())});
  append<uint32_t>(out, {uint32_t(j.size()), 0x4E4F534Au});
  out += j;
  append<uint32_t>(out, {uint32_t(bin.size()), 0x004E4942u});
  out += bin;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds OUT_DIR\n";
    return 2;
  }
  const fs::path out = argv[1];

  // ---- OBJ
  const std::string cube =
      "# a cube\no cube\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 -1\ng sides\nusemtl m\ns 1\n"
      "f 1/1/1 2/2/1 3/3/1 4\nf 5 8 7 6\nf 1//1 5//1 6//1 2//1\nf 2 6 7 3\nf -1 -2 -6 -5\nfo 5 1 4 8\n";
  put(out / "obj" / "cube.obj", cube);
  put(out / "obj" / "tri.obj", "v 0 0 0\nv 1 0 0 1\nv 0 1 0 0.5 0.5 0.5\nf 1 2 3\r\n");
  put(out / "obj" / "neg.obj", "v 0 0 0\nv 1e3 0 0\nv 0 -1e-3 +2\nf -3 -2 -1\n");

  // ---- OBJ sequences: keys separated by "#--key--" lines
  const std::string tri0 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
  const std::string tri1 = "v 0 0 1\nv 1 0 1\nv 0 1 2\nv 1 1 2\nf 1 2 3\nf 2 4 3\n";
  put(out / "obj_sequence" / "two.txt", tri0 + "#--key--\n" + tri1);
  put(out / "obj_sequence" / "three.txt", tri0 + "#--key--\n" + tri1 + "#--key--\n" + tri0);
  put(out / "obj_sequence" / "cube.txt", cube + "#--key--\n" + cube);

  // ---- PLY
  const std::string plyAscii =
      "ply\nformat ascii 1.0\ncomment seed\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 9\n3 0 1 2\n4 0 1 2 3\n";
  put(out / "ply" / "ascii.ply", plyAscii);
  {
    std::string b =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
        "property double z\nproperty float confidence\nelement face 1\nproperty list uchar uint vertex_index\n"
        "element extra 1\nproperty list ushort short junk\nend_header\n";
    append<double>(b, {0, 0, 0});
    append<float>(b, {1});
    append<double>(b, {1, 0, 0});
    append<float>(b, {1});
    append<double>(b, {0, 1, 0});
    append<float>(b, {1});
    append<uint8_t>(b, {3});
    append<uint32_t>(b, {0, 1, 2});
    append<uint16_t>(b, {2});
    append<int16_t>(b, {-1, 7});
    put(out / "ply" / "binary.ply", b);
  }
  {
    std::string b =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list int int8 vertex_indices\nend_header\n";
    append<float>(b, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    append<int32_t>(b, {3});
    append<int8_t>(b, {0, 1, 2});
    put(out / "ply" / "binary_small.ply", b);
  }

  // ---- glTF: positions (3 x VEC3 float), indices (3 x u16), times, values
  std::string bin;
  append<float>(bin, {0, 0, 0, 1, 0, 0, 0, 1, 0});  // 0..36
  append<uint16_t>(bin, {0, 1, 2, 0});              // 36..44
  append<float>(bin, {0, 1});                       // 44..52: times
  append<float>(bin, {0, 0, 0, 2, 0, 1});           // 52..76: translations
  append<float>(bin, {0, 0, 0, 1, 0, 0, 0.7071f, 0.7071f});  // 76..108: rotations
  append<float>(bin, {0, 0, 1, 0, 0, 1, 0, 0, 1});  // 108..144: morph target deltas
  append<float>(bin, {0, 1});                       // 144..152: weights
  const std::string views =
      "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
      "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":6},{\"buffer\":0,\"byteOffset\":44,\"byteLength\":8},"
      "{\"buffer\":0,\"byteOffset\":52,\"byteLength\":24},{\"buffer\":0,\"byteOffset\":76,\"byteLength\":32},"
      "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":144,\"byteLength\":8}]";
  const std::string accessors =
      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
      "\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"},"
      "{\"bufferView\":2,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\",\"min\":[0],\"max\":[1]},"
      "{\"bufferView\":3,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"},"
      "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"VEC4\"},"
      "{\"bufferView\":5,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
      "{\"bufferView\":6,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\"}]";
  const std::string staticBody =
      views + "," + accessors +
      ",\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
      "\"nodes\":[{\"mesh\":0,\"translation\":[1,2,3]}],\"scenes\":[{\"nodes\":[0]}],"
      "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0,0,1]}}]";
  put(out / "gltf" / "static.gltf", gltfJson(bin, staticBody, true));
  put(out / "gltf" / "static.glb", glb(gltfJson(bin, staticBody, false), bin));
  const std::string animBody =
      views + "," + accessors +
      ",\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]},"
      "{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"targets\":[{\"POSITION\":5}]}],\"weights\":[0]}],"
      "\"nodes\":[{\"mesh\":0,\"children\":[1]},{\"mesh\":1,\"scale\":[1,2,1]},"
      "{\"camera\":0,\"translation\":[0,0,5]}],\"cameras\":[{\"type\":\"perspective\",\"perspective\":"
      "{\"yfov\":0.8,\"znear\":0.1}}],\"scenes\":[{\"nodes\":[0,2]}],"
      "\"animations\":[{\"name\":\"move\",\"samplers\":[{\"input\":2,\"output\":3},"
      "{\"input\":2,\"output\":4,\"interpolation\":\"STEP\"},{\"input\":2,\"output\":6}],"
      "\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}},"
      "{\"sampler\":1,\"target\":{\"node\":0,\"path\":\"rotation\"}},"
      "{\"sampler\":2,\"target\":{\"node\":1,\"path\":\"weights\"}}]}]";
  put(out / "gltf" / "animated.gltf", gltfJson(bin, animBody, true));
  put(out / "gltf" / "animated.glb", glb(gltfJson(bin, animBody, false), bin));
  const std::string skinBody =
      views + "," + accessors +
      ",\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"JOINTS_0\":7,\"WEIGHTS_0\":8}}]}],"
      "\"skins\":[{\"joints\":[1]}],\"nodes\":[{\"mesh\":0,\"skin\":0},{\"translation\":[0,1,0]}],"
      "\"scenes\":[{\"nodes\":[0,1]}],\"animations\":[{\"samplers\":[{\"input\":2,\"output\":3,"
      "\"interpolation\":\"LINEAR\"}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"translation\"}}]}]";
  {
    // joints (3 x u8 VEC4) and weights (3 x float VEC4) appended as views 7, 8
    std::string b2 = bin;
    append<uint8_t>(b2, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});  // 152..164
    append<float>(b2, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});    // 164..212
    std::string v2 = views;
    v2.pop_back();
    v2 += ",{\"buffer\":0,\"byteOffset\":152,\"byteLength\":12},{\"buffer\":0,\"byteOffset\":164,\"byteLength\":48}]";
    std::string a2 = accessors;
    a2.pop_back();
    a2 += ",{\"bufferView\":7,\"componentType\":5121,\"count\":3,\"type\":\"VEC4\"},"
          "{\"bufferView\":8,\"componentType\":5126,\"count\":3,\"type\":\"VEC4\"}]";
    std::string body = skinBody;
    body.replace(0, views.size() + 1 + accessors.size(), v2 + "," + a2);
    put(out / "gltf" / "skinned.gltf", gltfJson(b2, body, true));
  }

  // ---- JSON scene files (tri.obj and tri.ply lie next to them when fuzzing)
  put(out / "scene_file" / "objects.json",
      "{\n  // comment\n  \"camera\": {\"eye\": [0, 1, 6], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 40},\n"
      "  \"shutter\": [0.0, 0.5], \"fps\": 24, \"steps\": \"auto\",\n"
      "  \"lights\": [{\"direction\": [-0.4, -1, -0.3], \"radiance\": [2.5, 2.4, 2.2]}],\n"
      "  \"sky\": [0.5, 0.6, 0.8],\n  \"objects\": [\n"
      "    {\"file\": \"tri.obj\", \"translate\": [1, 0, 0], \"rotate\": [90, 0, 1, 0], \"scale\": 2,"
      " \"diffuse\": [0.8, 0.6, 0.4], \"motion\": \"translate:0.5,0,0;rotate:30\"},\n"
      "    {\"file\": \"tri.ply\", \"scale\": [1, 2, 3]}\n  ]\n}\n");
  put(out / "scene_file" / "keys.json",
      "{\"camera\": {\"keys\": [{\"eye\": [0, 0, 5], \"target\": [0, 0, 0]}, {\"eye\": [1, 0, 5], \"target\": [0, 0, 0]}],"
      " \"aperture\": 0.1, \"focus\": 5}, \"steps\": 3, \"objects\": [{\"file\": \"tri.obj\"}]}\n");

  // ---- ray files
  std::vector<mbrt::Ray> rays;
  for (int i = 0; i < 8; ++i) {
    mbrt::Ray r;
    r.org = {0.1f * float(i) - 0.5f, 0.05f * float(i) - 0.4f, -3.0f};
    r.dir = {0.0f, 0.0f, 1.0f};
    r.time = float(i) / 7.0f;
    rays.push_back(r);
  }
  mbrt::Ray odd;
  odd.org = {0.5f, 0.5f, 0.5f};
  odd.dir = {1.0f, 0.0f, 0.0f};  // axis-parallel
  odd.tnear = 0.1f;
  odd.tfar = 10.0f;
  odd.time = 0.5f;
  rays.push_back(odd);
  odd.dir = {0.0f, 0.0f, 0.0f};  // invalid: zero direction
  rays.push_back(odd);
  odd.dir = {0.0f, 1.0f, 0.0f};
  odd.time = std::nanf("");  // invalid: NaN time
  rays.push_back(odd);
  const std::vector<uint8_t> bytes = mbrt::encodeRays(rays);
  put(out / "ray_file" / "rays.bin", std::string(bytes.begin(), bytes.end()));
  const std::vector<uint8_t> one = mbrt::encodeRays(std::span<const mbrt::Ray>(rays.data(), 1));
  put(out / "ray_file" / "one.bin", std::string(one.begin(), one.end()));
  // Very short and very long directions (hit distances near the float range).
  std::vector<mbrt::Ray> scaled(rays.begin(), rays.begin() + 8);
  for (size_t i = 0; i < scaled.size(); ++i) {
    const float scale = i % 2 ? 1e-38f * float(i) : 1e37f * float(i);
    scaled[i].dir = mbrt::Vec3f{0.01f * float(i), -0.02f, 1.0f} * scale;
    scaled[i].tnear = i % 3 ? 0.0f : -1e8f;
  }
  const std::vector<uint8_t> scaledBytes = mbrt::encodeRays(scaled);
  put(out / "ray_file" / "scaled.bin", std::string(scaledBytes.begin(), scaledBytes.end()));

  std::cout << "fuzz_make_seeds: wrote the seed corpus to " << out.string() << "\n";
  return 0;
}
