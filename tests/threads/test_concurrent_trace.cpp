// The concurrent half of the thread-safety contract (accel.h): many threads
// trace one Accel at once (single rays, batches, occlusion, statistics,
// filters that run on the tracing threads), and several accels are built
// over one scene at once, with answers equal to one thread's. Built and run
// under ThreadSanitizer by scripts/test-tsan.sh (mbrt_thread_tests), and in
// the normal build as the CTest threads.concurrent_trace.
//
// TBB is limited to one thread per caller (global_control): TSan cannot see
// the synchronization inside the uninstrumented libtbb, and the contract is
// about the callers' threads; every worker here is a std::thread.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <thread>

#include "test_util.h"

namespace mbrt {
namespace {

constexpr int kThreads = 8;

// Moving meshes (one with a partial time range), segments and a moving
// instance, with a filter on one mesh.
std::shared_ptr<Scene> threadScene(std::atomic<uint64_t>& filterCalls) {
  std::mt19937 rng(17);
  auto child = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*child, rng, 30, 2, 0.2f, 0.1f);
  auto scene = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*scene, rng, 150, 3, 0.2f, 0.2f);
  const uint32_t filtered = test::addRandomMovingTriangles(*scene, rng, 60, 2, 0.2f, 0.2f, {0.25f, 0.75f});
  scene->setFilter(filtered, [&filterCalls](const FilterArgs& a) {
    filterCalls.fetch_add(1, std::memory_order_relaxed);
    return a.candidate.primID % 2 == 0;
  });
  std::vector<Segment> segments;
  std::vector<std::vector<Vec3f>> steps(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (uint32_t i = 0; i < 40; ++i) {
    const Vec3f a{u(rng), u(rng), u(rng)};
    for (auto& s : steps) s.insert(s.end(), {a, a + Vec3f{0.1f, 0.2f, 0.0f}});
    segments.push_back({2 * i, 2 * i + 1});
  }
  scene->addSegments(std::move(segments), std::move(steps), std::vector<float>(80, 0.03f));
  scene->addInstance(child, {Affine3f::translate({0.3f, 0, 0}), Affine3f::translate({0.5f, 0.1f, 0})});
  return scene;
}

std::vector<Ray> threadRays(size_t count) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float special[] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  std::vector<Ray> rays;
  for (size_t i = 0; i < count; ++i) rays.push_back(test::randomRay(rng, i % 4 == 0 ? special[i % 5] : u(rng)));
  return rays;
}

bool sameHit(const Hit& a, const Hit& b) {
  return a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID && a.t == b.t;
}

// Every thread traces every ray (single calls, then one batch) and checks
// them against `expected`; returns the number of wrong answers.
size_t traceFromThreads(const Accel& accel, const std::vector<Ray>& rays, const std::vector<Hit>& expected,
                        const std::vector<uint8_t>& expectedAny) {
  std::atomic<size_t> wrong{0};
  std::atomic<int> ready{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < kThreads; ++k)
    threads.emplace_back([&, k] {
      ready.fetch_add(1);
      while (ready.load() < kThreads) std::this_thread::yield();  // start together
      for (size_t j = 0; j < rays.size(); ++j) {
        const size_t i = (j + size_t(k) * 97) % rays.size();  // different orders
        Hit hit;
        accel.intersect(rays[i], hit);
        wrong += sameHit(hit, expected[i]) ? 0 : 1;
        wrong += uint8_t(accel.occluded(rays[i])) == expectedAny[i] ? 0 : 1;
      }
      std::vector<Hit> hits(rays.size());
      accel.intersect(rays, hits);
      for (size_t i = 0; i < rays.size(); ++i) wrong += sameHit(hits[i], expected[i]) ? 0 : 1;
      wrong += accel.stats().primitives > 0 ? 0 : 1;
    });
  for (auto& t : threads) t.join();
  return wrong.load();
}

TEST(ConcurrentTrace, ManyThreadsTraceOneAccelOfEveryKind) {
  tbb::global_control oneThreadPerCaller(tbb::global_control::max_allowed_parallelism, 1);
  std::atomic<uint64_t> filterCalls{0};
  auto scene = threadScene(filterCalls);
  const auto rays = threadRays(test::scaled(4000, 300));
  for (AccelKind kind : availableAccelKinds()) {
    if (kind == AccelKind::Embree) continue;  // not instrumented; its own threads
    SCOPED_TRACE(std::string(toString(kind)));
    auto accel = test::buildKind(*scene, kind);
    std::vector<Hit> expected(rays.size());
    std::vector<uint8_t> expectedAny(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      accel->intersect(rays[i], expected[i]);
      expectedAny[i] = accel->occluded(rays[i]);
    }
    const uint64_t callsBefore = filterCalls.load();
    EXPECT_EQ(traceFromThreads(*accel, rays, expected, expectedAny), 0u);
    EXPECT_GT(filterCalls.load(), callsBefore);  // the filter ran on the tracing threads
  }
}

TEST(ConcurrentTrace, BuildsOverOneSceneRunAtOnce) {
  tbb::global_control oneThreadPerCaller(tbb::global_control::max_allowed_parallelism, 1);
  std::atomic<uint64_t> filterCalls{0};
  auto scene = threadScene(filterCalls);
  const auto rays = threadRays(test::scaled(1000, 200));
  const AccelKind kinds[] = {AccelKind::BvhInterp, AccelKind::Stbvh, AccelKind::Msbvh, AccelKind::Mbkd,
                             AccelKind::FuzzyKd, AccelKind::BvhSegments};
  std::vector<std::unique_ptr<Accel>> accels(std::size(kinds));
  std::vector<std::thread> threads;
  for (size_t k = 0; k < std::size(kinds); ++k)
    threads.emplace_back([&, k] { accels[k] = test::buildKind(*scene, kinds[k]); });
  for (auto& t : threads) t.join();
  auto brute = test::buildKind(*scene, AccelKind::Brute);
  for (size_t k = 0; k < accels.size(); ++k) {
    size_t wrong = 0;
    for (const Ray& r : rays) {
      Hit a, b;
      brute->intersect(r, a);
      accels[k]->intersect(r, b);
      // The same primitive, or a tie at the same distance (tests/oracle.h).
      wrong += a.valid() == b.valid() && (sameHit(a, b) || std::fabs(a.t - b.t) <= 1e-4f * std::max(1.0f, a.t)) ? 0 : 1;
    }
    EXPECT_EQ(wrong, 0u) << toString(kinds[k]);
  }
}

}  // namespace
}  // namespace mbrt
