#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan + coverage) in build-fuzz,
# writes the seed corpus and runs every target for a fixed number of
# executions. Prints one summary line per target (executions, crashes) and
# exits non-zero when any target crashed; crash inputs are kept in
# build-fuzz/artifacts/TARGET/ (turn each into a regression test).
#
#   bash scripts/fuzz.sh                  # 10000 executions per target
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh
#   FUZZ_TARGETS="fuzz_ply fuzz_obj" FUZZ_RUNS=200000 bash scripts/fuzz.sh
#   FUZZ_JOBS=2 ...                       # build parallelism (default 2)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

runs="${FUZZ_RUNS:-10000}"
jobs="${FUZZ_JOBS:-2}"
build_dir="${MBRT_FUZZ_BUILD_DIR:-build-fuzz}"
targets=(${FUZZ_TARGETS:-fuzz_obj fuzz_obj_sequence fuzz_ply fuzz_gltf fuzz_scene_file fuzz_ray_file})
cxx="${FUZZ_CXX:-$(command -v clang++-14 || command -v clang++)}"

cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_CXX_FLAGS="-gline-tables-only" -DMBRT_FUZZ=ON -DMBRT_BUILD_TESTS=OFF -DMBRT_BUILD_TOOLS=OFF \
  -DMBRT_WITH_EMBREE=OFF >/dev/null
cmake --build "$build_dir" -j"$jobs" --target "${targets[@]}" fuzz_make_seeds

seeds="$build_dir/seeds"
rm -rf "$seeds"
"$build_dir/fuzz/fuzz_make_seeds" "$seeds"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
failed=0
summary=()
for t in "${targets[@]}"; do
  name="${t#fuzz_}"
  corpus="$build_dir/corpus/$name"
  artifacts="$build_dir/artifacts/$name"
  rm -rf "$artifacts"
  mkdir -p "$corpus" "$artifacts"
  log="$build_dir/$t.log"
  start=$(date +%s)
  set +e
  "$build_dir/fuzz/$t" -runs="$runs" -max_len=8192 -timeout=20 -rss_limit_mb=2560 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" "$corpus" "$seeds/$name" >"$log" 2>&1
  rc=$?
  set -e
  secs=$(( $(date +%s) - start ))
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
  crashes=$(find "$artifacts" -type f | wc -l)
  summary+=("$(printf '%-20s executions %10s  crashes %s  (%ss, exit %s)' "$t" "${execs:-?}" "$crashes" "$secs" "$rc")")
  if [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    failed=1
    echo "fuzz.sh: $t failed, see $log and $artifacts/" >&2
    tail -40 "$log" >&2
  fi
done
printf '%s\n' "${summary[@]}"
[ "$failed" -eq 0 ] && echo "fuzz.sh: no crashes"
exit "$failed"
