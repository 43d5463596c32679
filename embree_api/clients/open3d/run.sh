#!/usr/bin/env bash
# Runs Open3D's RaycastingScene (raycast.py) with Debian's libembree3 and
# with the libembree3.so.3 in SHIM_DIR, compares the results (compare.py) and
# reports the time of each.
#
#   embree_api/clients/open3d/run.sh SHIM_DIR [RAYS]
#
# Two passes:
#   unchanged  Open3D exactly as Debian ships it. Its rays carry mask 0, and
#              Debian's Embree honours ray masks, so every ray misses; the
#              shim must answer the same.
#   mask_all   the same rays with mask 0xFFFFFFFF, set by the LD_PRELOAD
#              interposer mask_all.c in front of either library: the real
#              comparison of hits, counts and occlusion.
# Exits 1 on a real mismatch, a crash, or when the shim's file is not the one
# Open3D loaded; 77 (skipped) without python3-open3d; 0 otherwise.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ $# -lt 1 ]; then
  echo "usage: $0 SHIM_DIR [RAYS]" >&2
  exit 2
fi
shim_dir="$(realpath "$1")"
rays="${2:-100000}"
if [ ! -e "$shim_dir/libembree3.so.3" ]; then
  echo "open3d: no libembree3.so.3 in $shim_dir" >&2
  exit 2
fi
python=/usr/bin/python3
if ! "$python" -c "import open3d" 2>/dev/null; then
  echo "open3d: python3-open3d is not installed (scripts/install-deps.sh installs it): skipped"
  exit 77
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
gcc -O2 -Wall -Wextra -shared -fPIC -o "$work/mask_all.so" "$here/mask_all.c" -ldl

status=0
# run LABEL OUT [env assignments...]: one raycast.py run; fails loudly.
run() {
  local label="$1" out="$2"
  shift 2
  local rc=0
  env "$@" "$python" "$here/raycast.py" "$out" --rays "$rays" >"$work/$label.log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "open3d: FAILED $label (exit $rc):" >&2
    cat "$work/$label.log" >&2
    return 1
  fi
  sed 's/^/  /' "$work/$label.log"
}

loaded() {  # the libembree3 file a run mapped
  "$python" -c "import numpy, sys; print(numpy.load(sys.argv[1])['embree_library'])" "$1"
}

for pass in unchanged mask_all; do
  preload=()
  if [ "$pass" = mask_all ]; then preload=("LD_PRELOAD=$work/mask_all.so"); fi
  echo "== open3d, $pass rays"
  if ! run "embree_$pass" "$work/embree_$pass.npz" "${preload[@]}"; then status=1; continue; fi
  if ! run "shim_$pass" "$work/shim_$pass.npz" "${preload[@]}" "LD_LIBRARY_PATH=$shim_dir"; then
    status=1
    continue
  fi
  lib="$(loaded "$work/shim_$pass.npz")"
  if [ "$lib" != "$(realpath "$shim_dir/libembree3.so.3")" ]; then
    echo "open3d: FAILED: with LD_LIBRARY_PATH=$shim_dir Open3D loaded '$lib'" >&2
    status=1
    continue
  fi
  if ! "$python" "$here/compare.py" "$work/embree_$pass.npz" "$work/shim_$pass.npz"; then
    echo "open3d: FAILED: $pass results differ beyond float tolerance" >&2
    status=1
  fi
  "$python" - "$work/embree_$pass.npz" "$work/shim_$pass.npz" <<'EOF'
import sys, numpy
e, s = (numpy.load(p)["times"] for p in sys.argv[1:3])
for name, te, ts in zip(("cast_rays", "count_intersections", "test_occlusions"), e, s):
    print(f"  time {name}: embree {te * 1e3:.1f} ms, shim {ts * 1e3:.1f} ms, "
          f"shim speed / Embree speed {te / ts:.2f} (median of 3 per process)")
EOF
done
if [ "$status" -eq 0 ]; then echo "open3d: OK"; else echo "open3d: FAILED"; fi
exit "$status"
