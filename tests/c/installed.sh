#!/usr/bin/env bash
# The installed C API works from outside the build: examples/c/trace.c
# builds with cc and the installed mbrt.pc, and with CMake's
# find_package(mbrt) and mbrt::c, and both programs run.
#   bash installed.sh PREFIX WORK_DIR        (after cmake --install --prefix PREFIX)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
prefix="$1" work="$2"
pc="$(find "$prefix" -name mbrt.pc -path '*/pkgconfig/*' | head -1)"
[ -n "$pc" ] || { echo "installed.sh: no mbrt.pc under $prefix"; exit 1; }
libdir="$(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --variable=libdir mbrt)"
mkdir -p "$work"
# shellcheck disable=SC2046
cc -std=c99 -pedantic -Wall -Werror "$src/examples/c/trace.c" \
   $(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --cflags --libs mbrt) -lm -Wl,-rpath,"$libdir" \
   -o "$work/trace-pkg-config"
"$work/trace-pkg-config"

mkdir -p "$work/cmake-src"
cat > "$work/cmake-src/CMakeLists.txt" <<EOT
cmake_minimum_required(VERSION 3.22)
project(mbrt_c_consumer LANGUAGES C)
find_package(mbrt REQUIRED)
add_executable(trace "$src/examples/c/trace.c")
target_link_libraries(trace PRIVATE mbrt::c m)
EOT
cmake -S "$work/cmake-src" -B "$work/cmake-build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" > "$work/cmake.log"
cmake --build "$work/cmake-build" > "$work/cmake-build.log"
"$work/cmake-build/trace"
echo "installed.sh: the installed C API builds with pkg-config and with find_package(mbrt)"
