// Quantised motion nodes (bvh/motion_node.h): the decoded box of every lane,
// computed as the node test computes it, contains the lane's linear bounds at
// every time, whatever the lanes' size, spread, motion and distance from the
// origin; empty lanes never hit; the 4-lane distance terms and the packs
// (core/simd.h) compute what the scalar formulas do, bit for bit.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
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

// The node's distance terms (one 4-lane pack per term) are the scalar grid
// formula of gridAt, bit for bit; overflowed terms of wild rays are NaN.
TEST(MotionNode, DistanceTermsAreTheGridFormula) {
  Rng rng(6);
  for (int trial = 0; trial < 2000; ++trial) {
    LBounds lanes[8];
    const float scale = trial % 2 ? 1.0f : 1e30f;
    const uint32_t present = randomLanes<8>(rng, uniVec(rng, -scale, scale), scale, scale, lanes);
    detail::WideNode<8, true> node;
    node.clear();
    node.encode(lanes, present | 1u);
    const float t = uni(rng, 0.0f, 1.0f), omt = 1.0f - t;
    const bool tame = trial % 3 != 0;
    alignas(16) float org[4] = {0, 0, 0, 0}, rdir[4] = {0, 0, 0, 0}, A[4], B0[4], B1[4];
    for (int a = 0; a < 3; ++a) {
      org[a] = uni(rng, -1.0f, 1.0f) * (tame ? 1.0f : 1e38f);
      rdir[a] = trial % 5 == 0 && a == 1 ? kInf : uni(rng, -4.0f, 4.0f) * (tame ? 1.0f : 1e30f);
    }
    node.distanceTerms(t, omt, org, rdir, tame, A, B0, B1);
    float at[3], w0[3], w1[3];
    node.gridAt(t, omt, at, w0, w1);
    const auto expect = [&](float got, float x, float r) {
      if (!tame && std::isinf(x) && !std::isinf(r)) EXPECT_TRUE(std::isnan(got)) << "trial " << trial;
      else EXPECT_EQ(std::bit_cast<uint32_t>(got), std::bit_cast<uint32_t>(x)) << "trial " << trial;
    };
    for (int a = 0; a < 3; ++a) {
      expect(A[a], (at[a] - org[a]) * rdir[a], rdir[a]);
      expect(B0[a], w0[a] * rdir[a], rdir[a]);
      expect(B1[a], w1[a] * rdir[a], rdir[a]);
    }
  }
}

TEST(MotionNode, OccupiedLanesAreTheNonEmptyOnes) {
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    detail::WideNode<8, true> node8;
    detail::WideNode<4, true> node4;
    node8.clear();
    node4.clear();
    for (int l = 0; l < 8; ++l) node8.count[l] = rng() % 2 ? detail::kEmptyLane : uint8_t(rng() % 255);
    for (int l = 0; l < 4; ++l) node4.count[l] = node8.count[l];
    uint32_t want = 0;
    for (int l = 0; l < 8; ++l) want |= uint32_t(!node8.isEmpty(l)) << l;
    EXPECT_EQ(node8.occupiedLanes(), want);
    EXPECT_EQ(node4.occupiedLanes(), want & 0xFu);
  }
}

// Every pack follows the scalar rules of simd.h: min/max pick the second
// operand on NaN and ties, comparisons are ordered, truncation as cvttps.
template <int W>
void checkPackRules() {
  using P = detail::Pack<W>;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float xs[] = {1.0f, -0.0f, nan, 3.5f, -kInf, 2.0f, 0.0f, 1e10f};
  const float ys[] = {2.0f, 0.0f, 1.0f, nan, 5.0f, 2.0f, -0.0f, -3.0f};
  // Through volatile: the compiler folds constant conversions its own way.
  volatile float vx[W], vy[W];
  for (int i = 0; i < W; ++i) {
    vx[i] = xs[i % 8];
    vy[i] = ys[(i + W / 2) % 8];
  }
  alignas(32) float x[W], y[W], got[W];
  for (int i = 0; i < W; ++i) x[i] = vx[i], y[i] = vy[i];
  const P a = P::load(x), b = P::load(y);
  uint32_t le = 0, lt = 0;
  for (int i = 0; i < W; ++i) le |= uint32_t(x[i] <= y[i]) << i, lt |= uint32_t(x[i] < y[i]) << i;
  EXPECT_EQ(lessEqualMask(a, b), le);
  EXPECT_EQ(lessMask(a, b), lt);
  const auto same = [](float u, float v) { return std::bit_cast<uint32_t>(u) == std::bit_cast<uint32_t>(v); };
  vmin(a, b).store(got);
  for (int i = 0; i < W; ++i) EXPECT_TRUE(same(got[i], x[i] < y[i] ? x[i] : y[i])) << W << " lane " << i;
  vmax(a, b).store(got);
  for (int i = 0; i < W; ++i) EXPECT_TRUE(same(got[i], x[i] > y[i] ? x[i] : y[i])) << W << " lane " << i;
  (abs(a) | (lessLanes(a, b) & equalLanes(a, a))).store(got);
  for (int i = 0; i < W; ++i) EXPECT_EQ(std::isnan(got[i]), std::isnan(x[i]) || x[i] < y[i]) << W << " lane " << i;
  alignas(32) int32_t n[W];
  (a * P::set1(-1.5f)).storeTruncated(n);
  for (int i = 0; i < W; ++i) {
    const float v = x[i] * -1.5f;
    EXPECT_EQ(n[i], v > -0x1p31f && v < 0x1p31f ? int32_t(v) : INT32_MIN) << W << " lane " << i;
  }
}

TEST(MotionNode, PacksFollowTheScalarRules) {
  checkPackRules<1>();
  checkPackRules<2>();  // always the portable pack
  checkPackRules<4>();
  checkPackRules<8>();
  alignas(16) const float v[4] = {1.0f, 2.0f, 3.0f, 4.0f};
  EXPECT_EQ(detail::Pack<4>::load3(v).lane(3), 0.0f);
  EXPECT_EQ(detail::Pack<4>::load3(v).lane(2), 3.0f);
  float out[12];
  const auto p = detail::Pack<4>::load(v);
  detail::Pack<4>::storeXyz(p, p + p, p * p, clearLastLane(p), out);
  const float want[12] = {1, 2, 3, 2, 4, 6, 1, 4, 9, 1, 2, 3};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(out[i], want[i]);
}
