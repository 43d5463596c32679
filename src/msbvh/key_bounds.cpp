#include "msbvh/key_bounds.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "geometry/clip.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {

uint32_t chooseKeySegments(const SceneContext& ctx) {
  float need = 1.0f;
  for (uint32_t g = 0; g < ctx.scene().numGeometries(); ++g) {
    const Geometry& geo = ctx.geometry(g);
    if (geo.numSteps() <= 1) continue;
    need = std::max(need, float(geo.numSteps() - 1) / geo.timeRange().size());
  }
  uint32_t n = 1;
  while (n < kMaxKeySegments && float(n) < need * (1.0f - 1e-6f)) n *= 2;
  return n;
}

KeyBounder::KeyBounder(const SceneContext& ctx, uint32_t segments) : ctx_(ctx), n_(segments) {
  breaks_.resize(ctx.scene().numGeometries());
  for (uint32_t g = 0; g < breaks_.size(); ++g) {
    const Geometry& geo = ctx.geometry(g);
    if (geo.numSteps() <= 1) continue;
    for (uint32_t k = 0; k < geo.numSteps(); ++k) {
      const float t = geo.stepTime(k);
      const float x = t * float(n_);
      const float i = std::floor(x);
      if (x == i || i < 0.0f || i >= float(n_)) continue;  // on a key (or outside)
      breaks_[g].push_back({uint32_t(i), t, x - i});
    }
  }
}

namespace {

float radiusOf(const Geometry& g, const Segment& s) { return std::max(g.radii()[s.v0], g.radii()[s.v1]); }

// Margin for clipping round-off at leaves: far more than the error of a
// clip (a few ulp), far less than anything that matters for culling.
Vec3f clipMargin(const Box3f& b) {
  const float mag = std::max(maxComponent(Vec3f(std::fabs(b.lower.x), std::fabs(b.lower.y), std::fabs(b.lower.z))),
                             maxComponent(Vec3f(std::fabs(b.upper.x), std::fabs(b.upper.y), std::fabs(b.upper.z))));
  return Vec3f(mag * (1.0f / 16384.0f) + 1e-30f);
}

}  // namespace

Box3f KeyBounder::buildBox(PrimRef prim) const { return widen(boxAt(ctx_, prim, kBuildTime)); }

Box3f KeyBounder::clip(PrimRef prim, const Box3f& box) const {
  const Geometry& g = ctx_.geometry(prim.geomID);
  switch (g.type()) {
    case GeometryType::Triangles: {
      const Triangle& t = g.triangles()[prim.primID];
      return clipTriangleBounds(g.vertexAt(kBuildTime, t.v0), g.vertexAt(kBuildTime, t.v1),
                                g.vertexAt(kBuildTime, t.v2), box);
    }
    case GeometryType::Segments: {
      const Segment& s = g.segments()[prim.primID];
      const float r = radiusOf(g, s);
      const Vec3f a = g.vertexAt(kBuildTime, s.v0), b = g.vertexAt(kBuildTime, s.v1);
      float s0, s1;
      if (!clipSegment(a, b, grow(box, Vec3f(r)), s0, s1)) return {};
      Box3f c(lerp(a, b, s0));
      c.extend(lerp(a, b, s1));
      return intersect(grow(c, Vec3f(r)), box);
    }
    case GeometryType::Instance: {
      const Box3f c = intersect(buildBox(prim), box);
      return c.empty() ? Box3f() : c;
    }
  }
  return {};
}

void KeyBounder::chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes,
                      Box3f* pieces) const {
  const Geometry& g = ctx_.geometry(prim.geomID);
  if (g.type() != GeometryType::Triangles) return RefClipper::chop(prim, box, axis, planes, pieces);
  const Triangle& t = g.triangles()[prim.primID];
  chopTriangle(g.vertexAt(kBuildTime, t.v0), g.vertexAt(kBuildTime, t.v1), g.vertexAt(kBuildTime, t.v2), box, axis,
               planes, pieces);
}

BuildTimeClipper::BuildTimeClipper(const SceneContext& ctx, const KeyBounder& bounder)
    : ctx_(ctx), bounder_(bounder) {
  vertices_.resize(ctx.scene().numGeometries());
  for (uint32_t g = 0; g < vertices_.size(); ++g) {
    const Geometry& geo = ctx.geometry(g);
    if (geo.type() != GeometryType::Triangles) continue;
    std::vector<Vec3f>& v = vertices_[g];
    v.resize(geo.vertices(0).count);
    tbb::parallel_for(size_t(0), v.size(), [&](size_t i) { v[i] = geo.vertexAt(kBuildTime, uint32_t(i)); });
    bytes_ += v.size() * sizeof(Vec3f);
  }
}

bool BuildTimeClipper::corners(PrimRef prim, Vec3f (&v)[3]) const {
  const Geometry& g = ctx_.geometry(prim.geomID);
  if (g.type() != GeometryType::Triangles) return false;
  const Triangle& t = g.triangles()[prim.primID];
  const std::vector<Vec3f>& at = vertices_[prim.geomID];
  v[0] = at[t.v0];
  v[1] = at[t.v1];
  v[2] = at[t.v2];
  return true;
}

Box3f BuildTimeClipper::clip(PrimRef prim, const Box3f& box) const {
  Vec3f v[3];
  if (!corners(prim, v)) return bounder_.clip(prim, box);
  return clipTriangleBounds(v[0], v[1], v[2], box);
}

void BuildTimeClipper::chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes,
                            Box3f* pieces) const {
  Vec3f v[3];
  if (!corners(prim, v)) return bounder_.chop(prim, box, axis, planes, pieces);
  chopTriangle(v[0], v[1], v[2], box, axis, planes, pieces);
}

bool KeyBounder::pieceKeys(PrimRef prim, const Box3f& region, Box3f* out) const {
  const Geometry& g = ctx_.geometry(prim.geomID);
  const Box3f clipBox = grow(region, clipMargin(buildBox(prim)));
  switch (g.type()) {
    case GeometryType::Triangles: {
      const Triangle& t = g.triangles()[prim.primID];
      const ClippedPolygon poly = clipTriangle(g.vertexAt(kBuildTime, t.v0), g.vertexAt(kBuildTime, t.v1),
                                               g.vertexAt(kBuildTime, t.v2), clipBox);
      if (poly.count == 0) return false;
      keysOf(prim, out, [&](float time) {
        const Vec3f v0 = g.vertexAt(time, t.v0), v1 = g.vertexAt(time, t.v1), v2 = g.vertexAt(time, t.v2);
        Box3f b;
        for (int i = 0; i < poly.count; ++i) b.extend(evalBary(poly.bary[i], v0, v1, v2));
        return b;
      });
      return true;
    }
    case GeometryType::Segments: {
      const Segment& s = g.segments()[prim.primID];
      const float r = radiusOf(g, s);
      float s0 = 0.0f, s1 = 1.0f;
      // Axis points c(s) inside the region; the radius pads them below.
      if (!clipSegment(g.vertexAt(kBuildTime, s.v0), g.vertexAt(kBuildTime, s.v1), clipBox, s0, s1)) return false;
      keysOf(prim, out, [&](float time) {
        const Vec3f a = g.vertexAt(time, s.v0), b = g.vertexAt(time, s.v1);
        Box3f c(lerp(a, b, s0));
        c.extend(lerp(a, b, s1));
        return grow(c, Vec3f(r));
      });
      return true;
    }
    case GeometryType::Instance:
      keysOf(prim, out, [&](float time) { return boxAt(ctx_, prim, time); });
      return true;
  }
  return false;
}

// The n+1 key boxes of the piece whose box at a time `at` gives, pushed out
// at the breaks and padded against round-off (key_bounds.h).
template <class At>
void KeyBounder::keysOf(PrimRef prim, Box3f* out, const At& at) const {
  const Geometry& g = ctx_.geometry(prim.geomID);
  for (uint32_t i = 0; i <= n_; ++i) out[i] = at(float(i) / float(n_));
  for (const Break& br : breaks_[prim.geomID]) {
    Box3f& a = out[br.interval];
    Box3f& b = out[br.interval + 1];
    const Box3f line = lerp(a, b, br.fraction);
    const Box3f p = at(br.time);
    const Vec3f pushLo = min(Vec3f(0.0f), p.lower - line.lower), pushHi = max(Vec3f(0.0f), p.upper - line.upper);
    a.lower += pushLo;
    b.lower += pushLo;
    a.upper += pushHi;
    b.upper += pushHi;
  }
  // Round-off: positions between keys are interpolated from the mesh's
  // steps, whose coordinates may be far larger than the key boxes' (a vertex
  // passing near the origin between two distant steps); pad by a few ulp of
  // the largest coordinate the primitive has at any step, then widen.
  float mag = 0.0f;
  for (uint32_t k = 0; k < g.numSteps(); ++k) {
    const Box3f b = ctx_.keyBox(prim, k);
    mag = std::max(mag, maxComponent(max(Vec3f(std::fabs(b.lower.x), std::fabs(b.lower.y), std::fabs(b.lower.z)),
                                         Vec3f(std::fabs(b.upper.x), std::fabs(b.upper.y), std::fabs(b.upper.z)))));
  }
  const Vec3f pad(mag * 0x1p-19f);
  for (uint32_t i = 0; i <= n_; ++i) out[i] = widen(grow(out[i], pad));
}

}  // namespace mbrt::detail

namespace mbrt::detail {

uint32_t fitKeySegments(const SceneContext& ctx, uint32_t maxSegments) {
  if (maxSegments <= 1) return maxSegments;
  const std::vector<PrimRef> prims = ctx.primitives();
  const size_t sample = std::min<size_t>(prims.size(), 2048);
  if (sample == 0) return maxSegments;
  // Mean half area of the sampled primitives' interpolated key boxes at 16
  // times; each primitive is its own piece (clipped to its own box).
  auto meanArea = [&](uint32_t n) {
    const KeyBounder bounder(ctx, n);
    std::vector<Box3f> keys(n + 1);
    double sum = 0.0;
    for (size_t j = 0; j < sample; ++j) {
      const PrimRef prim = prims[j * prims.size() / sample];
      if (!bounder.pieceKeys(prim, bounder.buildBox(prim), keys.data())) continue;
      for (int i = 0; i < 16; ++i) {
        const float x = (float(i) + 0.5f) / 16.0f * float(n);
        const uint32_t k = std::min(uint32_t(x), n - 1);
        const Box3f b = lerp(keys[k], keys[k + 1], x - float(k));
        if (!b.empty()) sum += double(b.halfArea());
      }
    }
    return sum;
  };
  const double finest = meanArea(maxSegments);
  for (uint32_t n = 1; n < maxSegments; n *= 2)
    if (meanArea(n) <= finest * (1.0 + kKeyAreaSlack)) return n;
  return maxSegments;
}

}  // namespace mbrt::detail
