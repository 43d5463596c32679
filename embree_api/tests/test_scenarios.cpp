// Commit and update (refit and rebuild), shared and owned buffers, detach,
// disable, reference counts, user data, rtcInterpolate,
// rtcGetGeometryTransform and scene bounds: what scenarios.inl observes
// must be what the real libembree3 gives.
#include <gtest/gtest.h>

#include <cmath>

#include "embree_side.h"

namespace mbrt::embree_test {
namespace {

TEST(EmbreeApiScenarios, SameObservationsAsEmbree) {
  const std::vector<float> real = realEmbree().scenarios();
  const std::vector<float> ours = mbrtEmbree().scenarios();
  ASSERT_EQ(real.size(), ours.size());
  size_t differ = 0;
  for (size_t i = 0; i < real.size(); ++i) {
    const bool same = real[i] == ours[i] || std::fabs(real[i] - ours[i]) <= 1e-5f * std::max(1.0f, std::fabs(real[i]));
    if (!same && differ++ < 10) ADD_FAILURE() << "observation " << i << ": Embree " << real[i] << ", mbrt " << ours[i];
  }
  EXPECT_EQ(differ, 0u);
}

}  // namespace
}  // namespace mbrt::embree_test
