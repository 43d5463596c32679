// OBJ keyframe sequences, PLY, procedural motion and JSON scene files.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>

#include <unistd.h>

#include "error_of.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/loaders.h"
#include "temp_dir.h"

namespace mbrt {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = mbrt::test::freshProcessDir("mbrt_test_seq_");

std::string put(const std::string& name, const std::string& text) {
  fs::create_directories((kDir / name).parent_path());
  std::ofstream(kDir / name, std::ios::binary) << text;
  return (kDir / name).string();
}

using test::errorOf;

// Key i: a quad moved by i along x; `fo` in the second face line.
std::string key(int i, const char* faces = "f 1 2 3 4\nfo 1 3 5\n") {
  std::string s;
  for (int v = 0; v < 5; ++v)
    s += "v " + std::to_string(v % 2 + i) + " " + std::to_string(v / 2) + " 0\n";
  return s + faces;
}

TEST(ObjSequence, KeysInNameOrderAtEquidistantTimes) {
  // Written out of order: the loader sorts by name.
  for (int i : {2, 0, 1}) put("seq/k_0" + std::to_string(i) + ".obj", key(i));
  put("seq/readme.txt", "not a key");
  for (const std::string& spec : {(kDir / "seq").string(), (kDir / "seq" / "k_*.obj").string()}) {
    const SceneDescription d = loadSceneSpec(spec);
    const Scene& s = *d.scene;
    ASSERT_EQ(s.numGeometries(), 1u);
    const Geometry& g = s.geometry(0);
    ASSERT_EQ(g.numSteps(), 3u);
    ASSERT_EQ(g.numPrimitives(), 3u);  // quad fanned into 2, plus the fo triangle
    EXPECT_EQ(g.triangles()[1].v0, 0u);
    EXPECT_EQ(g.triangles()[1].v1, 2u);
    EXPECT_EQ(g.triangles()[1].v2, 3u);
    for (uint32_t k = 0; k < 3; ++k) {
      EXPECT_FLOAT_EQ(g.stepTime(k), 0.5f * float(k));
      EXPECT_FLOAT_EQ(g.vertexAtStep(k, 0).x, float(k));
    }
  }
}

TEST(ObjSequence, DifferentFacesNameTheFile) {
  put("bad/a_0.obj", key(0));
  const std::string b = put("bad/a_1.obj", key(1, "f 1 2 3 4\nf 1 3 4\n"));
  std::string e = errorOf([&] { loadSceneSpec((kDir / "bad").string()); });
  EXPECT_NE(e.find(b + ": not the same mesh as"), std::string::npos) << e;
  EXPECT_NE(e.find("triangle 2"), std::string::npos) << e;
  put("bad2/a_0.obj", key(0));
  const std::string c = put("bad2/a_1.obj", key(1, "f 1 2 3 4\n"));
  e = errorOf([&] { loadSceneSpec((kDir / "bad2").string()); });
  EXPECT_NE(e.find(c + ": not the same mesh"), std::string::npos) << e;
  EXPECT_NE(e.find("2 triangles after fanning, the first file has 3"), std::string::npos) << e;
  // NaN in a key names the file and line.
  put("nan/a_0.obj", key(0));
  const std::string n = put("nan/a_1.obj", "v 0 0 0\nv nan 0 0\n" + key(1).substr(key(1).find('\n', 10)));
  e = errorOf([&] { loadSceneSpec((kDir / "nan").string()); });
  EXPECT_NE(e.find(n + ":2:"), std::string::npos) << e;
  // Nothing matches / an empty folder / a missing file.
  e = errorOf([&] { loadSceneSpec((kDir / "nothing_*.obj").string()); });
  EXPECT_NE(e.find("no file matches"), std::string::npos) << e;
  fs::create_directories(kDir / "empty");
  e = errorOf([&] { loadSceneSpec((kDir / "empty").string()); });
  EXPECT_NE(e.find("has no .obj files"), std::string::npos) << e;
  e = errorOf([&] { loadSceneSpec((kDir / "missing.ply").string()); });
  EXPECT_NE(e.find("missing.ply"), std::string::npos) << e;
}

TEST(ObjSequence, WoodDollHas29KeysOf6658Triangles) {
  const fs::path dir = fs::path(MBRT_SHARED_DIR) / "scenes" / "wooddoll_utah";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir << " (the shared scenes)";
  const auto t0 = std::chrono::steady_clock::now();
  const SceneDescription d = loadSceneSpec((dir / "wooddoll_*.obj").string());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ info ] Wood Doll: %.0f ms\n", ms);
  const Geometry& g = d.scene->geometry(0);
  EXPECT_EQ(d.scene->numGeometries(), 1u);
  EXPECT_EQ(g.numSteps(), 29u);
  EXPECT_EQ(g.numPrimitives(), 6658u);
  EXPECT_EQ(g.vertices(0).count, 3747u);
  EXPECT_FLOAT_EQ(g.stepTime(28), 1.0f);
  d.scene->validate();
}

TEST(Ply, AsciiAndBinary) {
  const std::string ascii = put("m.ply",
                                "ply\nformat ascii 1.0\ncomment x\nelement vertex 4\nproperty float x\nproperty float y\n"
                                "property float z\nproperty float confidence\nelement face 1\n"
                                "property list uchar int vertex_indices\nend_header\n"
                                "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n4 0 1 2 3\n");
  const ObjMesh a = readPly(ascii);
  ASSERT_EQ(a.positions.size(), 4u);
  ASSERT_EQ(a.triangles.size(), 2u);
  EXPECT_EQ(a.triangles[1].v1, 2u);
  // Binary little-endian: double positions, an extra uchar property, int16 counts.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                    "property double z\nproperty uchar red\nelement face 1\nproperty list short uint vertex_index\nend_header\n";
  auto raw = [&](const void* p, size_t n) { bin.append(static_cast<const char*>(p), n); };
  for (int v = 0; v < 3; ++v) {
    const double xyz[3] = {double(v), double(v * v), 0.5};
    raw(xyz, sizeof xyz);
    const uint8_t red = 7;
    raw(&red, 1);
  }
  const int16_t count = 3;
  raw(&count, 2);
  const uint32_t idx[3] = {2, 1, 0};
  raw(idx, sizeof idx);
  const std::string binary = put("b.ply", bin);
  const ObjMesh b = readPly(binary);
  ASSERT_EQ(b.positions.size(), 3u);
  EXPECT_FLOAT_EQ(b.positions[2].y, 4.0f);
  EXPECT_EQ(b.triangles[0].v0, 2u);
  // Truncated binary, bad index, NaN.
  const std::string cut = put("cut.ply", bin.substr(0, bin.size() - 5));
  EXPECT_NE(errorOf([&] { readPly(cut); }).find(cut + ": file ends"), std::string::npos);
  const std::string badIndex = put("bi.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                             "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  EXPECT_NE(errorOf([&] { readPly(badIndex); }).find("uses vertex 7 of 3"), std::string::npos);
  const std::string nan = put("nan.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                         "end_header\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
  const std::string e = errorOf([&] { readPly(nan); });
  EXPECT_NE(e.find(nan + ":11: vertex 1 has a non-finite"), std::string::npos) << e;
  EXPECT_NE(errorOf([&] { readPly(put("g.ply", "garbage")); }).find("not a PLY file"), std::string::npos);
}

TEST(Ply, StanfordBunny) {
  const fs::path p = fs::path(MBRT_SHARED_DIR) / "scenes" / "stanford_bunny" / "bun_zipper.ply";
  if (!fs::exists(p)) GTEST_SKIP() << "no " << p;
  const ObjMesh m = readPly(p.string());
  EXPECT_EQ(m.positions.size(), 35947u);
  EXPECT_EQ(m.triangles.size(), 69451u);
}

TEST(ProceduralMotion, TranslateAndRotate) {
  const std::string obj = put("tri.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n");
  LoadOptions o;
  o.motion = "translate:1,0,0;rotate:90:0,0,1";
  const SceneDescription d = loadSceneSpec(obj, o);
  const Geometry& g = d.scene->geometry(0);
  EXPECT_EQ(g.numSteps(), 10u);  // one step per 10 degrees
  // The box centre (1,1,0) turns in place and moves by +x.
  const Vec3f end = g.vertexAtStep(g.numSteps() - 1, 1);  // (2,0,0) -> about (1,1,0): (2,2,0) + (1,0,0)
  EXPECT_NEAR(end.x, 3.0f, 1e-5f);
  EXPECT_NEAR(end.y, 2.0f, 1e-5f);
  EXPECT_NE(errorOf([] { parseProceduralMotion("spin:3"); }).find("unknown part"), std::string::npos);
  EXPECT_NE(errorOf([] { parseProceduralMotion("translate:1,x,0"); }).find("bad number"), std::string::npos);
}

TEST(SceneFile, CombinesFilesScenesTransformsCameraAndColours) {
  put("sf/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  put("sf/keys/k0.obj", key(0));
  put("sf/keys/k1.obj", key(1));
  const std::string path = put("sf/scene.json", R"({
    // comments are allowed
    "camera": {"eye": [0, 0, 9], "target": [0, 0, 0], "fov": 30},
    "lights": [{"direction": [0, -1, 0], "radiance": [1, 1, 1]}],
    "sky": [0.1, 0.2, 0.3],
    "objects": [
      {"file": "tri.obj", "translate": [10, 0, 0], "scale": 2, "diffuse": [1, 0, 0]},
      {"sequence": "keys"},
      {"scene": "demo", "size": 0.02, "rotate": [90, 0, 1, 0]},
      {"file": "tri.obj", "motion": "translate:0,1,0"}
    ]
  })");
  const SceneDescription d = loadSceneSpec(path);
  d.scene->validate();
  const Scene& s = *d.scene;
  EXPECT_NEAR(s.geometry(0).vertexAtStep(0, 1).x, 12.0f, 1e-6f);
  EXPECT_EQ(d.material(0).diffuse.x, 1.0f);
  EXPECT_EQ(s.geometry(1).numSteps(), 2u);
  bool srt = false;
  for (uint32_t g = 0; g < s.numGeometries(); ++g) srt = srt || s.geometry(g).hasSRTKeys();
  EXPECT_TRUE(srt);  // the demo's propeller, rotated with the object
  EXPECT_EQ(s.geometry(s.numGeometries() - 1).numSteps(), 2u);
  EXPECT_FLOAT_EQ(d.camera.keys[0].verticalFovDegrees, 30.0f);
  EXPECT_FLOAT_EQ(d.skyColor.z, 0.3f);
  ASSERT_EQ(d.lights.size(), 1u);
  // Errors name the file and the problem.
  const std::string bad = put("sf/bad.json", R"({"objects": [{"file": "nope.obj"}]})");
  EXPECT_NE(errorOf([&] { loadSceneSpec(bad); }).find(bad + ": object 0: no file"), std::string::npos);
  const std::string bad2 = put("sf/bad2.json", R"({"objects": [{"scene": "demo", "colour": [1,0,0]}]})");
  EXPECT_NE(errorOf([&] { loadSceneSpec(bad2); }).find("unknown key 'colour'"), std::string::npos);
  const std::string bad3 = put("sf/bad3.json", R"({"objects": [)");
  EXPECT_NE(errorOf([&] { loadSceneSpec(bad3); }).find(bad3 + ": not valid JSON"), std::string::npos);
}

}  // namespace
}  // namespace mbrt
