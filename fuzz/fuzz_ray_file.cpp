// libFuzzer target: the ray-file reader of `mbrt trace` (decodeRays), and
// the decoded rays -- any bit patterns: NaN, inf, denormals, zero
// directions, reversed intervals, times outside [0,1] -- traced through
// every structure of this build over a small moving scene. A ray a
// structure answers differently from brute is a crash too.
#include <memory>
#include <vector>

#include "fuzz_common.h"
#include "mbrt/ray_file.h"

namespace {

struct Fixture {
  mbrt::Scene scene;
  std::vector<std::unique_ptr<mbrt::Accel>> accels;  // [0] is brute
  Fixture() {
    std::vector<mbrt::Triangle> tris;
    std::vector<std::vector<mbrt::Vec3f>> steps(3);
    for (uint32_t i = 0; i < 40; ++i) {
      const float x = float(i % 8) * 0.25f - 1.0f, y = float(i / 8) * 0.4f - 1.0f;
      for (uint32_t s = 0; s < 3; ++s) {
        const float dz = 0.3f * float(s) * float(i % 3);
        steps[s].push_back({x, y, dz});
        steps[s].push_back({x + 0.3f, y, dz + 0.1f});
        steps[s].push_back({x, y + 0.5f, dz - 0.1f});
      }
      tris.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    scene.addTriangleMesh(std::move(tris), std::move(steps));
    scene.addSegments({{0, 1}}, {{{0, 0, 1}, {1, 1, 1}}}, {0.1f, 0.2f}, {0.2f, 0.8f});
    for (mbrt::AccelKind k : mbrt::availableAccelKinds()) {
      if (k == mbrt::AccelKind::Embree) continue;  // its own arithmetic: ties differ
      mbrt::BuildOptions o;
      o.kind = k;
      accels.push_back(mbrt::Accel::build(scene, o));
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Fixture fx;
  std::vector<mbrt::Ray> rays;
  try {
    rays = mbrt::decodeRays({data, size}, "fuzz.rays");
  } catch (const mbrt::Error&) {
    return 0;
  }
  for (const mbrt::Ray& r : rays) {
    mbrt::Hit ref;
    const bool refHit = fx.accels[0]->intersect(r, ref);
    const bool refOcc = fx.accels[0]->occluded(r);
    if (refHit && !refOcc) std::abort();
    for (size_t i = 1; i < fx.accels.size(); ++i) {
      mbrt::Hit h;
      const bool hit = fx.accels[i]->intersect(r, h);
      if (fx.accels[i]->options().kind == mbrt::AccelKind::Frozen) continue;  // only right at its build time
      if (hit != refHit) {
        std::fprintf(stderr, "kind %d: hit %d, brute %d\n", int(fx.accels[i]->options().kind), hit, refHit);
        std::abort();
      }
      (void)fx.accels[i]->occluded(r);
    }
  }
  return 0;
}
