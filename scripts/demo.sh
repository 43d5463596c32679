#!/usr/bin/env bash
# Installs the dependencies, builds mbrt (Release) and renders the demo scene.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/install-deps.sh
build_dir="${MBRT_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$(nproc)"
"$build_dir/mbrt" render --scene demo --out demo.png
echo
echo "The picture is in $(pwd)/demo.png"
