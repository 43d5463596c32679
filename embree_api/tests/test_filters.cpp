// What filter functions see, against the real libembree3: in a world where
// every mesh's filter records and accepts and the context filter records
// and rejects, both sides must call the filters for the same candidates
// along each ray, the geometry's filter before the context's, with the
// same arguments: tfar at the candidate, org/dir in the instance's space,
// object-space Ng, Embree's primID and u/v (quads over the quad), instID[0]
// in the hit and in the context, N of the packet traced.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "answers.h"
#include "embree_side.h"
#include "test_util.h"

namespace mbrt::embree_test {
namespace {

bool sameCall(const FilterCall& a, const FilterCall& b) {
  const float tScale = std::max(1.0f, std::fabs(a.tfar));
  return a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID && a.contextInstID == b.contextInstID &&
         a.N == b.N && std::fabs(a.tfar - b.tfar) <= 1e-4f * tScale && std::fabs(a.u - b.u) <= 2e-3f &&
         std::fabs(a.v - b.v) <= 2e-3f && closeTo(a.Ng, b.Ng, 1e-3f) && closeTo(a.org, b.org, 1e-4f) &&
         closeTo(a.dir, b.dir, 1e-4f);
}

std::string describeCall(const FilterCall& c) {
  char buf[300];
  std::snprintf(buf, sizeof buf, "%s g%u p%u i%u ctx.i%u N%u t %g u %g v %g Ng (%g %g %g) org (%g %g %g) dir (%g %g %g)",
                c.context ? "context" : "geometry", c.geomID, c.primID, c.instID, c.contextInstID, c.N, c.tfar, c.u,
                c.v, c.Ng.x, c.Ng.y, c.Ng.z, c.org.x, c.org.y, c.org.z, c.dir.x, c.dir.y, c.dir.z);
  return buf;
}

// Each geometry call is followed by the context call of the same candidate.
bool geometryFilterFirst(const std::vector<FilterCall>& log) {
  if (log.size() % 2) return false;
  for (size_t i = 0; i < log.size(); i += 2)
    if (log[i].context || !log[i + 1].context || !sameCall(log[i], log[i + 1])) return false;
  return true;
}

TEST(EmbreeApiFilters, FiltersSeeWhatEmbreeShows) {
  const TestWorld world = randomWorld(43, false);
  const std::vector<TestRay> rays = randomRays(47, test::scaled(800, 150));
  for (TraceMode mode : {TraceMode::Single, TraceMode::Packet8, TraceMode::Stream1M, TraceMode::StreamNM}) {
    const auto real = realEmbree().filterAudit(world, rays, mode);
    const auto ours = mbrtEmbree().filterAudit(world, rays, mode);
    size_t calls = 0, unmatched = 0, order = 0, instanced = 0;
    std::string first;
    for (size_t i = 0; i < rays.size(); ++i) {
      order += geometryFilterFirst(ours[i]) ? 0 : 1;
      // Candidates as sets: the traversal order differs, and a spatial
      // split may report a primitive twice.
      for (const FilterCall& c : ours[i]) {
        if (c.context) continue;
        ++calls;
        instanced += c.instID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
        const bool found = std::any_of(real[i].begin(), real[i].end(), [&](const FilterCall& r) { return sameCall(r, c); });
        if (!found && unmatched++ == 0) first = describeCall(c) + " for " + ref::describe(toMbrtRay(rays[i]));
      }
      for (const FilterCall& r : real[i]) {
        if (r.context) continue;
        const bool found = std::any_of(ours[i].begin(), ours[i].end(), [&](const FilterCall& c) { return sameCall(r, c); });
        if (!found && unmatched++ == 0) first = "Embree's " + describeCall(r) + " for " + ref::describe(toMbrtRay(rays[i]));
      }
    }
    std::printf("%-16s %zu filter calls (%zu in instances), %zu unmatched\n", modeName(mode), calls, instanced, unmatched);
    EXPECT_EQ(order, 0u) << modeName(mode) << ": the context filter did not follow the geometry filter";
    // Candidates on an edge may be seen by one side only.
    EXPECT_LE(unmatched, calls / 200 + 2) << modeName(mode) << ": " << first;
    EXPECT_GT(instanced, calls / 10) << modeName(mode);
  }
}

}  // namespace
}  // namespace mbrt::embree_test
