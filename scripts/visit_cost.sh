#!/usr/bin/env bash
# Instructions per ray of the trace phase (callgrind: deterministic on a
# loaded machine) of each kind on a scene's incoherent rays, with the nodes,
# leaves and primitive tests per ray that scripts/visit_cost.cpp counts
# (docs/performance.md, "The cost of a visit").
#
#   bash scripts/visit_cost.sh SCENE SIZE KIND[,KIND...] [RAYS]     (default 20000 rays)
#   FROZEN=t bash scripts/visit_cost.sh ...                           (every ray at t; embree-static rows)
#   TRAVERSAL_COST=c bash scripts/visit_cost.sh ...                   (the SAH's C_T, BuildOptions::traversalCost)
#
# Builds build/visit_cost from scripts/visit_cost.cpp against build/'s
# libraries when it is missing or older than them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
[ $# -ge 3 ] || { echo "usage: $0 SCENE SIZE KIND[,KIND...] [RAYS]" >&2; exit 2; }
scene="$1" size="$2" kinds="$3" rays="${4:-20000}"
tool=build/visit_cost
libs=(build/libmbrt_bench.a build/libmbrt_scenes.a build/libmbrt_accel.a)
if [ ! -x "$tool" ] || [ -n "$(find "${libs[@]}" scripts/visit_cost.cpp -newer "$tool" 2>/dev/null)" ]; then
  g++ -O2 -std=c++20 -mavx2 -mfma -Iinclude -Isrc scripts/visit_cost.cpp -o "$tool" "${libs[@]}" -ltbb -lembree3
fi
command -v valgrind >/dev/null || { echo "visit_cost.sh: valgrind is not installed" >&2; exit 1; }
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
printf '%-22s %12s  %s\n' kind instr/ray "counters (per ray)"
IFS=, read -ra list <<< "$kinds"
for kind in "${list[@]}"; do
  MODE=count valgrind --tool=callgrind --toggle-collect='*traceOnce*' --callgrind-out-file="$out/cg.out" \
    "$tool" "$scene" "$size" "$kind" "$rays" > "$out/stdout" 2> "$out/stderr"
  ir=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$out/stderr")
  n=$(sed -n 's/^\([0-9]*\) rays traced once.*/\1/p' "$out/stdout")
  counters=$(sed -n "s/^$kind  *//p" "$out/stdout" | head -n 1)
  printf '%-22s %12.1f  %s\n' "$kind" "$(echo "$ir / $n" | bc -l)" "$counters"
done
