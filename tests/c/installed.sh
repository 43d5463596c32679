#!/usr/bin/env bash
# The installed C API works from outside the build: examples/c/trace.c and
# frames.c build with cc and the installed mbrt.pc (also with --static,
# against libmbrt.a), and trace.c with CMake's find_package(mbrt) and
# mbrt::c, and the programs run.
#   bash installed.sh PREFIX WORK_DIR        (after cmake --install --prefix PREFIX)
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
prefix="$1" work="$2"
pc="$(find "$prefix" -name mbrt.pc -path '*/pkgconfig/*' | head -1)"
[ -n "$pc" ] || { echo "installed.sh: no mbrt.pc under $prefix"; exit 1; }
libdir="$(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --variable=libdir mbrt)"
mkdir -p "$work"
for example in trace frames; do
  # shellcheck disable=SC2046
  cc -std=c99 -pedantic -Wall -Werror "$src/examples/c/$example.c" \
     $(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --cflags --libs mbrt) -lm -Wl,-rpath,"$libdir" \
     -o "$work/$example-pkg-config"
  "$work/$example-pkg-config" > "$work/$example-pkg-config.out"
done
# The static library, as pkg-config --static tells a program to link it.
static="$(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --static --libs mbrt)"
# shellcheck disable=SC2046,SC2086
cc -std=c99 -pedantic -Wall -Werror "$src/examples/c/frames.c" $(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --cflags mbrt) \
   ${static/-lmbrt/-Wl,-Bstatic -lmbrt -Wl,-Bdynamic} -o "$work/frames-static"
if ldd "$work/frames-static" | grep -q 'libmbrt\.so'; then
  echo "installed.sh: frames-static depends on libmbrt.so" >&2
  exit 1
fi
"$work/frames-static" > "$work/frames-static.out"

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
