#!/usr/bin/env bash
# Embree's own tutorials (Debian's embree-tools) drawn twice, with the real
# libembree3 and with mbrt's (LD_LIBRARY_PATH=<build>/embree_api), and
# compared: the pictures pixel by pixel, and every ray traced by both
# (recorded by libmbrt_raylog.so) whose answers differ judged by the
# float64 reference on the scene mbrt traced (MBRT_EMBREE_DUMP):
# mbrt_embree_tutorial_check fails when mbrt's answer is the wrong one.
#
#   bash embree_api/clients/tutorials.sh BUILD_DIR [OUT_DIR]      the comparison
#   bash embree_api/clients/tutorials.sh --time BUILD_DIR [SIZE]  render speed, mbrt / Embree
#
# motion_blur_geometry also draws user geometry, curves and subdivision
# surfaces, which mbrt does not have: libmbrt_drop_unsupported.so leaves
# them out on both sides so that its triangle, quad and instance parts
# compare. quaternion_motion_blur draws only a user geometry: on mbrt it
# must stop with Embree's clear error. Exits 77 (skipped) without
# embree-tools.
set -euo pipefail

timing=0
if [ "${1:-}" = "--time" ]; then timing=1; shift; fi
build="$(cd "${1:?usage: tutorials.sh [--time] BUILD_DIR [OUT_DIR|SIZE]}" && pwd)"
shim="$build/embree_api"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if ! command -v triangle_geometry > /dev/null; then
  echo "tutorials.sh: Embree's tutorials are not installed (Debian: apt-get install embree-tools): skipped"
  exit 77
fi
for f in "$shim/libembree3.so.3" "$shim/libmbrt_raylog.so" "$shim/libmbrt_drop_unsupported.so" \
         "$shim/mbrt_embree_tutorial_check"; do
  [ -e "$f" ] || { echo "tutorials.sh: $f is missing: build the embree_api targets first" >&2; exit 1; }
done
drop="$shim/libmbrt_drop_unsupported.so"

# name | program | preload | arguments
cube="$here/../../tests/data/cube.obj"
tutorials=(
  "triangle_geometry|triangle_geometry||"
  "motion_blur_geometry|motion_blur_geometry|$drop|"
  "motion_blur_geometry_t1|motion_blur_geometry|$drop|--time 1"
  "instanced_geometry|instanced_geometry||"
  "intersection_filter|intersection_filter||"
  "intersection_filter_stream|intersection_filter||--mode stream"
  "dynamic_scene|dynamic_scene||"
  "pathtracer|pathtracer||-i $cube --triangle-plane -3 -0.5 -3 6 0 0 0 0 6 8 8 --triangle-sphere-mblur 1 0.3 0.5 0.4 0 0 0.45 24 --quad-sphere -1 0.2 0.8 0.4 16 --ambientlight 0.3 0.3 0.3 --directionallight -1 -2 -1 2 2 2 --vp 2.5 2 3 --vi 0 0 0 --vu 0 1 0 --fov 50 --spp 2 --max-path-length 4"
)

if [ "$timing" = 1 ]; then
  size="${2:-512}"
  # program args...: frames per second, BENCHMARK_RENDER_AVG of 3 frames
  # after 1 skipped; motion_blur_geometry and dynamic_scene have no
  # --benchmark: one headless frame (-o), its wall time with the program's
  # start and the build, marked with a *.
  fps() {
    if [ "$1" = motion_blur_geometry ] || [ "$1" = dynamic_scene ]; then
      local start end
      start="$(date +%s.%N)"
      "$@" --size "$size" "$size" -o "$tmp/frame.ppm" > /dev/null 2>&1
      end="$(date +%s.%N)"
      awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f\n", 1 / (b - a) }'
    else
      "$@" --size "$size" "$size" --benchmark 1 3 2>&1 | awk '/^BENCHMARK_RENDER_AVG /{print $2}'
    fi
  }
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  echo "render speed, frames per second at ${size}x${size}, median of 3 runs each (mbrt / Embree > 1: mbrt faster;"
  echo "* one headless frame with the program's start and the scene's build)"
  for t in "${tutorials[@]}"; do
    IFS='|' read -r name prog preload args <<< "$t"
    e=(); m=()
    for _ in 1 2 3; do
      # shellcheck disable=SC2086
      e+=("$(LD_PRELOAD="$preload" fps "$prog" $args)")
      # shellcheck disable=SC2086
      m+=("$(LD_PRELOAD="$preload" LD_LIBRARY_PATH="$shim" fps "$prog" $args)")
    done
    em="$(printf '%s\n' "${e[@]}" | sort -g | sed -n 2p)"; mm="$(printf '%s\n' "${m[@]}" | sort -g | sed -n 2p)"
    [ "$prog" = motion_blur_geometry ] || [ "$prog" = dynamic_scene ] && name="$name *"
    awk -v n="$name" -v e="$em" -v m="$mm" 'BEGIN { printf "%-28s Embree %8.2f fps   mbrt %8.2f fps   mbrt/Embree %.2f\n", n, e, m, (e > 0 ? m / e : 0) }'
  done
  exit 0
fi

out="${2:-$build/embree_tutorials}"
mkdir -p "$out"
failed=0
for t in "${tutorials[@]}"; do
  IFS='|' read -r name prog preload args <<< "$t"
  pre="$shim/libmbrt_raylog.so${preload:+:$preload}"
  # shellcheck disable=SC2086
  if ! LD_PRELOAD="$pre" MBRT_RAYLOG="$out/$name.embree.rays" \
      "$prog" --size 192 144 -o "$out/$name.embree.ppm" $args > "$out/$name.embree.log" 2>&1; then
    echo "tutorials.sh: $name failed on the real Embree:"; cat "$out/$name.embree.log"; failed=1; continue
  fi
  # shellcheck disable=SC2086
  if ! LD_LIBRARY_PATH="$shim" LD_PRELOAD="$pre" MBRT_RAYLOG="$out/$name.mbrt.rays" MBRT_EMBREE_DUMP="$out/$name.dump" \
      "$prog" --size 192 144 -o "$out/$name.mbrt.ppm" $args > "$out/$name.mbrt.log" 2>&1; then
    echo "tutorials.sh: $name failed on mbrt:"; cat "$out/$name.mbrt.log"; failed=1; continue
  fi
  "$shim/mbrt_embree_tutorial_check" "$name" "$out/$name.embree.ppm" "$out/$name.mbrt.ppm" \
    "$out/$name.embree.rays" "$out/$name.mbrt.rays" "$out/$name.dump" || failed=1
done

# A tutorial of user geometry only: mbrt must refuse it with Embree's error.
if LD_LIBRARY_PATH="$shim" quaternion_motion_blur --size 64 48 -o "$out/quaternion.ppm" > "$out/quaternion.log" 2>&1; then
  echo "tutorials.sh: quaternion_motion_blur ran on mbrt, which has no user geometry"; failed=1
elif grep -q "RTC_ERROR_UNKNOWN (rtcNewGeometry: RTC_GEOMETRY_TYPE_USER is not supported" "$out/quaternion.log"; then
  echo "quaternion_motion_blur: stops with $(cat "$out/quaternion.log")"
else
  echo "tutorials.sh: quaternion_motion_blur failed on mbrt without the expected error:"; cat "$out/quaternion.log"; failed=1
fi
[ -n "${MBRT_KEEP_RAYS:-}" ] || rm -f "$out"/*.rays  # large (MBRT_KEEP_RAYS=1 keeps them); the pictures and logs stay
[ "$failed" = 0 ] && echo "tutorials.sh: every picture matches Embree's but for rays settled for mbrt"
exit "$failed"
