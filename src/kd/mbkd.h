// `mbkd`: the motion-blur kd-tree of Yang et al. 2017 (kd/kd_builder.h):
// a kd-tree of the scene at t = 0.5 over a root cell holding every
// primitive over the whole shutter, with BP duplication and propagation and
// per-reference time intervals in the leaves. On a static scene it is the
// static SAH kd-tree.
#pragma once

#include <functional>
#include <memory>
#include <span>

#include "scene/scene_context.h"
#include "kd/kd_builder.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeMbkd(const SceneContext& context);

// Debug and statistics access for tests and docs.
class KdInspect {
 public:
  virtual ~KdInspect() = default;
  // fn(cell, primitives of the references, references) for every leaf.
  virtual void forEachLeaf(
      const std::function<void(const Box3f&, const PrimRef*, std::span<const KdLeafRef>)>& fn) const = 0;
  virtual const KdBuildStats& buildStats() const = 0;
};

}  // namespace mbrt::detail
