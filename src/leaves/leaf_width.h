// The leaf block a tree's SAH charges (BuildSettings::leafBlock): four when
// at least 3/4 of the primitives can be tested in blocks of four (the
// triangles of a mesh without a filter; a static tree's segments), else one
// (what is tested one by one, larger leaves of it only cost: hair leaves
// charged per block test several times the segments, docs/performance.md).
// With four, every leaf
// starts at a multiple of four in the reference table (bvh/build/wide_layout.h),
// which the block formats find their blocks by.
#pragma once

#include <cstddef>

#include "leaves/gathered_runs.h"
#include "leaves/leaf_format.h"

namespace mbrt::detail {

inline int leafBlockWidth(size_t blockable, size_t primitives) {
  return 4 * blockable >= 3 * primitives ? kLeafBlockWidth : 1;
}

// The leaf block of a motion tree over the scene (`bvh-interp`, `stbvh`,
// `bvh-segments`): four when at least 3/4 of its primitives are triangles
// without a filter, which its leaves test four at a time (copied into
// motion blocks, motion_blocks.h, or gathered, gathered_runs.h).
inline int triangleLeafBlockWidth(const SceneContext& ctx) {
  size_t triangles = 0, all = 0;
  for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id) {
    const Geometry& g = ctx.geometry(id);
    all += g.numPrimitives();
    if (g.type() == GeometryType::Triangles && !g.hasFilter()) triangles += g.numPrimitives();
  }
  return leafBlockWidth(triangles, all);
}

// Whether the table's leaves all start at a multiple of four with nothing
// kept in nodes, as the block formats need.
inline bool laidOutInBlocks(const LeafTable& table) {
  if (table.prims.size() % kLeafBlockWidth != 0 || table.someInNodes) return false;
  for (const LeafRange& l : table.leaves)
    if (l.begin % kLeafBlockWidth != 0) return false;
  return true;
}

}  // namespace mbrt::detail
