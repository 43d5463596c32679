#include "msbvh/msbvh.h"

#include <algorithm>
#include <new>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bvh/inspect.h"
#include "bvh/sah_cost.h"
#include "bvh/traverse.h"
#include "core/huge_pages.h"
#include "core/traced_structure.h"
#include "leaves/reference_leaves.h"
#include "scene/branching.h"
#include "scene/primitive_bounds.h"
#include "scene/primitive_intersect.h"
#include "msbvh/key_bounds.h"
#include "msbvh/msbvh_nodes.h"
#include "msbvh/sbvh_builder.h"

namespace mbrt::detail {
namespace {

// Leaves: the format `Leaves` (leaves/) over the tree's reference table.
template <int N, LeafFormat Leaves>
class Msbvh final : public TracedStructure<Msbvh<N, Leaves>>, public Inspect {
 public:
  explicit Msbvh(const SceneContext& ctx)
      : ctx_(ctx),
        stepSegments_(chooseKeySegments(ctx)),
        n_(fitKeySegments(ctx, stepSegments_)),
        bounder_(ctx, n_),
        nodes_(n_ + 1),
        stats_{n_} {
    const std::vector<PrimRef> prims = ctx.primitives();
    numPrims_ = prims.size();
    BuildBudget& budget = ctx.budget();
    std::vector<SplitRef> refs;
    {
      const BuildOptions& o = ctx.options();
      SbvhSettings s;
      s.maxLeafSize = std::min(o.maxLeafSize, 255);
      s.objectBins = o.sahBins;
      s.spatialBins = o.sahBins;
      s.traversalCost = o.traversalCost;
      ScopedCharge scratch(budget, size_t(double(prims.size()) * (1.0 + s.maxGrowth) * 2.0 * sizeof(SplitRef)),
                           "the MSBVH build references");
      // With the root's growth room (buildSbvh), so that it is not copied.
      reserveOnHugePages(refs, size_t(double(prims.size()) * (1.0 + double(s.maxGrowth))) + 1);
      refs.resize(prims.size());
      tbb::parallel_for(size_t(0), prims.size(), [&](size_t i) {
        refs[i] = {bounder_.buildBox(prims[i]), Box3f(Vec3f(-kInf), Vec3f(kInf)), prims[i]};
      });
      std::erase_if(refs, [](const SplitRef& r) { return r.box.empty() || !isFinite(r.box.lower) || !isFinite(r.box.upper); });
      const BuildTimeClipper clipper(ctx, bounder_);
      const ScopedCharge vertices(budget, clipper.bytes(), "the MSBVH build's vertices at the build time");
      const SbvhTree tree = buildSbvh(std::move(refs), s, clipper);
      if (!tree.empty()) {
        size_t nodes = 0, emitted = 0;
        countEmitted(tree, tree.root(), nodes, emitted);
        nodes_.reserve(nodes);
        reserveOnHugePages(prims_, emitted);
        reserveOnHugePages(regions_, emitted);
        emit(tree, tree.root(), 1);
        computeLeafKeys();
        propagate();
      }
    }
    charge_ = std::make_unique<ScopedCharge>(budget, byteCount(), "the MSBVH nodes");
    leaves_ = Leaves(ctx, leafTable());
  }

  std::any buildStats() const override { return &stats_; }


  void fillStats(AccelStats& s) const override {
    SahSums sums;
    sums.bytes = byteCount() + leaves_.bytes();
    sums.references = prims_.size();
    if (!nodes_.empty()) {
      sums.innerNodes = nodes_.size();
      sums.maxDepth = depth_ + 1;
      std::vector<Box3f> root(n_ + 1);
      for (int l = 0; l < N; ++l)
        if (!nodes_.node(0).isEmpty(l))
          for (uint32_t k = 0; k <= n_; ++k) root[k].extend(keys(0, k).get(l));
      sums.inner += meanArea([&](uint32_t k) { return root[k]; });
      for (uint32_t i = 0; i < nodes_.size(); ++i)
        for (int l = 0; l < N; ++l) {
          const MsNode<N>& node = nodes_.node(i);
          if (node.isEmpty(l)) continue;
          const double area = meanArea([&](uint32_t k) { return keys(i, k).get(l); });
          if (node.isLeaf(l)) {
            double seg = 0.0;
            for (uint32_t r = 0; r < node.count[l]; ++r)
              seg += double(activeSegments(ctx_, prims_[node.child[l] + r], {0.0f, 1.0f}));
            sums.leaves += area * seg;
            ++sums.leafNodes;
          } else {
            sums.inner += area;
          }
        }
    }
    sums.fill(s, sceneSahArea(ctx_));
  }

  // §5: same topology; every reference is re-clipped (to its region, see
  // docs/msbvh.md) with the new vertices and the keys recomputed bottom-up.
  bool refit() override {
    for (uint32_t g = 0; g < ctx_.scene().numGeometries(); ++g)
      if (ctx_.geometry(g).type() == GeometryType::Instance) return false;
    if (chooseKeySegments(ctx_) != stepSegments_) return false;  // other steps: other breaks
    if (nodes_.empty()) return numPrims_ == 0;
    computeLeafKeys();
    propagate();
    const size_t before = leaves_.bytes();
    leaves_ = Leaves(ctx_, leafTable());  // a format may keep the leaves' vertices
    ctx_.budget().release(before);
    return true;
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (nodes_.empty()) return;
    walk(0, fn);
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    auto add = [&](const void* p, size_t n) {
      const size_t a = out.size();
      out.resize(a + n);
      if (n) std::memcpy(out.data() + a, p, n);
    };
    add(nodes_.data(), nodes_.bytes());
    add(prims_.data(), prims_.size() * sizeof(PrimRef));
    add(regions_.data(), regions_.size() * sizeof(Box3f));
    return out;
  }

 private:
  size_t byteCount() const {
    return nodes_.bytes() + prims_.size() * sizeof(PrimRef) + regions_.size() * sizeof(Box3f);
  }
  KeyPlanes<N>& keys(uint32_t node, uint32_t k) { return nodes_.key(node, k); }
  const KeyPlanes<N>& keys(uint32_t node, uint32_t k) const { return nodes_.key(node, k); }

  template <class BoxOfKey>
  double meanArea(const BoxOfKey& boxOfKey) const {
    double sum = 0.0;
    for (int j = 0; j < 8; ++j) {
      const float x = float(j) / 7.0f * float(n_);
      const uint32_t k = std::min(uint32_t(x), n_ - 1);
      const Box3f a = boxOfKey(k), b = boxOfKey(k + 1);
      if (!a.empty() && !b.empty()) sum += double(lerp(a, b, x - float(k)).area());
    }
    return sum / 8.0;
  }

  // While there are fewer than N lanes, opens the lane with the largest area
  // among those `pick` accepts (nodes with children).
  template <class Pick>
  static void openLargest(const SbvhTree& tree, std::vector<const SbvhNode*>& lanes, const Pick& pick) {
    while (int(lanes.size()) < N) {
      int best = -1;
      float area = -1.0f;
      for (int i = 0; i < int(lanes.size()); ++i)
        if (pick(*lanes[size_t(i)]) && lanes[size_t(i)]->box.halfArea() > area) {
          best = i;
          area = lanes[size_t(i)]->box.halfArea();
        }
      if (best < 0) return;
      const SbvhNode* open = lanes[size_t(best)];
      lanes[size_t(best)] = &tree.child(*open, 0);
      lanes.push_back(&tree.child(*open, 1));
      std::rotate(lanes.begin() + best + 1, lanes.end() - 1, lanes.end());
    }
  }

  static void gatherRefs(const SbvhTree& tree, const SbvhNode& bin, std::vector<const SplitRef*>& out) {
    for (const SplitRef& r : bin.refs) out.push_back(&r);
    if (!bin.isLeaf())
      for (int i = 0; i < 2; ++i) gatherRefs(tree, tree.child(bin, i), out);
  }

  // The lanes of the wide node made from `bin`: the two children of a
  // binary node, its largest inner child opened until there are N (STBVH
  // §3.3's collapse), then lanes still free split its largest leaves (node
  // filling, sbvh_builder.h).
  static std::vector<const SbvhNode*> lanesOf(const SbvhTree& tree, const SbvhNode& bin) {
    std::vector<const SbvhNode*> lanes;
    if (bin.isLeaf() || bin.fill) {
      lanes.push_back(&bin);
    } else {
      lanes = {&tree.child(bin, 0), &tree.child(bin, 1)};
      openLargest(tree, lanes, [](const SbvhNode& c) { return !c.isLeaf() && !c.fill; });
    }
    openLargest(tree, lanes, [](const SbvhNode& c) { return !c.isLeaf() && c.fill; });
    return lanes;
  }

  // How many wide nodes and references emit(bin) writes, so that their
  // arrays are allocated once: grown node by node, the nodes' array (with
  // its n_ + 1 keys per node, 474 MB on `crowd`) was copied at every
  // doubling.
  static void countEmitted(const SbvhTree& tree, const SbvhNode& bin, size_t& nodes, size_t& refs) {
    ++nodes;
    for (const SbvhNode* c : lanesOf(tree, bin)) {
      if (c->isLeaf() || c->fill) refs += countRefs(tree, *c);
      else countEmitted(tree, *c, nodes, refs);
    }
  }
  static size_t countRefs(const SbvhTree& tree, const SbvhNode& bin) {
    size_t n = bin.refs.size();
    if (!bin.isLeaf())
      for (int i = 0; i < 2; ++i) n += countRefs(tree, tree.child(bin, i));
    return n;
  }

  // Binary SBVH -> N-wide nodes in depth-first order, each with the lanes
  // of lanesOf.
  uint32_t emit(const SbvhTree& tree, const SbvhNode& bin, uint32_t depth) {
    depth_ = std::max(depth_, depth);
    const std::vector<const SbvhNode*> lanes = lanesOf(tree, bin);
    const uint32_t index = nodes_.add();
    for (int l = 0; l < N; ++l) {
      nodes_.node(index).child[l] = kEmptyChild;
      nodes_.node(index).count[l] = 0;
    }
    for (int l = 0; l < int(lanes.size()); ++l) {
      const SbvhNode& c = *lanes[size_t(l)];
      if (c.isLeaf() || c.fill) {
        std::vector<const SplitRef*> order;
        gatherRefs(tree, c, order);
        nodes_.node(index).child[l] = uint32_t(prims_.size());
        nodes_.node(index).count[l] = uint8_t(order.size());
        // Sorted by geometry: the leaf test takes one run of a geometry at a time.
        std::stable_sort(order.begin(), order.end(),
                         [](const SplitRef* a, const SplitRef* b) { return a->prim.geomID < b->prim.geomID; });
        for (const SplitRef* r : order) {
          prims_.push_back(r->prim);
          regions_.push_back(r->region);
        }
      } else {
        const uint32_t child = emit(tree, c, depth + 1);
        nodes_.node(index).child[l] = child;
      }
    }
    stackSize_ = std::max(stackSize_, depth_ * uint32_t(N) + 1);
    return index;
  }

  void computeLeafKeys() {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes_.size()), [&](const tbb::blocked_range<size_t>& range) {
      std::vector<Box3f> lane(n_ + 1), piece(n_ + 1);  // per block of nodes, not per node
      for (size_t i = range.begin(); i != range.end(); ++i) computeLeafKeys(uint32_t(i), lane, piece);
    });
  }

  // The keys of node i's leaf lanes (`lane`, `piece`: n_ + 1 boxes of scratch).
  void computeLeafKeys(uint32_t i, std::vector<Box3f>& lane, std::vector<Box3f>& piece) {
    const MsNode<N>& node = nodes_.node(i);
    for (int l = 0; l < N; ++l) {
      if (node.isEmpty(l) || !node.isLeaf(l)) continue;
      std::fill(lane.begin(), lane.end(), Box3f());
      for (uint32_t r = 0; r < node.count[l]; ++r) {
        const uint32_t ref = node.child[l] + r;
        if (!bounder_.pieceKeys(prims_[ref], regions_[ref], piece.data())) continue;
        for (uint32_t k = 0; k <= n_; ++k) lane[k].extend(piece[k]);
      }
      for (uint32_t k = 0; k <= n_; ++k) keys(i, k).set(l, lane[k]);
    }
  }

  // Inner lanes: the union of the child's lanes, per key (children come
  // after their parents in depth-first order).
  void propagate() {
    for (size_t i = nodes_.size(); i-- > 0;) {
      const MsNode<N>& node = nodes_.node(uint32_t(i));
      for (int l = 0; l < N; ++l) {
        if (node.isEmpty(l)) {
          for (uint32_t k = 0; k <= n_; ++k) keys(uint32_t(i), k).set(l, Box3f());
          continue;
        }
        if (node.isLeaf(l)) continue;
        for (uint32_t k = 0; k <= n_; ++k) {
          Box3f b;
          const KeyPlanes<N>& c = keys(node.child[l], k);
          for (int cl = 0; cl < N; ++cl) b.extend(c.get(cl));
          keys(uint32_t(i), k).set(l, b);
        }
      }
    }
  }

  std::pair<uint32_t, uint32_t> walk(uint32_t index, const std::function<void(const LaneView&)>& fn) const {
    uint32_t first = ~0u, end = 0;
    const MsNode<N>& node = nodes_.node(index);
    for (int l = 0; l < N; ++l) {
      if (node.isEmpty(l)) continue;
      std::pair<uint32_t, uint32_t> r{node.child[l], node.child[l] + node.count[l]};
      if (!node.isLeaf(l)) r = walk(node.child[l], fn);
      auto box = [this, index, l](float t) {
        const float x = std::clamp(t, 0.0f, 1.0f) * float(n_);
        const uint32_t k = std::min(uint32_t(x), n_ - 1);
        const float f = x - float(k);
        const KeyPlanes<N>&a = keys(index, k), &b = keys(index, k + 1);
        Box3f out;
        for (int ax = 0; ax < 3; ++ax) {
          out.lower[ax] = lerpKey(a.plane[ax][0][l], b.plane[ax][0][l], f);
          out.upper[ax] = lerpKey(a.plane[ax][1][l], b.plane[ax][1][l], f);
        }
        return out;
      };
      fn(LaneView{{0.0f, 1.0f}, box, std::span<const PrimRef>(prims_.data() + r.first, r.second - r.first), {}});
      first = std::min(first, r.first);
      end = std::max(end, r.second);
    }
    return {first, end};
  }

  // Its leaves as the formats lay them out: every lane leaf, in node order.
  LeafTable leafTable() const {
    LeafTable t;
    t.prims = prims_;
    for (uint32_t i = 0; i < nodes_.size(); ++i)
      for (int l = 0; l < N; ++l) {
        const MsNode<N>& node = nodes_.node(i);
        if (!node.isEmpty(l) && node.isLeaf(l)) t.leaves.push_back({node.child[l], node.count[l]});
      }
    return t;
  }

  friend class TracedStructure<Msbvh<N, Leaves>>;
  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    if (nodes_.empty()) return false;
    const KeyRay<packWidth<N>()> r(ray, n_);
    const typename Leaves::RayState state = leaves_.rayState(ray);
    const auto nodeAt = [&](uint32_t i) -> const MsNode<N>& { return nodes_.node(i); };
    return wideTraverse<AnyHit, Count, N>(
        stackSize_, ray, counters, nodeAt,
        [&](const MsNode<N>&, uint32_t i, float* dist) {
          const KeyPlanes<N>* k = &nodes_.key(i, r.key);
          return intersectKeys<packWidth<N>()>(k[0], k[1], r, ray.tfar, dist);
        },
        [&](const TraversalItem& leaf) {
          const LeafRefs refs{prims_.data() + leaf.child, leaf.count, leaf.child};
          return leaves_.template test<AnyHit, Count>(ctx_, refs, ray, state, hit, counters);
        },
        // The header only: the two keys too (7 lines a child) measured slower.
        NodeLines<decltype(nodeAt)>{nodeAt, prefetchPays(nodes_.bytes())});
  }

  const SceneContext& ctx_;
  uint32_t stepSegments_;  // keys on every step (chooseKeySegments)
  uint32_t n_;             // the keys kept (fitKeySegments)
  KeyBounder bounder_;
  NodeBlocks<N> nodes_;  // per node: its header and (n_ + 1) keys
  std::vector<PrimRef> prims_;
  std::vector<Box3f> regions_;  // per reference: its spatial-split region (for refits)
  uint32_t depth_ = 0;
  uint32_t stackSize_ = 1;
  size_t numPrims_ = 0;
  std::unique_ptr<ScopedCharge> charge_;
  Leaves leaves_;
  MsbvhStats stats_;
};

}  // namespace

std::unique_ptr<Structure> makeMsbvh(const SceneContext& context) {
  return makeForBranching<Msbvh, ReferenceLeaves>(context);
}

}  // namespace mbrt::detail
