// The interface every acceleration structure implements. Accel (public)
// validates rays and counts statistics around it.
#pragma once

#include <string>

#include "core/prim_ref.h"
#include "core/ray_query.h"
#include "mbrt/accel_stats.h"
#include "mbrt/ray.h"

namespace mbrt::detail {

class Structure {
 public:
  virtual ~Structure() = default;
  // Closest hit along [ray.tnear, ray.tfar]; on a hit, ray.tfar = hit.t.
  virtual bool intersect(RayQuery& ray, Hit& hit) const = 0;
  virtual bool occluded(RayQuery& ray) const = 0;
  // As intersect, also counting the work done.
  virtual bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& counters) const = 0;
  // Node counts, references, bytes and SAH cost.
  virtual void fillStats(AccelStats& stats) const = 0;
  // Updates bounds for new vertex data without a new topology; false when
  // the structure cannot do that.
  virtual bool refit() { return false; }
  // After refit: what it did (true) or why it could not (false), in a few
  // words for Accel::lastUpdate; empty: "refit", or "kind cannot refit".
  virtual std::string refitSummary() const { return {}; }
  // The cluster a primitive belongs to in kinds that decompose the scene;
  // kInvalidId elsewhere.
  virtual uint32_t clusterOf(PrimRef) const { return kInvalidId; }
};

}  // namespace mbrt::detail
