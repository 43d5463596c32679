// Library-side I/O used by the `mbrt` command: PNG writer, OBJ loader, ray
// and hit files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "temp_dir.h"
#include "mbrt/accel.h"
#include "mbrt/io/image.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/ray_file.h"

using namespace mbrt;
using mbrt::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint32_t bigEndian32(const uint8_t* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

// The error message of `f`, or "" when it does not throw Error.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ---- PNG -------------------------------------------------------------------

TEST(PngWriter, WritesAReadablePng) {
  TempDir dir;
  Image image(37, 21);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image.at(x, y) = {x / 36.0f, y / 20.0f, 0.5f};
  const std::string path = dir.file("out.png");
  writePng(path, image);
  const auto bytes = readBytes(path);
  ASSERT_GT(bytes.size(), 33u);
  const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_TRUE(std::equal(signature, signature + 8, bytes.begin()));
  // The first chunk is IHDR: width and height big-endian, 8-bit RGB.
  EXPECT_EQ(std::string(bytes.begin() + 12, bytes.begin() + 16), "IHDR");
  EXPECT_EQ(bigEndian32(&bytes[16]), 37u);
  EXPECT_EQ(bigEndian32(&bytes[20]), 21u);
  EXPECT_EQ(bytes[24], 8);  // bit depth
  EXPECT_EQ(bytes[25], 2);  // colour type RGB
  // Ends with IEND.
  EXPECT_EQ(std::string(bytes.end() - 8, bytes.end() - 4), "IEND");
}

TEST(PngWriter, SrgbConversion) {
  EXPECT_EQ(linearToSrgb8(0.0f), 0);
  EXPECT_EQ(linearToSrgb8(1.0f), 255);
  EXPECT_EQ(linearToSrgb8(-3.0f), 0);
  EXPECT_EQ(linearToSrgb8(7.0f), 255);
  EXPECT_EQ(linearToSrgb8(std::nanf("")), 0);
  EXPECT_EQ(linearToSrgb8(0.5f), 188);      // 0.7354 * 255
  EXPECT_EQ(linearToSrgb8(0.001f), 3);      // linear segment: 12.92 * 0.001 * 255
  EXPECT_EQ(linearToSrgb8(0.22f), 129);
}

TEST(PngWriter, ErrorsNameThePath) {
  TempDir dir;
  Image image(2, 2);
  const std::string bad = dir.file("no/such/dir/out.png");
  const std::string msg = errorOf([&] { writePng(bad, image); });
  EXPECT_NE(msg.find(bad), std::string::npos) << msg;
  EXPECT_NE(errorOf([] { writePng("/tmp/x.png", Image()); }), "");
  EXPECT_THROW(Image(0, 5), Error);
  EXPECT_THROW(Image(5, -1), Error);
}

// ---- OBJ -------------------------------------------------------------------

TEST(ObjLoader, ReadsAllVertexForms) {
  TempDir dir;
  const std::string path = dir.write("good.obj",
                                     "# comment\r\n"
                                     "mtllib x.mtl\n"
                                     "o thing\n"
                                     "v 0 0 0\n"
                                     "v 1 0 0 1.0\n"        // w is dropped
                                     "v +1 1 0   # trailing comment\n"
                                     "v 0 1e0 0\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\n"
                                     "vn 0 0 1\n"
                                     "g group\nusemtl m\ns 1\n"
                                     "f 1 2 3\n"             // v
                                     "f 1/1 2/2 3/3\n"       // v/vt
                                     "f 1/1/1 3/3/1 4/2/1\n" // v/vt/vn
                                     "f 1//1 3//1 4//1\n"    // v//vn
                                     "f 1 2 3 4\n"           // quad: 2 triangles
                                     "f -4 -3 -2 -1\n"       // negative indices
                                     "fo 4 3 2\n"            // old keyword
                                     "l 1 2\n");
  const ObjMesh mesh = readObj(path);
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[1], Vec3f(1, 0, 0));
  EXPECT_EQ(mesh.positions[2], Vec3f(1, 1, 0));
  ASSERT_EQ(mesh.triangles.size(), 9u);
  auto tri = [&](size_t i) {
    const Triangle& t = mesh.triangles[i];
    return std::vector<uint32_t>{t.v0, t.v1, t.v2};
  };
  EXPECT_EQ(tri(0), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(tri(2), (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(tri(4), (std::vector<uint32_t>{0, 1, 2}));  // fan (a,b,c), (a,c,d)
  EXPECT_EQ(tri(5), (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(tri(6), (std::vector<uint32_t>{0, 1, 2}));  // -4 -3 -2 -1 = 1 2 3 4
  EXPECT_EQ(tri(7), (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(tri(8), (std::vector<uint32_t>{3, 2, 1}));
}

TEST(ObjLoader, NegativeIndicesAreRelativeToTheirLine) {
  std::istringstream in(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f -3 -2 -1\n"
      "v 5 5 5\n"
      "f -4 -3 -1\n");
  const ObjMesh mesh = readObj(in, "stream");
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0].v0, 0u);
  EXPECT_EQ(mesh.triangles[0].v2, 2u);
  EXPECT_EQ(mesh.triangles[1].v0, 0u);
  EXPECT_EQ(mesh.triangles[1].v1, 1u);
  EXPECT_EQ(mesh.triangles[1].v2, 3u);
}

TEST(ObjLoader, SceneTracesLikeTheFile) {
  TempDir dir;
  const std::string path = dir.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  auto scene = loadObjScene(path);
  ASSERT_EQ(scene->numGeometries(), 1u);
  EXPECT_EQ(scene->geometry(0).numSteps(), 1u);
  EXPECT_EQ(scene->geometry(0).numPrimitives(), 2u);
  BuildOptions opt;
  opt.kind = AccelKind::Brute;
  auto accel = Accel::build(*scene, opt);
  Ray ray{{-0.5f, 0.5f, 2.0f}, 0.0f, {0, 0, -1}, kInf, 0.3f};
  Hit hit;
  ASSERT_TRUE(accel->intersect(ray, hit));
  EXPECT_FLOAT_EQ(hit.t, 2.0f);
  EXPECT_EQ(hit.primID, 1u);  // the second triangle of the fan (1,3,4)
}

TEST(ObjLoader, MalformedFilesNameFileAndLine) {
  TempDir dir;
  struct Case {
    const char* text;
    const char* expect;  // part of the message after "file:line: "
    int line;
  };
  const Case cases[] = {
      {"v 0 0 0\nv 1 0 x\n", "bad number 'x'", 2},
      {"v 0 0\n", "'v' needs 3 coordinates", 1},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "vertex index 4 out of range", 5},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0 out of range", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "vertex index -4 out of range", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "at least 3 vertices", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3a\n", "bad vertex index '3a'", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", "texture coordinate index 2 out of range", 5},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", "normal index 1 out of range", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", "bad face vertex '1/'", 4},
      {"v 1e39 0 0\n", "number out of range", 1},
      {"v nan 0 0\n", "out of range", 1},
      {"v 0 0 0\nv 1 0 0\nvn 0 1\n", "'vn' needs 3 coordinates", 3},
  };
  for (const Case& c : cases) {
    const std::string path = dir.write("bad.obj", c.text);
    const std::string msg = errorOf([&] { readObj(path); });
    EXPECT_NE(msg.find(path + ":" + std::to_string(c.line) + ": "), std::string::npos) << c.text << " -> " << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.text << " -> " << msg;
  }
  // No faces at all, and missing files.
  const std::string empty = dir.write("empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_NE(errorOf([&] { readObj(empty); }).find("no faces"), std::string::npos);
  EXPECT_NE(errorOf([&] { readObj(dir.file("missing.obj")); }).find("cannot open"), std::string::npos);
  EXPECT_THROW(loadObjScene(empty), Error);
}

TEST(ObjLoader, ShippedCubeLoads) {
  const ObjMesh mesh = readObj(std::string(MBRT_SOURCE_DIR) + "/tests/data/cube.obj");
  EXPECT_EQ(mesh.positions.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
}

// ---- ray and hit files -------------------------------------------------------

TEST(RayFile, RoundTrip) {
  TempDir dir;
  std::vector<Ray> rays(3);
  rays[0] = Ray{{1, 2, 3}, 0.5f, {0, 0, -1}, kInf, 0.25f};
  rays[1] = Ray{{-1e-30f, 7, 8}, 0.0f, {1, 1, 1}, 100.0f, 1.0f};
  rays[2] = Ray{{0, 0, 0}, 2.0f, {0, 1, 0}, 1.0f, std::nanf("")};  // invalid rays survive too
  const std::string path = dir.file("rays.bin");
  writeRays(path, rays);
  EXPECT_EQ(fs::file_size(path), 3 * kRayRecordBytes);
  const std::vector<Ray> back = readRays(path);
  ASSERT_EQ(back.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].org, rays[i].org);
    EXPECT_EQ(back[i].dir, rays[i].dir);
    EXPECT_EQ(back[i].tnear, rays[i].tnear);
    EXPECT_EQ(back[i].tfar, rays[i].tfar);
    if (i < 2) EXPECT_EQ(back[i].time, rays[i].time);
  }
  EXPECT_TRUE(std::isnan(back[2].time));
  // Little-endian on disk: the first float is 1.0f = 0x3f800000.
  const auto bytes = readBytes(path);
  EXPECT_EQ(bytes[0], 0x00);
  EXPECT_EQ(bytes[2], 0x80);
  EXPECT_EQ(bytes[3], 0x3f);
}

TEST(RayFile, HitsRoundTripWithMisses) {
  TempDir dir;
  std::vector<Hit> hits(2);
  hits[0].t = 1.5f;
  hits[0].geomID = 3;
  hits[0].primID = 42;
  const std::string path = dir.file("hits.bin");
  writeHits(path, std::span<const Hit>(hits));
  EXPECT_EQ(fs::file_size(path), 2 * kHitRecordBytes);
  const auto back = readHits(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0], (HitRecord{1.5f, 3, 42}));
  EXPECT_TRUE(std::isinf(back[1].t) && back[1].t > 0);
  EXPECT_EQ(back[1].geomID, kInvalidId);
  EXPECT_EQ(back[1].primID, kInvalidId);
  EXPECT_FALSE(back[1].valid());
}

TEST(RayFile, BadSizesAndMissingFiles) {
  TempDir dir;
  const std::string path = dir.write("bad.bin", std::string(37, 'x'));
  const std::string msg = errorOf([&] { readRays(path); });
  EXPECT_NE(msg.find("not a multiple of 36"), std::string::npos) << msg;
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(errorOf([&] { readHits(path); }).find("not a multiple of 12"), std::string::npos);
  EXPECT_NE(errorOf([&] { readRays(dir.file("none.bin")); }).find("cannot open"), std::string::npos);
  EXPECT_NE(errorOf([&] { writeRays(dir.file("no/dir/r.bin"), std::vector<Ray>(1)); }).find("no folder"),
            std::string::npos);
  EXPECT_TRUE(readRays(dir.write("empty.bin", "")).empty());
}

TEST(RayFile, TracedFileHoldsTheExactHits) {
  // A triangle moving from z = 0 to z = 1 over the shutter, rays along +z
  // from z = -1: a ray at time s hits at t = 1 + s when x + y < 1 (y = 0.2).
  // The hit file written from stbvh's batched tracing of rays read back from
  // a ray file holds those hits, computed here by hand, not by another
  // structure.
  Scene scene;
  scene.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                                     {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}});
  BuildOptions opt;
  opt.kind = AccelKind::Stbvh;
  auto accel = Accel::build(scene, opt);
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i)
    rays.push_back(Ray{{0.2f + 0.01f * i, 0.2f, -1.0f}, 0.0f, {0, 0, 1}, kInf, i / 63.0f});
  TempDir dir;
  writeRays(dir.file("r.bin"), rays);
  const auto loaded = readRays(dir.file("r.bin"));
  ASSERT_EQ(encodeRays(loaded), encodeRays(rays));
  std::vector<Hit> hits(loaded.size());
  accel->intersect(loaded, hits);
  writeHits(dir.file("h.bin"), std::span<const Hit>(hits));
  const auto records = readHits(dir.file("h.bin"));
  ASSERT_EQ(records.size(), rays.size());
  size_t hitCount = 0;
  for (int i = 0; i < 64; ++i) {
    const HitRecord& r = records[size_t(i)];
    const float x = 0.2f + 0.01f * i;
    if (std::fabs(x + 0.2f - 1.0f) < 1e-4f) continue;  // on the edge x + y = 1: either answer is right
    if (x + 0.2f < 1.0f) {
      ASSERT_TRUE(r.valid()) << i;
      EXPECT_EQ(r.geomID, 0u);
      EXPECT_EQ(r.primID, 0u);
      // t = 1 + s up to float rounding of the interpolated vertex and of t:
      // 1e-6 is 8 ulps at t = 2.
      EXPECT_NEAR(r.t, 1.0f + i / 63.0f, 1e-6f) << i;
      ++hitCount;
    } else {
      EXPECT_EQ(r, HitRecord{}) << i;  // a miss: +inf and invalid ids
    }
  }
  EXPECT_EQ(hitCount, 60u);  // x = 0.2 .. 0.79
}
