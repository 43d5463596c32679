#!/usr/bin/env bash
# Builds the Debian package of mbrt (`cpack -G DEB` in the build folder,
# default build/, configured and built as scripts/test.sh does) and checks
# what it holds: libmbrt.so and libmbrt.a, the headers, the pkg-config
# file, the CMake package, the `mbrt` command and the Python module
# (dpkg-deb -c). Not part of CI: it needs the whole build.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir="${MBRT_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build_dir" -j"$(nproc)"
rm -f "$build_dir"/mbrt_*.deb
(cd "$build_dir" && cpack -G DEB > cpack.log)
deb="$(ls "$build_dir"/mbrt_*.deb)"
contents="$(dpkg-deb -c "$deb")"
missing=0
for path in ./usr/bin/mbrt ./usr/include/mbrt/mbrt.h ./usr/include/mbrt/accel.h \
            ./usr/lib/python3/dist-packages/mbrt/__init__.py ./usr/lib/python3/dist-packages/mbrt/_mbrt.pyi; do
  grep -qF " $path" <<<"$contents" || { echo "test-deb.sh: $deb lacks $path" >&2; missing=1; }
done
# In lib/ or lib/<multiarch>/, as GNUInstallDirs chose for the prefix.
for lib in libmbrt.so.0.1.0 libmbrt.a libmbrt_accel.a pkgconfig/mbrt.pc cmake/mbrt/mbrtConfig.cmake; do
  grep -qE " \./usr/lib/([a-z0-9_]+-linux-gnu/)?${lib//./\\.}\$" <<<"$contents" ||
    { echo "test-deb.sh: $deb lacks usr/lib/.../$lib" >&2; missing=1; }
done
grep -q "dist-packages/mbrt/_mbrt.cpython-.*\.so" <<<"$contents" || { echo "test-deb.sh: no Python extension" >&2; missing=1; }
[ "$missing" -eq 0 ] || exit 1
dpkg-deb -I "$deb" | grep -E "Package|Version|Depends"
echo "test-deb.sh: $deb holds the libraries, headers, command and Python module ($(wc -l <<<"$contents") entries)"
