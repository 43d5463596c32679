// The cost of a visit: mbrt's kinds against Embree 3 called directly
// (rtcIntersect1, as a renderer calls it), on the bench's incoherent rays
// (bench::incoherentRays: from all around the scene into it, nearly all
// hitting). Not built by CMake; docs/performance.md, "The cost of a visit".
//
// Two measurements:
// - time: thread CPU time per ray on one thread (the kinds alternated round
//   by round, each round in another order, so that what a loaded machine
//   adds spreads over all of them), and wall time on two threads; printed
//   as Embree's default mode ÷ the row (above 1: faster than Embree);
// - count (MODE=count): one pass of every kind through traceOnce(), so that
//     valgrind --tool=callgrind --toggle-collect='*traceOnce*' build/visit_cost ...
//   counts the instructions of the trace phase alone (deterministic on a
//   noisy machine); scripts/visit_cost.sh runs it per kind and divides.
//
// Build (after a Release build in build/):
//   g++ -O2 -std=c++20 -mavx2 -mfma -Iinclude -Isrc scripts/visit_cost.cpp -o build/visit_cost \
//     build/libmbrt_bench.a build/libmbrt_scenes.a build/libmbrt_accel.a -ltbb -lembree3
// Run: build/visit_cost SCENE SIZE KIND,KIND,... [RAYS [ROUNDS]]
//   KIND: an mbrt kind, `embree` (Embree's default mode, called directly),
//   `embree-robust` (RTC_SCENE_FLAG_ROBUST); with FROZEN=t in the
//   environment every ray is at time t, `frozen` is built there and
//   `embree-static` / `embree-static-robust` are Embree's static BVH of the
//   scene at t. Triangles and matrix instances. DUMP=file writes the rays
//   in `mbrt trace`'s format and exits.
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/bench.h"
#include "mbrt/scenes.h"

using namespace mbrt;

namespace {

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Embree fed the scene (shared vertex buffers; matrix instances).
class EmbreeScene {
 public:
  // frozen >= 0: Embree's static BVH of the scene at that time.
  EmbreeScene(RTCDevice device, const Scene& scene, bool robust, float frozen)
      : device_(device), frozen_(frozen) {
    root_ = make(scene, robust);
  }
  ~EmbreeScene() {
    for (RTCScene s : scenes_) rtcReleaseScene(s);
  }
  RTCScene root() const { return root_; }

 private:
  RTCScene make(const Scene& scene, bool robust) {
    RTCScene s = rtcNewScene(device_);
    scenes_.push_back(s);
    if (robust) rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
      const Geometry& g = scene.geometry(id);
      RTCGeometry geom = nullptr;
      if (g.type() == GeometryType::Triangles) {
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        const uint32_t steps = frozen_ >= 0.0f ? 1 : g.numSteps();
        rtcSetGeometryTimeStepCount(geom, steps);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, g.triangles().data(), 0,
                                   sizeof(Triangle), g.triangles().size());
        for (uint32_t k = 0; k < steps; ++k) {
          // Embree reads 16 bytes per vertex: a padded copy.
          std::vector<float>& v = copies_.emplace_back();
          const VertexBuffer& vb = g.vertices(k);
          for (size_t i = 0; i < vb.count; ++i) {
            const Vec3f p = frozen_ >= 0.0f ? g.vertexAt(frozen_, uint32_t(i)) : vb[i];
            v.insert(v.end(), {p.x, p.y, p.z, 0.0f});
          }
          rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, v.data(), 0,
                                     4 * sizeof(float), vb.count);
        }
      } else if (g.type() == GeometryType::Instance && !g.hasSRTKeys()) {
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, make(*g.instancedScene(), robust));
        const uint32_t steps = frozen_ >= 0.0f ? 1 : g.numSteps();
        rtcSetGeometryTimeStepCount(geom, steps);
        for (uint32_t k = 0; k < steps; ++k) {
          const Affine3f a = frozen_ >= 0.0f ? g.transformAt(frozen_) : g.transforms()[k];
          const float m[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z,
                               a.vz.x, a.vz.y, a.vz.z, a.p.x,  a.p.y,  a.p.z};
          rtcSetGeometryTransform(geom, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
        }
      } else {
        std::fprintf(stderr, "visit_cost: geometry %u: only triangles and matrix instances\n", id);
        std::exit(2);
      }
      if (frozen_ < 0.0f && !(g.timeRange().lo == 0.0f && g.timeRange().hi == 1.0f))
        rtcSetGeometryTimeRange(geom, g.timeRange().lo, g.timeRange().hi);
      rtcCommitGeometry(geom);
      rtcAttachGeometryByID(s, geom, id);
      rtcReleaseGeometry(geom);
    }
    rtcCommitScene(s);
    return s;
  }

  RTCDevice device_;
  float frozen_;
  RTCScene root_;
  std::vector<RTCScene> scenes_;
  std::vector<std::vector<float>> copies_;
};

struct Row {
  std::string name;
  std::unique_ptr<Accel> accel;
  std::unique_ptr<EmbreeScene> embree;

  bool trace(const Ray& r, float& t) const {
    if (accel) {
      Hit h;
      const bool hit = accel->intersect(r, h);
      t = h.t;
      return hit;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = r.org.x, rh.ray.org_y = r.org.y, rh.ray.org_z = r.org.z;
    rh.ray.dir_x = r.dir.x, rh.ray.dir_y = r.dir.y, rh.ray.dir_z = r.dir.z;
    rh.ray.tnear = r.tnear, rh.ray.tfar = r.tfar, rh.ray.time = r.time;
    rh.ray.mask = r.mask, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree->root(), &ctx, &rh);
    t = rh.ray.tfar;
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
};

// The trace phase that callgrind counts (--toggle-collect='*traceOnce*').
[[gnu::noinline]] double traceOnce(const Row& row, const std::vector<Ray>& rays) {
  double sum = 0.0;
  for (const Ray& r : rays) {
    float t;
    if (row.trace(r, t)) sum += t;
  }
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s SCENE SIZE KIND,KIND,... [RAYS [ROUNDS]]\n", argv[0]);
    return 2;
  }
  const std::string name = argv[1];
  const double size = std::atof(argv[2]);
  const std::string kinds = argv[3];
  const size_t n = argc > 4 ? size_t(std::atol(argv[4])) : 200000;
  const int rounds = argc > 5 ? std::max(1, std::atoi(argv[5])) : 3;
  const bool count = std::getenv("MODE") && std::string(std::getenv("MODE")) == "count";

  const ProceduralScene ps = makeProceduralScene(name, size, 1);
  std::optional<float> frozen;  // FROZEN=t: every ray at time t
  if (const char* f = std::getenv("FROZEN")) frozen = float(std::atof(f));
  const std::vector<Ray> rays = bench::incoherentRays(*ps.scene, n, 7, frozen);
  if (const char* dump = std::getenv("DUMP")) {  // DUMP=file: the rays in `mbrt trace`'s format, and stop
    std::FILE* f = std::fopen(dump, "wb");
    for (const Ray& r : rays) {
      const float v[9] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, r.time};
      std::fwrite(v, sizeof v, 1, f);
    }
    std::fclose(f);
    return 0;
  }
  RTCDevice device = rtcNewDevice(count ? "threads=1" : nullptr);
  std::vector<Row> rows;
  for (size_t p = 0; p <= kinds.size();) {
    size_t q = kinds.find(',', p);
    if (q == std::string::npos) q = kinds.size();
    Row row;
    row.name = kinds.substr(p, q - p);
    p = q + 1;
    if (row.name.starts_with("embree")) {
      const bool robust = row.name.ends_with("-robust");
      const bool frozenRow = row.name.starts_with("embree-static");
      if (frozenRow && !frozen) {
        std::fprintf(stderr, "embree-static needs FROZEN=t\n");
        return 2;
      }
      if (!robust && !(row.name == "embree" || row.name == "embree-static")) {
        std::fprintf(stderr, "unknown kind %s\n", row.name.c_str());
        return 2;
      }
      row.embree = std::make_unique<EmbreeScene>(device, *ps.scene, robust, frozenRow ? *frozen : -1.0f);
    } else {
      const auto kind = parseAccelKind(row.name);
      if (!kind) {
        std::fprintf(stderr, "unknown kind %s\n", row.name.c_str());
        return 2;
      }
      BuildOptions o;
      o.kind = *kind;
      if (frozen) o.frozenTime = *frozen;
      if (const char* ct = std::getenv("TRAVERSAL_COST")) o.traversalCost = float(std::atof(ct));
      row.accel = Accel::build(*ps.scene, o);
    }
    rows.push_back(std::move(row));
  }

  // Hit rate and, for mbrt rows, nodes and primitive tests per ray.
  for (const Row& row : rows) {
    size_t hits = 0;
    TraversalCounters c;
    for (const Ray& r : rays) {
      float t;
      if (row.accel) {
        Hit h;
        hits += row.accel->intersect(r, h, c) ? 1 : 0;
      } else {
        hits += row.trace(r, t) ? 1 : 0;
      }
    }
    const double k = 1.0 / double(rays.size());
    if (row.accel)
      std::printf("%-14s hits %.1f%%, per ray: %.2f nodes, %.2f leaves, %.2f primitive tests (%.2f in blocks), %.1f MB\n",
                  row.name.c_str(), 100.0 * double(hits) * k, double(c.nodesVisited) * k, double(c.leavesVisited) * k,
                  double(c.primitiveTests) * k, double(c.blockPrimitiveTests) * k,
                  double(row.accel->stats().bytes) * 1e-6);
    else
      std::printf("%-14s hits %.1f%%\n", row.name.c_str(), 100.0 * double(hits) * k);
  }
  if (count) {
    double sum = 0.0;
    for (const Row& row : rows) sum += traceOnce(row, rays);
    std::printf("%zu rays traced once per row (checksum %g)\n", rays.size(), sum);
    rtcReleaseDevice(device);
    return 0;
  }

  const size_t base = [&] {  // the ratios' denominator: Embree's default mode (static with FROZEN)
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i].name == (frozen ? "embree-static" : "embree")) return i;
    return size_t(0);
  }();
  std::vector<std::vector<double>> one(rows.size()), two(rows.size());
  double sink = 0.0;
  for (int r = 0; r < rounds; ++r)
    for (size_t j = 0; j < rows.size(); ++j) {
      const size_t i = (j + size_t(r)) % rows.size();
      const double s = threadSeconds();
      sink += traceOnce(rows[i], rays);
      one[i].push_back(threadSeconds() - s);
      const auto w = std::chrono::steady_clock::now();
      tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& b) {
        float t;
        for (size_t k = b.begin(); k != b.end(); ++k) rows[i].trace(rays[k], t);
      });
      two[i].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w).count());
    }
  std::printf("%zu incoherent rays, %d rounds (checksum %g); ratios: %s's time / the row's\n", rays.size(), rounds, sink,
              rows[base].name.c_str());
  for (size_t i = 0; i < rows.size(); ++i) {
    std::vector<double> r1, r2;
    for (int r = 0; r < rounds; ++r) {
      r1.push_back(one[base][size_t(r)] / one[i][size_t(r)]);
      r2.push_back(two[base][size_t(r)] / two[i][size_t(r)]);
    }
    std::printf("%-14s 1 thread %6.0f ns/ray (x%.3f)   2 threads %6.0f ns/ray (x%.3f)\n", rows[i].name.c_str(),
                median(one[i]) / double(rays.size()) * 1e9, median(r1), median(two[i]) / double(rays.size()) * 1e9,
                median(r2));
  }
  rows.clear();
  rtcReleaseDevice(device);
}
