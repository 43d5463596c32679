// Work whose parallel algorithms no outside cancellation can cut short.
//
// TBB cancels the algorithms nested in a task when a sibling task of an
// enclosing algorithm throws, and a cancelled parallel_for returns quietly
// with some of its iterations never run. A build cut short that way returns
// a tree with children never stored, and laying it out reads garbage. Builds
// that run beside other work (the trees of bvh-segments, a caller's own
// parallel loop around Accel::build) therefore run isolated: their own
// exceptions still propagate, an outside one only waits for them to finish.
#pragma once

#include <tbb/task_group.h>

namespace mbrt::detail {

template <class F>
void runIsolatedFromCancellation(const F& work) {
  tbb::task_group_context context(tbb::task_group_context::isolated);
  tbb::task_group group(context);
  group.run_and_wait(work);
}

}  // namespace mbrt::detail
