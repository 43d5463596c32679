// Builds a triangle that moves from z = 0 to z = 2 over the shutter, traces
// one ray at time 0.5 with every structure this mbrt has, and checks that
// each hits it at z = 1 (t = 2). Exits 1 on a wrong answer.
#include <cmath>
#include <cstdio>
#include <string>

#include <mbrt/accel.h>

int main() {
  mbrt::Scene scene;
  const std::vector<mbrt::Vec3f> step0{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<mbrt::Vec3f> step1{{0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
  scene.addTriangleMesh({{0, 1, 2}}, {step0, step1});

  mbrt::Ray ray;
  ray.org = {0.25f, 0.25f, -1.0f};
  ray.dir = {0, 0, 1};
  ray.time = 0.5f;

  int failures = 0;
  for (mbrt::AccelKind kind : mbrt::availableAccelKinds()) {
    const std::string name(mbrt::toString(kind));
    try {
      mbrt::BuildOptions options;
      options.kind = kind;
      auto accel = mbrt::Accel::build(scene, options);
      mbrt::Hit hit;
      const bool found = accel->intersect(ray, hit);
      const bool ok = found && std::fabs(hit.t - 2.0f) < 1e-5f && hit.geomID == 0 && hit.primID == 0;
      std::printf("consumer: %-13s hit=%d t=%g geomID=%u primID=%u %s\n", name.c_str(), int(found), hit.t,
                  hit.geomID, hit.primID, ok ? "OK" : "WRONG (expected a hit at t = 2)");
      failures += ok ? 0 : 1;
    } catch (const mbrt::Error& e) {
      std::printf("consumer: %-13s error: %s\n", name.c_str(), e.what());
      ++failures;
    }
  }
  if (failures) {
    std::fprintf(stderr, "consumer: %d wrong answers\n", failures);
    return 1;
  }
  std::printf("consumer: OK\n");
  return 0;
}
