// The scene dump of MBRT_EMBREE_DUMP (scene_dump.h). Layout, all 32-bit
// little-endian words: "MBRTEMB1", the number of scenes, then each scene
// (instanced ones before the scenes that instance them): its geometry
// count, and per geometry
//   kind (0 mesh, 1 instance), Embree id, mask, time range lo and hi (float),
//   steps, filtered (0/1: filter functions run on it, which the dump lacks);
//   mesh: quads (0/1), primitive map size and entries (0: identity),
//         triangle count and indices, vertex count and steps x xyz floats;
//   instance: scene index, SRT keys (0/1), the keys (10 floats: scale,
//         rotation wxyz, translation; or 12: the columns and translation),
//         pivot (0/1) and, for 1, the inner instance's matrix keys.
#include "scene_dump.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

namespace mbrt::embree_api {
namespace {

class Writer {
 public:
  void word(uint32_t w) { out_.push_back(w); }
  void real(float f) {
    uint32_t w;
    std::memcpy(&w, &f, 4);
    out_.push_back(w);
  }
  void vec(Vec3f v) {
    real(v.x);
    real(v.y);
    real(v.z);
  }
  void matrices(const mbrt::Geometry& g) {
    for (const Affine3f& m : g.transforms()) {
      vec(m.vx);
      vec(m.vy);
      vec(m.vz);
      vec(m.p);
    }
  }
  const std::vector<uint32_t>& words() const { return out_; }

 private:
  std::vector<uint32_t> out_;
};

class Dumper {
 public:
  uint32_t scene(const Snapshot& s) {
    const auto it = index_.find(&s);
    if (it != index_.end()) return it->second;
    std::vector<uint32_t> children(s.entries.size(), 0);
    for (size_t i = 0; i < s.entries.size(); ++i)
      if (s.entries[i].child) children[i] = scene(*s.entries[i].child);
    Writer& w = scenes_.emplace_back();
    const uint32_t n = s.scene ? s.scene->numGeometries() : 0;
    w.word(n);
    for (uint32_t id = 0; id < n; ++id) {
      const mbrt::Geometry& g = s.scene->geometry(id);
      const GeomEntry& e = s.entries[id];
      const bool instance = g.type() == GeometryType::Instance;
      w.word(instance ? 1 : 0);
      w.word(e.embreeID);
      w.word(g.mask());
      w.real(g.timeRange().lo);
      w.real(g.timeRange().hi);
      w.word(g.numSteps());
      w.word(g.hasFilter() ? 1 : 0);
      if (!instance) {
        w.word(e.prims.quads ? 1 : 0);
        w.word(e.prims.kept ? uint32_t(e.prims.kept->size()) : 0);
        if (e.prims.kept)
          for (uint32_t k : *e.prims.kept) w.word(k);
        w.word(g.numPrimitives());
        for (const Triangle& t : g.triangles()) w.word(t.v0), w.word(t.v1), w.word(t.v2);
        const size_t count = g.vertices(0).count;
        w.word(uint32_t(count));
        for (uint32_t k = 0; k < g.numSteps(); ++k)
          for (size_t i = 0; i < count; ++i) w.vec(g.vertices(k)[i]);
        continue;
      }
      w.word(children[id]);
      w.word(g.hasSRTKeys() ? 1 : 0);
      if (g.hasSRTKeys()) {
        for (const SRTKey& k : g.srtKeys()) {
          w.vec(k.scale);
          w.real(k.rotation.w), w.real(k.rotation.x), w.real(k.rotation.y), w.real(k.rotation.z);
          w.vec(k.translation);
        }
      } else {
        w.matrices(g);
      }
      // A quaternion key with skew or shift: the S matrices in between.
      const bool pivot = g.instancedScene() != e.child->scene.get();
      w.word(pivot ? 1 : 0);
      if (pivot) w.matrices(g.instancedScene()->geometry(0));
    }
    return index_[&s] = uint32_t(scenes_.size() - 1);
  }

  bool write(const std::string& path) const {
    const std::string tmp = path + ".part";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return false;
    bool ok = std::fwrite("MBRTEMB1", 1, 8, f) == 8;
    const uint32_t count = uint32_t(scenes_.size());
    ok = ok && std::fwrite(&count, 4, 1, f) == 1;
    for (const Writer& w : scenes_)
      ok = ok && std::fwrite(w.words().data(), 4, w.words().size(), f) == w.words().size();
    ok = std::fclose(f) == 0 && ok;
    return ok && std::rename(tmp.c_str(), path.c_str()) == 0;
  }

 private:
  std::vector<Writer> scenes_;
  std::unordered_map<const Snapshot*, uint32_t> index_;
};

}  // namespace

bool dumpIfAsked(const Snapshot& snapshot) {
  const char* path = std::getenv("MBRT_EMBREE_DUMP");
  if (!path || !*path) return true;
  Dumper d;
  d.scene(snapshot);
  return d.write(path);
}

}  // namespace mbrt::embree_api
