// The one dispatch of the three tracing entry points onto a structure's
// traversal: a kind writes
//   template <bool AnyHit, bool Count>
//   bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const;
// once (AnyHit: stop at the first accepted hit, hit may be null; Count:
// counters is non-null), and derives from TracedStructure<Kind>.
#pragma once

#include "core/structure.h"

namespace mbrt::detail {

template <class Kind>
class TracedStructure : public Structure {
 public:
  bool intersect(RayQuery& ray, Hit& hit) const final { return kind().template trace<false, false>(ray, &hit, nullptr); }
  bool occluded(RayQuery& ray) const final { return kind().template trace<true, false>(ray, nullptr, nullptr); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& counters) const final {
    return kind().template trace<false, true>(ray, &hit, &counters);
  }

 private:
  const Kind& kind() const { return static_cast<const Kind&>(*this); }
};

}  // namespace mbrt::detail
