#include "reference64.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

namespace mbrt::ref {
namespace {

// ---- double vectors ---------------------------------------------------------

V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double len(V3 a) { return std::sqrt(dot(a, a)); }
V3 of(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3f toF(V3 v) { return {float(v.x), float(v.y), float(v.z)}; }
double maxAbs(V3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }
double comp(V3 v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

// Affine map in double: x' = c0*x.x + c1*x.y + c2*x.z + p.
struct M34 {
  V3 c[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  V3 p;
  V3 vec(V3 v) const { return c[0] * v.x + c[1] * v.y + c[2] * v.z; }
  V3 point(V3 v) const { return vec(v) + p; }
  double det() const { return dot(c[0], cross(c[1], c[2])); }
  double norm() const { return std::sqrt(dot(c[0], c[0]) + dot(c[1], c[1]) + dot(c[2], c[2])); }
  // Inverse by the adjugate: rows of L^-1 are (c1 x c2, c2 x c0, c0 x c1) / det.
  M34 inverse() const {
    const double d = det();
    const V3 r0 = cross(c[1], c[2]) * (1 / d), r1 = cross(c[2], c[0]) * (1 / d), r2 = cross(c[0], c[1]) * (1 / d);
    M34 m;
    m.c[0] = {r0.x, r1.x, r2.x};
    m.c[1] = {r0.y, r1.y, r2.y};
    m.c[2] = {r0.z, r1.z, r2.z};
    m.p = m.vec(p) * -1.0;
    return m;
  }
};

M34 of(const Affine3f& a) {
  M34 m;
  m.c[0] = of(a.vx);
  m.c[1] = of(a.vy);
  m.c[2] = of(a.vz);
  m.p = of(a.p);
  return m;
}

// ---- time lookup --------------------------------------------------------------

// The model's time range rule: [lo, hi), a range ending at 1 contains 1.
bool alive(TimeRange r, float time) { return time >= r.lo && (time < r.hi || (r.hi >= 1.0f && time <= r.hi)); }

// Step segment k and fraction f at `time` for S equidistant steps over [lo,hi].
void stepAt(const Geometry& g, float time, uint32_t& k, double& f) {
  const uint32_t S = g.numSteps();
  if (S == 1) {
    k = 0, f = 0;
    return;
  }
  const TimeRange r = g.timeRange();
  const double local = (double(time) - r.lo) * double(S - 1) / (double(r.hi) - r.lo);
  const double fl = std::clamp(std::floor(local), 0.0, double(S - 2));
  k = uint32_t(fl);
  f = std::clamp(local - fl, 0.0, 1.0);
}

V3 vertexAt(const Geometry& g, uint32_t k, double f, uint32_t index) {
  const V3 a = of(g.vertices(k)[index]);
  if (g.numSteps() == 1) return a;
  const V3 b = of(g.vertices(k + 1)[index]);
  return a * (1 - f) + b * f;
}

// ---- instance keys --------------------------------------------------------------

struct Q {
  double w, x, y, z;
};

// Slerp along the shorter arc; the angle from atan2 of |a-b| and |a+b|
// (accurate for nearby keys, where acos of the dot product is not).
Q slerp64(Q a, Q b, double t) {
  if (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z < 0) b = {-b.w, -b.x, -b.y, -b.z};
  const double dn = std::sqrt((a.w - b.w) * (a.w - b.w) + (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                              (a.z - b.z) * (a.z - b.z));
  const double sn = std::sqrt((a.w + b.w) * (a.w + b.w) + (a.x + b.x) * (a.x + b.x) + (a.y + b.y) * (a.y + b.y) +
                              (a.z + b.z) * (a.z + b.z));
  const double theta = 2 * std::atan2(dn, sn);  // angle between a and b on the unit 4-sphere
  double wa = 1 - t, wb = t;
  if (theta > 1e-12) {
    wa = std::sin((1 - t) * theta) / std::sin(theta);
    wb = std::sin(t * theta) / std::sin(theta);
  }
  Q q{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// T * R * S.
M34 srtMatrix(V3 s, Q q, V3 t) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  M34 m;
  m.c[0] = V3{1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)} * s.x;
  m.c[1] = V3{2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)} * s.y;
  m.c[2] = V3{2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)} * s.z;
  m.p = t;
  return m;
}

M34 instanceAt(const Geometry& g, float time) {
  uint32_t k;
  double f;
  stepAt(g, time, k, f);
  if (g.hasSRTKeys()) {
    const SRTKey& a = g.srtKeys()[k];
    const SRTKey& b = g.srtKeys()[g.numSteps() == 1 ? k : k + 1];
    const Q qa{a.rotation.w, a.rotation.x, a.rotation.y, a.rotation.z};
    const Q qb{b.rotation.w, b.rotation.x, b.rotation.y, b.rotation.z};
    return srtMatrix(of(a.scale) * (1 - f) + of(b.scale) * f, slerp64(qa, qb, f),
                     of(a.translation) * (1 - f) + of(b.translation) * f);
  }
  const M34 a = of(g.transforms()[k]);
  if (g.numSteps() == 1) return a;
  const M34 b = of(g.transforms()[k + 1]);
  M34 m;
  for (int i = 0; i < 3; ++i) m.c[i] = a.c[i] * (1 - f) + b.c[i] * f;
  m.p = a.p * (1 - f) + b.p * f;
  return m;
}

// ---- boxes --------------------------------------------------------------------

struct Box {
  V3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  void grow(V3 v, double r = 0) {
    lo = {std::min(lo.x, v.x - r), std::min(lo.y, v.y - r), std::min(lo.z, v.z - r)};
    hi = {std::max(hi.x, v.x + r), std::max(hi.y, v.y + r), std::max(hi.z, v.z + r)};
  }
  void grow(const Box& b) {
    if (b.empty()) return;
    grow(b.lo);
    grow(b.hi);
  }
  bool empty() const { return !(lo.x <= hi.x); }
};

// Does the line o + t d, t in [tn, tf], meet the box (grown by a relative
// 1e-9 for the rounding of the double interpolation)?
bool lineMeetsBox(const Box& b, V3 o, V3 d, double tn, double tf) {
  if (b.empty()) return false;
  const double m = 1e-9 * std::max(maxAbs(b.lo), maxAbs(b.hi)) + 1e-300;
  double t0 = tn, t1 = tf;
  for (int i = 0; i < 3; ++i) {
    const double oi = comp(o, i), di = comp(d, i), lo = comp(b.lo, i) - m, hi = comp(b.hi, i) + m;
    if (di == 0) {
      if (oi < lo || oi > hi) return false;
      continue;
    }
    double a = (lo - oi) / di, c = (hi - oi) / di;
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

// ---- the scene as the reference sees it -----------------------------------------

struct Reference::Node {
  struct Geom {
    Box box;
    std::vector<Box> prims;
    const Node* child = nullptr;
  };
  const Scene* scene = nullptr;
  std::vector<Geom> geoms;
  Box box;
};

const Reference::Node* Reference::nodeFor(const Scene& scene) {
  auto it = nodes_.find(&scene);
  if (it != nodes_.end()) return it->second.get();
  auto node = std::make_unique<Node>();
  node->scene = &scene;
  node->geoms.resize(scene.numGeometries());
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    Node::Geom& out = node->geoms[id];
    if (g.type() == GeometryType::Instance) {
      out.child = nodeFor(*g.instancedScene());
      continue;  // culled in the instance's space, by the child's box
    }
    out.prims.resize(g.numPrimitives());
    for (uint32_t p = 0; p < g.numPrimitives(); ++p) {
      Box& b = out.prims[p];
      for (uint32_t k = 0; k < g.numSteps(); ++k) {
        if (g.type() == GeometryType::Triangles) {
          const Triangle& t = g.triangles()[p];
          for (uint32_t v : {t.v0, t.v1, t.v2}) b.grow(of(g.vertices(k)[v]));
        } else {
          const Segment& s = g.segments()[p];
          for (uint32_t v : {s.v0, s.v1}) b.grow(of(g.vertices(k)[v]), std::max(0.0f, g.radii()[v]));
        }
      }
      out.box.grow(b);
    }
  }
  // The node's box, for culling in its parent's instance space. Nested
  // instances are not culled (a box over slerped keys is not simply the
  // hull of the keys' boxes).
  for (const Node::Geom& g : node->geoms) node->box.grow(g.box);
  for (const Node::Geom& g : node->geoms)
    if (g.child) node->box = Box{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}};
  const Node* raw = node.get();
  nodes_.emplace(&scene, std::move(node));
  return raw;
}

Reference::Reference(const Scene& scene) { root_ = nodeFor(scene); }
Reference::~Reference() = default;

namespace {

// The ray at one instance level: origin and direction in that level's space,
// and the scale of the float computation, a + b*t, in that space's units.
struct LocalRay {
  V3 o, d;
  double a, b;
  double cond;  // product of the instance transforms' condition numbers above
  float time;
  uint32_t mask;
  double tnear, tfar;
  uint32_t instID;
};

struct Tracer {
  const Ray& ray;
  bool cull;
  std::vector<Candidate>& out;

  // Adds a candidate in [tnear, tfar] (or within its bound of them).
  void add(const LocalRay& r, const Geometry& g, uint32_t geomID, uint32_t primID, double t, double tb,
           bool ambiguous, float u, float v, V3 ng) {
    // A float t below the smallest normal float keeps only a few bits, and
    // none under flush-to-zero (which Embree sets on the TBB threads it
    // joins): any t in [0, 2 FLT_MIN] answers for one there.
    tb = std::max(tb, std::fabs(t) < 2.0 * std::numeric_limits<float>::min()
                          ? 2.0 * std::numeric_limits<float>::min()
                          : 0.0);
    if (!(t >= r.tnear - tb && t <= r.tfar + tb)) return;
    if (t < r.tnear + tb || t > r.tfar - tb) ambiguous = true;
    if (t > double(std::numeric_limits<float>::max())) return;  // not a finite float: never reported
    if (g.hasFilter()) {
      Hit h;
      h.t = float(t);
      h.u = u, h.v = v;
      h.Ng = toF(ng);
      h.geomID = geomID, h.primID = primID;
      const Ray lr{toF(r.o), ray.tnear, toF(r.d), ray.tfar, ray.time, ray.mask};
      if (!g.filter()(FilterArgs{lr, h, g.userData()})) return;
    }
    out.push_back({t, tb, geomID, primID, r.instID, ambiguous});
  }

  void triangle(const LocalRay& r, const Geometry& g, uint32_t geomID, uint32_t primID, uint32_t k, double f) {
    const Triangle& tri = g.triangles()[primID];
    const V3 v0 = vertexAt(g, k, f, tri.v0), v1 = vertexAt(g, k, f, tri.v1), v2 = vertexAt(g, k, f, tri.v2);
    const V3 A = v0 - r.o, B = v1 - r.o, C = v2 - r.o;
    // Plücker edge functions: the signed volumes of the ray with each edge;
    // E_i / |edge_i x d| is the distance of the ray's line from edge i's line.
    const double E0 = dot(r.d, cross(B, C)), E1 = dot(r.d, cross(C, A)), E2 = dot(r.d, cross(A, B));
    const V3 n = cross(v1 - v0, v2 - v0);
    const double dn = dot(n, r.d);
    const double t = dn != 0 ? dot(n, A) / dn : kInf;
    const double vmax = std::max({len(v0), len(v1), len(v2)});
    const double S = r.a + r.b * (std::isfinite(t) ? std::fabs(t) : 0.0) + r.cond * vmax;
    const double delta = kEdgeUlps * kUlp * S;
    auto edgeDist = [&](double E, V3 p, V3 q) {
      const double c = len(cross(q - p, r.d));
      if (c > 1e-300) return std::fabs(E) / c;
      return len(cross(p - r.o, r.d)) / len(r.d);  // ray parallel to the edge
    };
    const double dmin = std::min({edgeDist(E0, v1, v2), edgeDist(E1, v2, v0), edgeDist(E2, v0, v1)});
    const bool inside = (E0 > 0 && E1 > 0 && E2 > 0) || (E0 < 0 && E1 < 0 && E2 < 0);
    const bool nearEdge = dmin <= delta || !(len(n) > 0);
    if (!inside && !nearEdge) return;
    const double cosTheta = std::fabs(dn) / (len(n) * len(r.d));
    const double tb = cosTheta > 0 ? kTUlps * kUlp * S / (len(r.d) * cosTheta) : kInf;
    const double sum = E0 + E1 + E2;
    add(r, g, geomID, primID, std::isfinite(t) ? t : r.tnear, tb, nearEdge, sum != 0 ? float(E1 / sum) : 0.0f,
        sum != 0 ? float(E2 / sum) : 0.0f, n);
  }

  // Signed distance-like function of the round segment: min over s in [0,1]
  // of |x - p(s)| - r(s), the hull of the spheres being the union of the
  // spheres along the segment with linearly varying radius. Convex in x
  // (the partial minimum of a jointly convex function), the Euclidean
  // distance outside. The minimizing s is in closed form.
  static double segmentField(V3 x, V3 p0, V3 p1, double r0, double r1) {
    const V3 e = p1 - p0, w = x - p0;
    const double L = len(e);
    const double ends = std::min(len(w) - r0, len(x - p1) - r1);
    if (!(L > 0)) return ends;
    const double k = (r1 - r0) / L;  // radius change per unit length
    if (std::fabs(k) >= 1) return ends;
    const double q = dot(w, e) / L;  // axial coordinate of x
    const double h = len(w - e * (q / L));
    const double sigma = std::clamp(q + k * h / std::sqrt(1 - k * k), 0.0, L);
    const V3 c = p0 + e * (sigma / L);
    return std::min(ends, len(x - c) - (r0 + k * sigma));
  }

  void segment(const LocalRay& r, const Geometry& g, uint32_t geomID, uint32_t primID, uint32_t k, double f) {
    const Segment& seg = g.segments()[primID];
    const V3 p0 = vertexAt(g, k, f, seg.v0), p1 = vertexAt(g, k, f, seg.v1);
    const double r0 = std::max(0.0f, g.radii()[seg.v0]), r1 = std::max(0.0f, g.radii()[seg.v1]);
    if (r0 <= 0 && r1 <= 0) return;
    const double dl = len(r.d);
    const V3 dn = r.d * (1 / dl);
    const V3 c = (p0 + p1) * 0.5;
    const double R = 0.5 * len(p1 - p0) + std::max(r0, r1);
    const double tc = dot(c - r.o, dn);  // distance units along dn
    const double dist = len(c - r.o - dn * tc);
    const double Sbase = r.a + r.cond * (std::max(len(p0), len(p1)) + std::max(r0, r1));
    const double deltaMax = kEdgeUlps * kUlp * (Sbase + r.b * (std::fabs(tc) + R) / dl);
    if (dist > R + deltaMax) return;
    auto phi = [&](double s) { return segmentField(r.o + dn * s, p0, p1, r0, r1); };
    // Golden-section search for the minimum of the convex phi, which lies
    // within 3R of tc (beyond, phi exceeds its value at tc).
    // phi >= |x - c| - R: at tc +- span it exceeds 2 deltaMax + 2R, above
    // every level searched below.
    const double span = 3 * R + 8 * deltaMax + 1e-300;
    double lo = tc - span, hi = tc + span;
    const double gr = 0.5 * (std::sqrt(5.0) - 1);
    double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1 = phi(x1), f2 = phi(x2);
    for (int i = 0; i < 80 && hi - lo > 1e-17 * (std::fabs(tc) + R); ++i) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - gr * (hi - lo), f1 = phi(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + gr * (hi - lo), f2 = phi(x2);
      }
    }
    const double tmin = f1 < f2 ? x1 : x2, fmin = std::min(f1, f2);
    const double S = Sbase + r.b * std::fabs(tmin) / dl;
    const double deltaEdge = kEdgeUlps * kUlp * S, deltaT = kTUlps * kUlp * S;
    if (fmin > deltaEdge) return;
    const bool grazing = fmin > -deltaEdge;
    // Where phi crosses `level` between `outside` (phi > level) and `inside`.
    auto root = [&](double outside, double inside, double level) {
      for (int i = 0; i < 200 && std::fabs(outside - inside) > 1e-17 * (std::fabs(tc) + R); ++i) {
        const double m = 0.5 * (outside + inside);
        (phi(m) > level ? outside : inside) = m;
      }
      return 0.5 * (outside + inside);
    };
    // The t bound as intervals: entry and exit of the solid grown and shrunk
    // by deltaT (a float tracer answers for a solid moved by its rounding),
    // widened by deltaT along the ray for the rounding of t itself.
    const double inLo = root(tc - span, tmin, deltaT), outHi = root(tc + span, tmin, deltaT);
    const double inHi = fmin < -deltaT ? root(tc - span, tmin, -deltaT) : tmin;
    const double outLo = fmin < -deltaT ? root(tc + span, tmin, -deltaT) : tmin;
    const double enter = 0.5 * (inLo + inHi) / dl, tbIn = (0.5 * (inHi - inLo) + deltaT) / dl;
    const double exit = 0.5 * (outLo + outHi) / dl, tbOut = (0.5 * (outHi - outLo) + deltaT) / dl;
    // The hit is the entry, or the exit when the ray starts inside.
    add(r, g, geomID, primID, enter, tbIn, grazing, 0, 0, {});
    if (enter - tbIn <= r.tnear)
      add(r, g, geomID, primID, exit, tbOut, grazing || enter + tbIn >= r.tnear, 0, 0, {});
  }

  void scene(const Reference::Node& node, const LocalRay& r) {
    const Scene& s = *node.scene;
    for (uint32_t id = 0; id < s.numGeometries(); ++id) {
      const Geometry& g = s.geometry(id);
      if ((g.mask() & r.mask) == 0 || !alive(g.timeRange(), r.time)) continue;
      const Reference::Node::Geom& ng = node.geoms[id];
      if (g.type() == GeometryType::Instance) {
        const M34 m = instanceAt(g, r.time);
        if (m.det() == 0) continue;
        const M34 inv = m.inverse();
        LocalRay lr = r;
        lr.o = inv.point(r.o);
        lr.d = inv.vec(r.d);
        const double ni = inv.norm();
        lr.a = ni * (r.a + len(m.p)) + len(lr.o);
        lr.b = ni * r.b + len(lr.d);
        lr.cond = r.cond * ni * m.norm();
        lr.instID = r.instID == kInvalidId ? id : r.instID;
        if (cull && !lineMeetsBox(ng.child->box, lr.o, lr.d, r.tnear, r.tfar)) continue;
        scene(*ng.child, lr);
        continue;
      }
      if (cull && !lineMeetsBox(ng.box, r.o, r.d, r.tnear, r.tfar)) continue;
      uint32_t k;
      double f;
      stepAt(g, r.time, k, f);
      for (uint32_t p = 0; p < g.numPrimitives(); ++p) {
        if (cull && !lineMeetsBox(ng.prims[p], r.o, r.d, r.tnear, r.tfar)) continue;
        if (g.type() == GeometryType::Triangles)
          triangle(r, g, id, p, k, f);
        else
          segment(r, g, id, p, k, f);
      }
    }
  }
};

bool validRay(const Ray& r) {
  auto fin = [](Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  return fin(r.org) && fin(r.dir) && std::isfinite(r.tnear) && !std::isnan(r.tfar) &&
         !(r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) && r.time >= 0 && r.time <= 1 && r.tnear <= r.tfar;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string ids(uint32_t g, uint32_t p, uint32_t i) {
  return "g" + std::to_string(g) + " p" + std::to_string(p) + (i == kInvalidId ? "" : " i" + std::to_string(i));
}

}  // namespace

void Reference::candidates(const Ray& ray, std::vector<Candidate>& out, bool cull) const {
  out.clear();
  if (!validRay(ray)) return;
  LocalRay r;
  r.o = of(ray.org);
  r.d = of(ray.dir);
  r.a = len(r.o);
  r.b = len(r.d);
  r.cond = 1;
  r.time = ray.time;
  r.mask = ray.mask;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.instID = kInvalidId;
  Tracer tr{ray, cull, out};
  tr.scene(*root_, r);
}

std::string describe(const Ray& ray) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "ray org (%.9g,%.9g,%.9g) dir (%.9g,%.9g,%.9g) t [%.9g,%.9g] time %.9g mask %x",
                ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tnear, ray.tfar, ray.time,
                ray.mask);
  return buf;
}

namespace {

// The closest-hit verdict from one candidate list; `retry` set when the
// library's hit is not among them (the caller retries without culling).
Verdict closestFrom(const std::vector<Candidate>& c, const Ray& ray, const Hit& hit, bool& retry) {
  Verdict v;
  retry = false;
  const Candidate* firstDefinite = nullptr;
  for (const Candidate& x : c)
    if (!x.ambiguous && (!firstDefinite || x.t < firstDefinite->t)) firstDefinite = &x;
  if (!hit.valid()) {
    v.ok = firstDefinite == nullptr;
    v.ambiguous = !c.empty();
    if (!v.ok)
      v.why = describe(ray) + ": missed, reference hits " +
              ids(firstDefinite->geomID, firstDefinite->primID, firstDefinite->instID) + " at t " +
              num(firstDefinite->t);
    return v;
  }
  const Candidate* match = nullptr;
  for (const Candidate& x : c)
    if (x.geomID == hit.geomID && x.primID == hit.primID && x.instID == hit.instID &&
        std::fabs(double(hit.t) - x.t) <= x.tBound)
      match = &x;
  if (!match) {
    retry = true;
    v.ok = false;
    v.why = describe(ray) + ": hit " + ids(hit.geomID, hit.primID, hit.instID) + " at t " + num(hit.t) +
            " that the reference does not find there" +
            (firstDefinite ? " (reference: " + ids(firstDefinite->geomID, firstDefinite->primID, firstDefinite->instID) +
                                 " at t " + num(firstDefinite->t) + ")"
                           : "");
    return v;
  }
  v.ambiguous = match->ambiguous;
  for (const Candidate& x : c)
    if (!x.ambiguous && x.t < double(hit.t) - x.tBound - match->tBound) {
      v.ok = false;
      v.why = describe(ray) + ": hit " + ids(hit.geomID, hit.primID, hit.instID) + " at t " +
              num(hit.t) + ", reference has a closer hit " + ids(x.geomID, x.primID, x.instID) +
              " at t " + num(x.t);
      return v;
    }
  for (const Candidate& x : c)
    if (&x != match && x.t <= double(hit.t) + x.tBound + match->tBound) v.ambiguous = true;  // a tie
  return v;
}

Verdict anyFrom(const std::vector<Candidate>& c, const Ray& ray, bool occluded, bool& retry) {
  Verdict v;
  retry = occluded && c.empty();
  const bool definite = std::any_of(c.begin(), c.end(), [](const Candidate& x) { return !x.ambiguous; });
  v.ok = occluded ? !c.empty() : !definite;
  v.ambiguous = !c.empty() && !definite;
  if (!v.ok) v.why = describe(ray) + (occluded ? ": occluded, the reference finds nothing" : ": not occluded, the reference hits");
  return v;
}

}  // namespace

void Reference::judge(const Ray& ray, const Hit* hit, const bool* occluded, Verdict& closest, Verdict& any) const {
  std::vector<Candidate> c;
  candidates(ray, c, true);
  bool retryC = false, retryA = false;
  if (hit) closest = closestFrom(c, ray, *hit, retryC);
  if (occluded) any = anyFrom(c, ray, *occluded, retryA);
  if (!retryC && !retryA) return;
  candidates(ray, c, false);  // culling keeps every definite hit, not every near miss
  if (retryC) closest = closestFrom(c, ray, *hit, retryC);
  if (retryA) any = anyFrom(c, ray, *occluded, retryA);
}

Verdict Reference::judgeClosest(const Ray& ray, const Hit& hit) const {
  Verdict c, a;
  judge(ray, &hit, nullptr, c, a);
  return c;
}

Verdict Reference::judgeAny(const Ray& ray, bool occluded) const {
  Verdict c, a;
  judge(ray, nullptr, &occluded, c, a);
  return a;
}

RefReport judgeBatch(const Reference& ref, const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                     const std::vector<uint8_t>& occluded) {
  std::atomic<size_t> nHits{0}, nAmb{0}, nWrong{0}, nAnyWrong{0};
  std::mutex mu;
  RefReport rep;
  rep.rays = rays.size();
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
    Verdict c, a;
    const bool occ = occluded[i] != 0;
    ref.judge(rays[i], &hits[i], &occ, c, a);
    if (hits[i].valid()) ++nHits;
    if (c.ambiguous || a.ambiguous) ++nAmb;
    if (!c.ok) ++nWrong;
    if (!a.ok) ++nAnyWrong;
    if (!c.ok || !a.ok) {
      std::lock_guard<std::mutex> lock(mu);
      if (rep.firstFailure.empty()) rep.firstFailure = !c.ok ? c.why : a.why;
    }
  });
  rep.hits = nHits, rep.ambiguous = nAmb, rep.wrong = nWrong, rep.anyWrong = nAnyWrong;
  return rep;
}

}  // namespace mbrt::ref
