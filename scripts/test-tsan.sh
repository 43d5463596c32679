#!/usr/bin/env bash
# ThreadSanitizer run of the concurrent half of the thread-safety contract
# (include/mbrt/accel.h): builds the kernel library (mbrt_accel) and the one
# small test target mbrt_thread_tests (tests/threads/) with
# -DMBRT_SANITIZE=thread in build-tsan -- nothing else, to stay cheap -- and
# runs both its tests: 8 threads tracing one accel of every kind at once
# (single rays, batches, occlusion, stats, a filter on the tracing threads),
# and six accels built over one scene by six threads at once; and, when the
# Embree API is built (embree_api/, Embree 3's headers found), its thread
# test: eight threads tracing one committed scene through libembree3.so.3
# (rtcIntersect1M, rtcIntersect8, rtcOccluded1, a filter function). TBB's own
# allocator is replaced there by one on malloc that TSan sees
# (tests/threads/tbbmalloc_for_tsan.cpp). Any report fails the run.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs="${MBRT_JOBS:-$(nproc)}"
build_dir="${MBRT_TSAN_BUILD_DIR:-build-tsan}"
start=$SECONDS

# -O1: sanitizer builds compile faster and the checks matter more than speed.
# No Embree, tools or Python: the target links mbrt_accel alone.
# Unity build (CMakeLists.txt): 86 s of CPU instead of 119 s for a clean tree.
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DMBRT_SANITIZE=thread -DMBRT_WITH_EMBREE=OFF -DMBRT_BUILD_TOOLS=OFF -DMBRT_PYTHON=OFF -DCMAKE_UNITY_BUILD=ON > /dev/null
targets=(mbrt_thread_tests)
embree_api=0
if grep -q '^MBRT_EMBREE_API:BOOL=ON' "$build_dir/CMakeCache.txt"; then
  targets+=(mbrt_embree_api_thread_tests)
  embree_api=1
fi
cmake --build "$build_dir" -j"$jobs" --target "${targets[@]}"
built=$SECONDS

export TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1 abort_on_error=1 second_deadlock_stack=1}"
"$build_dir/mbrt_thread_tests" --gtest_brief=1
if [ "$embree_api" = 1 ]; then
  "$build_dir/embree_api/mbrt_embree_api_thread_tests" --gtest_brief=1
else
  echo "test-tsan.sh: the Embree API is not built here (no Embree 3 headers): its thread test skipped"
fi
echo "test-tsan.sh: no ThreadSanitizer report; build $((built - start)) s, run $((SECONDS - built)) s"
