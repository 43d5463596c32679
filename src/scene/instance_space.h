// The ray in an instance's space (or a fuzzy kd-tree cluster's frame) at the
// ray's time, without forming the inverse matrix. For the interpolated key M
// = [L | p] with the columns c0, c1, c2 of L, the rows of L^-1 are the
// cofactor rows c1×c2, c2×c0 and c0×c1 divided by det L (Cramer's rule), so
// the local ray is (L^-1 (org - p), L^-1 dir) from three cross products, six
// dot products and one division, in double: the origin's offset from p is
// taken before any rounding, which keeps a far ray's origin as accurate as a
// near one's.
//
// Two kinds of matrix keys need less per ray (InstanceMotion, made once per
// instance by its SceneContext):
//  - translation only (every key's L the identity): the local ray is the
//    ray with its origin moved by -p, its direction and everything made from
//    it (reciprocal, watertight shear) kept; three subtractions;
//  - one linear part under every key (L constant, p moving): the cofactor
//    rows and 1 / det L are those of L, made once; six dot products.
// Interpolating p is exact in both (lerp(L, L, f) is L: see lerp in
// mbrt/math.h for equal keys, and 1·(1-f) + 1·f rounds to 1 for every f);
// element-wise interpolated matrices whose L changes (and SRT keys) take
// the general path, where L^-1 of the lerp is not the lerp of inverses.
#pragma once

#include <cmath>

#include "core/ray_query.h"
#include "core/vec3d.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

// What a hit in the instance needs to come back: M^-T n for its normal.
struct InstanceFrame {
  Vec3f cofactor[3];  // the rows of det(L) L^-1
  float invDet = 0.0f;

  Vec3f normalToWorld(Vec3f n) const {
    return (cofactor[0] * n.x + cofactor[1] * n.y + cofactor[2] * n.z) * invDet;
  }
};

// The cofactor rows of L = [c0 c1 c2] and 1 / det L, in double; false when
// L is singular.
struct CofactorRows {
  Vec3d r[3];
  double invDet = 0.0;

  bool make(const Affine3f& m) {
    const Vec3d c0 = toD(m.vx), c1 = toD(m.vy), c2 = toD(m.vz);
    r[0] = cross(c1, c2);
    r[1] = cross(c2, c0);
    r[2] = cross(c0, c1);
    const double det = dot(c0, r[0]);
    if (!(std::fabs(det) > 1e-30)) return false;
    invDet = 1.0 / det;
    return true;
  }
  // The local ray of `ray` with its origin offset o = org - p (in double).
  void apply(Vec3d o, const RayQuery& ray, RayQuery& local) const {
    const Vec3d d = toD(ray.dir);
    local.setup({float(dot(r[0], o) * invDet), float(dot(r[1], o) * invDet), float(dot(r[2], o) * invDet)},
                {float(dot(r[0], d) * invDet), float(dot(r[1], d) * invDet), float(dot(r[2], d) * invDet)},
                ray.tnear, ray.tfar, ray.time, ray.mask);
  }
  InstanceFrame frame() const { return {{toF(r[0]), toF(r[1]), toF(r[2])}, float(invDet)}; }
};

// Sets `local` to the ray in the space that m maps to world space, and
// `frame` (when given: closest-hit queries) to what its hits need; false
// when m is singular (a flat instance: no hit).
inline bool toLocalSpace(const Affine3f& m, const RayQuery& ray, RayQuery& local, InstanceFrame* frame) {
  CofactorRows rows;
  if (!rows.make(m)) return false;
  rows.apply(toD(ray.org) - toD(m.p), ray, local);
  if (frame) *frame = rows.frame();
  return true;
}

// An instance's keys, classified once (see the top of this file).
class InstanceMotion {
 public:
  enum class Kind : uint8_t { Translation, ConstantLinear, General };

  InstanceMotion() = default;
  explicit InstanceMotion(const Geometry& g) {
    const auto keys = g.transforms();
    if (g.type() != GeometryType::Instance || g.hasSRTKeys() || keys.empty()) return;
    const Affine3f& first = keys.front();
    bool sameLinear = true;
    for (const Affine3f& k : keys) sameLinear = sameLinear && k.vx == first.vx && k.vy == first.vy && k.vz == first.vz;
    if (!sameLinear) return;
    const Affine3f identity;
    if (first.vx == identity.vx && first.vy == identity.vy && first.vz == identity.vz) {
      kind_ = Kind::Translation;
    } else {
      kind_ = Kind::ConstantLinear;
      singular_ = !rows_.make(first);
    }
    if (!singular_) frame_ = kind_ == Kind::Translation ? CofactorRows{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, 1.0}.frame()
                                                         : rows_.frame();
  }

  Kind kind() const { return kind_; }

  // The ray in instance g's space at the ray's time (g: the instance this
  // motion was made of).
  bool toLocal(const Geometry& g, const RayQuery& ray, RayQuery& local, InstanceFrame* frame) const {
    switch (kind_) {
      case Kind::Translation: {
        const Vec3f p = offsetAt(g, ray.time);
        local = ray;
        local.org = toF(toD(ray.org) - toD(p));
        if (frame) *frame = frame_;
        return true;
      }
      case Kind::ConstantLinear: {
        if (singular_) return false;
        rows_.apply(toD(ray.org) - toD(offsetAt(g, ray.time)), ray, local);
        if (frame) *frame = frame_;
        return true;
      }
      case Kind::General:
        break;
    }
    return toLocalSpace(g.transformAt(ray.time), ray, local, frame);
  }

 private:
  // p of the interpolated key, as Geometry::transformAt makes it (equal
  // keys: the key itself).
  static Vec3f offsetAt(const Geometry& g, float time) {
    const auto keys = g.transforms();
    uint32_t s;
    float f;
    g.segmentAt(time, s, f);
    if (g.numSteps() == 1) return keys[0].p;
    const Vec3f a = keys[s].p, b = keys[s + 1].p;
    return a == b ? a : lerp(a, b, f);
  }

  Kind kind_ = Kind::General;
  bool singular_ = false;
  CofactorRows rows_;
  InstanceFrame frame_;
};

// The ray in instance g's space at the ray's time (its keys interpolated).
inline bool toInstanceSpace(const Geometry& g, const RayQuery& ray, RayQuery& local, InstanceFrame* frame) {
  return toLocalSpace(g.transformAt(ray.time), ray, local, frame);
}

}  // namespace mbrt::detail
