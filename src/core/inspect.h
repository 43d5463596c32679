// What tests and docs may look at in a built structure: one interface that
// every kind with a tree implements (the BVH family, msbvh, mbkd, fuzzykd),
// each answering what it has. Reached through inspect(structure); a query
// a kind cannot answer throws Error, never returns nothing.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/structure.h"
#include "mbrt/error.h"
#include "mbrt/math.h"

namespace mbrt::detail {

// A lane of a wide BVH node, or a leaf cell of a kd-tree.
struct LaneView {
  TimeRange range;                             // global times the lane serves
  std::function<Box3f(float globalTime)> box;  // as the node stores it (decoded); a kd cell is constant
  std::span<const PrimRef> below;              // references under the lane
  // Per reference of `below`, the times it is stored for (kd leaves keep
  // intervals per reference); empty: `range` for every one.
  std::span<const TimeRange> times;
};

class Inspect {
 public:
  virtual ~Inspect() = default;
  // Every lane (BVH family, msbvh) or leaf cell (kd-trees).
  virtual void forEachLane(const std::function<void(const LaneView&)>&) const { refuse("lanes"); }
  // The tree's bytes (nodes, references, time ranges): equal bytes, equal trees.
  virtual std::vector<uint8_t> bytes() const { refuse("bytes"); }
  // The kind's own build figures, as a pointer to its statistics type
  // (KdBuildStats, FuzzyKdStats, MsbvhStats); read them with statsOf.
  virtual std::any buildStats() const { return {}; }

 private:
  [[noreturn]] static void refuse(const char* what) {
    throw Error(std::string("this structure has no ") + what + " to inspect");
  }
};

// The inspection interface of a structure; Error for kinds without one
// (brute, embree).
inline const Inspect& inspect(const Structure& s) {
  const auto* i = dynamic_cast<const Inspect*>(&s);
  if (!i) throw Error("this kind of structure has nothing to inspect");
  return *i;
}

// The kind's build statistics of type `Stats`; Error when it keeps others.
template <class Stats>
const Stats& statsOf(const Inspect& i) {
  const std::any a = i.buildStats();
  const Stats* const* s = std::any_cast<const Stats*>(&a);
  if (!s) throw Error("this structure keeps no statistics of the type asked for");
  return **s;
}
template <class Stats>
const Stats& statsOf(const Structure& s) {
  return statsOf<Stats>(inspect(s));
}

}  // namespace mbrt::detail
