// The SAH's choice for one node of the BVH family (STBVH §3.2-3.3,
// Algorithm 1): the best binned object split, a temporal split when the
// object split is poor, or a leaf, by the MBSAH (segment counts). Knows
// references and costs, not trees: builder.h makes the nodes.
#pragma once

#include <span>
#include <utility>
#include <vector>

#include "bvh/heuristics/binned_sah.h"
#include "bvh/build/builder.h"

namespace mbrt::detail {

// References made by a temporal split, charged to the budget while they
// live. Moving keeps the buffer, so spans into it stay valid.
class OwnedRefs {
 public:
  OwnedRefs() = default;
  OwnedRefs(BuildBudget& budget, std::vector<BuildRef>&& refs) : refs_(std::move(refs)) {
    budget.charge(bytes(), "the temporal split references");
    budget_ = &budget;
  }
  OwnedRefs(OwnedRefs&& o) noexcept : budget_(std::exchange(o.budget_, nullptr)), refs_(std::move(o.refs_)) {}
  OwnedRefs& operator=(OwnedRefs&& o) noexcept {
    release();
    budget_ = std::exchange(o.budget_, nullptr);
    refs_ = std::move(o.refs_);
    return *this;
  }
  ~OwnedRefs() { release(); }
  std::span<BuildRef> span() { return refs_; }

 private:
  size_t bytes() const { return refs_.size() * sizeof(BuildRef); }
  void release() {
    if (budget_) budget_->release(bytes());
    budget_ = nullptr;
  }
  BuildBudget* budget_ = nullptr;
  std::vector<BuildRef> refs_;
};

// The references of both halves of a temporal split at `time`, in the order
// of the node's references (when none is dropped from a half).
struct TemporalHalves {
  float time = 0.0f;
  std::span<BuildRef> refs[2];
  bool alignedWith(std::span<const BuildRef> node) const {
    return !node.empty() && refs[0].size() == node.size() && refs[1].size() == node.size();
  }
};

struct Decision {
  enum Kind { Leaf, Object, Temporal } kind = Leaf;
  size_t mid = 0;        // Object: size of the left side (references reordered)
  ObjectSplit split;     // Leaf: the best object split, to fill lanes with
  RefSetInfo sides[2];   // Object, Temporal: the children's summaries
  TemporalHalves halves;  // Temporal: the split; Object: the one tried, for the children
  OwnedRefs made[2];      // the halves' storage, when this node made them
};

// Chooses splits with one build's settings; charges temporal splits'
// references to the build's budget.
class SplitChooser {
 public:
  SplitChooser(const BuildSettings& settings, BuildBudget& budget) : s_(settings), budget_(budget) {}

  // The decision for a node's references over `range` (reordered when the
  // decision is an object split). `tried`: a temporal split of the same
  // references an ancestor made and rejected, reused when the same time is
  // tried again (the Fig. 4 bounds are the same).
  Decision choose(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth,
                  const TemporalHalves& tried);

  // The best binned object split (none at the depth limit or for one reference).
  ObjectSplit objectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int depth) const;

  // The object split, or the median where binning cannot separate the
  // references; `sides` gets both children's summaries.
  static size_t partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                          RefSetInfo sides[2]);

 private:
  static size_t partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                          RefSetInfo sides[2], std::span<BuildRef> (&along)[2]);
  void temporalHalves(std::span<BuildRef> refs, TimeRange range, float time, const TemporalHalves& tried,
                      Decision& d);
  static void dropHalves(Decision& d);

  const BuildSettings& s_;
  BuildBudget& budget_;
};

}  // namespace mbrt::detail
