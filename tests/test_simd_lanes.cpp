// The packs' lane masks turned into bits (core/simd.h, laneBits) agree with
// the bit-mask comparisons on every lane, NaN, signed zeros and infinities
// included, for the widths the kernels use (4: leaf blocks, 8: nodes).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/simd.h"

namespace mbrt {
namespace {

template <int W>
void checkLaneBits() {
  using P = detail::Pack<W>;
  const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                           1e-40f, -1e-40f, 3.5f};
  std::mt19937 rng(11);
  for (int trial = 0; trial < 2000; ++trial) {
    alignas(32) float a[W], b[W];
    for (int i = 0; i < W; ++i) {
      a[i] = special[rng() % std::size(special)];
      b[i] = special[rng() % std::size(special)];
    }
    const P pa = P::load(a), pb = P::load(b);
    uint32_t less = 0, equal = 0;
    for (int i = 0; i < W; ++i) {
      less |= uint32_t(a[i] < b[i]) << i;
      equal |= uint32_t(a[i] == b[i]) << i;
    }
    ASSERT_EQ(laneBits(lessLanes(pa, pb)), less) << "trial " << trial;
    ASSERT_EQ(laneBits(equalLanes(pa, pb)), equal) << "trial " << trial;
    ASSERT_EQ(laneBits(lessLanes(pa, pb) | equalLanes(pa, pb)), less | equal) << "trial " << trial;
    ASSERT_EQ(laneBits(lessLanes(pa, pb) & lessLanes(pb, pa)), 0u) << "trial " << trial;
    ASSERT_EQ(lessMask(pa, pb), less) << "trial " << trial;
    ASSERT_EQ(equalMask(pa, pb), equal) << "trial " << trial;
  }
}

TEST(SimdLanes, LaneBitsAgreeWithTheComparisons) {
  checkLaneBits<4>();
  checkLaneBits<8>();
}

}  // namespace
}  // namespace mbrt
