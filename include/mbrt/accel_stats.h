// What a structure reports of itself (AccelStats) and of the work a ray
// did (TraversalCounters): the papers' metrics, one definition for all kinds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mbrt {

// Structure statistics. sahCost follows the one SAH formula of docs/design.md for all
// kinds (C_T = C_I = 1, areas averaged over time, MBSAH segment counts).
struct AccelStats {
  std::string kind;
  size_t primitives = 0;        // triangles + segments + instances, all levels
  size_t references = 0;        // primitive references in leaves
  size_t innerNodes = 0;
  size_t leafNodes = 0;
  size_t maxDepth = 0;
  size_t bytes = 0;             // structure memory, excluding vertex buffers
  size_t leafBlockBytes = 0;    // of bytes: the triangles copied into the leaves
  size_t peakBuildBytes = 0;    // largest memory in use during the build
  double sahCost = 0.0;
  double buildSeconds = 0.0;
  uint64_t invalidRays = 0;     // rays refused since the build
  // Kinds that split the scene into objects (auto): one line per object,
  // what was extracted, its residual, the kind chosen and why.
  std::string objects;
  // What the last build, rebuild or refit did (Accel::lastUpdate).
  std::string update;
};

// Per-ray work, for the papers' metrics: nodes visited, box tests (an
// 8-wide node is 8), leaves visited (a non-empty leaf the ray entered) and
// ray-primitive tests; of those, the ones made in a leaf block (several
// triangles against the ray at once, in SIMD lanes), which cost a fraction
// of a test made one triangle at a time.
struct TraversalCounters {
  uint64_t rays = 0;
  uint64_t nodesVisited = 0;
  uint64_t boxTests = 0;
  uint64_t leavesVisited = 0;
  uint64_t primitiveTests = 0;
  uint64_t blockPrimitiveTests = 0;  // part of primitiveTests
  uint64_t maxNodesVisited = 0;
  uint64_t maxPrimitiveTests = 0;

  void add(const TraversalCounters& o);
};

}  // namespace mbrt
