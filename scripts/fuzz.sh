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
#   FUZZ_PARALLEL=6 ...                   # targets run at once (default 1)
#   FUZZ_SECONDS=3600 ...                 # stop each target after this long
#                                         # (libFuzzer -max_total_time; the
#                                         # summary shows the executions reached)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

runs="${FUZZ_RUNS:-10000}"
jobs="${FUZZ_JOBS:-2}"
parallel="${FUZZ_PARALLEL:-1}"
seconds="${FUZZ_SECONDS:-0}"
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
# Runs one target; writes its summary line to $build_dir/TARGET.summary.
fuzz_one() {
  local t="$1" name="${1#fuzz_}"
  local corpus="$build_dir/corpus/$name" artifacts="$build_dir/artifacts/$name" log="$build_dir/$1.log"
  rm -rf "$artifacts"
  mkdir -p "$corpus" "$artifacts"
  local start rc execs crashes
  start=$(date +%s)
  set +e
  "$build_dir/fuzz/$t" -runs="$runs" -max_total_time="$seconds" -max_len=8192 -timeout=20 -rss_limit_mb=2560 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" "$seeds/$name" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
  crashes=$(find "$artifacts" -type f | wc -l)
  printf '%-20s executions %10s  crashes %s  (%ss, exit %s)\n' "$t" "${execs:-?}" "$crashes" \
    "$(( $(date +%s) - start ))" "$rc" >"$build_dir/$t.summary"
  if [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    echo "fuzz.sh: $t failed, see $log and $artifacts/" >&2
    tail -40 "$log" >&2
  fi
}

for t in "${targets[@]}"; do
  rm -f "$build_dir/$t.summary"
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait
failed=0
for t in "${targets[@]}"; do
  if [ -f "$build_dir/$t.summary" ]; then cat "$build_dir/$t.summary"; else echo "$t: no summary (interrupted?)"; fi
  grep -qs 'crashes 0  .*exit 0)' "$build_dir/$t.summary" || failed=1
done
[ "$failed" -eq 0 ] && echo "fuzz.sh: no crashes"
exit "$failed"
