#!/usr/bin/env bash
# examples/c/trace.c links with the static libmbrt.a and the libraries it
# needs (pkg-config's Libs.private), with no libmbrt.so in sight, and runs.
#   bash static_link.sh SOURCE_DIR LIBMBRT_A WORK_DIR "EXTRA_FLAGS"
set -euo pipefail
src="$1" archive="$2" work="$3" flags="$4"
mkdir -p "$work"
# shellcheck disable=SC2086
cc -std=c99 -pedantic -Wall -Werror -I"$src/include" "$src/examples/c/trace.c" "$archive" $flags -o "$work/trace-static"
if ldd "$work/trace-static" | grep -q 'libmbrt\.so'; then
  echo "static_link.sh: the program depends on libmbrt.so" >&2
  exit 1
fi
"$work/trace-static"
echo "static_link.sh: examples/c/trace.c linked with libmbrt.a"
