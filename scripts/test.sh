#!/usr/bin/env bash
# Installs the dependencies, builds mbrt (Release), runs every test, then
# installs mbrt into a temporary prefix and builds and runs
# examples/consumer against it with find_package(mbrt), and the C example
# against the installed libmbrt.so (pkg-config and find_package), and
# `pip install --no-build-isolation .` of the Python module into a venv.
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
cmake --build "$tmp/consumer-build" -j"$jobs" -- -v > "$tmp/consumer-build.log"
# The consumer links mbrt::accel alone: the kernel must not bring the
# loaders' and images' libraries with it.
if grep -E 'libpng|tinygltf|nlohmann|OpenEXR|libIex|libImath' "$tmp/consumer-build.log"; then
  echo "test.sh: examples/consumer (mbrt::accel only) links an io library" >&2
  exit 1
fi
if ldd "$tmp/consumer-build/consumer" | grep -E 'libpng|OpenEXR|Iex|Imath'; then
  echo "test.sh: examples/consumer (mbrt::accel only) depends on an io library" >&2
  exit 1
fi
"$tmp/consumer-build/consumer"
"$tmp/prefix/bin/mbrt" --version
# The C API from the install: pkg-config and find_package(mbrt) with mbrt::c.
bash tests/c/installed.sh "$tmp/prefix" "$tmp/capi"
# The Python module through pip, offline, into a venv (reuses the build).
if grep -q '^MBRT_PYTHON:BOOL=ON' "$build_dir/CMakeCache.txt"; then
  bash tests/python/pip_install.sh "$build_dir"
fi

echo "test.sh: all tests passed"
