// mbrt.Accel: build, trace numpy arrays of rays (GIL released, every core
// through TBB), statistics, rebuild and refit.
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <optional>

#include "bindings.h"
#include "result_memory.h"

namespace mbrt::python {
namespace {

// One ray component for every ray: a base pointer and a byte stride (0: the
// same value for every ray).
struct Column {
  const char* base = nullptr;
  py::ssize_t stride = 0;
  template <class T>
  T at(size_t i) const {
    T v;
    std::memcpy(&v, base + py::ssize_t(i) * stride, sizeof(T));
    return v;
  }
};

// The rays of a call, read in place from the caller's arrays: org xyz, dir
// xyz, tnear, tfar, time (float32) and mask (uint32).
struct RayColumns {
  size_t count = 0;
  Column c[10];
  std::vector<py::array> keep;  // arrays converted to float32 / uint32
  float scalars[4] = {0.0f, kInf, 0.0f, 0.0f};
  uint32_t maskScalar = 0xFFFFFFFFu;

  // Set when the rays are one C-contiguous (N, 9) float32 array and the
  // mask is one number: a ray is then 9 consecutive floats.
  const float* packed = nullptr;

  Ray ray(size_t i) const {
    Ray r;
    if (packed) {
      const float* f = packed + 9 * i;
      r.org = {f[0], f[1], f[2]};
      r.dir = {f[3], f[4], f[5]};
      r.tnear = f[6], r.tfar = f[7], r.time = f[8];
      r.mask = maskScalar;
      return r;
    }
    r.org = {c[0].at<float>(i), c[1].at<float>(i), c[2].at<float>(i)};
    r.dir = {c[3].at<float>(i), c[4].at<float>(i), c[5].at<float>(i)};
    r.tnear = c[6].at<float>(i);
    r.tfar = c[7].at<float>(i);
    r.time = c[8].at<float>(i);
    r.mask = c[9].at<uint32_t>(i);
    return r;
  }
};

using FloatArray = py::array_t<float, py::array::forcecast>;

void setCount(RayColumns& rays, py::ssize_t n, const char* what) {
  if (rays.count == size_t(-1)) {
    rays.count = size_t(n);
  } else if (size_t(n) != rays.count) {
    fail(std::string(what) + " has " + std::to_string(n) + " rays, expected " + std::to_string(rays.count));
  }
}

// An (N, 3) array into columns first..first+2.
void vectors(RayColumns& rays, const py::object& object, int first, const char* what) {
  FloatArray a = FloatArray::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(1) != 3) fail(std::string(what) + " must have shape (N, 3)");
  setCount(rays, a.shape(0), what);
  for (int k = 0; k < 3; ++k) rays.c[first + k] = {reinterpret_cast<const char*>(a.data()) + k * a.strides(1), a.strides(0)};
  rays.keep.push_back(a);
}

// A scalar (every ray) or an (N,) array into one column.
template <class T>
void values(RayColumns& rays, const py::object& object, int column, T& scalar, const char* what) {
  if (object.is_none()) {
    rays.c[column] = {reinterpret_cast<const char*>(&scalar), 0};
    return;
  }
  auto a = py::array_t<T, py::array::forcecast>::ensure(object);
  if (!a || a.ndim() > 1) fail(std::string(what) + " must be a number or an array of shape (N,)");
  if (a.ndim() == 0) {
    scalar = *a.data();
    rays.c[column] = {reinterpret_cast<const char*>(&scalar), 0};
    return;
  }
  setCount(rays, a.shape(0), what);
  rays.c[column] = {reinterpret_cast<const char*>(a.data()), a.strides(0)};
  rays.keep.push_back(a);
}

// rays: (N, 9) float32 as in a ray file (org, dir, tnear, tfar, time), or
// org/dir (N, 3) with tnear/tfar/time/mask as numbers or (N,) arrays.
void readRays(RayColumns& out, const py::object& rays, const py::object& org, const py::object& dir,
              const py::object& tnear, const py::object& tfar, const py::object& time, const py::object& mask) {
  out.count = size_t(-1);
  if (!rays.is_none()) {
    if (!org.is_none() || !dir.is_none()) fail("give either rays (N, 9) or org and dir, not both");
    FloatArray a = FloatArray::ensure(rays);
    if (!a || a.ndim() != 2 || a.shape(1) != 9)
      fail("rays must have shape (N, 9): org xyz, dir xyz, tnear, tfar, time (the ray file layout)");
    out.count = size_t(a.shape(0));
    for (int k = 0; k < 9; ++k) out.c[k] = {reinterpret_cast<const char*>(a.data()) + k * a.strides(1), a.strides(0)};
    out.keep.push_back(a);
    if (!tnear.is_none() || !tfar.is_none() || !time.is_none())
      fail("tnear, tfar and time are columns of rays (N, 9); give them only with org and dir");
  } else {
    if (org.is_none() || dir.is_none()) fail("give rays (N, 9), or org and dir (N, 3)");
    vectors(out, org, 0, "org");
    vectors(out, dir, 3, "dir");
    values<float>(out, tnear, 6, out.scalars[0], "tnear");
    values<float>(out, tfar, 7, out.scalars[1], "tfar");
    values<float>(out, time, 8, out.scalars[2], "time");
  }
  values<uint32_t>(out, mask, 9, out.maskScalar, "mask");
  const py::array& first = out.keep.front();
  if (!rays.is_none() && out.c[9].stride == 0 && (first.flags() & py::array::c_style))
    out.packed = static_cast<const float*>(first.data());
}

// What intersect() returns: one numpy array per field.
struct PyHits {
  py::array_t<float> t, u, v, ng;
  py::array_t<uint32_t> geomID, primID, instID;
};

// Seven arrays of n hits, views into one recycled block (result_memory.h).
PyHits newHits(py::ssize_t n) {
  const py::ssize_t padded = (n + 15) / 16 * 16;  // each array starts 64-byte aligned
  const ResultBlock block = acquireResultBlock(size_t(padded) * 9 * 4);
  py::ssize_t offset = 0;
  auto take = [&](auto type, std::vector<py::ssize_t> shape) {
    using T = decltype(type);
    auto* first = reinterpret_cast<T*>(block.data + offset);
    offset += padded * (shape.size() == 2 ? 3 : 1) * py::ssize_t(sizeof(T));
    std::vector<py::ssize_t> strides = shape.size() == 2 ? std::vector<py::ssize_t>{12, 4} : std::vector<py::ssize_t>{4};
    return py::array_t<T>(shape, strides, first, block.owner);
  };
  PyHits h;
  h.t = take(float{}, {n});
  h.u = take(float{}, {n});
  h.v = take(float{}, {n});
  h.ng = take(float{}, {n, 3});
  h.geomID = take(uint32_t{}, {n});
  h.primID = take(uint32_t{}, {n});
  h.instID = take(uint32_t{}, {n});
  return h;
}

template <class Body>
void parallelOverRays(size_t count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

py::object intersect(const PyAccel& self, const py::object& rays, const py::object& org, const py::object& dir,
                     const py::object& tnear, const py::object& tfar, const py::object& time, const py::object& mask,
                     const py::object& out) {
  RayColumns in;
  readRays(in, rays, org, dir, tnear, tfar, time, mask);
  const py::ssize_t n = py::ssize_t(in.count);
  py::object result = out;
  if (out.is_none()) {
    result = py::cast(newHits(n));
  } else if (!py::isinstance<PyHits>(out) || out.cast<PyHits&>().t.size() != n) {
    fail("out must be an mbrt.Hits of as many rays (" + std::to_string(n) + ")");
  }
  PyHits& h = result.cast<PyHits&>();
  float *t = h.t.mutable_data(), *u = h.u.mutable_data(), *v = h.v.mutable_data(), *ng = h.ng.mutable_data();
  uint32_t *g = h.geomID.mutable_data(), *p = h.primID.mutable_data(), *inst = h.instID.mutable_data();
  {
    py::gil_scoped_release nogil;
    std::shared_lock lock(sceneLock());
    self.checkCurrent();
    const Accel& accel = self.get();
    parallelOverRays(in.count, [&](size_t i) {
      Hit hit;
      accel.intersect(in.ray(i), hit);
      t[i] = hit.t, u[i] = hit.u, v[i] = hit.v;
      ng[3 * i] = hit.Ng.x, ng[3 * i + 1] = hit.Ng.y, ng[3 * i + 2] = hit.Ng.z;
      g[i] = hit.geomID, p[i] = hit.primID, inst[i] = hit.instID;
    });
  }
  return result;
}

py::array_t<bool> occluded(const PyAccel& self, const py::object& rays, const py::object& org,
                           const py::object& dir, const py::object& tnear, const py::object& tfar,
                           const py::object& time, const py::object& mask) {
  RayColumns in;
  readRays(in, rays, org, dir, tnear, tfar, time, mask);
  py::array_t<bool> out(py::ssize_t(in.count));
  bool* o = out.mutable_data();
  {
    py::gil_scoped_release nogil;
    std::shared_lock lock(sceneLock());
    self.checkCurrent();
    const Accel& accel = self.get();
    parallelOverRays(in.count, [&](size_t i) { o[i] = accel.occluded(in.ray(i)); });
  }
  return out;
}

AccelKind kindNamed(const std::string& kind, const char* what) {
  const auto parsed = parseAccelKind(kind);
  if (!parsed) {
    std::string list;
    for (AccelKind k : availableAccelKinds()) list += (list.empty() ? "" : ", ") + std::string(toString(k));
    fail("unknown " + std::string(what) + " '" + kind + "' (available: " + list + ")");
  }
  return *parsed;
}

BuildOptions buildOptions(const std::string& kind, int branching, int maxLeafSize, int sahBins, float traversalCost,
                          float frozenTime, size_t memoryBudget, int maxInstanceDepth, const std::string& embreeMode,
                          float autoFitTolerance, const std::optional<std::string>& autoLeafKind) {
  BuildOptions o;
  o.kind = kindNamed(kind, "accel kind");
  o.autoFitTolerance = autoFitTolerance;
  if (autoLeafKind) o.autoLeafKind = kindNamed(*autoLeafKind, "auto_leaf_kind");
  o.branching = branching;
  o.maxLeafSize = maxLeafSize;
  o.sahBins = sahBins;
  o.traversalCost = traversalCost;
  o.frozenTime = frozenTime;
  o.memoryBudget = memoryBudget;
  o.maxInstanceDepth = maxInstanceDepth;
  if (embreeMode == "robust") o.embreeMode = BuildOptions::EmbreeMode::Robust;
  else if (embreeMode == "default") o.embreeMode = BuildOptions::EmbreeMode::Default;
  else if (embreeMode == "static") o.embreeMode = BuildOptions::EmbreeMode::Static;
  else if (embreeMode == "static-robust") o.embreeMode = BuildOptions::EmbreeMode::StaticRobust;
  else fail("embree_mode must be 'robust', 'default', 'static' or 'static-robust', got '" + embreeMode + "'");
  return o;
}

py::dict statsDict(const AccelStats& s) {
  py::dict d;
  d["kind"] = s.kind;
  d["primitives"] = s.primitives;
  d["references"] = s.references;
  d["inner_nodes"] = s.innerNodes;
  d["leaf_nodes"] = s.leafNodes;
  d["max_depth"] = s.maxDepth;
  d["bytes"] = s.bytes;
  d["leaf_block_bytes"] = s.leafBlockBytes;
  d["peak_build_bytes"] = s.peakBuildBytes;
  d["sah_cost"] = s.sahCost;
  d["build_seconds"] = s.buildSeconds;
  d["invalid_rays"] = s.invalidRays;
  return d;
}

// rebuild() and refit() replace the structure: nothing may trace it meanwhile.
template <class F>
auto exclusive(PyAccel& self, F&& change) {
  py::gil_scoped_release nogil;
  std::unique_lock lock(sceneLock());
  auto result = change();
  self.builtVersion = deepVersion(self.scene->scene());
  return result;
}

const char* kRaysDoc = R"doc(
Rays are either `rays`, an (N, 9) float32 array laid out as a ray file (org
xyz, dir xyz, tnear, tfar, time), or `org` and `dir` (N, 3) arrays with
`tnear` (default 0), `tfar` (default inf) and `time` (default 0) as numbers
or (N,) arrays. `mask` (a number or (N,) uint32, default all bits) selects
geometries. Arrays of other dtypes are converted. Invalid rays (NaN, zero
direction, time outside [0, 1], tnear > tfar) miss and are counted in
stats()["invalid_rays"]. The GIL is released and the rays are traced on
every core (TBB); any number of Python threads may trace at once.)doc";

}  // namespace

void bindAccel(py::module_& m) {
  using namespace pybind11::literals;
  py::class_<PyHits>(m, "Hits", "Closest hits, one entry per ray (misses: t = inf, ids = 0xFFFFFFFF).")
      .def_readonly("t", &PyHits::t, "(N,) float32 distance along the ray (inf on a miss)")
      .def_readonly("geom_id", &PyHits::geomID, "(N,) uint32 geometry id (in the instanced scene for instance hits)")
      .def_readonly("prim_id", &PyHits::primID, "(N,) uint32 primitive id")
      .def_readonly("inst_id", &PyHits::instID, "(N,) uint32 id of the outermost instance, 0xFFFFFFFF if none")
      .def_readonly("u", &PyHits::u, "(N,) float32 barycentric of v1 (segments: along the segment)")
      .def_readonly("v", &PyHits::v, "(N,) float32 barycentric of v2")
      .def_readonly("ng", &PyHits::ng, "(N, 3) float32 unnormalized geometric normal in world space")
      .def_property_readonly(
          "hit", [](const PyHits& h) { return h.geomID.attr("__ne__")(py::int_(kInvalidId)); },
          "(N,) bool: whether the ray hit")
      .def("__len__", [](const PyHits& h) { return h.t.size(); });

  const std::string intersectDoc = std::string(
      "Closest hits of the rays: an mbrt.Hits. out=hits writes into an earlier result of as many rays\n"
      "(and returns it) instead of allocating new arrays.\n") + kRaysDoc;
  const std::string occludedDoc = std::string("Whether each ray hits anything in [tnear, tfar]: (N,) bool.\n") + kRaysDoc;
  py::class_<PyAccel, std::shared_ptr<PyAccel>>(m, "Accel", R"doc(
An acceleration structure over a Scene. kind is any kind name of the
command line (mbrt.kinds()). The Accel keeps its scene alive. Building
reads the scene only; adding geometry or setting masks afterwards makes
tracing raise mbrt.Error until rebuild().)doc")
      .def(py::init([](std::shared_ptr<PyScene> scene, const std::string& kind, int branching, int maxLeafSize,
                       int sahBins, float traversalCost, float frozenTime, size_t memoryBudget,
                       int maxInstanceDepth, const std::string& embreeMode, float autoFitTolerance,
                       const std::optional<std::string>& autoLeafKind) {
             if (!scene) fail("Accel needs an mbrt.Scene");
             auto a = std::make_shared<PyAccel>();
             a->scene = std::move(scene);
             const BuildOptions o = buildOptions(kind, branching, maxLeafSize, sahBins, traversalCost, frozenTime,
                                                 memoryBudget, maxInstanceDepth, embreeMode, autoFitTolerance,
                                                 autoLeafKind);
             py::gil_scoped_release nogil;
             std::shared_lock lock(sceneLock());
             a->accel = Accel::build(a->scene->scene(), o);
             a->builtVersion = deepVersion(a->scene->scene());
             return a;
           }),
           "scene"_a, "kind"_a = "auto", py::kw_only(), "branching"_a = 8, "max_leaf_size"_a = 8,
           "sah_bins"_a = 32, "traversal_cost"_a = 1.0f, "frozen_time"_a = 0.5f, "memory_budget"_a = 0,
           "max_instance_depth"_a = 8, "embree_mode"_a = "robust", "auto_fit_tolerance"_a = 1e-5f,
           "auto_leaf_kind"_a = py::none(),
           "Builds the structure (GIL released); the default kind is \"auto\" (docs/auto.md), as on the command\n"
           "line. auto_fit_tolerance and auto_leaf_kind apply to \"auto\" only: a part becomes an instance when\n"
           "its affine keys reproduce every vertex within that fraction of its diagonal, and auto_leaf_kind\n"
           "forces the kind of every object (None: chosen per object by cost). Raises mbrt.Error for a bad\n"
           "scene or options.")
      .def("intersect", &intersect, "rays"_a = py::none(), py::kw_only(), "org"_a = py::none(),
           "dir"_a = py::none(), "tnear"_a = py::none(), "tfar"_a = py::none(), "time"_a = py::none(),
           "mask"_a = py::none(), "out"_a = py::none(), intersectDoc.c_str())
      .def("occluded", &occluded, "rays"_a = py::none(), py::kw_only(), "org"_a = py::none(), "dir"_a = py::none(),
           "tnear"_a = py::none(), "tfar"_a = py::none(), "time"_a = py::none(), "mask"_a = py::none(),
           occludedDoc.c_str())
      .def(
          "rebuild", [](PyAccel& self) { exclusive(self, [&] { self.get().rebuild(); return true; }); },
          "Rebuilds from the scene (after its arrays changed in place or geometry was added).")
      .def(
          "refit", [](PyAccel& self) { return exclusive(self, [&] { return self.get().refit(); }); },
          "Updates bounds keeping the topology where the kind can (returns True), else rebuilds (False).")
      .def(
          "stats",
          [](const PyAccel& self) {
            AccelStats s;
            {
              py::gil_scoped_release nogil;
              std::shared_lock lock(sceneLock());
              s = self.get().stats();
            }
            return statsDict(s);
          },
          "Structure statistics as a dict: kind, primitives, references, inner_nodes, leaf_nodes, max_depth,\n"
          "bytes, peak_build_bytes, sah_cost, build_seconds, invalid_rays.")
      .def_property_readonly("kind", [](const PyAccel& self) { return std::string(toString(self.get().options().kind)); })
      .def_property_readonly("scene", [](const PyAccel& self) { return self.scene; })
      .def("__repr__", [](const PyAccel& self) {
        return "<mbrt.Accel " + std::string(toString(self.get().options().kind)) + " over '" +
               self.scene->description->name + "'>";
      });
}

}  // namespace mbrt::python
