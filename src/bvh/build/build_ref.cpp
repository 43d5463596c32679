#include "bvh/build/build_ref.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace mbrt::detail {

bool usableBounds(const LBounds& b) {
  return !b.b0.empty() && !b.b1.empty() && isFinite(b.b0.lower) && isFinite(b.b0.upper) &&
         isFinite(b.b1.lower) && isFinite(b.b1.upper);
}

std::vector<BuildRef> makeBuildRefs(std::span<const PrimRef> prims, const RefMaker& maker) {
  std::vector<BuildRef> refs(prims.size());
  std::vector<uint8_t> keep(prims.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, prims.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      keep[i] = maker.make(prims[i], refs[i]) && usableBounds(refs[i].bounds);
  });
  size_t n = 0;  // serial compaction keeps the order deterministic
  for (size_t i = 0; i < refs.size(); ++i)
    if (keep[i]) refs[n++] = refs[i];
  refs.resize(n);
  return refs;
}

}  // namespace mbrt::detail
