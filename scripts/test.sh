#!/usr/bin/env bash
# Installs the dependencies, builds mbrt (Release), runs every test, then
# installs mbrt into a temporary prefix and builds and runs
# examples/consumer against it with find_package(mbrt).
# Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs="$(nproc)"
bash scripts/install-deps.sh

build_dir="${MBRT_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$jobs"
(cd "$build_dir" && ctest --output-on-failure -j"$jobs")

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build_dir" --prefix "$tmp/prefix"
cmake -S examples/consumer -B "$tmp/consumer-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix"
cmake --build "$tmp/consumer-build" -j"$jobs"
"$tmp/consumer-build/consumer"
"$tmp/prefix/bin/mbrt" --version

echo "test.sh: all tests passed"
