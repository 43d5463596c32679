#!/usr/bin/env bash
# Fails unless libmbrt.so exports the C API and nothing else: every defined
# dynamic symbol starts with mbrt, and the entry points of mbrt.h are there.
#   bash check_exports.sh LIBRARY
set -euo pipefail
lib="$1"
symbols="$(nm -D --defined-only "$lib" | awk '{print $NF}')"
[ -n "$symbols" ] || { echo "check_exports: $lib exports no symbols"; exit 1; }
others="$(grep -v '^mbrt' <<<"$symbols" || true)"
if [ -n "$others" ]; then
  echo "check_exports: $lib exports symbols outside the C API:"
  head -20 <<<"$others"
  exit 1
fi
for name in mbrtGetVersion mbrtNewDevice mbrtGetError mbrtNewScene mbrtNewTriangleMesh mbrtNewAccel \
            mbrtIntersect1 mbrtOccluded1 mbrtIntersectM mbrtOccludedM mbrtGetAccelStats; do
  grep -qx "$name" <<<"$symbols" || { echo "check_exports: $lib does not export $name"; exit 1; }
done
echo "check_exports: $(wc -l <<<"$symbols") symbols, all of the C API"
