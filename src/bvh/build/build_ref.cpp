#include "bvh/build/build_ref.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/huge_pages.h"

namespace mbrt::detail {

std::vector<BuildRef> makeBuildRefs(std::span<const PrimRef> prims, const RefMaker& maker) {
  std::vector<BuildRef> refs;
  resizeOnHugePages(refs, prims.size());
  std::vector<uint8_t> keep(prims.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, prims.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      keep[i] = maker.make(prims[i], refs[i]) && isUsable(refs[i].bounds);
  });
  size_t n = 0;  // serial compaction keeps the order deterministic
  for (size_t i = 0; i < refs.size(); ++i)
    if (keep[i]) refs[n++] = refs[i];
  refs.resize(n);
  return refs;
}

}  // namespace mbrt::detail
