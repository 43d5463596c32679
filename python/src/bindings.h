// The Python module `mbrt` (pybind11 + numpy): what its parts share.
//
// Ownership. A Python Scene owns its mbrt::Scene (and, for loaded scenes,
// the camera, materials and lights around it) and keeps alive every numpy
// array whose memory it shares and every scene it instances. A Python Accel
// holds its Scene, so a scene can never be freed before an accel built on
// it: the dangling scene of the C++ API cannot happen here.
//
// Thread safety (accel.h): tracing, rendering, benchmarks and builds only
// read scenes and may run from any number of Python threads at once, each
// with the GIL released and TBB using every core. Changing a scene (adding
// geometry, masks) and rebuild()/refit() need exclusive access: they take
// the module's scene lock for writing, the readers take it for reading, so
// Python code cannot break the contract. Changing a shared numpy array in
// place is not seen by the lock: do it while no call traces the scene, then
// call rebuild() or refit().
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <shared_mutex>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/io/scene_description.h"

namespace mbrt::python {

namespace py = pybind11;

// Readers (trace, render, bench, build) share it; writers (scene changes,
// rebuild, refit) hold it alone. Always taken with the GIL released.
std::shared_mutex& sceneLock();

struct PyScene {
  std::shared_ptr<SceneDescription> description;  // description->scene is the geometry
  std::vector<py::object> keepAlive;              // shared numpy arrays, instanced Scenes
  std::vector<uint32_t> sharedGeometries;         // ids whose vertices are a caller's array

  Scene& scene() const { return *description->scene; }
};

// The sum of the versions of a scene and every scene it instances (each
// once): what changes when any of them gains geometry or new data.
uint64_t deepVersion(const Scene& scene);

struct PyAccel {
  std::shared_ptr<PyScene> scene;
  std::unique_ptr<Accel> accel;  // null after a frame's update failed (Document.frames)
  uint64_t builtVersion = 0;     // deepVersion(scene) at the last build

  // The structure; throws Error when a frame's update left it without one.
  Accel& get() const;
  // Throws Error when the scene gained geometry since the build (or moved
  // on to another frame since the last update).
  void checkCurrent() const;
};

// Throws mbrt::Error(message): raised in Python as mbrt.Error.
[[noreturn]] void fail(const std::string& message);

void bindScene(py::module_& m);
void bindAccel(py::module_& m);
void bindLoaders(py::module_& m);  // scenes.make, scenes.names
void bindAnimation(py::module_& m);  // load, Document, Timeline, Frame
void bindRender(py::module_& m);
void bindBench(py::module_& m);

}  // namespace mbrt::python
