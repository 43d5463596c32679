#!/usr/bin/env bash
# examples/c/trace.c and examples/c/frames.c (whose animation pulls in the
# loaders and their libpng and OpenEXR) link with the static libmbrt.a and
# the libraries it needs (pkg-config's Libs.private), with no libmbrt.so in
# sight, and run.
#   bash static_link.sh SOURCE_DIR LIBMBRT_A WORK_DIR "EXTRA_FLAGS"
set -euo pipefail
src="$1" archive="$2" work="$3" flags="$4"
mkdir -p "$work"
for example in trace frames; do
  # shellcheck disable=SC2086
  cc -std=c99 -pedantic -Wall -Werror -I"$src/include" "$src/examples/c/$example.c" "$archive" $flags \
     -o "$work/$example-static"
  if ldd "$work/$example-static" | grep -q 'libmbrt\.so'; then
    echo "static_link.sh: $example depends on libmbrt.so" >&2
    exit 1
  fi
  "$work/$example-static" > "$work/$example.out"
done
echo "static_link.sh: examples/c/trace.c and frames.c linked with libmbrt.a"
