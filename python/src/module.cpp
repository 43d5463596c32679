// The module `mbrt._mbrt`: errors, version, kinds and the parts' bindings.
#include <unordered_set>

#include "bindings.h"
#include "mbrt/build_options.h"
#include "mbrt/error.h"

namespace mbrt::python {

std::shared_mutex& sceneLock() {
  static std::shared_mutex lock;
  return lock;
}

void fail(const std::string& message) { throw Error(message); }

namespace {
void addVersions(const Scene& scene, std::unordered_set<const Scene*>& seen, uint64_t& sum) {
  if (!seen.insert(&scene).second) return;
  sum += scene.version();
  for (uint32_t g = 0; g < scene.numGeometries(); ++g)
    if (const Scene* child = scene.geometry(g).instancedScene()) addVersions(*child, seen, sum);
}
}  // namespace

uint64_t deepVersion(const Scene& scene) {
  std::unordered_set<const Scene*> seen;
  uint64_t sum = 0;
  addVersions(scene, seen, sum);
  return sum;
}

Accel& PyAccel::get() const {
  if (!accel) fail("this accel has no structure: its last update (Document.frames) failed");
  return *accel;
}

void PyAccel::checkCurrent() const {
  get();
  if (deepVersion(scene->scene()) != builtVersion)
    fail("the scene changed since this accel was built (geometry added, masks set, or another frame): call "
         "rebuild() or refit()");
}

}  // namespace mbrt::python

PYBIND11_MODULE(_mbrt, m) {
  namespace py = pybind11;
  using namespace mbrt::python;
  m.doc() = "mbrt: ray tracing with motion blur (STBVH, MSBVH, MBKD, fuzzy kd-trees) over numpy arrays.";
  py::register_exception<mbrt::Error>(m, "Error", PyExc_RuntimeError);
#ifdef MBRT_VERSION
  m.attr("__version__") = MBRT_VERSION;
#endif
  m.def(
      "kinds",
      [] {
        std::vector<std::string> names;
        for (mbrt::AccelKind k : mbrt::availableAccelKinds()) names.emplace_back(mbrt::toString(k));
        return names;
      },
      "The accel kinds this build can construct (the names `Accel(kind=...)` and `mbrt trace --accel` take).");
  bindScene(m);
  bindAccel(m);
  bindLoaders(m);
  bindAnimation(m);
  bindRender(m);
  bindBench(m);
}
