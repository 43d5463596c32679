#!/usr/bin/env bash
# Copies include/, src/ and tools/ of the tree in $1, adds one include of the
# accel façade to a core header, and expects scripts/check-layers.sh to fail
# naming that file; also expects it to pass on the unchanged copy.
set -euo pipefail
src="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/tree/scripts"
cp -r "$src/include" "$src/src" "$src/tools" "$tmp/tree/"
cp "$src/scripts/check-layers.sh" "$tmp/tree/scripts/"
bash "$tmp/tree/scripts/check-layers.sh" "$tmp/tree" > /dev/null
sed -i '0,/#include "/s//#include "accel\/structure_factory.h"\n#include "/' "$tmp/tree/src/core/structure.h"
if out="$(bash "$tmp/tree/scripts/check-layers.sh" "$tmp/tree")"; then
  echo "layers_check_fails: an upward include in src/core/structure.h passed the check"
  exit 1
fi
grep -q 'src/core/structure.h: core includes "accel/structure_factory.h"' <<< "$out" || {
  echo "layers_check_fails: the check failed without naming the upward include:"; echo "$out"; exit 1; }
echo "layers_check_fails: the upward include was found"
