// The reader of MBRT_EMBREE_DUMP files (scene_dump_read.h; the layout is
// written down in embree_api/src/scene_dump.cpp).
#include "scene_dump_read.h"

#include <cstdio>
#include <cstring>

#include "mbrt/error.h"

namespace mbrt::embree_test {
namespace {

class Reader {
 public:
  explicit Reader(std::vector<uint32_t> w) : w_(std::move(w)) {}
  uint32_t word() {
    if (at_ >= w_.size()) throw Error("scene dump: truncated");
    return w_[at_++];
  }
  float real() {
    const uint32_t x = word();
    float f;
    std::memcpy(&f, &x, 4);
    return f;
  }
  Vec3f vec() {
    const float x = real(), y = real(), z = real();
    return {x, y, z};
  }
  std::vector<Affine3f> matrices(uint32_t n) {
    std::vector<Affine3f> m(n);
    for (Affine3f& a : m) a.vx = vec(), a.vy = vec(), a.vz = vec(), a.p = vec();
    return m;
  }

 private:
  std::vector<uint32_t> w_;
  size_t at_ = 0;
};

void readScene(Reader& r, SceneDump& dump) {
  DumpedScene s;
  s.scene = std::make_shared<Scene>();
  const uint32_t n = r.word();
  for (uint32_t id = 0; id < n; ++id) {
    DumpedGeometry g;
    g.instance = r.word() == 1;
    g.embreeID = r.word();
    const uint32_t mask = r.word();
    const float lo = r.real(), hi = r.real();
    const uint32_t steps = r.word();
    g.filtered = r.word() == 1;
    s.filtered = s.filtered || g.filtered;
    uint32_t got;
    if (!g.instance) {
      g.quads = r.word() == 1;
      g.kept.resize(r.word());
      for (uint32_t& k : g.kept) k = r.word();
      std::vector<Triangle> tris(r.word());
      for (Triangle& t : tris) t.v0 = r.word(), t.v1 = r.word(), t.v2 = r.word();
      const uint32_t count = r.word();
      std::vector<std::vector<Vec3f>> pos(steps, std::vector<Vec3f>(count));
      for (auto& step : pos)
        for (Vec3f& p : step) p = r.vec();
      got = s.scene->addTriangleMesh(std::move(tris), std::move(pos), {lo, hi});
    } else {
      g.child = r.word();
      if (g.child >= dump.scenes.size()) throw Error("scene dump: instance of a scene not read yet");
      std::shared_ptr<const Scene> child = dump.scenes[g.child].scene;
      s.filtered = s.filtered || dump.scenes[g.child].filtered;
      const bool srt = r.word() == 1;
      std::vector<SRTKey> keys;
      std::vector<Affine3f> matrices;
      if (srt) {
        keys.resize(steps);
        for (SRTKey& k : keys) {
          k.scale = r.vec();
          k.rotation.w = r.real(), k.rotation.x = r.real(), k.rotation.y = r.real(), k.rotation.z = r.real();
          k.translation = r.vec();
        }
      } else {
        matrices = r.matrices(steps);
      }
      if (r.word() == 1) {  // pivot: the S matrices as an inner instance
        auto inner = std::make_shared<Scene>();
        inner->addInstance(child, r.matrices(steps), {lo, hi});
        child = inner;
      }
      got = srt ? s.scene->addInstance(child, keys, {lo, hi}) : s.scene->addInstance(child, matrices, {lo, hi});
    }
    s.scene->setMask(got, mask);
    s.geometries.push_back(std::move(g));
  }
  dump.scenes.push_back(std::move(s));
}

uint32_t mbrtPrim(const DumpedGeometry& g, uint32_t prim, float u, float v) {
  const uint32_t want = g.quads ? 2 * prim + (u + v > 1.0f ? 1 : 0) : prim;
  if (g.kept.empty()) return want;
  for (uint32_t i = 0; i < g.kept.size(); ++i)
    if (g.kept[i] == want) return i;
  return kInvalidId;
}

}  // namespace

SceneDump readSceneDump(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("scene dump: cannot open " + path);
  char magic[8];
  std::vector<uint32_t> words;
  const bool ok = std::fread(magic, 1, 8, f) == 8 && std::memcmp(magic, "MBRTEMB1", 8) == 0;
  uint32_t w;
  while (ok && std::fread(&w, 4, 1, f) == 1) words.push_back(w);
  std::fclose(f);
  if (!ok) throw Error("scene dump: " + path + " is not an MBRT_EMBREE_DUMP file");
  Reader r(std::move(words));
  SceneDump dump;
  const uint32_t count = r.word();
  for (uint32_t i = 0; i < count; ++i) readScene(r, dump);
  if (dump.scenes.empty()) throw Error("scene dump: no scene");
  return dump;
}

Hit SceneDump::toMbrtHit(uint32_t geomID, uint32_t primID, uint32_t instID, float t, float u, float v) const {
  Hit h;
  const DumpedScene& top = scenes.back();
  const DumpedScene* where = &top;
  if (instID != kInvalidId) {
    for (uint32_t i = 0; i < top.geometries.size(); ++i)
      if (top.geometries[i].instance && top.geometries[i].embreeID == instID) {
        h.instID = i;
        where = &scenes[top.geometries[i].child];
      }
    if (h.instID == kInvalidId) return Hit();
  }
  for (uint32_t i = 0; i < where->geometries.size(); ++i) {
    const DumpedGeometry& g = where->geometries[i];
    if (g.instance || g.embreeID != geomID) continue;
    h.geomID = i;
    h.primID = mbrtPrim(g, primID, u, v);
  }
  if (h.geomID == kInvalidId || h.primID == kInvalidId) return Hit();
  h.t = t;
  h.u = u;
  h.v = v;
  return h;
}

}  // namespace mbrt::embree_test
