#!/usr/bin/env bash
# `pip install --no-build-isolation .` offline into a temporary venv (numpy
# from Debian through --system-site-packages), reusing the CMake build folder
# $1, then imports mbrt from outside the source tree and traces a scene.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_dir="$(cd "$1" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$tmp/venv"
(cd "$root" && MBRT_CMAKE_BUILD_DIR="$build_dir" "$tmp/venv/bin/pip" install --no-build-isolation --no-index \
  --no-cache-dir -q .)
rm -rf "$root/python/mbrt.egg-info"
cd "$tmp"
"$tmp/venv/bin/python" - <<'PY'
import mbrt, numpy as np
assert mbrt.__file__.startswith(__import__("sys").prefix), mbrt.__file__
scene = mbrt.scenes.make("crowd", size=0.005)
hits = mbrt.Accel(scene, "stbvh").intersect(org=np.zeros((4, 3)) + [0, 1, 30], dir=[[0, 0, -1]] * 4, time=0.5)
assert len(hits) == 4
print("pip_install.sh: mbrt", mbrt.__version__, "installed in a venv from", mbrt.__file__)
PY
