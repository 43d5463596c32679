// The measured traversal cost of a structure (docs/auto.md, "Cost model"):
// a fixed sample of rays through its scene's bounds at random times, traced
// with the counting traversal; the cost per ray is the work counted, in units
// of one node visit. The SAH prices a tree alone; these counts also see what
// the SAH does not: instance entries (a ray transform and a second traversal
// set-up each), references split into several leaves, overlapping objects.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "scene/scene_context.h"

namespace mbrt::detail {

// The cost per ray, in units of one node visit:
//
//   own x (nodes + primitive x tests one triangle at a time
//                + blockPrimitive x tests in leaf blocks + entry x instance entries
//                - (1 - frozenWork) x the same counts made inside `frozen` objects)
//     x (1 + cachePerDoubling x log2(cached / cacheBytes))   (cached >= cacheBytes)
//
// with own = frozenWork for `frozen`, 1 for the other kinds, and cached the
// structure's bytes with its leaf blocks' bytes (AccelStats::leafBlockBytes)
// counted at leafBlockByteShare. An entry's own test in its parent's leaf
// is part of the entry's weight, not a primitive test.
//
// Weights fitted to the thread CPU time per ray of every kind on the
// bench's secondary rays of the suite and the real scenes
// (docs/performance.md, "The cost model fitted to time" and "The cost
// model with leaf blocks"): a node visit and a triangle test cost about
// the same (~35 ns on this machine), whatever the kind; what differs
// between kinds at equal counts is the memory they read: each doubling of
// a structure's bytes above ~1 MB (the second-level cache of a core) costs
// a quarter more per event (cache misses). A triangle tested in a leaf
// block (leaves/triangle_blocks.h, leaves/motion_blocks.h: eight triangles against the
// ray at once, their vertices stored in the block) costs a quarter of one
// tested alone. A block is read whole, front to back (288 bytes per key
// for eight triangles), which the hardware prefetches, where a node visit or
// a triangle fetched through its index misses at random: the blocks' bytes
// weigh a quarter of the rest in the cache factor (with them at full
// weight the model ranks `bvh-interp` on `translate` at 0.96 of `msbvh`'s
// cost where it takes 0.79 of its time, and the fit's error is 12 % rms
// instead of 8 %). `frozen`'s nodes hold one box per child and its blocks
// one position per vertex (no interpolation at the ray's time): its counts
// cost 0.8 of the same counts in a tree with linear bounds (`bvh-interp`
// over the same static objects), inside an instance as well as alone.
// An entry into an instanced structure (the instance's test, the ray's
// transform and the child traversal's set-up, some 550 instructions on
// data that stays in the caches) weighs 0.7 of a node visit, which misses
// them (docs/performance.md, "Instance entries priced by time").
// A round segment's test (a rounded cone: square roots and a dozen dot
// products) costs 3.7 node visits where a triangle's costs one; an object
// weighs its tests made one at a time by its mix of the two (weightsFor).
struct RayCostWeights {
  double node = 1.0;
  double primitive = 1.0;  // a test made one at a time: 1 for a triangle, segment for a segment
  double segment = 3.7;
  double blockPrimitive = 0.25;
  double frozenWork = 0.8;
  double entry = 0.7;
  double cacheBytes = double(size_t(1) << 20);
  double cachePerDoubling = 0.25;
  double leafBlockByteShare = 0.25;
  // The factor on the work of a structure of `bytes`, `leafBlockBytes` of
  // them in leaf blocks.
  double cacheFactor(size_t bytes, size_t leafBlockBytes = 0) const {
    const double cached = double(bytes) - (1.0 - leafBlockByteShare) * double(std::min(leafBlockBytes, bytes));
    return 1.0 + cachePerDoubling * std::log2(std::max(1.0, cached / cacheBytes));
  }
};

// The weights for the structures of `scene`: its tests made one at a time
// priced by its share of segments among its triangles and segments.
RayCostWeights weightsFor(const Scene& scene);

// The sample is what a renderer's secondary rays look like (the bench's
// secondary set): kSampleRays / 2 rays from a sphere around the scene's
// bounds (sceneBounds) towards points inside them, at times in [0, 1]
// (sampleRays), and as many diffuse bounces from their hits, cycling
// through the hits (measureRayCost adds them: every correct structure finds
// the same hits), all from a fixed seed (the choice a build makes does not
// change from run to run).
constexpr uint32_t kSampleRays = 2048;
std::vector<RayQuery> sampleRays(const SceneContext& context);

// What the objects traced through instances did while counting was on:
// their entries, and the counts made inside `frozen` objects (which
// RayCost::work weighs at frozenWork).
struct EntryTally {
  std::atomic<uint64_t> entries{0};
  std::atomic<uint64_t> frozenNodes{0}, frozenPrimitives{0}, frozenBlockPrimitives{0};

  struct Counts {
    double entries = 0, frozenNodes = 0, frozenPrimitives = 0, frozenBlockPrimitives = 0;
  };
  Counts read() const {
    return {double(entries.load()), double(frozenNodes.load()), double(frozenPrimitives.load()),
            double(frozenBlockPrimitives.load())};
  }
};

// Counts the calls into a structure (owned elsewhere) traced through an
// instance, while counting is on (only the choice's own sample; off
// afterwards, so that concurrent tracing never writes). Its statistics are
// the owner's, made when the structure was built (a refit changes none of
// the figures a parent reads of a child: bytes, nodes, references).
class EntryCounting final : public Structure {
 public:
  EntryCounting(const Structure& s, const AccelStats& stats, EntryTally& tally, const std::atomic<bool>& on,
                bool frozen)
      : s_(&s), stats_(&stats), tally_(tally), on_(on), frozen_(frozen) {}
  bool intersect(RayQuery& ray, Hit& hit) const override { return s_->intersect(ray, hit); }
  bool occluded(RayQuery& ray) const override { return s_->occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    if (!on_.load(std::memory_order_relaxed)) return s_->intersectCounted(ray, hit, c);
    tally_.entries.fetch_add(1, std::memory_order_relaxed);
    const TraversalCounters before = c;
    const bool found = s_->intersectCounted(ray, hit, c);
    if (frozen_) {
      tally_.frozenNodes.fetch_add(c.nodesVisited - before.nodesVisited, std::memory_order_relaxed);
      tally_.frozenPrimitives.fetch_add(c.primitiveTests - before.primitiveTests, std::memory_order_relaxed);
      tally_.frozenBlockPrimitives.fetch_add(c.blockPrimitiveTests - before.blockPrimitiveTests,
                                             std::memory_order_relaxed);
    }
    return found;
  }
  void fillStats(AccelStats& s) const override { s = *stats_; }
  uint32_t clusterOf(PrimRef p) const override { return s_->clusterOf(p); }

 private:
  const Structure* s_;
  const AccelStats* stats_;
  EntryTally& tally_;
  const std::atomic<bool>& on_;
  bool frozen_;
};

struct RayCost {
  // Per ray; blockPrimitives is the part of primitives tested in leaf
  // blocks; the frozen* counts are the part made inside `frozen` objects
  // entered through instances.
  double nodes = 0, primitives = 0, blockPrimitives = 0, entries = 0;
  double frozenNodes = 0, frozenPrimitives = 0, frozenBlockPrimitives = 0;
  // The counted work alone, in node visits.
  double work(const RayCostWeights& w, AccelKind kind) const {
    const auto events = [&](double n, double prims, double blocks) {
      return w.node * n + w.primitive * (prims - blocks) + w.blockPrimitive * blocks;
    };
    // Each entry was one instance test of a parent's leaf, in primitives.
    const double ownPrims = primitives - std::min(entries, primitives - blockPrimitives);
    const double counted = events(nodes, ownPrims, blockPrimitives) + w.entry * entries -
                           (1.0 - w.frozenWork) * events(frozenNodes, frozenPrimitives, frozenBlockPrimitives);
    return (kind == AccelKind::Frozen ? w.frozenWork : 1.0) * counted;
  }
  // The work weighed by the cache factor of a structure of `bytes`,
  // `leafBlockBytes` of them in leaf blocks.
  double total(const RayCostWeights& w, AccelKind kind, size_t bytes, size_t leafBlockBytes) const {
    return work(w, kind) * w.cacheFactor(bytes, leafBlockBytes);
  }
};

// Diffuse bounces from the hits of `rays` (hits[i] of rays[i]; misses
// skipped): as many as `rays`, cycling through the hit points, each
// cosine-distributed about the normal turned towards the incoming ray, from
// 1e-4 of the incoming ray's length off the surface, at the time of the ray
// that hit; none when nothing was hit.
std::vector<RayQuery> bounceRays(const std::vector<RayQuery>& rays, const std::vector<Hit>& hits);

// Traces `rays` through s with counting, then their bounceRays; the cost
// is per traced ray. `tally` (may be null) is read before and after, for
// structures whose children are EntryCounting.
RayCost measureRayCost(const Structure& s, const std::vector<RayQuery>& rays, const EntryTally* tally = nullptr);

}  // namespace mbrt::detail
