// A structure built straight from the kind registry inside a TBB arena of a
// given thread count: its bytes and statistics. For the tests that a build
// is the same whatever the thread count (accel.h: deterministic builds).
#pragma once

#include <tbb/task_arena.h>

#include <cstdint>
#include <vector>

#include "accel/structure_factory.h"
#include "core/inspect.h"
#include "mbrt/accel.h"
#include "scene/scene_context.h"

namespace mbrt::test {

struct BuiltInArena {
  std::vector<uint8_t> bytes;  // the tree as stored (Inspect::bytes)
  AccelStats stats;
};

inline BuiltInArena buildInArena(const Scene& scene, const BuildOptions& options, int threads) {
  BuiltInArena built;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    detail::BuildBudget budget;
    detail::SceneContext ctx(scene, options, budget);
    auto s = detail::makeStructure(ctx);
    built.bytes = detail::inspect(*s).bytes();
    s->fillStats(built.stats);
  });
  return built;
}

}  // namespace mbrt::test
