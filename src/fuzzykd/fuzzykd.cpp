#include "fuzzykd/fuzzykd.h"

#include <chrono>

#include <tbb/parallel_for.h>

#include "core/sah_sums.h"
#include "scene/scene_area.h"
#include "scene/primitive_bounds.h"
#include "kd/kd_builder.h"
#include "kd/kd_traverse.h"

namespace mbrt::detail {
namespace {

using Clock = std::chrono::steady_clock;

constexpr uint32_t kMinMeshTriangles = 32;
constexpr uint32_t kMinClusterTriangles = 4;
constexpr uint32_t kMaxSubdivisions = 16;
constexpr double kNumericPad = 2e-5;

// Depth limit of a cluster's tree: the kd core's 8 + 1.3 log2(N) less three
// levels. A fuzzy box holds its triangle in every frame, so it is larger
// than the triangle in any one: the deepest cells of a static tree, which
// separate neighbouring triangles, cannot separate their fuzzy boxes and
// only duplicate references. Cutting them is what brings the fuzzy trees
// to <= 1.5x a per-frame tree's memory at 1.2-1.6x its work per ray
// (docs/fuzzykd.md, the sweep).
constexpr int kFuzzyDepthCut = 3;
int fuzzyTreeDepth(size_t prims) {
  return std::max(1, int(8.0 + 1.3 * std::log2(double(std::max<size_t>(prims, 1)))) - kFuzzyDepthCut);
}

// A cluster's kd-tree in compact form: the kd core's nodes, and leaf
// references without the time interval (a fuzzy box holds over the whole
// shutter, so every interval would be [0, 1]): 4 bytes per reference.
struct FuzzyTree {
  std::vector<KdNode> nodes;
  std::vector<uint32_t> refs;  // indices into the cluster's prims
  Box3f root;
  uint32_t depth = 0;

  explicit FuzzyTree(const KdTree& t = {}) : nodes(t.nodes), root(t.root), depth(t.depth) {
    refs.reserve(t.refs.size());
    for (const KdLeafRef& r : t.refs) refs.push_back(r.prim);
  }
  size_t bytes() const { return nodes.size() * sizeof(KdNode) + refs.size() * sizeof(uint32_t); }
};

struct Cluster {
  uint32_t geomID = 0;
  std::vector<Affine3f> xfm;  // per geometry step: local -> world
  std::vector<Box3f> keyBoxes;  // world, per step
  std::vector<PrimRef> prims;
  FuzzyTree tree;
};

struct TopNode {
  LBounds bounds;
  uint32_t left = 0, right = 0;  // inner: children
  uint32_t item = ~0u;           // leaf: cluster index (clusters.size(): the world tree)
};

// Calls fn(node, cell, depth) for every node of a kd-tree, cells split at
// the nodes' planes.
template <class Fn>
void walkCells(const std::vector<KdNode>& nodes, uint32_t node, const Box3f& cell, const Fn& fn, int depth = 1) {
  fn(node, cell, depth);
  const KdNode& n = nodes[node];
  if (n.isLeaf()) return;
  Box3f l = cell, r = cell;
  l.upper[n.axis()] = n.split();
  r.lower[n.axis()] = n.split();
  walkCells(nodes, node + 1, l, fn, depth + 1);
  walkCells(nodes, n.rightChild(), r, fn, depth + 1);
}

// Surface area of the parallelepiped a local box becomes under the map m.
double mappedArea(const Affine3f& m, const Box3f& box) {
  const Vec3f e = box.upper - box.lower;
  const Vec3f a = m.vx * e.x, b = m.vy * e.y, c = m.vz * e.z;
  return 2.0 * (double(length(cross(a, b))) + double(length(cross(b, c))) + double(length(cross(c, a))));
}

bool finiteBounds(const LBounds& b) {
  return isFinite(b.b0.lower) && isFinite(b.b0.upper) && isFinite(b.b1.lower) && isFinite(b.b1.upper) &&
         !b.b0.empty() && !b.b1.empty();
}

class FuzzyKd final : public Structure, public FuzzyKdInspect {
 public:
  explicit FuzzyKd(const SceneContext& ctx) : ctx_(ctx) {
    const auto t0 = Clock::now();
    std::vector<PrimRef> world;
    const Scene& scene = ctx.scene();
    std::vector<std::vector<PrimRef>> perGeometry(scene.numGeometries());
    Box3f sceneBox;
    for (uint32_t g = 0; g < scene.numGeometries(); ++g) {
      const Geometry& geo = ctx.geometry(g);
      for (uint32_t p = 0; p < geo.numPrimitives(); ++p) {
        const LBounds b = linearBounds(ctx, {g, p}, {0.0f, 1.0f});
        if (!finiteBounds(b)) continue;
        perGeometry[g].push_back({g, p});
        sceneBox.extend(b.hull());
      }
    }
    worldMag_ = sceneBox.empty() ? 1.0 : std::max(normInf(toD(sceneBox.lower)), normInf(toD(sceneBox.upper)));
    for (uint32_t g = 0; g < scene.numGeometries(); ++g)
      if (!decomposeMesh(g, ctx.geometry(g), perGeometry[g]))
        world.insert(world.end(), perGeometry[g].begin(), perGeometry[g].end());
    stats_.decomposeSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto t1 = Clock::now();
    clusterOfPrim_.resize(scene.numGeometries());
    for (uint32_t g = 0; g < scene.numGeometries(); ++g) clusterOfPrim_[g].assign(ctx.geometry(g).numPrimitives(), ~0u);
    for (const Cluster& c : clusters_)
      for (const PrimRef& p : c.prims) clusterOfPrim_[p.geomID][p.primID] = uint32_t(&c - clusters_.data());
    worldPrims_ = std::move(world);
    buildTop();
    stats_.treeSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
    stats_.clusters = clusters_.size();
    stats_.worldPrims = worldPrims_.size();
    stats_.worldTreeBytes = worldTree_.bytes() + worldPaths_.bytes() + worldPrims_.size() * sizeof(PrimRef);
    for (const Cluster& c : clusters_) {
      stats_.fuzzyPrims += c.prims.size();
      stats_.fuzzyTreeBytes += c.tree.bytes();
      stats_.fuzzyNodes += c.tree.nodes.size();
      stats_.fuzzyRefs += c.tree.refs.size();
      stats_.topBytes += c.xfm.size() * sizeof(Affine3f) + c.keyBoxes.size() * sizeof(Box3f) +
                         c.prims.size() * sizeof(PrimRef);
    }
    stats_.topBytes += top_.size() * sizeof(TopNode);
    computeSah();
  }

  bool intersect(RayQuery& ray, Hit& hit) const override { return traverse<false, false>(ray, &hit, nullptr); }
  bool occluded(RayQuery& ray) const override { return traverse<true, false>(ray, nullptr, nullptr); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    return traverse<false, true>(ray, &hit, &c);
  }

  void fillStats(AccelStats& s) const override {
    s.references = worldTree_.refs.size();
    size_t nodes = worldTree_.nodes.size() + top_.size();
    for (const Cluster& c : clusters_) {
      s.references += c.tree.refs.size();
      nodes += c.tree.nodes.size();
      s.maxDepth = std::max<size_t>(s.maxDepth, c.tree.depth);
    }
    s.maxDepth = std::max<size_t>(s.maxDepth, worldTree_.depth);
    size_t leaves = 0;
    auto countLeaves = [&](const std::vector<KdNode>& nodes) {
      for (const KdNode& n : nodes) leaves += n.isLeaf();
    };
    countLeaves(worldTree_.nodes);
    for (const Cluster& c : clusters_) countLeaves(c.tree.nodes);
    s.leafNodes = leaves;
    s.innerNodes = nodes - leaves;
    s.bytes = stats_.fuzzyTreeBytes + stats_.worldTreeBytes + stats_.topBytes;
    s.sahCost = sahCost_;
  }

  const FuzzyKdStats& fuzzyStats() const override { return stats_; }
  uint32_t clusterOf(PrimRef p) const override {
    if (p.geomID >= clusterOfPrim_.size() || p.primID >= clusterOfPrim_[p.geomID].size()) return ~0u;
    return clusterOfPrim_[p.geomID][p.primID];
  }

 private:
  // Decomposes one geometry into clusters; false: all its primitives go
  // to the world tree. Small clusters and unsafe ones are sent there too
  // (through `rest`).
  bool decomposeMesh(uint32_t g, const Geometry& geo, const std::vector<PrimRef>& prims) {
    if (geo.type() != GeometryType::Triangles || geo.numSteps() < 2 || prims.size() < kMinMeshTriangles ||
        prims.size() != geo.numPrimitives())
      return false;
    DecomposeParams params;
    uint32_t pieces = 0;
    const auto tris = geo.triangles();
    connectedPieces(tris, uint32_t(geo.vertices(0).count), pieces);
    // Many pieces (unwelded seams, debris): start from one cluster instead.
    if (pieces > params.maxClusters) params.startFromPieces = false;
    const auto keys = geometryKeys(geo);
    Decomposition d = decomposeMotion(tris, keys, params);
    stats_.decomposedMeshes++;
    stats_.rmsResidual = std::max(stats_.rmsResidual, d.rmsResidual);
    std::vector<std::vector<PrimRef>> members(d.numClusters);
    for (uint32_t p = 0; p < tris.size(); ++p) members[d.clusterOf[p]].push_back({g, p});
    std::vector<PrimRef> rest;
    for (uint32_t c = 0; c < d.numClusters; ++c) {
      if (members[c].size() < kMinClusterTriangles || !makeCluster(g, geo, d.transforms[c], members[c])) {
        if (members[c].size() >= kMinClusterTriangles) ++stats_.fallbackClusters;
        rest.insert(rest.end(), members[c].begin(), members[c].end());
      }
    }
    stats_.decomposedGeometry.push_back(g);
    stats_.decompositions.push_back(std::move(d));
    restWorld_.insert(restWorld_.end(), rest.begin(), rest.end());
    return true;
  }

  // Fuzzy boxes with the motion-blur pad (see fuzzykd.h) and the tree.
  bool makeCluster(uint32_t g, const Geometry& geo, const std::vector<Affine3d>& W, std::vector<PrimRef>& prims) {
    Cluster c;
    c.geomID = g;
    for (const Affine3d& w : W) c.xfm.push_back(w.toFloat());
    std::vector<Affine3d> Wf;  // the float maps, as traversal uses them
    for (const Affine3f& w : c.xfm) Wf.push_back(Affine3d::fromFloat(w));
    const uint32_t K = uint32_t(Wf.size());
    std::vector<Box3f> boxes;
    bool ok = false;
    for (uint32_t n = 1; n <= kMaxSubdivisions && !ok; n *= 2) {
      // Per sub-segment: inverse maps at both ends, linear-part change, beta.
      const uint32_t segs = K - 1;
      struct Sub {
        Affine3d inva, invb;
        Mat3d D;
        double beta;
      };
      std::vector<Sub> subs(size_t(segs) * n);
      bool valid = true;
      double invNorm = 0;
      for (uint32_t k = 0; k < segs && valid; ++k)
        for (uint32_t j = 0; j < n && valid; ++j) {
          const Affine3d A = lerp(Wf[k], Wf[k + 1], double(j) / n), B = lerp(Wf[k], Wf[k + 1], double(j + 1) / n);
          Sub& s = subs[size_t(k) * n + j];
          if (!A.inverse(s.inva) || !B.inverse(s.invb)) {
            valid = false;
            break;
          }
          s.D = B.L - A.L;
          const double ra = (s.inva.L * s.D).normInf(), rb = (s.invb.L * s.D).normInf();
          double beta = 1e300;
          if (ra < 0.5) beta = std::min(beta, s.inva.L.normInf() / (1.0 - ra));
          if (rb < 0.5) beta = std::min(beta, s.invb.L.normInf() / (1.0 - rb));
          if (!(beta < 1e300)) valid = false;
          s.beta = beta;
          invNorm = std::max({invNorm, s.inva.L.normInf(), s.invb.L.normInf()});
        }
      if (!valid) continue;
      boxes.assign(prims.size(), Box3f{});
      std::vector<double> pad(prims.size(), 0.0);
      const auto tris = geo.triangles();
      tbb::parallel_for(size_t(0), prims.size(), [&](size_t i) {
        const Triangle& t = tris[prims[i].primID];
        Box3f b;
        double p = 0;
        for (uint32_t k = 0; k < segs; ++k)
          for (uint32_t v : {t.v0, t.v1, t.v2}) {
            const Vec3d x0 = toD(geo.vertexAtStep(k, v)), x1 = toD(geo.vertexAtStep(k + 1, v));
            for (uint32_t j = 0; j < n; ++j) {
              const Sub& s = subs[size_t(k) * n + j];
              const Vec3d qa = s.inva.apply(lerp(x0, x1, double(j) / n));
              const Vec3d qb = s.invb.apply(lerp(x0, x1, double(j + 1) / n));
              b.extend(Vec3f(float(qa.x), float(qa.y), float(qa.z)));
              b.extend(Vec3f(float(qb.x), float(qb.y), float(qb.z)));
              p = std::max(p, 0.25 * s.beta * normInf(s.D * (qb - qa)));
            }
          }
        boxes[i] = b;
        pad[i] = p;
      });
      Box3f all;
      for (const Box3f& b : boxes) all.extend(b);
      const double localMag = std::max(normInf(toD(all.lower)), normInf(toD(all.upper)));
      const double extent = normInf(toD(all.upper - all.lower));
      const double maxPad = *std::max_element(pad.begin(), pad.end());
      if (maxPad > 0.01 * extent && n < kMaxSubdivisions) continue;  // refine
      if (maxPad > 0.25 * extent) return false;  // too loose: world tree
      const double num = kNumericPad * (localMag + invNorm * worldMag_) + 1e-30;
      for (size_t i = 0; i < boxes.size(); ++i) {
        const float e = float((pad[i] + num) * (1.0 + 1e-6));
        boxes[i].lower = boxes[i].lower - Vec3f(e);
        boxes[i].upper = boxes[i].upper + Vec3f(e);
        boxes[i] = widen(boxes[i]);
        stats_.fuzzyBoxArea += boxes[i].area();
      }
      stats_.maxSubdivisions = std::max(stats_.maxSubdivisions, n);
      ok = true;
    }
    if (!ok) return false;
    const KdPaths paths = KdPaths::fromBoxes(boxes);
    Box3f root;
    for (const Box3f& b : boxes) root.extend(b);
    KdBuildParams params;
    params.sah.traversal = ctx_.options().traversalCost;
    params.maxDepth = fuzzyTreeDepth(paths.size());
    KdBuildStats bs;
    KdTree tree;
    buildKdTree(paths, root, params, ctx_.budget(), tree, bs);
    c.tree = FuzzyTree(tree);
    c.keyBoxes.assign(K, Box3f{});
    for (const PrimRef& p : prims)
      for (uint32_t k = 0; k < K; ++k) c.keyBoxes[k].extend(ctx_.keyBox(p, k));
    c.prims = std::move(prims);
    clusters_.push_back(std::move(c));
    return true;
  }

  void buildTop() {
    worldPrims_.insert(worldPrims_.end(), restWorld_.begin(), restWorld_.end());
    restWorld_.clear();
    if (!worldPrims_.empty()) {  // (rebuilt with the fallback triangles)
      worldPaths_ = KdPaths::fromContext(ctx_, worldPrims_);
      Box3f root;
      for (uint32_t i = 0; i < worldPaths_.size(); ++i) root.extend(worldPaths_.hull(i));
      KdBuildParams params;
      params.sah.traversal = ctx_.options().traversalCost;
      KdBuildStats bs;
      worldTree_ = {};
      buildKdTree(worldPaths_, root, params, ctx_.budget(), worldTree_, bs);
    }
    std::vector<std::pair<LBounds, uint32_t>> items;
    for (uint32_t c = 0; c < clusters_.size(); ++c) {
      LBounds b;
      b.b0 = Box3f{};
      b.b1 = Box3f{};
      for (const PrimRef& p : clusters_[c].prims) b.extend(linearBounds(ctx_, p, {0.0f, 1.0f}));
      items.push_back({b, c});
    }
    if (!worldPrims_.empty()) {
      LBounds b;
      for (const PrimRef& p : worldPrims_) b.extend(linearBounds(ctx_, p, {0.0f, 1.0f}));
      items.push_back({b, uint32_t(clusters_.size())});
    }
    if (!items.empty()) buildTopNode(items, 0, items.size());
  }

  uint32_t buildTopNode(std::vector<std::pair<LBounds, uint32_t>>& items, size_t lo, size_t hi) {
    const uint32_t index = uint32_t(top_.size());
    top_.push_back({});
    LBounds b = items[lo].first;
    for (size_t i = lo + 1; i < hi; ++i) b.extend(items[i].first);
    if (hi - lo == 1) {
      top_[index].bounds = b;
      top_[index].item = items[lo].second;
      return index;
    }
    const Box3f h = b.hull();
    const Vec3f d = h.upper - h.lower;
    const int axis = d.x >= d.y ? (d.x >= d.z ? 0 : 2) : (d.y >= d.z ? 1 : 2);
    const size_t mid = (lo + hi) / 2;
    std::nth_element(items.begin() + lo, items.begin() + mid, items.begin() + hi, [&](const auto& a, const auto& c) {
      const Box3f ha = a.first.hull(), hc = c.first.hull();
      return ha.lower[axis] + ha.upper[axis] < hc.lower[axis] + hc.upper[axis];
    });
    const uint32_t l = buildTopNode(items, lo, mid);
    const uint32_t r = buildTopNode(items, mid, hi);
    top_[index].bounds = b;
    top_[index].left = l;
    top_[index].right = r;
    return index;
  }

  template <bool AnyHit, bool Count>
  bool traverse(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    if (top_.empty()) return false;
    uint32_t stack[128];
    int sp = 0;
    stack[sp++] = 0;
    bool found = false;
    const float time = ray.time;
    while (sp > 0) {
      const TopNode& n = top_[stack[--sp]];
      if constexpr (Count) {
        ++counters->nodesVisited;
        ++counters->boxTests;
      }
      float tmin, tmax;
      if (!clipToBox(ray, n.bounds.at(time), tmin, tmax)) continue;
      if (n.item == ~0u) {
        // Nearer child last (popped first).
        float la, lb, ua, ub;
        const bool hl = clipToBox(ray, top_[n.left].bounds.at(time), la, ua);
        const bool hr = clipToBox(ray, top_[n.right].bounds.at(time), lb, ub);
        if (hl && hr) {
          if (la < lb) {
            stack[sp++] = n.right;
            stack[sp++] = n.left;
          } else {
            stack[sp++] = n.left;
            stack[sp++] = n.right;
          }
        } else if (hl) {
          stack[sp++] = n.left;
        } else if (hr) {
          stack[sp++] = n.right;
        }
        continue;
      }
      bool h;
      if (n.item == clusters_.size()) {
        if (counters) ++counters->boxTests;
        h = kdTraverse<AnyHit, Count>(worldTree_, ctx_, worldPrims_.data(), ray, hit, counters,
                                      BoxFilter{worldPaths_});
      } else {
        h = traverseCluster<AnyHit, Count>(clusters_[n.item], ray, hit, counters);
      }
      if (h) {
        if constexpr (AnyHit) return true;
        found = true;
      }
    }
    return found;
  }

  template <bool AnyHit, bool Count>
  bool traverseCluster(const Cluster& c, RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    const Geometry& geo = ctx_.geometry(c.geomID);
    uint32_t s;
    float f;
    geo.segmentAt(ray.time, s, f);
    const Box3f wb = lerp(c.keyBoxes[s], c.keyBoxes[s + 1], f);
    if constexpr (Count) ++counters->boxTests;
    if (!rayHitsBox(ray, wb)) return false;
    const Affine3f xfm = lerp(c.xfm[s], c.xfm[s + 1], f);
    const Affine3f inv = xfm.inverse();
    RayQuery local;
    local.setup(inv.xfmPoint(ray.org), inv.xfmVector(ray.dir), ray.tnear, ray.tfar, ray.time, ray.mask);
    const FuzzyTree& tree = c.tree;
    KdMailbox mailbox;
    return kdWalk<AnyHit, Count>(tree, local, counters, [&](const KdNode& n) {
      bool found = false;
      const uint32_t* refs = tree.refs.data() + n.first();
      for (uint32_t i = 0, cnt = n.count(); i < cnt; ++i) {
        const uint32_t prim = refs[i];
        if (mailbox.seen(prim)) continue;
        if constexpr (Count) ++counters->primitiveTests;
        if constexpr (AnyHit) {
          if (occludedPrimitive(ctx_, c.prims[prim], ray)) return true;
        } else if (intersectPrimitive(ctx_, c.prims[prim], ray, *hit, Count ? counters : nullptr)) {
          found = true;
          local.tfar = ray.tfar;
        }
      }
      return found;
    });
  }

  // DESIGN.md's SAH (C_T = C_I = 1, areas averaged over 8 times). Top-level
  // nodes count with their linear bounds; a cluster with its world key box
  // and its tree's cells, whose area is that of the cell's image in world
  // space (a parallelepiped under the cluster's map at each time, §3: the
  // ray is mapped into the cell's frame, so that is the area it must hit);
  // a leaf counts the active segments of its triangles. The world tree's
  // cells count as mbkd's.
  void computeSah() {
    const double sceneArea = sceneSahArea(ctx_);
    if (!(sceneArea > 0.0)) return;
    constexpr int kTimes = 8;
    double sum = 0.0;
    for (const TopNode& n : top_) sum += meanSurfaceArea(n.bounds);
    for (const Cluster& c : clusters_) {
      const Geometry& geo = ctx_.geometry(c.geomID);
      Affine3f xfm[kTimes];
      for (int k = 0; k < kTimes; ++k) {
        uint32_t s;
        float f;
        geo.segmentAt(float(k) / (kTimes - 1), s, f);
        xfm[k] = lerp(c.xfm[s], c.xfm[s + 1], f);
        sum += double(lerp(c.keyBoxes[s], c.keyBoxes[s + 1], f).area()) / kTimes;
      }
      walkCells(c.tree.nodes, 0, c.tree.root, [&](uint32_t node, const Box3f& cell, int) {
        double area = 0.0;
        for (const Affine3f& m : xfm) area += mappedArea(m, cell) / kTimes;
        const KdNode& n = c.tree.nodes[node];
        double seg = 1.0;
        if (n.isLeaf()) {
          seg = 0.0;
          for (uint32_t i = 0; i < n.count(); ++i)
            seg += activeSegments(ctx_, c.prims[c.tree.refs[n.first() + i]], {0.0f, 1.0f});
        }
        sum += area * seg;
      });
    }
    if (!worldTree_.empty())
      walkCells(worldTree_.nodes, 0, worldTree_.root, [&](uint32_t node, const Box3f& cell, int) {
        const KdNode& n = worldTree_.nodes[node];
        double seg = 1.0;
        if (n.isLeaf()) {
          seg = 0.0;
          for (uint32_t i = 0; i < n.count(); ++i) {
            const KdLeafRef& r = worldTree_.refs[n.first() + i];
            seg += activeSegments(ctx_, worldPrims_[r.prim], {r.t0, r.t1});
          }
        }
        sum += double(cell.area()) * seg;
      });
    sahCost_ = sum / sceneArea;
  }

  struct BoxFilter {
    static constexpr bool kActive = true;
    const KdPaths& paths;
    bool operator()(uint32_t prim, const RayQuery& ray) const { return rayHitsBox(ray, paths.boxAt(prim, ray.time)); }
  };

  const SceneContext& ctx_;
  double worldMag_ = 1.0;
  std::vector<Cluster> clusters_;
  std::vector<PrimRef> worldPrims_, restWorld_;
  KdPaths worldPaths_;
  KdTree worldTree_;
  std::vector<TopNode> top_;
  std::vector<std::vector<uint32_t>> clusterOfPrim_;  // [geomID][primID]
  FuzzyKdStats stats_;
  double sahCost_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeFuzzyKd(const SceneContext& context) { return std::make_unique<FuzzyKd>(context); }

}  // namespace mbrt::detail
