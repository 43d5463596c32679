#!/usr/bin/env bash
# Renders scene.py with Blender's Cycles through Debian's libembree3 and
# through the libembree3.so.3 in SHIM_DIR, checks that the pictures agree
# within sampling noise (compare.py) and reports the render times.
#
#   embree_api/clients/cycles/run.sh SHIM_DIR [OUT_DIR]
#
# Renders, interleaved so that drifting machine load hits both sides alike:
# Embree and shim with seeds 1, 2, 3, then Embree seed 1 without motion blur
# (proof that the scene exercises motion blur); then hair.py through the
# shim, which has no curves: Cycles must log the shim's Embree error and
# finish the render without the hair. Every render must exit 0,
# and the shim's renders must have mapped SHIM_DIR's file (scene.py reads
# /proc/self/maps inside Blender). Embree errors Cycles logged (through the
# device error callback, shown with --debug-cycles --verbose 1) are printed.
# OUT_DIR keeps the pictures and logs (default: a temporary folder).
# Exits 1 on a crash, a wrong library, or pictures beyond noise; 77
# (skipped) without blender.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ $# -lt 1 ]; then
  echo "usage: $0 SHIM_DIR [OUT_DIR]" >&2
  exit 2
fi
shim_dir="$(realpath "$1")"
shim_lib="$shim_dir/libembree3.so.3"
if [ ! -e "$shim_lib" ]; then
  echo "cycles: no libembree3.so.3 in $shim_dir" >&2
  exit 2
fi
if ! command -v blender >/dev/null; then
  echo "cycles: blender is not installed (scripts/install-deps.sh installs it): skipped"
  exit 77
fi
if [ $# -ge 2 ]; then
  out="$(realpath "$2")"
  mkdir -p "$out"
else
  out="$(mktemp -d)"
  trap 'rm -rf "$out"' EXIT
fi

status=0
# render NAME SEED [scene.py options...]: one Blender run; NAME starting with
# "shim" runs with LD_LIBRARY_PATH=SHIM_DIR.
render() {
  local name="$1" seed="$2"
  shift 2
  local env_args=() expect
  expect="$(realpath /usr/lib/x86_64-linux-gnu/libembree3.so.3)"
  if [[ "$name" == shim* ]]; then
    env_args=("LD_LIBRARY_PATH=$shim_dir")
    expect="$(realpath "$shim_lib")"
  fi
  local rc=0
  touch "$out/$name.log.start"
  env "${env_args[@]}" blender -b --factory-startup --python-exit-code 1 --debug-cycles \
    --verbose 1 --python "$here/scene.py" -- "$out/$name.png" --seed "$seed" "$@" \
    >"$out/$name.log" 2>&1 || rc=$?
  grep -E "embree\.cpp:[0-9]+\]" "$out/$name.log" | sed "s/^/  $name: Embree error: /" || true
  if [ "$rc" -ne 0 ] || [ ! -e "$out/$name.npy" ]; then
    echo "cycles: FAILED $name: blender exited $rc (last lines of $out/$name.log):" >&2
    grep -v "^Fra:" "$out/$name.log" | tail -15 >&2
    if [ "$rc" -ge 128 ] && [ /tmp/blender.crash.txt -nt "$out/$name.log.start" ]; then
      echo "cycles: Blender's crash report (/tmp/blender.crash.txt):" >&2
      head -40 /tmp/blender.crash.txt >&2
    fi
    return 1
  fi
  local mapped
  mapped="$(sed -n 's/^scene.py: libembree3 mapped: //p' "$out/$name.log")"
  if [ "$mapped" != "$expect" ]; then
    echo "cycles: FAILED $name: Blender mapped '$mapped', expected '$expect'" >&2
    return 1
  fi
  sed -n "s/^scene.py: render_seconds /  $name: render_seconds /p" "$out/$name.log"
}

for seed in 1 2 3; do
  render "embree_$seed" "$seed" || status=1
  render "shim_$seed" "$seed" || status=1
done
render embree_static 1 --no-motion-blur || status=1

# A call the shim does not have: hair (hair.py). Cycles must log the shim's
# Embree error for the curve geometry and finish the render, not crash.
rc=0
LD_LIBRARY_PATH="$shim_dir" blender -b --factory-startup --python-exit-code 1 --debug-cycles --verbose 1 \
  --python "$here/hair.py" -- "$out/shim_hair.png" > "$out/shim_hair.log" 2>&1 || rc=$?
hair_error="$(grep -E "embree\.cpp:[0-9]+\] rtcNewGeometry: RTC_GEOMETRY_TYPE_CURVE is not supported" \
  "$out/shim_hair.log" | head -1 || true)"
if [ "$rc" -ne 0 ] || ! grep -q "^hair.py: libembree3 mapped: $(realpath "$shim_lib")\$" "$out/shim_hair.log" \
    || ! grep -q "^hair.py: rendered" "$out/shim_hair.log" || [ -z "$hair_error" ]; then
  echo "cycles: FAILED: hair through the shim (exit $rc) did not end in Cycles logging the shim's error" \
    "and finishing the render; last lines of $out/shim_hair.log:" >&2
  grep -v "^Fra:" "$out/shim_hair.log" | tail -15 >&2
  status=1
else
  echo "  shim_hair: rendered without the hair; Cycles logged: ${hair_error#*] }"
fi

if [ "$status" -eq 0 ]; then
  /usr/bin/python3 "$here/compare.py" "$out"/embree_{1,2,3}.npy "$out"/shim_{1,2}.npy \
    "$out/embree_static.npy" || status=1
  /usr/bin/python3 - "$out" <<'EOF'
import re, statistics, sys
def seconds(name):
    text = open(f"{sys.argv[1]}/{name}.log").read()
    return float(re.search(r"render_seconds ([0-9.]+)", text).group(1))
e = statistics.median(seconds(f"embree_{s}") for s in (1, 2, 3))
m = statistics.median(seconds(f"shim_{s}") for s in (1, 2, 3))
print(f"  render time (median of 3): embree {e:.2f} s, shim {m:.2f} s, "
      f"shim speed / Embree speed {e / m:.2f}")
EOF
fi
if [ "$status" -eq 0 ]; then echo "cycles: OK"; else echo "cycles: FAILED"; fi
exit "$status"
