// Materials and textures: lookups on a tiny glTF and a tiny OBJ + .mtl
// written here, checked against hand-computed colours; missing and corrupt
// textures; the stage; the framing of a closed room; the shared models.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "error_of.h"
#include "mbrt/io/image.h"
#include "mbrt/io/loaders.h"
#include "mbrt/io/texture.h"
#include "mbrt/render.h"
#include "temp_dir.h"
#include "test_util.h"

namespace mbrt {
namespace {

using test::errorOf;
using test::TempDir;

// The sRGB curve undone, written out independently of the renderer's table.
float linear(int byte) {
  const double c = byte / 255.0;
  return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

// A 2x2 PNG with the sRGB bytes given, top row first: TL, TR, BL, BR.
std::vector<uint8_t> png2x2(const std::array<std::array<int, 3>, 4>& texels) {
  // encodePng applies the sRGB curve to linear values: give it the linear
  // value of each byte, which it maps back to the same byte.
  Image img(2, 2);
  for (int i = 0; i < 4; ++i) img.at(i % 2, i / 2) = {linear(texels[i][0]), linear(texels[i][1]), linear(texels[i][2])};
  return encodePng(img);
}

const std::array<std::array<int, 3>, 4> kTexels{{{255, 0, 0}, {0, 128, 0}, {0, 0, 64}, {200, 200, 200}}};

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A unit quad in z = 0 (vertices (0,0), (1,0), (1,1), (0,1)) with texture
// coordinates (x, 1 - y), a base colour factor (0.5, 1, 0.25) and a 2x2
// texture: "file" (tex.png beside the glTF), "view" (PNG inside the .bin) or
// "none" (no texture). `sampler`: the glTF sampler's JSON.
std::string writeQuad(const TempDir& dir, const std::string& source, const std::string& sampler,
                      const std::vector<uint8_t>& pngBytes) {
  std::vector<uint8_t> bin;
  auto put = [&](const void* p, size_t n) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t at = bin.size();
    bin.insert(bin.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
    return at;
  };
  const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const float uv[] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
  const size_t p0 = put(pos, sizeof pos), p1 = put(uv, sizeof uv), p2 = put(idx, sizeof idx);
  const size_t p3 = put(pngBytes.data(), pngBytes.size());
  writeBytes(dir.file("quad.bin"), bin);
  if (source == "file") writeBytes(dir.file("tex.png"), pngBytes);
  auto view = [](size_t off, size_t len) {
    return "{\"buffer\":0,\"byteOffset\":" + std::to_string(off) + ",\"byteLength\":" + std::to_string(len) + "}";
  };
  const std::string image = source == "view" ? "{\"bufferView\":3,\"mimeType\":\"image/png\"}" : "{\"uri\":\"tex.png\"}";
  const std::string texture = source == "none" ? "" : ",\"baseColorTexture\":{\"index\":0}";
  const std::string json =
      "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"quad.bin\",\"byteLength\":" + std::to_string(bin.size()) +
      "}],\"bufferViews\":[" + view(p0, sizeof pos) + "," + view(p1, sizeof uv) + "," + view(p2, sizeof idx) + "," +
      view(p3, pngBytes.size()) +
      "],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
      "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
      "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
      "\"images\":[" + image + "],\"samplers\":[" + sampler + "],\"textures\":[{\"source\":0,\"sampler\":0}],"
      "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,1,0.25,1]" + texture + "}}],"
      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":0}]}],"
      "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
  return dir.write("quad.gltf", json);
}

constexpr const char* kNearestClamp = "{\"magFilter\":9728,\"wrapS\":33071,\"wrapT\":33071}";
constexpr const char* kLinearRepeat = "{\"magFilter\":9729}";

Vec3f texelColor(int i) { return {linear(kTexels[i][0]), linear(kTexels[i][1]), linear(kTexels[i][2])}; }
const Vec3f kFactor{0.5f, 1.0f, 0.25f};

void expectColor(Vec3f got, Vec3f want, const std::string& what) {
  EXPECT_NEAR(got.x, want.x, 1e-5f) << what;
  EXPECT_NEAR(got.y, want.y, 1e-5f) << what;
  EXPECT_NEAR(got.z, want.z, 1e-5f) << what;
}

// A hit on triangle `prim` of the quad with barycentrics (u, v).
Hit quadHit(uint32_t prim, float u, float v) {
  Hit h;
  h.t = 1.0f;
  h.u = u;
  h.v = v;
  h.Ng = {0, 0, 1};
  h.geomID = 0;
  h.primID = prim;
  return h;
}

TEST(Materials, GltfTextureLookupAtKnownBarycentrics) {
  for (const std::string source : {"file", "view"}) {
    TempDir dir;
    const SceneDescription d = loadGltf(writeQuad(dir, source, kNearestClamp, png2x2(kTexels)));
    ASSERT_EQ(d.textures.size(), 1u) << source;
    EXPECT_EQ(d.textures[0].width, 2);
    ASSERT_EQ(d.surfaces.size(), 1u);
    ASSERT_EQ(d.surfaces[0].texcoords.size(), 4u);
    // Triangle 0 = (v0, v1, v2): uv = w0 (0,1) + u (1,1) + v (1,0) = (u + v, 1 - v).
    // (u, v) = (0.1, 0.1): uv (0.2, 0.9), bottom-left texel.
    expectColor(albedoAt(d, quadHit(0, 0.1f, 0.1f)), kFactor * texelColor(2), source + " bottom-left");
    // (0.6, 0.2): uv (0.8, 0.8), bottom-right texel.
    expectColor(albedoAt(d, quadHit(0, 0.6f, 0.2f)), kFactor * texelColor(3), source + " bottom-right");
    // Triangle 1 = (v0, v2, v3): uv = w0 (0,1) + u (1,0) + v (0,0) = (u, w0).
    // (0.3, 0.1): uv (0.3, 0.6) bottom-left; (0.2, 0.7): uv (0.2, 0.1) top-left.
    expectColor(albedoAt(d, quadHit(1, 0.3f, 0.1f)), kFactor * texelColor(2), source + " t1 bottom-left");
    expectColor(albedoAt(d, quadHit(1, 0.2f, 0.7f)), kFactor * texelColor(0), source + " top-left");
    // (0.7, 0.1): uv (0.7, 0.2), top-right.
    expectColor(albedoAt(d, quadHit(1, 0.7f, 0.1f)), kFactor * texelColor(1), source + " top-right");
  }
}

TEST(Materials, BilinearFilteringAndRepeat) {
  TempDir dir;
  const SceneDescription d = loadGltf(writeQuad(dir, "file", kLinearRepeat, png2x2(kTexels)));
  const Texture& t = d.textures.at(0);
  EXPECT_FALSE(t.nearest);
  // At texel centres, the texel itself.
  expectColor(textureColor(t, {0.25f, 0.25f}), texelColor(0), "centre TL");
  expectColor(textureColor(t, {0.75f, 0.75f}), texelColor(3), "centre BR");
  // Halfway between TL and TR centres, and the middle of all four.
  expectColor(textureColor(t, {0.5f, 0.25f}), (texelColor(0) + texelColor(1)) * 0.5f, "TL|TR");
  expectColor(textureColor(t, {0.5f, 0.5f}),
              (texelColor(0) + texelColor(1) + texelColor(2) + texelColor(3)) * 0.25f, "middle");
  // Repeat: u = 0 lies between the last and the first column: 1/4 of the
  // way from TR (x = -0.5 wraps to column 1) ... exactly halfway.
  expectColor(textureColor(t, {0.0f, 0.25f}), (texelColor(0) + texelColor(1)) * 0.5f, "wrap u");
  expectColor(textureColor(t, {1.25f, -0.75f}), texelColor(0), "repeat");
  // (u, v) = (0.375, 0.25): 3/4 TL, 1/4 TR.
  expectColor(textureColor(t, {0.375f, 0.25f}), texelColor(0) * 0.75f + texelColor(1) * 0.25f, "3/4");
  // Through an actual trace: the hit's barycentrics pick the same colour.
  auto accel = test::buildKind(*d.scene, AccelKind::Brute);
  Ray r;
  r.org = {0.375f, 0.75f, 1.0f};  // uv (x, 1 - y) = (0.375, 0.25)
  r.dir = {0, 0, -1};
  Hit h;
  ASSERT_TRUE(accel->intersect(r, h));
  expectColor(albedoAt(d, h), kFactor * (texelColor(0) * 0.75f + texelColor(1) * 0.25f), "traced");
}

TEST(Materials, AoRenderShowsTheTexture) {
  TempDir dir;
  SceneDescription d = loadGltf(writeQuad(dir, "file", kNearestClamp, png2x2(kTexels)));
  auto accel = test::buildKind(*d.scene, AccelKind::Brute);
  RenderOptions o;
  o.width = o.height = 16;
  o.spp = 1;
  o.integrator = IntegratorKind::Ao;
  const RenderResult r = render(d, *accel, o);
  const RenderCamera camera(d, o.width, o.height, o.shutterOpen, o.shutterClose);
  int hits = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      Hit h;
      if (!accel->intersect(primaryRay(camera, o, x, y, 0), h)) continue;
      ++hits;
      // A flat quad with nothing above: every occlusion ray is open.
      const Vec3f want = albedoAt(d, h);
      const Rgb got = r.image.at(x, y);
      expectColor({got.r, got.g, got.b}, want, "pixel " + std::to_string(x) + "," + std::to_string(y));
    }
  EXPECT_GT(hits, 16);
}

TEST(Materials, FactorWithoutTextureAndBadTextures) {
  TempDir dir;
  const SceneDescription plain = loadGltf(writeQuad(dir, "none", kNearestClamp, png2x2(kTexels)));
  EXPECT_TRUE(plain.textures.empty());
  expectColor(albedoAt(plain, quadHit(0, 0.1f, 0.1f)), kFactor, "factor only");

  // A missing texture file and a corrupt one: an Error naming the image.
  TempDir missing;
  const std::string path = writeQuad(missing, "file", kNearestClamp, png2x2(kTexels));
  std::filesystem::remove(missing.file("tex.png"));
  EXPECT_NE(errorOf([&] { loadGltf(path); }).find("tex.png"), std::string::npos) << errorOf([&] { loadGltf(path); });
  std::vector<uint8_t> corrupt = png2x2(kTexels);
  corrupt.resize(corrupt.size() / 2);  // truncated
  TempDir bad;
  const std::string e = errorOf([&] { loadGltf(writeQuad(bad, "view", kNearestClamp, corrupt)); });
  EXPECT_NE(e.find("image 0"), std::string::npos) << e;
  EXPECT_NE(e.find("corrupt"), std::string::npos) << e;
  const std::vector<uint8_t> garbage{'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'};
  EXPECT_NE(errorOf([&] { decodeTexture(garbage, "g.png"); }).find("g.png: not a PNG or JPEG"), std::string::npos);
  EXPECT_NE(errorOf([&] { readTexture(dir.file("absent.png")); }).find("absent.png"), std::string::npos);

  // A description whose surfaces do not fit the scene is refused by render().
  SceneDescription wrong = loadGltf(writeQuad(dir, "file", kNearestClamp, png2x2(kTexels)));
  wrong.surfaces[0].texcoords.pop_back();
  auto accel = test::buildKind(*wrong.scene, AccelKind::Brute);
  RenderOptions o;
  o.width = o.height = 4;
  EXPECT_NE(errorOf([&] { render(wrong, *accel, o); }).find("3 texture coordinates for 4 vertices"), std::string::npos);
}

// Two quads side by side (x in [0,1] and [1,2]): the first with material
// "red" (Kd), the second "tex" (map_Kd with options, texture coordinates).
std::string writeObj(const TempDir& dir, const std::string& mapLine) {
  writeBytes(dir.file("t.png"), png2x2(kTexels));
  dir.write("m.mtl", "newmtl red\nKd 0.8 0.1 0.2\nnewmtl tex\nKd 1 1 1\n" + mapLine + "\n");
  return dir.write("m.obj",
                   "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                   "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                   "usemtl red\nf 1 2 3 4\nusemtl tex\nf 2/1 5/2 6/3 3/4\n");
}

TEST(Materials, ObjMtlDiffuseAndMap) {
  TempDir dir;
  const SceneDescription d = loadSceneSpec(writeObj(dir, "map_Kd -s 1 1 1 t.png"));
  ASSERT_EQ(d.surfaces.size(), 1u);
  const GeometrySurface& s = d.surfaces[0];
  ASSERT_EQ(d.textures.size(), 1u);
  ASSERT_EQ(s.faceMaterials.size(), 4u);
  expectColor(s.materials[s.faceMaterials[0]].diffuse, {0.8f, 0.1f, 0.2f}, "Kd");
  EXPECT_EQ(s.materials[s.faceMaterials[0]].texture, -1);
  EXPECT_EQ(s.materials[s.faceMaterials[2]].texture, 0);
  // Vertex 2 and 3 (1-based) are used with and without vt: split into 8 vertices.
  const Geometry& g = d.scene->geometry(0);
  EXPECT_EQ(g.vertices(0).count, 8u);
  ASSERT_EQ(s.texcoords.size(), 8u);
  // Triangle 2 = (2/1, 5/2, 6/3): vt (0,0), (1,0), (1,1), v flipped: (0,1), (1,1), (1,0).
  Hit h;
  h.geomID = 0;
  h.primID = 2;
  // Bilinear and repeating (no sampler in OBJ): looked up at texel centres.
  h.u = 0.5f;  // uv = w0 (0,1) + u (1,1) + v (1,0) = (0.75, 0.75): the bottom-right texel
  h.v = 0.25f;
  expectColor(albedoAt(d, h), texelColor(3), "map_Kd bottom-right");
  h.u = 0.0f;  // uv (0.25, 0.75): bottom-left
  expectColor(albedoAt(d, h), texelColor(2), "map_Kd bottom-left");
  h.primID = 0;
  expectColor(albedoAt(d, h), {0.8f, 0.1f, 0.2f}, "Kd face");
}

TEST(Materials, ObjBadMaterialFiles) {
  TempDir dir;
  std::string obj = writeObj(dir, "map_Kd missing.png");
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("missing.png"), std::string::npos);
  dir.write("m.mtl", "Kd 1 1 1\n");
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("m.mtl:1: 'Kd' before the first 'newmtl'"), std::string::npos)
      << errorOf([&] { loadSceneSpec(obj); });
  dir.write("m.mtl", "newmtl red\nKd 2 0 0\n");
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("[0, 1]"), std::string::npos);
  dir.write("m.mtl", "newmtl red\n");
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("usemtl 'tex' is not defined"), std::string::npos);
  std::filesystem::remove(dir.file("m.mtl"));
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("m.mtl"), std::string::npos);
  writeBytes(dir.file("t.png"), {1, 2, 3, 4, 5});
  dir.write("m.mtl", "newmtl red\nnewmtl tex\nmap_Kd t.png\n");
  EXPECT_NE(errorOf([&] { loadSceneSpec(obj); }).find("t.png"), std::string::npos);
}

TEST(Materials, StageUnderALoadedModelOnly) {
  TempDir dir;
  SceneDescription d = loadGltf(writeQuad(dir, "file", kNearestClamp, png2x2(kTexels)));
  const Box3f before = sceneBounds(*d.scene);
  ASSERT_TRUE(addStage(d));
  ASSERT_EQ(d.scene->numGeometries(), 2u);
  d.scene->validate();
  const Geometry& ground = d.scene->geometry(1);
  EXPECT_LT(ground.vertexAtStep(0, 0).y, before.lower.y);
  // The quad (z = 0 plane, y in [0,1]) stands on the ground; a point of the
  // ground behind it, lit by a sun from +z above, is in its shadow.
  d.lights = {DirectionalLight{normalize(Vec3f{0, -1, -1}), {1, 1, 1}}};
  auto accel = test::buildKind(*d.scene, AccelKind::Brute);
  auto sunRayFrom = [&](Vec3f p) {
    Ray r;
    r.org = p;
    r.dir = -d.lights[0].direction;
    return r;
  };
  const float y = ground.vertexAtStep(0, 0).y + 1e-4f;
  EXPECT_TRUE(accel->occluded(sunRayFrom({0.5f, y, -0.5f})));
  EXPECT_FALSE(accel->occluded(sunRayFrom({0.5f, y, 3.0f})));
  // The ground is checkered, the quad keeps its texture.
  Hit h;
  Ray down;
  down.org = {5.0f, 10.0f, 5.0f};
  down.dir = {0, -1, 0};
  ASSERT_TRUE(accel->intersect(down, h));
  EXPECT_EQ(h.geomID, 1u);
  EXPECT_GT(dot(h.Ng, Vec3f{0, 1, 0}), 0.0f);
  const Vec3f c = albedoAt(d, h);
  EXPECT_TRUE(std::abs(c.x - linear(200)) < 1e-5f || std::abs(c.x - linear(165)) < 1e-5f) << c.x;
  expectColor(albedoAt(d, quadHit(0, 0.1f, 0.1f)), kFactor * texelColor(2), "model");
  // A built-in scene brings its own environment: no stage.
  SceneDescription suite = loadSceneSpec("translate", {.size = 0.01});
  const uint32_t n = suite.scene->numGeometries();
  EXPECT_FALSE(addStage(suite));
  EXPECT_EQ(suite.scene->numGeometries(), n);
}

TEST(Materials, SceneFilesKeepTexturesAndMayAskForTheStage) {
  TempDir dir;
  writeQuad(dir, "file", kNearestClamp, png2x2(kTexels));
  const std::string path = dir.write(
      "s.json",
      "{\"stage\": true, \"objects\": [{\"file\": \"quad.gltf\"}, {\"file\": \"quad.gltf\", \"translate\": [2, 0, 0]},"
      " {\"file\": \"quad.gltf\", \"translate\": [4, 0, 0], \"diffuse\": [0.1, 0.2, 0.3]}]}");
  SceneDescription d = loadSceneSpec(path);
  EXPECT_FALSE(d.bringsEnvironment);
  ASSERT_EQ(d.textures.size(), 3u);  // one per object
  ASSERT_EQ(d.materials.size(), 3u);
  EXPECT_EQ(d.materials[1].texture, 1);
  Hit h = quadHit(0, 0.1f, 0.1f);
  h.geomID = 1;
  expectColor(albedoAt(d, h), kFactor * texelColor(2), "second object");
  h.geomID = 2;  // "diffuse" replaces the factor, the texture stays
  expectColor(albedoAt(d, h), Vec3f{0.1f, 0.2f, 0.3f} * texelColor(2), "diffuse override");
  EXPECT_TRUE(addStage(d));
  const std::string plain = dir.write("p.json", "{\"objects\": [{\"file\": \"quad.gltf\"}]}");
  EXPECT_TRUE(loadSceneSpec(plain).bringsEnvironment);
  const std::string bad = dir.write("b.json", "{\"stage\": 1, \"objects\": [{\"file\": \"quad.gltf\"}]}");
  EXPECT_NE(errorOf([&] { loadSceneSpec(bad); }).find("'stage' must be true or false"), std::string::npos);
}

// An axis-aligned box [0,sx]x[0,sy]x[0,sz] as 12 triangles, facing inwards
// (a room) or outwards (a solid).
std::shared_ptr<Scene> boxScene(Vec3f size, bool inwards) {
  std::vector<Vec3f> v;
  for (int i = 0; i < 8; ++i) v.push_back({i & 1 ? size.x : 0, i & 2 ? size.y : 0, i & 4 ? size.z : 0});
  // Outward-facing quads (counter-clockwise seen from outside).
  const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Triangle> t;
  for (const auto& f : q) {
    t.push_back({f[0], f[1], f[2]});
    t.push_back({f[0], f[2], f[3]});
  }
  if (inwards)
    for (Triangle& tri : t) std::swap(tri.v1, tri.v2);
  auto s = std::make_shared<Scene>();
  s->addTriangleMesh(std::move(t), std::vector<std::vector<Vec3f>>{std::move(v)});
  return s;
}

bool inside(const Box3f& b, Vec3f p) {
  return p.x > b.lower.x && p.x < b.upper.x && p.y > b.lower.y && p.y < b.upper.y && p.z > b.lower.z && p.z < b.upper.z;
}

TEST(Materials, DefaultFramingFromInsideAClosedRoom) {
  const Vec3f size{10, 4, 6};
  const Box3f box = sceneBounds(*boxScene(size, true));
  const CameraSpec room = frameScene(*boxScene(size, true));
  EXPECT_TRUE(inside(box, room.eye));
  EXPECT_GT(room.target.x, room.eye.x);  // along the longer axis
  const CameraSpec solid = frameScene(*boxScene(size, false));
  EXPECT_FALSE(inside(box, solid.eye));
  EXPECT_GT(solid.eye.z, box.upper.z);  // the usual view from the front
}

// ---- the shared models (skipped when ../shared is absent) ----

std::string shared(const std::string& rel) {
  const std::string p = std::string(MBRT_SHARED_DIR) + "/scenes/" + rel;
  return std::filesystem::exists(p) ? p : std::string();
}

TEST(Materials, SharedModelsRenderWithTheirTextures) {
  for (const std::string rel : {"cesium_man/CesiumMan.glb", "fox/Fox.glb"}) {
    const std::string path = shared(rel);
    if (path.empty()) GTEST_SKIP() << "../shared/scenes/" << rel << " is absent";
    const SceneDescription d = loadSceneSpec(path);
    ASSERT_FALSE(d.textures.empty()) << rel;
    EXPECT_GT(d.textures[0].width, 1) << rel;
    ASSERT_FALSE(d.surfaces.empty()) << rel;
    EXPECT_FALSE(d.surfaces[0].texcoords.empty()) << rel;
    // Primary hits see more than one colour: the texture, not a flat albedo.
    auto accel = test::buildKind(*d.scene, AccelKind::BvhInterp);
    RenderOptions o;
    o.width = o.height = 24;
    const RenderCamera camera(d, o.width, o.height, 0.0f, 1.0f);
    std::vector<Vec3f> seen;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        Hit h;
        if (accel->intersect(primaryRay(camera, o, x, y, 0), h)) seen.push_back(albedoAt(d, h));
      }
    ASSERT_GT(seen.size(), 10u) << rel;
    float spread = 0.0f;
    for (const Vec3f& c : seen) {
      const Vec3f d = c - seen[0];
      spread = std::max({spread, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    }
    EXPECT_GT(spread, 0.05f) << rel;
  }
}

TEST(Materials, SponzaIsFramedFromInside) {
  const std::string path = shared("sponza_dabrovic/sponza.obj");
  if (path.empty()) GTEST_SKIP() << "../shared/scenes/sponza_dabrovic is absent";
  const SceneDescription d = loadSceneSpec(path);
  EXPECT_TRUE(inside(sceneBounds(*d.scene), d.camera.keys.at(0).eye));
}

}  // namespace
}  // namespace mbrt
