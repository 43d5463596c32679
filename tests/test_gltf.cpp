// glTF loading: a tiny hand-made file (skin, morph targets, rigid and STEP
// animation) checked against positions computed by hand; the shared real
// models; bad input.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include <sys/stat.h>
#include <unistd.h>

#include "error_of.h"
#include "gltf_test_file.h"
#include "mbrt/io/gltf.h"
#include "mbrt/io/loaders.h"
#include "temp_dir.h"

namespace mbrt {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = mbrt::test::freshProcessDir("mbrt_test_gltf_");

std::string writeTestFile(const std::string& name, bool nanPosition = false) {
  return test::writeTinyGltf(kDir, name, nanPosition);
}

void expectNear(Vec3f a, Vec3f b, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, 1e-5f) << what;
  EXPECT_NEAR(a.y, b.y, 1e-5f) << what;
  EXPECT_NEAR(a.z, b.z, 1e-5f) << what;
}

using test::errorOf;

TEST(Gltf, HandMadeFileGivesHandComputedPositions) {
  const std::string path = writeTestFile("tiny");
  GltfOptions o;
  o.shutterOpen = 0.0;
  o.shutterClose = 1.0;
  o.steps.steps = 3;  // keys at 0, 0.5, 1 s
  const SceneDescription d = loadGltf(path, o);
  const Scene& s = *d.scene;
  ASSERT_EQ(s.numGeometries(), 3u);
  s.validate();
  // Skinned: v0 on joint 0 (still), v1 on joint 1 (moves up 2t), v2 half on each.
  const Geometry& g0 = s.geometry(0);
  ASSERT_EQ(g0.type(), GeometryType::Triangles);
  ASSERT_EQ(g0.numSteps(), 3u);
  for (uint32_t k = 0; k < 3; ++k) {
    const float t = 0.5f * float(k);
    expectNear(g0.vertexAtStep(k, 0), {0, 0, 0}, "skin v0");
    expectNear(g0.vertexAtStep(k, 1), {1, 2 * t, 0}, "skin v1");
    expectNear(g0.vertexAtStep(k, 2), {1, 1 + t, 0}, "skin v2");
  }
  // Morphed: weight w = 3t^2 - 2t^3 (0, 0.5, 1).
  const Geometry& g1 = s.geometry(1);
  ASSERT_EQ(g1.numSteps(), 3u);
  const float w[3] = {0.0f, 0.5f, 1.0f};
  for (uint32_t k = 0; k < 3; ++k) {
    expectNear(g1.vertexAtStep(k, 0), {5, 0, w[k]}, "morph v0");
    expectNear(g1.vertexAtStep(k, 1), {6, 0, 2 * w[k]}, "morph v1");
    expectNear(g1.vertexAtStep(k, 2), {5, 1, 0}, "morph v2");
  }
  EXPECT_NEAR(d.material(1).diffuse.y, 0.4f, 1e-6f);
  // Rigid: an SRT instance turning about z, STEP translation.
  const Geometry& g2 = s.geometry(2);
  ASSERT_EQ(g2.type(), GeometryType::Instance);
  ASSERT_TRUE(g2.hasSRTKeys());
  ASSERT_EQ(g2.numSteps(), 3u);
  expectNear(g2.transformAt(0.0f).xfmPoint({1, 0, 0}), {11, 0, 0}, "rigid t=0");
  const float c = std::sqrt(0.5f);
  expectNear(g2.transformAt(0.5f).xfmPoint({1, 0, 0}), {10 + c, c, 0}, "rigid t=0.5");
  expectNear(g2.transformAt(1.0f).xfmPoint({1, 0, 0}), {10, 1, 3}, "rigid t=1");
  // Between keys the slerp keeps the turn: at t=0.25, 22.5 degrees.
  expectNear(g2.transformAt(0.25f).xfmPoint({1, 0, 0}), {10 + std::cos(0.3926991f), std::sin(0.3926991f), 0}, "rigid t=0.25");
}

TEST(Gltf, AutomaticStepsDifferPerMesh) {
  const std::string path = writeTestFile("auto");
  GltfOptions o;
  o.shutterOpen = 0.0;
  o.shutterClose = 1.0;
  LoadReport report;
  const SceneDescription d = loadGltf(path, o, &report);
  EXPECT_EQ(d.scene->geometry(0).numSteps(), 2u);  // the skin moves linearly
  EXPECT_GT(d.scene->geometry(1).numSteps(), 3u);  // the cubic weight curve needs more
  EXPECT_GT(d.scene->geometry(2).numSteps(), 2u);  // the STEP jump needs keys around it
  EXPECT_FALSE(report.lines.empty());
}

TEST(Gltf, ShutterAndClips) {
  const std::string path = writeTestFile("shutter");
  // Default: the first clip from its start, 1/48 s.
  const SceneDescription d = loadGltf(path);
  EXPECT_DOUBLE_EQ(d.shutterOpen, 0.0);
  EXPECT_NEAR(d.shutterClose, 1.0 / 48.0, 1e-12);
  // A zero-length shutter: a sharp frame, every geometry S = 1.
  GltfOptions sharp;
  sharp.shutterOpen = sharp.shutterClose = 0.5;
  const SceneDescription f = loadGltf(path, sharp);
  for (uint32_t g = 0; g < f.scene->numGeometries(); ++g) EXPECT_EQ(f.scene->geometry(g).numSteps(), 1u);
  expectNear(f.scene->geometry(0).vertexAtStep(0, 2), {1, 1.5f, 0}, "sharp skin v2");
  // Clip by name and by index; unknown clip.
  GltfOptions byName;
  byName.clip = "other";
  EXPECT_NO_THROW(loadGltf(path, byName));
  byName.clip = "1";
  EXPECT_NO_THROW(loadGltf(path, byName));
  byName.clip = "walk";
  const std::string e = errorOf([&] { loadGltf(path, byName); });
  EXPECT_NE(e.find("no animation clip 'walk'"), std::string::npos) << e;
  EXPECT_NE(e.find("'move'"), std::string::npos) << e;
  // A shutter outside the clip.
  GltfOptions outside;
  outside.shutterOpen = 0.5;
  outside.shutterClose = 2.0;
  const std::string e2 = errorOf([&] { loadGltf(path, outside); });
  EXPECT_NE(e2.find("outside clip"), std::string::npos) << e2;
  EXPECT_NE(e2.find(path), std::string::npos) << e2;
}

TEST(Gltf, BadInputGivesClearErrors) {
  fs::create_directories(kDir);
  const std::string missing = (kDir / "missing.glb").string();
  EXPECT_NE(errorOf([&] { loadGltf(missing); }).find("cannot open '" + missing), std::string::npos);
  const std::string garbage = (kDir / "garbage.gltf").string();
  std::ofstream(garbage) << "{ this is not json";
  std::string e = errorOf([&] { loadGltf(garbage); });
  EXPECT_NE(e.find(garbage + ": not a valid glTF file"), std::string::npos) << e;
  // A truncated .glb: the header says more than there is.
  const std::string truncated = (kDir / "truncated.glb").string();
  {
    std::ofstream out(truncated, std::ios::binary);
    const uint32_t header[5] = {0x46546C67u, 2u, 4000u, 2000u, 0x4E4F534Au};
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    out << "{\"asset\":{\"version\":\"2.0\"}";
  }
  e = errorOf([&] { loadGltf(truncated); });
  EXPECT_NE(e.find(truncated + ": not a valid glTF file"), std::string::npos) << e;
  // A truncated buffer: the .bin is shorter than the accessors need.
  const std::string good = writeTestFile("cut");
  fs::resize_file(kDir / "cut.bin", 40);
  e = errorOf([&] { loadGltf(good); });
  EXPECT_NE(e.find(good), std::string::npos) << e;
  // NaN in the positions.
  const std::string nan = writeTestFile("nan", true);
  e = errorOf([&] { loadGltf(nan); });
  EXPECT_NE(e.find(nan + ": mesh 0 primitive 0 POSITION: element 0 is not finite"), std::string::npos) << e;
  // Through the general entry point too.
  e = errorOf([&] { loadSceneSpec(nan); });
  EXPECT_NE(e.find("not finite"), std::string::npos) << e;
}

// Found by fuzz_gltf: a node naming a camera the file does not have was
// used as the camera (out-of-bounds read).
TEST(Gltf, NodeNamingAMissingCameraIsRefused) {
  test::GltfWriter w;
  w.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  const std::string path = w.write(kDir, "missing_camera",
                                   "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
                                   "\"nodes\":[{\"mesh\":0},{\"camera\":3}],\"scenes\":[{\"nodes\":[0,1]}],\"scene\":0");
  const std::string e = errorOf([&] { loadGltf(path); });
  EXPECT_NE(e.find(path + ": node 1 uses camera 3 that does not exist"), std::string::npos) << e;
}

// External buffer URIs are read only when they name a regular file inside
// the glTF's folder whose size is a declared byteLength, checked before
// reading: never a device, a FIFO (which would block), a directory, a file
// elsewhere, or a file larger than declared.
TEST(Gltf, ExternalBufferUrisAreGuarded) {
  const fs::path dir = kDir / "uris";
  fs::create_directories(dir / "sub");
  const auto gltfNaming = [&](const std::string& uri, size_t byteLength = 100) {
    const fs::path p = dir / "buffer.gltf";
    std::ofstream(p) << "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"" << uri
                     << "\",\"byteLength\":" << byteLength << "}]}";
    return p.string();
  };
  const auto errorFor = [&](const std::string& uri, size_t byteLength = 100) {
    const std::string path = gltfNaming(uri, byteLength);
    return errorOf([&] { loadGltf(path); });
  };
  // An absolute URI is joined to the folder (tinygltf): not found there.
  EXPECT_NE(errorFor("/dev/zero").find("File not found : /dev/zero"), std::string::npos) << errorFor("/dev/zero");
  EXPECT_NE(errorFor("../../../../../../etc/passwd").find("outside the glTF's folder"), std::string::npos);
  EXPECT_NE(errorFor("sub/../buffer.gltf").find("outside the glTF's folder"), std::string::npos);
  EXPECT_NE(errorFor("sub").find("is not a regular file"), std::string::npos) << errorFor("sub");
  fs::create_symlink("/dev/zero", dir / "zero.bin");
  EXPECT_NE(errorFor("zero.bin").find("is not a regular file"), std::string::npos) << errorFor("zero.bin");
  ASSERT_EQ(::mkfifo((dir / "fifo.bin").c_str(), 0600), 0);
  EXPECT_NE(errorFor("fifo.bin").find("is not a regular file"), std::string::npos) << errorFor("fifo.bin");
  // A huge (sparse) file: refused by its size, not read.
  std::ofstream(dir / "huge.bin").put('x');
  fs::resize_file(dir / "huge.bin", uintmax_t(1) << 40);
  EXPECT_NE(errorFor("huge.bin").find("1099511627776 bytes, the size of no declared buffer"), std::string::npos)
      << errorFor("huge.bin");
  fs::resize_file(dir / "huge.bin", 100);
  // The declared size: read (the file has no meshes, which is another error).
  EXPECT_EQ(errorFor("huge.bin").find("huge.bin"), std::string::npos) << errorFor("huge.bin");
  EXPECT_NE(errorFor("sub/../huge.bin").find("outside the glTF's folder"), std::string::npos);
  EXPECT_NE(errorFor("missing.bin").find("File not found"), std::string::npos) << errorFor("missing.bin");
  // The glTF itself must be a regular file.
  EXPECT_NE(errorOf([&] { loadGltf((dir / "sub").string()); }).find("is not a regular file"), std::string::npos);
  EXPECT_NE(errorOf([&] { loadGltf((dir / "fifo.bin").string()); }).find("is not a regular file"), std::string::npos);
}

// The shared real models (skipped without ../shared).
TEST(Gltf, SharedModelsLoadWithPlausibleBounds) {
  const fs::path dir = fs::path(MBRT_SHARED_DIR) / "scenes";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir << " (the shared scenes)";
  const char* files[] = {"cesium_man/CesiumMan.glb", "fox/Fox.glb", "rigged_figure/RiggedFigure.glb",
                         "rigged_simple/RiggedSimple.glb", "animated_morph_sphere/AnimatedMorphSphere.glb"};
  for (const char* f : files) {
    const std::string path = (dir / f).string();
    if (!fs::exists(path)) {
      ADD_FAILURE() << "missing " << path;
      continue;
    }
    LoadReport report;
    const auto t0 = std::chrono::steady_clock::now();
    const SceneDescription d = loadGltf(path, {}, &report);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    d.scene->validate();
    Box3f box;
    uint32_t most = 0;
    for (uint32_t g = 0; g < d.scene->numGeometries(); ++g) {
      const Geometry& geom = d.scene->geometry(g);
      most = std::max(most, geom.numSteps());
      if (geom.type() != GeometryType::Triangles) continue;
      for (uint32_t k = 0; k < geom.numSteps(); ++k)
        for (size_t i = 0; i < geom.vertices(k).count; ++i) box.extend(geom.vertexAtStep(k, uint32_t(i)));
    }
    ASSERT_FALSE(box.empty()) << f;
    EXPECT_TRUE(isFinite(box.lower) && isFinite(box.upper)) << f;
    const float size = maxComponent(box.size());
    EXPECT_GT(size, 1e-3f) << f;
    EXPECT_LT(size, 1e4f) << f;
    std::string lines;
    for (const auto& l : report.lines) lines += "\n  " + l;
    std::printf("[ info ] %s: %.1f ms, %u geometries, up to %u steps, size %.3g%s\n", f, ms,
                d.scene->numGeometries(), most, size, lines.c_str());
  }
  // Fox has 3 clips: each loads, by index and by name.
  const std::string fox = (dir / "fox/Fox.glb").string();
  if (fs::exists(fox)) {
    for (const char* clip : {"0", "1", "2"}) {
      GltfOptions o;
      o.clip = clip;
      EXPECT_NO_THROW(loadGltf(fox, o)) << clip;
    }
    GltfOptions o;
    o.clip = "Run";
    EXPECT_NO_THROW(loadGltf(fox, o));
  }
}

}  // namespace
}  // namespace mbrt
