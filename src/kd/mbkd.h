// `mbkd`: the motion-blur kd-tree of Yang et al. 2017 (kd/kd_builder.h):
// a kd-tree of the scene at t = 0.5 over a root cell holding every
// primitive over the whole shutter, with BP duplication and propagation and
// per-reference time intervals in the leaves. On a static scene it is the
// static SAH kd-tree.
#pragma once

#include <memory>

#include "scene/scene_context.h"
#include "kd/kd_builder.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeMbkd(const SceneContext& context);

// The structure answers core/inspect.h: its leaf cells as lanes, with each
// reference's time interval, and statsOf<KdBuildStats>.

}  // namespace mbrt::detail
