// Builds that run beside other parallel work are never cut short: a build
// that runs out of budget fails with an Error while sibling builds run
// (bvh-segments builds one tree per time segment at once), and a build in a
// caller's parallel work whose sibling task throws still completes whole
// (TBB cancels nested algorithms silently; core/isolated_work.h).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "mbrt/accel.h"
#include "mbrt/scenes.h"
#include "oracle.h"
#include "test_util.h"

namespace mbrt {
namespace {

TEST(BuildCancellation, SegmentTreesOutOfBudgetFailWithAnError) {
  const ProceduralScene ps = makeProceduralScene("deform", 0.02, 1);
  BuildOptions o;
  o.kind = AccelKind::BvhSegments;
  const size_t peak = Accel::build(*ps.scene, o)->stats().peakBuildBytes;
  tbb::task_arena arena(2);
  for (int tenth = 1; tenth <= 12; ++tenth) {
    o.memoryBudget = peak * size_t(tenth) / 10;
    arena.execute([&] {
      try {
        auto accel = Accel::build(*ps.scene, o);
        EXPECT_LE(accel->stats().bytes, o.memoryBudget);
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("memory budget"), std::string::npos) << e.what();
      }
    });
  }
}

TEST(BuildCancellation, BuildBesideAThrowingTaskCompletes) {
  const ProceduralScene ps = makeProceduralScene("translate", 0.1, 3);
  const auto brute = test::buildKind(*ps.scene, AccelKind::Brute);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 400), test::scaled(50, 10), 7);
  const test::OracleAnswers expected = test::oracleAnswers(*brute, rays);
  for (AccelKind kind : {AccelKind::Stbvh, AccelKind::BvhSegments, AccelKind::Msbvh}) {
    std::atomic<bool> building{false};
    std::unique_ptr<Accel> built;
    tbb::task_arena arena(2);
    arena.execute([&] {
      tbb::task_group group;
      group.run([&] {
        BuildOptions o;
        o.kind = kind;
        building = true;
        built = Accel::build(*ps.scene, o);
      });
      group.run([&] {
        // Throws once the build has started (or after a second alone).
        const auto start = std::chrono::steady_clock::now();
        while (!building && std::chrono::steady_clock::now() - start < std::chrono::seconds(1))
          std::this_thread::yield();
        throw std::runtime_error("a sibling task fails");
      });
      EXPECT_THROW(group.wait(), std::runtime_error);
    });
    if (!built) continue;  // the build never started: nothing to check
    const test::OracleReport rep = test::compareWithOracleHits(expected, *built, rays);
    EXPECT_EQ(rep.wrong + rep.anyWrong, 0u) << toString(kind) << ": " << rep.firstFailure;
  }
}

}  // namespace
}  // namespace mbrt
