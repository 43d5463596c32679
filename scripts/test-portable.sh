#!/usr/bin/env bash
# Builds the GoogleTest suite with the portable scalar packs
# (-DMBRT_SIMD=scalar: no instruction-set flags, core/isa.h picks level 0)
# in build-scalar and runs it, so that the fallback a non-x86 machine gets
# keeps compiling and passing. Without Embree (the peer has nothing to do
# with mbrt's packs) and without the long Agreement.* run, which the default
# build covers. Heavy tests run at MBRT_TEST_SCALE (default here 0.25).
# Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs="${MBRT_JOBS:-$(nproc)}"
build_dir="${MBRT_SCALAR_BUILD_DIR:-build-scalar}"
start=$SECONDS

# -O1: compiles in about half the time of -O3; the tests check results, not speed.
# Unity build (CMakeLists.txt): 142 s of CPU instead of 296 s for a clean tree.
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DMBRT_SIMD=scalar -DMBRT_BUILD_TOOLS=OFF -DMBRT_WITH_EMBREE=OFF -DCMAKE_UNITY_BUILD=ON
cmake --build "$build_dir" -j"$jobs" --target mbrt_tests

export MBRT_TEST_SCALE="${MBRT_TEST_SCALE:-0.25}"
"$build_dir/mbrt_tests" --gtest_filter='-Agreement.*' --gtest_brief=1

echo "test-portable.sh: scalar packs, all tests passed in $((SECONDS - start)) s"
