// The MSBVH's nodes (Grünschloß et al. 2011 §3.2): per node a header (lanes'
// children and counts) and n + 1 keys of per-lane boxes, in one array of
// blocks; the node test interpolates the two keys around the ray's time.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <new>
#include <vector>

#include "bvh/traverse.h"
#include "core/huge_pages.h"
#include "core/simd.h"

namespace mbrt::detail {

// Lanes without anything below: a box no ray can enter at any time, finite
// so that interpolating two of them stays well defined.
constexpr float kEmptyLo = 1e38f, kEmptyHi = -1e38f;
constexpr uint32_t kEmptyChild = 0xFFFFFFFFu;

// One key of one node: plane[axis][0 lower / 1 upper][lane].
template <int N>
struct alignas(32) KeyPlanes {
  float plane[3][2][N];

  void set(int lane, const Box3f& b) {
    const bool e = b.empty();
    for (int a = 0; a < 3; ++a) {
      plane[a][0][lane] = e ? kEmptyLo : b.lower[a];
      plane[a][1][lane] = e ? kEmptyHi : b.upper[a];
    }
  }
  Box3f get(int lane) const {
    Box3f b;
    for (int a = 0; a < 3; ++a) {
      b.lower[a] = plane[a][0][lane];
      b.upper[a] = plane[a][1][lane];
    }
    return b.lower.x == kEmptyLo ? Box3f() : b;
  }
};

template <int N>
struct alignas(32) MsNode {
  uint32_t child[N];  // inner: node index; leaf: first reference; kEmptyChild: empty lane
  uint8_t count[N];   // 0: inner (or empty); > 0: leaf size
  bool isEmpty(int lane) const { return child[lane] == kEmptyChild; }
  bool isLeaf(int lane) const { return count[lane] != 0; }
};

// Nodes in one array of blocks: node i's header, then its n+1 keys. A node
// visit reads one contiguous run of cache lines (header, keys k and k+1)
// instead of two arrays, as a bvh-interp node is one block.
template <int N>
class NodeBlocks {
 public:
  explicit NodeBlocks(uint32_t numKeys)
      : numKeys_(numKeys), stride_((sizeof(MsNode<N>) + numKeys * sizeof(KeyPlanes<N>)) / sizeof(Chunk)) {}

  size_t size() const { return chunks_.size() / stride_; }
  bool empty() const { return chunks_.empty(); }
  size_t bytes() const { return chunks_.size() * sizeof(Chunk); }
  const void* data() const { return chunks_.data(); }

  void reserve(size_t nodes) { reserveOnHugePages(chunks_, nodes * stride_); }
  uint32_t add() {
    const uint32_t index = uint32_t(size());
    chunks_.resize(chunks_.size() + stride_);
    ::new (at(index)) MsNode<N>();
    for (uint32_t k = 0; k < numKeys_; ++k) ::new (&key(index, k)) KeyPlanes<N>();
    return index;
  }
  MsNode<N>& node(uint32_t i) { return *std::launder(reinterpret_cast<MsNode<N>*>(at(i))); }
  const MsNode<N>& node(uint32_t i) const { return *std::launder(reinterpret_cast<const MsNode<N>*>(at(i))); }
  KeyPlanes<N>& key(uint32_t i, uint32_t k) { return keysOf(at(i))[k]; }
  const KeyPlanes<N>& key(uint32_t i, uint32_t k) const { return keysOf(at(i))[k]; }

 private:
  struct alignas(32) Chunk {
    unsigned char bytes[32];
  };
  static_assert(sizeof(MsNode<N>) % sizeof(Chunk) == 0 && sizeof(KeyPlanes<N>) % sizeof(Chunk) == 0);
  Chunk* at(uint32_t i) { return chunks_.data() + size_t(i) * stride_; }
  const Chunk* at(uint32_t i) const { return chunks_.data() + size_t(i) * stride_; }
  static KeyPlanes<N>* keysOf(Chunk* c) {
    return std::launder(reinterpret_cast<KeyPlanes<N>*>(c + sizeof(MsNode<N>) / sizeof(Chunk)));
  }
  static const KeyPlanes<N>* keysOf(const Chunk* c) {
    return std::launder(reinterpret_cast<const KeyPlanes<N>*>(c + sizeof(MsNode<N>) / sizeof(Chunk)));
  }

  uint32_t numKeys_;
  size_t stride_;  // chunks per node
  std::vector<Chunk> chunks_;
};

// The node ray (bvh/traverse.h) whose box time is the fraction between the
// two keys around the ray's time.
template <int W>
struct KeyRay : NodeRay<W> {
  uint32_t key;  // interval: keys key and key + 1

  KeyRay(const RayQuery& ray, uint32_t segments)
      : KeyRay(ray, segments, std::clamp(ray.time, 0.0f, 1.0f) * float(segments)) {}

 private:
  KeyRay(const RayQuery& ray, uint32_t segments, float x)
      : NodeRay<W>(ray, x - float(std::min(uint32_t(x), segments - 1))), key(std::min(uint32_t(x), segments - 1)) {}
};

// The node test at the interpolated box lerp(k0, k1, f) = k0 + f*(k1 - k0).
template <int W, int N>
inline uint32_t intersectKeys(const KeyPlanes<N>& k0, const KeyPlanes<N>& k1, const KeyRay<W>& r, float tfar,
                              float* dist) {
  using P = Pack<W>;
  const P far = P::set1(tfar), inf = P::set1(kInf);
  uint32_t mask = 0;
  for (int base = 0; base < N; base += W) {
    P tn = r.tnear, tf = inf;
    for (int a = 0; a < 3; ++a) {
      const int nearK = r.nearPlane[a], farK = 1 - nearK;
      const P lo0 = P::load(&k0.plane[a][nearK][base]), lo1 = P::load(&k1.plane[a][nearK][base]);
      const P hi0 = P::load(&k0.plane[a][farK][base]), hi1 = P::load(&k1.plane[a][farK][base]);
      const P lo = fmadd(r.time, lo1 - lo0, lo0);  // r.time: the fraction between the keys
      const P hi = fmadd(r.time, hi1 - hi0, hi0);
      tn = vmax((lo - r.org[a]) * r.rdir[a], tn);
      tf = vmin((hi - r.org[a]) * r.rdir[a], tf);
    }
    tf = vmin(robustFar(tf), far);
    mask |= lessEqualMask(tn, tf) << base;
    tn.store(dist + base);
  }
  return mask;
}

// The same arithmetic, one lane, for inspection.
inline float lerpKey(float a, float b, float f) { return madd(f, b - a, a); }

}  // namespace mbrt::detail
