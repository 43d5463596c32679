// A cluster of the fuzzy kd-tree (Günther et al. 2006 §3): triangles of one
// mesh, one affine map per key (local frame -> world), its world key boxes
// and one kd-tree over the triangles' fuzzy boxes (fuzzy_boxes.h), built
// once for the whole shutter.
#pragma once

#include <vector>

#include "decompose/affine_fit.h"
#include "kd/kd_node.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

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
  std::vector<Affine3f> xfm;    // per geometry step: local -> world
  std::vector<Box3f> keyBoxes;  // world, per step
  std::vector<PrimRef> prims;
  FuzzyTree tree;

  // Its world box at `time` (interpolated key boxes).
  Box3f boxAt(const Geometry& geo, float time) const {
    uint32_t s;
    float f;
    geo.segmentAt(time, s, f);
    return lerp(keyBoxes[s], keyBoxes[s + 1], f);
  }
  // Its map at `time` (element-wise interpolation of the key maps).
  Affine3f mapAt(const Geometry& geo, float time) const {
    uint32_t s;
    float f;
    geo.segmentAt(time, s, f);
    return lerp(xfm[s], xfm[s + 1], f);
  }
  size_t topBytes() const {
    return xfm.size() * sizeof(Affine3f) + keyBoxes.size() * sizeof(Box3f) + prims.size() * sizeof(PrimRef);
  }
};

// The cluster of the triangles `prims` of geometry g under the maps
// `maps` (per step, local -> world): fuzzy boxes and their tree. False when
// their fuzzy boxes have no usable bound (fuzzy_boxes.h): the triangles go
// to the world tree. `prims` moves into the cluster on success;
// subdivisions: raised to the sub-sampling used.
bool makeCluster(const SceneContext& ctx, uint32_t g, const std::vector<Affine3d>& maps, std::vector<PrimRef>& prims,
                 double worldMag, Cluster& out, uint32_t& subdivisions);

}  // namespace mbrt::detail
