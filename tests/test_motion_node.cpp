// Quantised motion nodes (bvh/motion_node.h): the decoded box of every lane,
// computed as the node test computes it, contains the lane's linear bounds at
// every time, whatever the lanes' size, spread, motion and distance from the
// origin; empty lanes never hit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bvh/traverse.h"

using namespace mbrt;

namespace {

using Rng = std::mt19937;
float uni(Rng& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
Vec3f uniVec(Rng& rng, float lo, float hi) { return {uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)}; }

// The decoded box (floats, as the node test computes it) contains the
// linear bounds at t, evaluated exactly (in double).
bool containsAt(const Box3f& decoded, const LBounds& b, double t) {
  for (int a = 0; a < 3; ++a) {
    const double lo = (1.0 - t) * double(b.b0.lower[a]) + t * double(b.b1.lower[a]);
    const double hi = (1.0 - t) * double(b.b0.upper[a]) + t * double(b.b1.upper[a]);
    if (!(double(decoded.lower[a]) <= lo && hi <= double(decoded.upper[a]))) return false;
  }
  return true;
}

// Random lanes around `centre`: size up to `size`, moving up to `motion`;
// some lanes extrapolated from a short time range, so that their planes
// cross at t = 0 or 1 as a spatial-temporal lane's may.
template <int N>
uint32_t randomLanes(Rng& rng, Vec3f centre, float size, float motion, LBounds (&lanes)[N]) {
  uint32_t present = 0;
  for (int l = 0; l < N; ++l) {
    if (rng() % 6 == 0) continue;
    Box3f b0(centre + uniVec(rng, -size, size)), b1(b0.lower + uniVec(rng, -motion, motion));
    b0.extend(b0.lower + uniVec(rng, 0.0f, size));
    b1.extend(b1.lower + uniVec(rng, 0.0f, size));
    if (rng() % 4 == 0) {  // a lane serving [t0, t0 + 0.1], extrapolated to 0 and 1
      const float t0 = uni(rng, 0.0f, 0.9f);
      const LBounds local(b0, b1);
      const Box3f at0 = local.at(-t0 / 0.1f), at1 = local.at((1.0f - t0) / 0.1f);
      b0 = at0;
      b1 = at1;
    }
    lanes[l] = LBounds(b0, b1);
    present |= 1u << l;
  }
  return present;
}

template <int N>
void checkConservative(uint64_t seed, int trials) {
  Rng rng{uint32_t(seed)};
  const float offsets[] = {0.0f, 3.0f, -250.0f, 1.0e4f};
  const float sizes[] = {1.0f, 1e-3f, 1e-6f};
  for (int trial = 0; trial < trials; ++trial) {
    const float offset = offsets[trial % 4], size = sizes[trial / 4 % 3];
    const float motion = size * uni(rng, 0.0f, 20.0f);
    LBounds lanes[N];
    const uint32_t present = randomLanes<N>(rng, uniVec(rng, -1.0f, 1.0f) + Vec3f(offset), size, motion, lanes);
    detail::WideNode<N, true> node;
    node.clear();
    node.encode(lanes, present);
    for (int l = 0; l < N; ++l) {
      ASSERT_EQ(node.isEmpty(l), !(present >> l & 1u));
      if (node.isEmpty(l)) continue;
      for (int k = 0; k <= 64; ++k) {
        const float t = k == 64 ? 1.0f : float(k) / 64.0f + uni(rng, 0.0f, 1.0f / 64.0f);
        ASSERT_TRUE(containsAt(node.boxAt(l, t), lanes[l], double(t)))
            << "trial " << trial << " lane " << l << " t " << t << " offset " << offset << " size " << size;
      }
    }
  }
}

}  // namespace

TEST(MotionNode, DecodedBoxesContainTheLinearBounds) {
  checkConservative<8>(1, 3000);
  checkConservative<4>(2, 1000);
  checkConservative<2>(3, 1000);
}

// The grid is fine enough to keep boxes tight: a lane's decoded box is at
// most a few grid steps larger than its bounds (here: lanes in a unit node).
TEST(MotionNode, DecodedBoxesAreTight) {
  Rng rng(4);
  double worst = 0.0;
  for (int trial = 0; trial < 500; ++trial) {
    LBounds lanes[8];
    const uint32_t present = randomLanes<8>(rng, Vec3f(0.0f), 0.5f, 0.5f, lanes);
    detail::WideNode<8, true> node;
    node.clear();
    node.encode(lanes, present);
    for (int l = 0; l < 8; ++l) {
      if (node.isEmpty(l)) continue;
      for (int a = 0; a < 3; ++a) {
        const double span = std::max(node.step0[a], node.step1[a]);
        for (float t : {0.0f, 1.0f}) {
          const Box3f got = node.boxAt(l, t), want = lanes[l].at(t);
          worst = std::max(worst, (double(want.lower[a]) - got.lower[a]) / span);
          worst = std::max(worst, (double(got.upper[a]) - want.upper[a]) / span);
        }
      }
    }
  }
  EXPECT_LE(worst, 1.01);  // one step (plus the float margin)
}

TEST(MotionNode, EmptyLanesNeverHit) {
  Rng rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    LBounds lanes[8];
    uint32_t present = randomLanes<8>(rng, Vec3f(0.0f), 1.0f, 0.5f, lanes) & 0x55u;
    detail::WideNode<8, true> node;
    node.clear();
    node.encode(lanes, present);
    // A ray through the whole node at every lane.
    Ray ray{Vec3f(-10.0f, 0.1f, 0.2f), 0.0f, Vec3f(1.0f, 0.001f, 0.002f), 100.0f, uni(rng, 0.0f, 1.0f)};
    detail::RayQuery q(ray);
    alignas(32) float dist[8];
    const uint32_t mask = detail::intersectNode<1>(node, detail::NodeRay<1>(q, ray.time), q.tfar, dist);
    EXPECT_EQ(mask & ~present, 0u);
  }
}

TEST(MotionNode, EightLanesFitThreeCacheLines) {
  EXPECT_EQ(sizeof(detail::WideNode<8, true>), 192u);
  EXPECT_EQ(sizeof(detail::WideNode<4, true>), 128u);
}
