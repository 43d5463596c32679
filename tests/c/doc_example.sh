#!/usr/bin/env bash
# The example of docs/c-api.md (its one ```c block) compiles with cc against
# libmbrt.so and runs successfully, so that the documented code stays true.
#   bash doc_example.sh SOURCE_DIR LIBRARY_DIR WORK_DIR [CFLAGS]
# CFLAGS: extra compiler flags (the sanitizers of a sanitized libmbrt.so).
set -euo pipefail
src="$1" libdir="$2" work="$3" extra="${4:-}"
rm -rf "$work" && mkdir -p "$work"
awk '/^```c$/{on=1; next} /^```$/{on=0} on' "$src/docs/c-api.md" > "$work/example.c"
[ -s "$work/example.c" ] || { echo "doc_example: no \`\`\`c block in docs/c-api.md"; exit 1; }
cc -std=c99 -pedantic -Wall -Wextra -Werror $extra -I"$src/include" "$work/example.c" \
   -L"$libdir" -lmbrt -Wl,-rpath,"$libdir" -lm -o "$work/example"
"$work/example"
