// Conservative quantisation of a motion node's lanes (motion_node.h).
//
// Per axis the grid spans every plane of every lane at t = 0 and at t = 1
// (extrapolated planes may cross: all four values count). Lower planes
// round down, upper planes up (in double, with a slack), after moving them
// out by a margin. The margin covers the node test's rounding relative to
// the grid (traverse.h; the rest, relative to the distance, is the far
// distance's 2 gamma(5), robust_slab.h), so the decoded plane lies outside
// the lane's linear bounds at t = 0 and t = 1 by more than the evaluation
// can err, and hence, the decoded planes being linear in t, at every t in
// between.
#include "bvh/nodes/wide_node.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <cmath>
#include <limits>

namespace mbrt::detail {
namespace {

constexpr double kMarginUlps = 16.0;  // in 2^-24 of the grid's magnitude plus spans (bound: ~6 + 8)
constexpr double kLevels = 255.0;
// Levels are computed in double from the planes' exact offsets to the
// origin: their error, some 2^-45 of a step, is far below this slack, so
// floor(x - slack) never rounds a plane inwards.
constexpr double kLevelSlack = 1e-3;

float roundDown(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -kInf) : f;
}
float roundUp(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, kInf) : f;
}

// The grid step covering [origin, top] in kLevels steps.
float stepFor(double origin, double top) {
  float step = roundUp(std::max(0.0, top - origin) / kLevels);
  while (origin + double(step) * kLevels < top) step = std::nextafter(step, kInf);
  return step;
}

}  // namespace

template <int N>
void WideNode<N, true>::encode(const LBounds (&lanes)[N], uint32_t lanesPresent) {
  // Lanes without bounds are empty; a lane that gets bounds stops being
  // empty (its caller says what it holds).
  for (int l = 0; l < N; ++l) {
    if (!(lanesPresent >> l & 1u)) count[l] = kEmptyLane;
    else if (count[l] == kEmptyLane) count[l] = kInnerLane;
  }
  if (lanesPresent == 0) {
    std::memset(origin, 0, sizeof(float) * 12);  // origin, drift, step0, step1
    std::memset(q, 0, sizeof(q));
    return;
  }
  // Absent lanes take the bounds of a present one: they change no span, and
  // the loops below run without branches (their levels are zeroed after).
  const int some = std::countr_zero(lanesPresent);
  for (int a = 0; a < 3; ++a) {
    // planes[k][lane]: lower / upper at t = 0, lower / upper at t = 1 (as q).
    float planes[4][N];
    for (int l = 0; l < N; ++l) {
      const LBounds& b = lanes[lanesPresent >> l & 1u ? l : some];
      planes[0][l] = b.b0.lower[a];
      planes[1][l] = b.b0.upper[a];
      planes[2][l] = b.b1.lower[a];
      planes[3][l] = b.b1.upper[a];
    }
    float lo[2], hi[2];  // span of all planes at t = 0 and 1
    for (int e = 0; e < 2; ++e) {
      lo[e] = kInf;
      hi[e] = -kInf;
      for (int l = 0; l < N; ++l) {
        lo[e] = std::min(lo[e], std::min(planes[2 * e][l], planes[2 * e + 1][l]));
        hi[e] = std::max(hi[e], std::max(planes[2 * e][l], planes[2 * e + 1][l]));
      }
    }
    const double magnitude = std::max(std::max(std::fabs(lo[0]), std::fabs(hi[0])), std::max(std::fabs(lo[1]), std::fabs(hi[1])));
    const double margin = kMarginUlps * 0x1p-24 * (magnitude + (double(hi[0]) - lo[0]) + (double(hi[1]) - lo[1]));
    origin[a] = roundDown(lo[0] - margin);
    drift[a] = roundDown(lo[1] - margin - double(origin[a]));
    const double at[2] = {double(origin[a]), double(origin[a]) + double(drift[a])};  // grid origin at t = 0, 1
    step0[a] = stepFor(at[0], hi[0] + margin);
    step1[a] = stepFor(at[1], hi[1] + margin);
    const double steps[2] = {double(step0[a]), double(step1[a])};
    for (int e = 0; e < 2; ++e) {
      // Level 0 is below every lower plane and level 255 above every upper
      // one (origin and step above), so clamping keeps planes outside. In
      // double, 1 / step is finite even for a denormal step.
      const double inv = steps[e] > 0.0 ? 1.0 / steps[e] : 0.0;
      const double out = margin * inv + kLevelSlack;
      alignas(32) float down[N], up[N];
      for (int l = 0; l < N; ++l) {  // offsets exact in double
        down[l] = float(std::floor((double(planes[2 * e][l]) - at[e]) * inv - out));
        up[l] = float(std::ceil((double(planes[2 * e + 1][l]) - at[e]) * inv + out));
      }
      // Clamped to the levels in lanes, without branches. The levels are
      // whole numbers, exact in float below 2^24 and still on the same side
      // of 0 and 255 above. vmax / vmin keep their second operand on NaN:
      // a NaN lower level becomes 0, a NaN upper level 255.
      using P = Pack<N>;
      const P zero = P::set1(0.0f), top = P::set1(float(kLevels));
      alignas(32) int32_t levels[2][N];
      vmin(vmax(P::load(down), zero), top).storeTruncated(levels[0]);
      vmax(vmin(P::load(up), top), zero).storeTruncated(levels[1]);
      for (int l = 0; l < N; ++l) {
        q[a][2 * e][l] = uint8_t(levels[0][l]);
        q[a][2 * e + 1][l] = uint8_t(levels[1][l]);
      }
    }
    for (int l = 0; l < N; ++l)
      if (!(lanesPresent >> l & 1u)) q[a][0][l] = q[a][1][l] = q[a][2][l] = q[a][3][l] = 0;
  }
}

template struct WideNode<2, true>;
template struct WideNode<4, true>;
template struct WideNode<8, true>;

}  // namespace mbrt::detail
