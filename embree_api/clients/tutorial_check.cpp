// Compares what an Embree program drew and traced with the real
// libembree3 and with mbrt's (embree_api/clients/tutorials.sh):
//
//   mbrt_embree_tutorial_check NAME real.ppm mbrt.ppm real.rays mbrt.rays scene.dump
//
// Counts the differing pixels of the two pictures, matches the rays of the
// two ray logs (raylog.cpp) that were traced by both (same ray, bit for
// bit), and has the float64 reference (tests/reference64.h), on the scene
// mbrt traced (MBRT_EMBREE_DUMP), judge both answers wherever they differ:
// settled for mbrt (Embree's answer wrong), both acceptable (within the
// reference's ulp bands), or mbrt wrong -- a failure (exit status 1).
// Differences on scenes with filter functions, which the dump cannot carry,
// are listed, not judged.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "raylog.h"
#include "reference64.h"
#include "scene_dump_read.h"

using namespace mbrt;
using namespace mbrt::embree_test;

namespace {

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

Image readPpm(const std::string& path) {
  Image im;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("cannot open " + path);
  int maxval = 0;
  if (std::fscanf(f, "P6 %d %d %d", &im.width, &im.height, &maxval) != 3 || maxval != 255) {
    std::fclose(f);
    throw Error(path + ": not a binary 8-bit PPM");
  }
  std::fgetc(f);
  im.rgb.resize(size_t(im.width) * im.height * 3);
  const size_t got = std::fread(im.rgb.data(), 1, im.rgb.size(), f);
  std::fclose(f);
  if (got != im.rgb.size()) throw Error(path + ": truncated");
  return im;
}

std::vector<RayRecord> readLog(const std::string& path) {
  std::vector<RayRecord> out;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("cannot open " + path);
  RayRecord r;
  while (std::fread(&r, sizeof r, 1, f) == 1) out.push_back(r);
  std::fclose(f);
  return out;
}

// The call and the ray's org, tnear, dir, time, tfar and mask (programs
// leave id and flags uninitialised).
using Key = std::array<uint32_t, 11>;
Key keyOf(const RayRecord& r) {
  Key k;
  k[0] = r.call;
  std::memcpy(&k[1], &r.in, 10 * sizeof(uint32_t));
  return k;
}

Ray toRay(const RTCRay& r) {
  Ray m;
  m.org = {r.org_x, r.org_y, r.org_z};
  m.dir = {r.dir_x, r.dir_y, r.dir_z};
  m.tnear = r.tnear;
  m.tfar = r.tfar;
  m.time = std::fmin(std::fmax(r.time, 0.0f), 1.0f);
  m.mask = r.mask;
  return m;
}

bool hitOf(const RayRecord& r) { return r.call == 0 ? r.out.hit.geomID != RTC_INVALID_GEOMETRY_ID : r.out.ray.tfar < 0; }

bool sameAnswer(const RayRecord& a, const RayRecord& b) {
  if (hitOf(a) != hitOf(b)) return false;
  if (a.call == 1 || !hitOf(a)) return true;
  const RTCHit &x = a.out.hit, &y = b.out.hit;
  return x.geomID == y.geomID && x.primID == y.primID && x.instID[0] == y.instID[0] &&
         std::fabs(a.out.ray.tfar - b.out.ray.tfar) <= 1e-4f * std::fmax(1.0f, std::fabs(a.out.ray.tfar));
}

constexpr size_t kNone = ~size_t(0);

// Finds, among the records not paired yet, one of the same call, time and
// mask whose org, dir and tnear agree with a ray to 1e-4 (relative to their
// size plus one): cells of 1e-3 on the origin, the 27 around it.
class NearMatcher {
 public:
  NearMatcher(const std::vector<RayRecord>& records, const std::vector<bool>& used) : records_(records) {
    for (size_t i = 0; i < records.size(); ++i)
      if (!used[i]) cells_[cellOf(records[i], 0, 0, 0)].push_back(i);
  }
  size_t take(const RayRecord& r) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(cellOf(r, dx, dy, dz));
          if (it == cells_.end()) continue;
          auto& v = it->second;
          for (size_t k = 0; k < v.size(); ++k)
            if (close(records_[v[k]], r)) {
              const size_t i = v[k];
              v.erase(v.begin() + long(k));
              return i;
            }
        }
    return kNone;
  }

 private:
  using Cell = std::array<int64_t, 7>;
  static constexpr double kCell = 1e-3;
  static Cell cellOf(const RayRecord& r, int dx, int dy, int dz) {
    auto q = [](float x, int d) { return int64_t(std::floor(double(x) / kCell)) + d; };
    uint32_t t;
    std::memcpy(&t, &r.in.time, 4);
    return {int64_t(r.call), int64_t(t), int64_t(r.in.mask), 0, q(r.in.org_x, dx), q(r.in.org_y, dy), q(r.in.org_z, dz)};
  }
  static bool close(const RayRecord& a, const RayRecord& b) {
    auto near = [](float x, float y) { return std::fabs(x - y) <= 1e-4f * (std::fabs(x) + 1.0f); };
    return a.call == b.call && near(a.in.tnear, b.in.tnear) && near(a.in.org_x, b.in.org_x) && near(a.in.org_y, b.in.org_y) &&
           near(a.in.org_z, b.in.org_z) && near(a.in.dir_x, b.in.dir_x) && near(a.in.dir_y, b.in.dir_y) &&
           near(a.in.dir_z, b.in.dir_z);
  }
  const std::vector<RayRecord>& records_;
  std::map<Cell, std::vector<size_t>> cells_;
};

ref::Verdict judge(const ref::Reference& reference, const SceneDump& dump, const RayRecord& r) {
  const Ray ray = toRay(r.in);
  if (r.call == 1) return reference.judgeAny(ray, r.out.ray.tfar < 0);
  const RTCHit& h = r.out.hit;
  const Hit hit = h.geomID == RTC_INVALID_GEOMETRY_ID
                      ? Hit()
                      : dump.toMbrtHit(h.geomID, h.primID, h.instID[0], r.out.ray.tfar, h.u, h.v);
  return reference.judgeClosest(ray, hit);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: %s NAME real.ppm mbrt.ppm real.rays mbrt.rays scene.dump\n", argv[0]);
    return 2;
  }
  try {
    const std::string name = argv[1];
    const Image a = readPpm(argv[2]), b = readPpm(argv[3]);
    if (a.width != b.width || a.height != b.height) throw Error("the pictures differ in size");
    size_t pixels = 0;
    int maxDiff = 0;
    for (size_t p = 0; p < a.rgb.size(); p += 3) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.rgb[p + c]) - int(b.rgb[p + c])));
      pixels += d > 0;
      maxDiff = std::max(maxDiff, d);
    }
    const std::vector<RayRecord> real = readLog(argv[4]), ours = readLog(argv[5]);
    const SceneDump dump = readSceneDump(argv[6]);
    const ref::Reference reference(*dump.scenes.back().scene);
    // Pairs: rays traced by both bit for bit, then (a shadow or bounce ray
    // from a hit whose t differs in its last bits) rays of the same call,
    // time and mask whose org, dir and tnear agree to 1e-4.
    std::map<Key, std::vector<size_t>> byKey;
    for (size_t i = 0; i < real.size(); ++i) byKey[keyOf(real[i])].push_back(i);
    std::vector<bool> realUsed(real.size(), false);
    std::vector<std::pair<size_t, size_t>> pairs;  // (real, ours)
    std::vector<size_t> leftOver;
    size_t exact = 0;
    for (size_t j = 0; j < ours.size(); ++j) {
      auto it = byKey.find(keyOf(ours[j]));
      if (it == byKey.end() || it->second.empty()) {
        leftOver.push_back(j);
        continue;
      }
      pairs.emplace_back(it->second.back(), j);
      realUsed[it->second.back()] = true;
      it->second.pop_back();
      ++exact;
    }
    NearMatcher near(real, realUsed);
    for (size_t j : leftOver) {
      const size_t i = near.take(ours[j]);
      if (i != kNone) pairs.emplace_back(i, j);
    }
    size_t differ = 0, settled = 0, acceptable = 0, wrong = 0, unjudged = 0;
    std::vector<std::string> examples;
    for (auto [i, j] : pairs) {
      const RayRecord &e = real[i], &r = ours[j];
      if (sameAnswer(e, r)) continue;
      ++differ;
      const ref::Verdict vm = judge(reference, dump, r), ve = judge(reference, dump, e);
      std::string what;
      if (vm.ok && !ve.ok) {
        ++settled, what = "settled for mbrt: Embree " + ve.why;
      } else if (vm.ok) {
        ++acceptable, what = "both acceptable";
      } else if (dump.scenes.back().filtered) {
        ++unjudged, what = "not judged (filter functions): " + vm.why;
      } else {
        ++wrong, what = "mbrt wrong: " + vm.why;
      }
      if (examples.size() < 3 || (!vm.ok && !dump.scenes.back().filtered))
        examples.push_back(std::string(r.call ? "occlusion " : "closest hit ") + ref::describe(toRay(r.in)) + ": " + what);
    }
    const size_t both = pairs.size();
    std::printf("%s: %zu of %dx%d pixels differ (largest difference %d/255); %zu rays traced by both (%zu bit for "
                "bit), %zu answered differently: %zu settled for mbrt, %zu both acceptable, %zu not judged, %zu mbrt "
                "wrong (%zu rays of Embree's and %zu of mbrt's traced by one side only)\n",
                name.c_str(), pixels, a.width, a.height, maxDiff, both, exact, differ, settled, acceptable, unjudged,
                wrong, real.size() - both, ours.size() - both);
    if (pixels > 0 && differ == 0)
      std::printf("  every paired ray has the same answer: the pixels differ by the shading of the same hits "
                  "(u, v, Ng and t rounded differently)\n");
    for (const std::string& e : examples) std::printf("  %s\n", e.c_str());
    return wrong == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 2;
  }
}
