#!/usr/bin/env bash
# A plain C compiler (cc, C99, no CMake) builds examples/c/trace.c with
# mbrt.h alone (copied apart from the other headers) against libmbrt.so,
# and the program runs and gives the right answers.
#   bash plain_cc.sh SOURCE_DIR LIBRARY_DIR WORK_DIR [CFLAGS]
# CFLAGS: extra compiler flags (the sanitizers of a sanitized libmbrt.so).
set -euo pipefail
src="$1" libdir="$2" work="$3" extra="${4:-}"
rm -rf "$work" && mkdir -p "$work/include/mbrt"
cp "$src/include/mbrt/mbrt.h" "$work/include/mbrt/"
cc -std=c99 -pedantic -Wall -Wextra -Werror $extra -I"$work/include" "$src/examples/c/trace.c" \
   -L"$libdir" -lmbrt -Wl,-rpath,"$libdir" -lm -o "$work/trace"
"$work/trace"
