// libFuzzer target: the ray-file reader of `mbrt trace` (decodeRays), and
// the decoded rays -- any bit patterns: NaN, inf, denormals, zero
// directions, reversed intervals, times outside [0,1] -- traced through
// brute and one other structure of this build (ray i: structure i mod n,
// so every structure sees rays and an execution costs two traversals) over
// a small moving scene. A ray a structure answers differently from brute
// (hit or miss, any hit, or the closest hit: the same primitive at the same
// t, or a tie on a shared edge: another primitive at the same t) is a crash
// too.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_common.h"
#include "hostile_ray_scene.h"
#include "mbrt/io/ray_file.h"

namespace {

// Origins farther than this from the scene (about 5,000 times its size) are
// a known open limit (docs/robustness.md, "Open"): the structures' slab
// tests stop being conservative and may miss what brute hits. Such rays
// are still traced (no crash allowed), not compared.
constexpr float kComparedOriginReach = 1e4f;

bool originNear(const mbrt::Ray& r) {
  return std::fabs(r.org.x) <= kComparedOriginReach && std::fabs(r.org.y) <= kComparedOriginReach &&
         std::fabs(r.org.z) <= kComparedOriginReach;
}

// The oracle rule of tests/oracle.h: the same primitive within 1e-5
// relative t, another one (a tie) within 1e-4.
bool sameClosestHit(const mbrt::Hit& a, const mbrt::Hit& b) {
  if (a.valid() != b.valid()) return false;
  if (!a.valid()) return true;
  const bool samePrim = a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID;
  const float tol = samePrim ? 1e-5f : 1e-4f;
  return std::fabs(a.t - b.t) <= tol * std::max(1.0f, std::fabs(a.t));
}

struct Fixture {
  mbrt::Scene scene = mbrt::test::hostileRayScene();
  std::vector<std::unique_ptr<mbrt::Accel>> accels;  // [0] is brute
  Fixture() {
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
  for (size_t n = 0; n < rays.size(); ++n) {
    const mbrt::Accel& tested = *fx.accels[1 + n % (fx.accels.size() - 1)];
    mbrt::Ray r = rays[n];
    // `frozen` is right only at its build time: asked there (valid times only).
    if (tested.options().kind == mbrt::AccelKind::Frozen && r.time >= 0.0f && r.time <= 1.0f)
      r.time = tested.options().frozenTime;
    mbrt::Hit ref, h;
    const bool refHit = fx.accels[0]->intersect(r, ref), refOcc = fx.accels[0]->occluded(r);
    if (refHit != refOcc || (refHit && !std::isfinite(ref.t))) std::abort();
    const bool hit = tested.intersect(r, h), occ = tested.occluded(r);
    if ((hit != refHit || occ != refOcc || !sameClosestHit(ref, h)) && originNear(r)) {
      std::fprintf(stderr, "%s: hit %d occluded %d g%u p%u i%u t %.9g, brute %d %d g%u p%u i%u t %.9g\n",
                   std::string(mbrt::toString(tested.options().kind)).c_str(), hit, occ, h.geomID, h.primID,
                   h.instID, h.t, refHit, refOcc, ref.geomID, ref.primID, ref.instID, ref.t);
      std::abort();
    }
  }
  return 0;
}
