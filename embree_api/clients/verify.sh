#!/usr/bin/env bash
# The tests of Embree's own embree_verify (Debian's embree-tools) that
# cover what mbrt's Embree API implements -- triangles, quads, instances
# with motion, filters, masks, buffers, bounds, interpolation, packets and
# streams -- run on mbrt's libembree3.so.3 (LD_LIBRARY_PATH=<build>/embree_api),
# one ISA's set (AVX2 where the CPU has it, else SSE4.2). Every test matched
# must pass. docs/embree-api.md lists which of embree_verify's tests this
# set leaves out and why (most also draw user geometry, curves, grids or
# subdivision surfaces). A pattern ending in "#first" counts only the first
# half of what it matches: embree_verify's instancing group holds the same
# names twice, quad spheres first, then subdivision spheres (verify.cpp
# registers them in that order). Exits 77 (skipped) without embree-tools.
#
#   bash embree_api/clients/verify.sh BUILD_DIR [--watertight]
#
# --watertight adds the watertightness tests (minutes).
set -euo pipefail
build="$(cd "${1:?usage: verify.sh BUILD_DIR [--watertight]}" && pwd)"
shim="$build/embree_api"
if ! command -v embree_verify > /dev/null; then
  echo "verify.sh: embree_verify is not installed (Debian: apt-get install embree-tools): skipped"
  exit 77
fi
[ -e "$shim/libembree3.so.3" ] || { echo "verify.sh: $shim/libembree3.so.3 is missing: build first" >&2; exit 1; }
isa=SSE4.2
grep -qw avx2 /proc/cpuinfo && isa=AVX2

patterns=(
  multiple_devices types_test "empty_scene.*"
  "triangle_hit.*" "quad_hit.*" "inactive_rays.*"
  "intersection_filter.triangles.*"
  "get_bounds.triangles.*" "get_bounds.quads.*" "get_linear_bounds.triangles.*" "get_linear_bounds.quads.*"
  "buffer_stride.triangles.*" "buffer_stride.quads.*"
  "interpolate.triangles.*"
  "ray_alignment_test.*triangles" "ray_alignment_test.*quads"
  "user_geometry_id.*" "instancing.*#first"
)
if [ "${2:-}" = "--watertight" ]; then
  patterns+=("watertight_triangles.*" "watertight_quads.*")
fi

failed=0
total=0
for p in "${patterns[@]}"; do
  half=0
  if [[ "$p" == *"#first" ]]; then half=1; p="${p%#first}"; fi
  out="$(LD_LIBRARY_PATH="$shim" embree_verify --no-colors --flatten --sequential --run "$isa.$p" 2>&1)" || true
  results="$(grep -E '\[(PASSED|FAILED|SKIPPED)\]' <<< "$out" || true)"
  if ! grep -q "Tests failed:" <<< "$out"; then  # it stopped before its summary: a crash
    results+=$'\n'"$(tail -5 <<< "$out")"
  elif [ "$half" = 1 ]; then
    n="$(grep -c . <<< "$results" || true)"
    results="$(head -n $((n / 2)) <<< "$results")"
  elif ! grep -q "Tests failed: 0" <<< "$out"; then
    results+=$'\n'"$(tail -5 <<< "$out")"
  fi
  passed="$(grep -c '\[PASSED\]' <<< "$results" || true)"
  bad="$(grep -v '\[PASSED\]\|\[SKIPPED\]' <<< "$results" || true)"
  total=$((total + passed))
  if [ "$passed" -eq 0 ] || [ -n "$bad" ]; then
    echo "verify.sh: $isa.$p: $passed passed, failures:"; echo "${bad:-no test ran}"; failed=1
  else
    printf "%-44s %5d passed\n" "$isa.$p$([ "$half" = 1 ] && echo ' (first half)')" "$passed"
  fi
done
echo "verify.sh: $total of embree_verify's tests on mbrt's libembree3.so.3, $([ $failed = 0 ] && echo 'all passed' || echo 'some FAILED')"
exit "$failed"
