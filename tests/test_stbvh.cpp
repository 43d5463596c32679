// stbvh: the MBSAH on the STBVH paper's Fig. 3 1-D examples, time ranges of
// spatial-temporal lanes, exact time boundaries and a deterministic parallel
// build of a scene with many temporal splits. (Oracle agreement and
// conservativeness: test_oracle.cpp, test_bvh.cpp.)
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <random>

#include "bvh/heuristics/binned_sah.h"
#include "bvh/kinds/bvh_structure.h"
#include "bvh/kinds/stbvh_tuning.h"
#include "bvh/inspect.h"
#include "bvh/heuristics/temporal_split.h"
#include "accel/structure_factory.h"
#include "scene/scene_context.h"
#include "scene/primitive_bounds.h"
#include "mbrt/accel.h"
#include "mbrt/scenes.h"

using namespace mbrt;

namespace {

// A "1-D line" [a, b] on x: a triangle in z = 0 with y extent 1, so the
// half-area of its box is exactly its length b - a (as in Fig. 3).
// `path` gives the line's lower end at each step; the length stays `len`.
void addLine(Scene& scene, const std::vector<float>& path, float len) {
  std::vector<std::vector<Vec3f>> pos;
  for (float a : path) pos.push_back({{a, 0, 0}, {a + len, 0, 0}, {a, 1, 0}});
  scene.addTriangleMesh({{0, 1, 2}}, std::move(pos));
}

// The same TemporalSource the stbvh kind uses, over a test context.
struct Timing final : detail::TemporalSource {
  const detail::SceneContext& ctx;
  explicit Timing(const detail::SceneContext& c) : ctx(c) {}
  TimeRange stepRange(detail::PrimRef p, uint32_t& segments) const override {
    segments = ctx.geometry(p.geomID).numSteps() - 1;
    return ctx.geometry(p.geomID).timeRange();
  }
  bool remake(const detail::BuildRef& ref, TimeRange r, detail::BuildRef& out) const override {
    out = ref;
    out.bounds = detail::linearBounds(ctx, ref.prim, r);
    out.active = detail::activeSegments(ctx, ref.prim, r);
    return true;
  }
};

struct Costs {
  float leaf, object, temporal;
  bool temporalTried;
};

// Leaf, best object split and temporal split costs at the root (unnormalised).
Costs rootCosts(const Scene& scene) {
  BuildOptions o;
  detail::BuildBudget budget;
  detail::SceneContext ctx(scene, o, budget);
  std::vector<detail::BuildRef> refs;
  for (const detail::PrimRef& p : ctx.primitives()) {
    detail::BuildRef r;
    r.prim = p;
    r.bounds = detail::linearBounds(ctx, p, {0.0f, 1.0f});
    r.active = detail::activeSegments(ctx, p, {0.0f, 1.0f});
    refs.push_back(r);
  }
  const detail::RefSetInfo info = detail::summarize(refs);
  const detail::ObjectSplit object = detail::findObjectSplit(refs, info, detail::adaptiveObjectBins(32, refs.size()));
  Costs c;
  c.leaf = detail::mbsahArea(info.bounds) * float(info.active);
  c.object = object.cost;
  const Timing timing(ctx);
  float time = 0.0f;
  c.temporalTried = detail::temporalSplitTime(refs, {0.0f, 1.0f}, timing, time);
  EXPECT_TRUE(c.temporalTried);
  EXPECT_EQ(time, 0.5f);  // centre, snapped to the step of the line with most segments
  c.temporal = detail::evaluateTemporalSplit(refs, {0.0f, 1.0f}, time, timing).cost;
  return c;
}

// Time ranges of the lanes of an stbvh over `scene` with geometry `geomID` below.
std::vector<TimeRange> laneRanges(const Scene& scene, uint32_t geomID) {
  BuildOptions o;
  o.kind = AccelKind::Stbvh;
  detail::BuildBudget budget;
  detail::SceneContext ctx(scene, o, budget);
  auto s = detail::makeStructure(ctx);
  std::vector<TimeRange> all;
  detail::inspect(*s).forEachLane([&](const detail::LaneView& v) {
    for (const detail::PrimRef& p : v.below)
      if (p.geomID == geomID) {
        all.push_back(v.range);
        break;
      }
  });
  return all;
}

}  // namespace

// Fig. 3, first example: two separated objects with different step counts,
// moving down. The object split is tight, the temporal split loose: object.
TEST(Mbsah, SeparatedObjectsTakeTheObjectSplit) {
  Scene scene;
  addLine(scene, {10.0f, 8.0f}, 1.0f);          // 1 segment
  addLine(scene, {0.0f, -1.0f, -2.0f}, 1.0f);   // 2 segments
  const Costs c = rootCosts(scene);
  // Leaf: union [-1, 10] at t = 0.5 x 3 segments. Object: 1 x 1 + 1 x 2.
  EXPECT_NEAR(c.leaf, 11.0f * 3.0f, 1e-3f);
  EXPECT_NEAR(c.object, 3.0f, 1e-3f);
  // Temporal at 0.5: the merged linear bounds of each half are 11 long at
  // its centre (b0 and b1 merge separately), 2 segments, half the time each.
  EXPECT_NEAR(c.temporal, 11.0f + 11.0f, 1e-3f);
  EXPECT_LT(c.object, detail::kTemporalTry * c.leaf);         // temporal not even tried (θ)
  EXPECT_LT(c.object, detail::kTemporalPenalty * c.temporal);  // and would lose (λ)
  // The single-segment line was never split in time (only a root temporal split could).
  const std::vector<TimeRange> ranges = laneRanges(scene, 0);
  EXPECT_FALSE(ranges.empty());
  for (const TimeRange& r : ranges) EXPECT_EQ(r, (TimeRange{0.0f, 1.0f}));
}

// Fig. 3, second example: curved motion (up, then back down). Linear bounds
// over the whole shutter are loose for every object split; the temporal
// split at the turning point is tight: temporal.
TEST(Mbsah, CurvedMotionTakesTheTemporalSplit) {
  Scene scene;
  addLine(scene, {0.0f, 10.0f, 0.0f}, 1.0f);
  addLine(scene, {1.5f, 11.5f, 1.5f}, 1.0f);
  const Costs c = rootCosts(scene);
  // Whole shutter: each line bounded by [a, a + 11]; the union [0, 12.5].
  EXPECT_NEAR(c.leaf, 12.5f * 4.0f, 1e-3f);
  EXPECT_NEAR(c.object, 11.0f * 2.0f * 2.0f, 1e-3f);
  // Halves: at t = 0.25 and 0.75 the lines span [2.5, 5]: 2.5 x 2 segments x 1/2, twice.
  EXPECT_NEAR(c.temporal, 5.0f, 1e-3f);
  EXPECT_GE(c.object, detail::kTemporalTry * c.leaf);
  EXPECT_LT(detail::kTemporalPenalty * c.temporal, c.object);
  // In the tree (two more lines on the same paths, so that a leaf of pairs
  // is not enough either): the root splits time at the turning point.
  addLine(scene, {0.2f, 10.2f, 0.2f}, 1.0f);
  addLine(scene, {1.3f, 11.3f, 1.3f}, 1.0f);
  const std::vector<TimeRange> ranges = laneRanges(scene, 0);
  bool left = false, right = false;
  for (const TimeRange& r : ranges) {
    left |= r.lo == 0.0f && r.hi == 0.5f;
    right |= r.lo == 0.5f && r.hi == 1.0f;
  }
  EXPECT_TRUE(left && right);
}

// The split time snaps to the steps of the reference with the most active
// segments (STBVH §3.3), ties to the least geometry: here geometry 0 has 4
// segments (the centre is its step 0.5) and geometry 1 has 3 (its step
// nearest the centre is 2/3), their references in runs in either order.
TEST(Stbvh, SplitTimeFollowsTheMostActiveReference) {
  struct Steps final : detail::TemporalSource {
    TimeRange stepRange(detail::PrimRef p, uint32_t& segments) const override {
      segments = p.geomID == 0 ? 4 : 3;
      return {0.0f, 1.0f};
    }
    bool remake(const detail::BuildRef&, TimeRange, detail::BuildRef&) const override { return false; }
  };
  const Steps steps;
  auto ref = [](uint32_t geom, uint32_t prim, uint32_t active) {
    detail::BuildRef r;
    r.prim = {geom, prim};
    r.active = active;
    return r;
  };
  auto splitTime = [&](const std::vector<detail::BuildRef>& refs) {
    float time = -1.0f;
    EXPECT_TRUE(detail::temporalSplitTime(refs, {0.0f, 1.0f}, steps, time));
    return time;
  };
  const float step0 = 0.5f, step1 = 2.0f / 3.0f;
  // The most active reference decides, wherever it sits in its run.
  EXPECT_EQ(splitTime({ref(0, 0, 2), ref(0, 1, 2), ref(1, 0, 1), ref(1, 1, 3), ref(1, 2, 1)}), step1);
  EXPECT_EQ(splitTime({ref(1, 0, 1), ref(1, 1, 1), ref(0, 0, 1), ref(0, 1, 2)}), step0);
  // Ties go to the least geometry, whichever run comes first.
  EXPECT_EQ(splitTime({ref(1, 0, 2), ref(0, 5, 2), ref(0, 6, 1)}), step0);
  EXPECT_EQ(splitTime({ref(0, 9, 2), ref(1, 0, 2)}), step0);
  // A geometry in two runs: its later run counts too.
  EXPECT_EQ(splitTime({ref(0, 0, 1), ref(1, 0, 2), ref(0, 1, 3)}), step0);
  EXPECT_EQ(splitTime({ref(1, 0, 1), ref(0, 0, 2), ref(1, 1, 3)}), step1);
  // A range no longer than the shortest segment (1/4) takes no split.
  float time = -1.0f;
  EXPECT_FALSE(detail::temporalSplitTime(std::vector<detail::BuildRef>{ref(0, 0, 1), ref(1, 0, 1)},
                                         {0.25f, 0.5f}, steps, time));
}

// A ray exactly on an inner split time sees only the right-hand lanes; a ray
// at time 1 still sees the last lanes; hits match brute force there.
TEST(Stbvh, TimeBoundariesAreExact) {
  Scene scene;
  // Lines that jump far away between two steps: more than a leaf holds,
  // overlapping (object splits cannot separate them), so time gets split.
  for (int i = 0; i < 12; ++i) {
    std::vector<float> path;
    for (int k = 0; k <= 8; ++k) path.push_back((k < 5) == (i % 2 == 0) ? 0.1f * float(i) : 20.0f + 0.1f * float(i));
    addLine(scene, path, 1.0f);
  }
  BuildOptions o, bo;
  o.kind = AccelKind::Stbvh;
  bo.kind = AccelKind::Brute;
  auto st = Accel::build(scene, o);
  auto brute = Accel::build(scene, bo);
  EXPECT_GT(st->stats().references, 12u);  // temporal splits made copies
  int hits = 0;
  for (int k = 0; k <= 64; ++k)
    for (float x : {0.5f, 20.5f, 10.0f})
      for (float y : {0.01f, 0.3f}) {
        const float t = float(k) / 64.0f;
        Ray ray{{x, y, -1.0f}, 0.0f, {0, 0, 1}, kInf, t};
        Hit h, hb;
        const bool f = st->intersect(ray, h), fb = brute->intersect(ray, hb);
        ASSERT_EQ(f, fb) << "time " << t << " x " << x;
        ASSERT_EQ(st->occluded(ray), fb) << "time " << t;
        if (f) {
          ++hits;
          EXPECT_EQ(h.t, hb.t);  // coplanar lines: ids may tie
        }
      }
  EXPECT_GT(hits, 20);
}

// Many temporal splits (two turns of a rotating mesh): the build gives the
// same bytes and SAH with 1 and 2 threads, and node time ranges nest.
TEST(Stbvh, DeterministicWithTemporalSplits) {
  const ProceduralScene ps = makeProceduralScene("rotate", 0.05, 3);
  for (int width : {4, 8}) {
    BuildOptions o;
    o.kind = AccelKind::Stbvh;
    o.branching = width;
    std::vector<uint8_t> bytes[2];
    double sah[2];
    size_t timed[2];
    for (int t = 0; t < 2; ++t) {
      tbb::task_arena arena(t + 1);
      arena.execute([&] {
        detail::BuildBudget budget;
        detail::SceneContext ctx(*ps.scene, o, budget);
        auto s = detail::makeStructure(ctx);
        const detail::Inspect& inspect = detail::inspect(*s);
        bytes[t] = inspect.bytes();
        AccelStats st;
        s->fillStats(st);
        sah[t] = st.sahCost;
        timed[t] = 0;
        inspect.forEachLane([&](const detail::LaneView& v) {
          timed[t] += !(v.range == TimeRange{0.0f, 1.0f});
          EXPECT_LT(v.range.lo, v.range.hi);
        });
      });
    }
    EXPECT_EQ(bytes[0], bytes[1]) << "N=" << width;
    EXPECT_EQ(sah[0], sah[1]) << "N=" << width;
    EXPECT_GT(timed[0], 0u) << "rotation should make temporal splits";
  }
}

// Temporal splits buy a lower SAH than bvh-interp on curved motion.
TEST(Stbvh, BeatsInterpOnRotation) {
  const ProceduralScene ps = makeProceduralScene("rotate", 0.05, 3);
  BuildOptions o;
  o.kind = AccelKind::BvhInterp;
  const double interp = Accel::build(*ps.scene, o)->stats().sahCost;
  o.kind = AccelKind::Stbvh;
  const AccelStats st = Accel::build(*ps.scene, o)->stats();
  EXPECT_LT(st.sahCost, 0.5 * interp);
  EXPECT_GT(st.peakBuildBytes, st.bytes);
}

// Node filling (builder.h): below the SAH's leaf decisions the spare lanes
// of a wide node get the split leaves, so 8-wide nodes are nearly full where
// they were half empty (hairball: 4.4 lanes per inner node for stbvh, 3.6
// for bvh-interp before filling). With leaf blocks of four (the motion
// kinds' default on triangles, leaves/leaf_width.h) leaves of four or fewer are
// not split, so a node keeps spare lanes only when all its lanes are such
// leaves. `stbvh` is checked on `hair` (segments: per-reference leaves).
TEST(Stbvh, WideNodesAreFilled) {
  const ProceduralScene hair = makeProceduralScene("hair", 0.05, 1);
  BuildOptions o;
  o.kind = AccelKind::Stbvh;
  o.branching = 8;
  const AccelStats st = Accel::build(*hair.scene, o)->stats();
  ASSERT_GT(st.innerNodes, 1u);
  const double stbvhLanes = double(st.innerNodes - 1 + st.leafNodes) / double(st.innerNodes);
  EXPECT_GT(stbvhLanes, 5.0);  // 5.4 lanes per inner node
  EXPECT_LE(stbvhLanes, 8.0);
  const ProceduralScene ps = makeProceduralScene("hairball", 0.05, 1);
  o.kind = AccelKind::BvhInterp;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(*ps.scene, o, budget);
  const std::vector<detail::PrimRef> prims = ctx.primitives();
  for (int leafBlock : {1, 4}) {
    detail::WideBvh<8, true> bvh;
    detail::buildWideBvh(ctx, prims, detail::ShutterRefs(ctx), bvh, {.leafBlock = leafBlock});
    size_t inner = 0, lanes = 0, spareWithSplittable = 0;
    for (const auto& node : bvh.nodes) {
      int used = 0;
      bool splittable = false;
      for (int i = 0; i < 8; ++i) {
        if (node.isEmpty(i)) continue;
        ++used;
        const bool leaf = node.isLeaf(i);
        const size_t refs = !leaf ? 0 : node.count[i] == detail::kInlineLeaf ? 1 : node.count[i];
        splittable = splittable || !leaf || refs > size_t(leafBlock);
      }
      ++inner;
      lanes += size_t(used);
      spareWithSplittable += used < 8 && splittable;
    }
    ASSERT_GT(inner, 1u);
    if (leafBlock == 1) EXPECT_GT(double(lanes) / double(inner), 5.0);  // lanes per node
    EXPECT_EQ(spareWithSplittable, 0u) << "leaf block " << leafBlock;
  }
}

// A temporal split tried and rejected is handed to the object-split
// children, which take their part instead of recomputing the halves
// (split_choice.h): the trees must be byte for byte those of recomputing
// every trial, on scenes where many trials are rejected.
TEST(Stbvh, ReusedTemporalSplitsGiveTheSameTrees) {
  for (const char* name : {"translate", "crowd", "deform"}) {
    const ProceduralScene ps = makeProceduralScene(name, 0.05, 2);
    BuildOptions o;
    o.kind = AccelKind::Stbvh;
    detail::BuildBudget budget;
    detail::SceneContext ctx(*ps.scene, o, budget);
    const std::vector<detail::PrimRef> prims = ctx.primitives();
    const detail::SceneTemporalSource timing(ctx);
    std::vector<uint8_t> bytes[2];
    for (int reuse = 0; reuse < 2; ++reuse) {
      detail::WideBvh<8, true> bvh;
      detail::WideBuildTuning tuning = detail::stbvhTuning(timing, 1);
      tuning.reuseTriedTemporalSplits = reuse == 1;
      detail::buildWideBvh(ctx, prims, detail::ShutterRefs(ctx), bvh, tuning);
      ASSERT_GT(bvh.times.size(), 0u) << name << ": no temporal split to check";
      detail::appendBytes(bvh, bytes[reuse]);
    }
    EXPECT_EQ(bytes[0], bytes[1]) << name;
  }
}

// λ against leaves (BuildSettings::temporalLeafPenalty): a primitive moving
// in a straight line over 5 segments stays one reference, since its linear
// bounds are exact and a temporal split would only halve its segment count;
// the same primitive moving out and back is split in time. (With λ_leaf = 1
// the straight one is split too: leaf 5A against C_T A + 2.6A.)
TEST(Stbvh, StraightMotionKeepsLeavesWhole) {
  for (bool curved : {false, true}) {
    Scene scene;
    std::vector<float> path;
    for (int k = 0; k < 6; ++k) path.push_back(curved ? 4.0f * std::sin(float(k) / 5.0f * 3.14159265f) : float(k));
    addLine(scene, path, 0.5f);
    BuildOptions o;
    o.kind = AccelKind::Stbvh;
    const AccelStats st = Accel::build(scene, o)->stats();
    if (curved) EXPECT_GT(st.references, 1u);
    else EXPECT_EQ(st.references, 1u);
  }
}

// The parallel partition of a large node (32768 references and more) makes
// exactly the moves of the serial Hoare partition (the k-th reference going
// right from the front swapped with the k-th going left from the back), so
// trees do not change with the node size at which it takes over; the
// references moved along (a rejected temporal split's) follow.
TEST(BinnedSah, ParallelPartitionMakesTheSerialMoves) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<detail::BuildRef> refs(50000);
  for (size_t i = 0; i < refs.size(); ++i) {
    const Vec3f c{u(rng), u(rng), u(rng)};
    refs[i].bounds = LBounds(Box3f(c - Vec3f(0.01f), c + Vec3f(0.01f)), Box3f(c, c + Vec3f(0.02f)));
    refs[i].prim = {0, uint32_t(i)};
  }
  const detail::RefSetInfo info = detail::summarize(refs);
  const detail::ObjectSplit split = detail::findObjectSplit(refs, info, 32);
  ASSERT_TRUE(split.valid());
  // The serial Hoare partition, by hand.
  std::vector<detail::BuildRef> expected = refs;
  auto goesLeft = [&](const detail::BuildRef& r) { return split.binAt(r.centroid()[split.axis]) < split.bin; };
  size_t i = 0, j = expected.size();
  while (true) {
    while (i < j && goesLeft(expected[i])) ++i;
    while (i < j && !goesLeft(expected[j - 1])) --j;
    if (i == j) break;
    std::swap(expected[i++], expected[--j]);
  }
  std::vector<detail::BuildRef> along = refs;
  detail::RefSetInfo sides[2];
  const size_t mid = detail::partitionObject(refs, split, sides, along);
  EXPECT_EQ(mid, i);
  size_t moved = 0;
  for (size_t k = 0; k < refs.size(); ++k) {
    EXPECT_EQ(refs[k].prim.primID, expected[k].prim.primID) << k;
    EXPECT_EQ(along[k].prim.primID, expected[k].prim.primID) << k;
    moved += refs[k].prim.primID != k;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_GT(moved, refs.size() / 4);
  const detail::RefSetInfo left = detail::summarize(std::span<const detail::BuildRef>(refs).first(mid));
  EXPECT_EQ(sides[0].active, left.active);
  EXPECT_EQ(sides[0].bounds.b0.lower.x, left.bounds.b0.lower.x);
  EXPECT_EQ(sides[1].active, refs.size() - mid);
}
