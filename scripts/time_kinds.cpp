// Thread CPU time per ray of several kinds on the bench's secondary rays of
// one scene, alternated, for measurements on a loaded machine (not built by
// CMake; docs/performance.md, "The cost model fitted to time").
//
// Wall-clock rays/s on a machine shared with other builds swings by ±50 %
// between byte-identical structures; the calling thread's CPU time
// (CLOCK_THREAD_CPUTIME_ID) does not count the time the thread waits
// descheduled, and alternating the kinds round by round (each round a
// different order) spreads what remains (cache sharing) over all of them.
// Prints per kind its memory, traversal counters and the median of its
// per-round time divided by the first kind's.
//
// Build (from the repository, after a Release build in build/):
//   g++ -O2 -std=c++20 -mavx2 -mfma -Iinclude -Isrc -Itools scripts/time_kinds.cpp tools/bench_scenes.cpp \
//     -o build/time_kinds build/libmbrt_bench.a build/libmbrt_io.a build/libmbrt_scenes.a \
//     build/libmbrt_accel.a -lpng -lz -ltbb -lembree3
// Run: build/time_kinds SCENE SIZE KIND,KIND,... ROUNDS [RAYS_OUT [PRIMARY_SIDE]]
//   A KIND of auto:LEAF is auto with every object of kind LEAF (the
//   autoLeafKind option); Embree's rows are named as in the bench
//   (embreeRowName: `embree` its default flags, `embree-robust` its robust
//   mode, `embree-static` its static BVH at the frozen time,
//   `embree-static-robust` that BVH with its robust flag).
//   With FROZEN=t in the environment every ray is at time t, and `frozen`
//   and the `embree-static` rows are built there. SIZE is that of a
//   built-in scene, as --size; the real scenes of the bench go by name.
//   The secondary set comes from PRIMARY_SIDE^2 primaries (128 = --quick);
//   RAYS_OUT, when given and not "", gets the rays in `mbrt trace`'s format.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "mbrt/accel.h"
#include "mbrt/bench.h"
#include "mbrt/scenes.h"

using namespace mbrt;

namespace {

uint64_t hashName(const std::string& s) {  // as the bench's seed per scene
  uint64_t h = 1469598103934665603ull;
  for (char c : s) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s SCENE SIZE KIND,KIND,... ROUNDS [RAYS_OUT [PRIMARY_SIDE]]\n", argv[0]);
    return 2;
  }
  const std::string name = argv[1];
  const double size = std::atof(argv[2]);
  const std::string kinds = argv[3];
  const int rounds = std::max(1, std::atoi(argv[4]));
  const char* dump = argc > 5 && argv[5][0] != 0 ? argv[5] : nullptr;  // "": none
  const int side = argc > 6 ? std::atoi(argv[6]) : 128;
  bool real = false;
  for (const std::string& r : tools::realBenchSceneNames()) real |= r == name;
  const ProceduralScene ps = real ? tools::loadRealBenchScene(name) : makeProceduralScene(name, size, 1);
  const auto reference = bench::accelCandidate(AccelKind::Stbvh, BuildOptions::EmbreeMode::Robust).build(*ps.scene);
  const bench::RaySets sets = bench::makeRaySets(ps, *reference, side, side, 1 ^ hashName(ps.name), {}, true);
  std::vector<Ray> rays = sets[bench::RaySet::Secondary];
  // FROZEN=t: every ray at time t, and `frozen` and `embree-static` frozen
  // there (the kernel-to-kernel comparison of the bench's frozen set).
  std::optional<float> frozenTime;
  if (const char* f = std::getenv("FROZEN")) {
    frozenTime = float(std::atof(f));
    for (Ray& r : rays) r.time = *frozenTime;
  }
  if (dump) {
    std::ofstream f(dump, std::ios::binary);
    for (const Ray& r : rays) {
      const float v[9] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, r.time};
      f.write(reinterpret_cast<const char*>(v), sizeof v);
    }
  }
  std::vector<std::string> names;
  std::vector<std::unique_ptr<Accel>> accels;
  for (size_t p = 0; p <= kinds.size();) {
    size_t q = kinds.find(',', p);
    if (q == std::string::npos) q = kinds.size();
    names.push_back(kinds.substr(p, q - p));
    p = q + 1;
    BuildOptions o;
    const size_t colon = names.back().find(':');
    const std::optional<BuildOptions::EmbreeMode> embreeMode = parseEmbreeRow(names.back());
    const auto kind = embreeMode ? std::optional<AccelKind>(AccelKind::Embree)
                                 : parseAccelKind(names.back().substr(0, colon));
    const auto leafKind =
        colon == std::string::npos ? std::optional<AccelKind>() : parseAccelKind(names.back().substr(colon + 1));
    if (!kind || (colon != std::string::npos && (!leafKind || *kind != AccelKind::Auto))) {
      std::fprintf(stderr, "unknown kind %s\n", names.back().c_str());
      return 2;
    }
    o.kind = *kind;
    if (embreeMode) o.embreeMode = *embreeMode;
    if (frozenTime) o.frozenTime = *frozenTime;
    o.autoLeafKind = leafKind;
    const auto t0 = std::chrono::steady_clock::now();
    accels.push_back(Accel::build(*ps.scene, o));
    const double buildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const AccelStats st = accels.back()->stats();
    TraversalCounters c;
    for (const Ray& r : rays) {
      Hit h;
      accels.back()->intersect(r, h, c);
    }
    const double n = double(rays.size());
    std::printf("%-12s build %.3f s, %.3f MB (%.3f MB in leaves), per ray: %.3f nodes, %.3f primitive tests (%.3f in "
                "blocks)\n",
                names.back().c_str(), buildS, double(st.bytes) * 1e-6, double(st.leafBlockBytes) * 1e-6,
                double(c.nodesVisited) / n,
                double(c.primitiveTests) / n, double(c.blockPrimitiveTests) / n);
  }
  std::vector<std::vector<double>> t(accels.size());
  double sink = 0;
  for (int r = 0; r < rounds; ++r)
    for (size_t j = 0; j < accels.size(); ++j) {
      const size_t i = (j + size_t(r)) % accels.size();
      const double s = threadSeconds();
      for (const Ray& ray : rays) {
        Hit h;
        if (accels[i]->intersect(ray, h)) sink += h.t;
      }
      t[i].push_back(threadSeconds() - s);
    }
  std::printf("%zu secondary rays, %d rounds (checksum %g)\n", rays.size(), rounds, sink);
  for (size_t i = 0; i < accels.size(); ++i) {
    std::vector<double> ratio;
    for (int r = 0; r < rounds; ++r) ratio.push_back(t[i][size_t(r)] / t[0][size_t(r)]);
    std::printf("%-12s median %.2f ms, %.0f ns per ray; time / %s's: %.3f\n", names[i].c_str(), median(t[i]) * 1e3,
                median(t[i]) / double(rays.size()) * 1e9, names[0].c_str(), median(ratio));
  }
}
