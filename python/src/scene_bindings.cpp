// mbrt.Scene: meshes, segments and instances from numpy arrays.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

#include "bindings.h"

namespace mbrt::python {
namespace {

using FloatArray = py::array_t<float, py::array::forcecast>;

// Vertex steps from an (S, N, 3) array (or (N, 3): one step). float32 steps
// whose vertices are packed (12 bytes apart, 4 between coordinates) are
// shared; anything else is copied once into a float32 array the scene keeps.
struct Steps {
  std::vector<VertexBuffer> buffers;
  py::array owner;  // the memory the buffers point into
  bool shared = false;
};

Steps vertexSteps(const py::object& object, bool share, const char* what) {
  py::array a = py::array::ensure(object);
  if (!a) fail(std::string(what) + " must be an array of shape (S, N, 3) or (N, 3)");
  if (a.ndim() != 2 && a.ndim() != 3)
    fail(std::string(what) + " must have shape (S, N, 3) or (N, 3), got " + std::to_string(a.ndim()) + " dimensions");
  if (a.shape(a.ndim() - 1) != 3)
    fail(std::string(what) + ": the last dimension must be 3 (x, y, z), got " + std::to_string(a.shape(a.ndim() - 1)));
  const bool packed = a.dtype().is(py::dtype::of<float>()) && a.strides(a.ndim() - 1) == 4 &&
                      a.strides(a.ndim() - 2) == 12;
  Steps out;
  out.shared = share && packed;
  if (out.shared) {
    out.owner = a;
  } else {
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u') fail(std::string(what) + " must hold numbers");
    using namespace pybind11::literals;
    out.owner = py::module_::import("numpy").attr("array")(a, "dtype"_a = "float32", "order"_a = "C", "copy"_a = true);
  }
  const bool oneStep = out.owner.ndim() == 2;
  const size_t steps = oneStep ? 1 : size_t(out.owner.shape(0));
  const size_t count = size_t(out.owner.shape(oneStep ? 0 : 1));
  const ptrdiff_t stepStride = oneStep ? 0 : out.owner.strides(0);
  const bool contiguous = out.owner.flags() & py::array::c_style;
  for (size_t s = 0; s < steps; ++s) {
    VertexBuffer b;
    b.data = static_cast<const char*>(out.owner.data()) + ptrdiff_t(s) * stepStride;
    b.stride = 12;
    b.count = count;
    // The later steps of a C-contiguous array follow this one.
    b.padding = contiguous ? (steps - 1 - s) * count * 12 : 0;
    out.buffers.push_back(b);
  }
  return out;
}

template <class Index, int Width>
std::vector<Index> indexRows(const py::object& object, const char* what) {
  py::array a = py::array::ensure(object);
  if (!a) fail(std::string(what) + " must be an integer array of shape (M, " + std::to_string(Width) + ")");
  const char kind = a.dtype().kind();
  if (kind != 'u' && kind != 'i')
    fail(std::string(what) + " must be an integer array (uint32), got dtype " + std::string(py::str(a.dtype())));
  if (a.ndim() != 2 || a.shape(1) != Width)
    fail(std::string(what) + " must have shape (M, " + std::to_string(Width) + ")");
  if (kind == 'i' && a.size() > 0 && a.attr("min")().cast<long long>() < 0)
    fail(std::string(what) + " must not be negative");
  if (a.size() > 0 && a.attr("max")().cast<unsigned long long>() > 0xFFFFFFFFull)
    fail(std::string(what) + " must fit in uint32");
  auto rows = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<Index> out(size_t(a.shape(0)));
  std::memcpy(out.data(), rows.data(), out.size() * sizeof(Index));
  return out;
}

TimeRange timeRange(std::pair<float, float> range) { return {range.first, range.second}; }

// (S, 3, 4) or (S, 4, 4) row-major object-to-world matrices, or one (3, 4) / (4, 4).
std::vector<Affine3f> transformKeys(const py::object& object) {
  FloatArray a = FloatArray::ensure(object);
  if (!a || (a.ndim() != 2 && a.ndim() != 3))
    fail("transforms must have shape (S, 3, 4) or (S, 4, 4), or (3, 4) or (4, 4) for one key");
  const bool one = a.ndim() == 2;
  const py::ssize_t rows = a.shape(one ? 0 : 1), cols = a.shape(one ? 1 : 2);
  if ((rows != 3 && rows != 4) || cols != 4) fail("transforms: each key must be a 3x4 or 4x4 matrix");
  const size_t keys = one ? 1 : size_t(a.shape(0));
  std::vector<Affine3f> out(keys);
  for (size_t k = 0; k < keys; ++k) {
    auto m = [&](py::ssize_t r, py::ssize_t c) {
      return one ? a.at(r, c) : a.at(py::ssize_t(k), r, c);
    };
    if (rows == 4 && (m(3, 0) != 0.0f || m(3, 1) != 0.0f || m(3, 2) != 0.0f || m(3, 3) != 1.0f))
      fail("transforms: the last row of a 4x4 key must be 0 0 0 1 (key " + std::to_string(k) + ")");
    out[k].vx = {m(0, 0), m(1, 0), m(2, 0)};
    out[k].vy = {m(0, 1), m(1, 1), m(2, 1)};
    out[k].vz = {m(0, 2), m(1, 2), m(2, 2)};
    out[k].p = {m(0, 3), m(1, 3), m(2, 3)};
  }
  return out;
}

FloatArray rowsOf(const py::object& object, py::ssize_t width, const char* what) {
  FloatArray a = FloatArray::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(1) != width)
    fail(std::string(what) + " must have shape (S, " + std::to_string(width) + ")");
  return a;
}

std::vector<SRTKey> srtKeys(const py::object& scale, const py::object& rotation, const py::object& translation) {
  FloatArray s = rowsOf(scale, 3, "scale"), r = rowsOf(rotation, 4, "rotation"),
             t = rowsOf(translation, 3, "translation");
  if (s.shape(0) != r.shape(0) || s.shape(0) != t.shape(0))
    fail("scale, rotation and translation must have the same number of keys");
  std::vector<SRTKey> keys(size_t(s.shape(0)));
  for (py::ssize_t k = 0; k < s.shape(0); ++k) {
    keys[size_t(k)].scale = {s.at(k, 0), s.at(k, 1), s.at(k, 2)};
    keys[size_t(k)].rotation = {r.at(k, 0), r.at(k, 1), r.at(k, 2), r.at(k, 3)};
    keys[size_t(k)].translation = {t.at(k, 0), t.at(k, 1), t.at(k, 2)};
  }
  return keys;
}

// Runs a scene change with the GIL released and the scene lock held alone.
template <class F>
auto exclusive(F&& change) {
  py::gil_scoped_release nogil;
  std::unique_lock lock(sceneLock());
  return change();
}

uint32_t addMesh(PyScene& self, const py::object& indices, const py::object& steps, std::pair<float, float> range,
                 bool share) {
  auto triangles = indexRows<Triangle, 3>(indices, "indices");
  Steps s = vertexSteps(steps, share, "steps");
  const uint32_t id = exclusive(
      [&] { return self.scene().addTriangleMesh(std::move(triangles), std::move(s.buffers), timeRange(range)); });
  self.keepAlive.push_back(s.owner);
  if (s.shared) self.sharedGeometries.push_back(id);
  return id;
}

uint32_t addSegments(PyScene& self, const py::object& indices, const py::object& steps, const py::object& radii,
                     std::pair<float, float> range, bool share) {
  auto segments = indexRows<Segment, 2>(indices, "indices");
  Steps s = vertexSteps(steps, share, "steps");
  FloatArray r = FloatArray::ensure(radii);
  if (!r || r.ndim() != 1) fail("radii must have shape (N,): one radius per vertex");
  std::vector<float> radiusList(r.data(), r.data() + r.size());
  const uint32_t id = exclusive([&] {
    return self.scene().addSegments(std::move(segments), std::move(s.buffers), std::move(radiusList),
                                    timeRange(range));
  });
  self.keepAlive.push_back(s.owner);
  if (s.shared) self.sharedGeometries.push_back(id);
  return id;
}

template <class Keys>
uint32_t addInstance(PyScene& self, const std::shared_ptr<PyScene>& child, const py::object& childObject,
                     Keys keys, std::pair<float, float> range) {
  if (!child) fail("add_instance: the instanced scene must be an mbrt.Scene");
  std::shared_ptr<const Scene> shared = child->description->scene;
  const uint32_t id =
      exclusive([&] { return self.scene().addInstance(std::move(shared), std::move(keys), timeRange(range)); });
  self.keepAlive.push_back(childObject);
  return id;
}

py::dict geometryInfo(const PyScene& self, uint32_t geomID) {
  if (geomID >= self.scene().numGeometries())
    fail("no geometry " + std::to_string(geomID) + " (the scene has " + std::to_string(self.scene().numGeometries()) +
         ")");
  const Geometry& g = self.scene().geometry(geomID);
  static const char* kTypes[] = {"triangles", "segments", "instance"};
  py::dict d;
  d["type"] = kTypes[int(g.type())];
  d["primitives"] = g.numPrimitives();
  d["steps"] = g.numSteps();
  d["time_range"] = py::make_tuple(g.timeRange().lo, g.timeRange().hi);
  d["mask"] = g.mask();
  if (g.type() != GeometryType::Instance) {
    d["vertices"] = g.numSteps() ? g.vertices(0).count : 0;
    d["shared"] = std::find(self.sharedGeometries.begin(), self.sharedGeometries.end(), geomID) !=
                  self.sharedGeometries.end();
  }
  return d;
}

py::array boundsOf(const PyScene& self) {
  Box3f b;
  {
    py::gil_scoped_release nogil;
    std::shared_lock lock(sceneLock());
    b = sceneBounds(self.scene());
  }
  py::array_t<float> out({2, 3});
  auto o = out.mutable_unchecked<2>();
  o(0, 0) = b.lower.x, o(0, 1) = b.lower.y, o(0, 2) = b.lower.z;
  o(1, 0) = b.upper.x, o(1, 1) = b.upper.y, o(1, 2) = b.upper.z;
  return out;
}

}  // namespace

void bindScene(py::module_& m) {
  using namespace pybind11::literals;
  const std::pair<float, float> whole{0.0f, 1.0f};
  py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", R"doc(
A scene: moving triangle meshes, moving round segments and instances of
other scenes. Geometry ids count up from 0 in the order of adding.

Vertex steps are an (S, N, 3) array: S equidistant time steps over the
geometry's time range (S = 1: static; an (N, 3) array is one step). float32
steps with packed vertices are shared, not copied: change the array in
place, then call Accel.rebuild() (or refit()) to see the change. Other
arrays (float64, strided) are copied once. The scene keeps every array it
shares alive.)doc")
      .def(py::init([] {
             auto s = std::make_shared<PyScene>();
             s->description = std::make_shared<SceneDescription>();
             s->description->scene = std::make_shared<Scene>();
             s->description->name = "python";
             s->description->camera.keys.clear();  // render() frames the scene
             return s;
           }),
           "An empty scene.")
      .def("add_triangle_mesh", &addMesh, "indices"_a, "steps"_a, "time_range"_a = whole, "share"_a = true,
           R"doc(Adds a triangle mesh: indices (M, 3) uint32, steps (S, N, 3) float32 (or (N, 3)),
over time_range (lo, hi) in [0, 1]. share=False copies the vertices even
when they could be shared. Returns the geometry id.)doc")
      .def("add_segments", &addSegments, "indices"_a, "steps"_a, "radii"_a, "time_range"_a = whole,
           "share"_a = true,
           R"doc(Adds round linear segments: indices (M, 2) uint32, steps (S, N, 3), radii (N,)
(one per vertex, the same at every step). Returns the geometry id.)doc")
      .def(
          "add_instance",
          [](PyScene& self, const py::object& child, const py::object& transforms, std::pair<float, float> range) {
            auto keys = transformKeys(transforms);
            return addInstance(self, child.cast<std::shared_ptr<PyScene>>(), child, std::move(keys), range);
          },
          "scene"_a, "transforms"_a, "time_range"_a = whole,
          R"doc(Adds an instance of another scene: transforms (S, 3, 4) or (S, 4, 4) row-major
object-to-world keys (or one (3, 4) / (4, 4) matrix), interpolated element-wise.
Returns the geometry id.)doc")
      .def(
          "add_instance_srt",
          [](PyScene& self, const py::object& child, const py::object& scale, const py::object& rotation,
             const py::object& translation, std::pair<float, float> range) {
            auto keys = srtKeys(scale, rotation, translation);
            return addInstance(self, child.cast<std::shared_ptr<PyScene>>(), child, std::move(keys), range);
          },
          "scene"_a, "scale"_a, "rotation"_a, "translation"_a, "time_range"_a = whole,
          R"doc(Adds an instance with SRT keys: scale (S, 3), rotation (S, 4) quaternions
(w, x, y, z), translation (S, 3); scale and translation are interpolated
linearly, the rotation by slerp, composed as T*R*S. Returns the geometry id.)doc")
      .def(
          "set_mask",
          [](PyScene& self, uint32_t geomID, uint32_t mask) {
            exclusive([&] { self.scene().setMask(geomID, mask); });
          },
          "geom_id"_a, "mask"_a, "Sets a geometry's mask (rays hit it when ray.mask & mask != 0); rebuild() after.")
      .def_property_readonly("num_geometries", [](const PyScene& s) { return s.scene().numGeometries(); })
      .def_property_readonly("num_primitives", [](const PyScene& s) { return s.scene().numPrimitives(); },
                             "Triangles + segments + instances at this level.")
      .def_property_readonly("name", [](const PyScene& s) { return s.description->name; })
      .def_property_readonly("version", [](const PyScene& s) { return deepVersion(s.scene()); },
                             "Changes whenever this scene or a scene it instances changes.")
      .def("geometry", &geometryInfo, "geom_id"_a,
           "A dict describing one geometry: type, primitives, steps, time_range, mask; for meshes and\n"
           "segments also vertices and shared (whether the scene reads the caller's array).")
      .def("bounds", &boundsOf, "The (2, 3) array [lower, upper] of the scene over the whole shutter.")
      .def(
          "validate",
          [](const PyScene& self) {
            py::gil_scoped_release nogil;
            std::shared_lock lock(sceneLock());
            self.scene().validate();
          },
          "Raises mbrt.Error when the scene cannot be built (what Accel would raise).")
      .def("__len__", [](const PyScene& s) { return s.scene().numGeometries(); })
      .def("__repr__", [](const PyScene& s) {
        return "<mbrt.Scene '" + s.description->name + "': " + std::to_string(s.scene().numGeometries()) +
               " geometries, " + std::to_string(s.scene().numPrimitives()) + " primitives>";
      });
}

}  // namespace mbrt::python
