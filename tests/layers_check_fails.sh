#!/usr/bin/env bash
# Copies include/, src/ and tools/ of the tree in $1, adds one include of the
# accel façade to a core header, and expects scripts/check-layers.sh to fail
# naming that file; then one include of another kind (stbvh) to auto, which
# may use only bvh's cluster tree, likewise; also expects the check to pass
# on the unchanged copy.
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
# auto may use one tree of bvh/ (cluster_bvh.h), not bvh's other kinds.
sed -i '0,/#include "/s//#include "bvh\/kinds\/stbvh.h"\n#include "/' "$tmp/tree/src/auto/auto_kind.cpp"
if out="$(bash "$tmp/tree/scripts/check-layers.sh" "$tmp/tree")"; then
  echo "layers_check_fails: auto including another kind (bvh/kinds/stbvh.h) passed the check"
  exit 1
fi
grep -q 'src/auto/auto_kind.cpp: auto includes "bvh/kinds/stbvh.h"' <<< "$out" || {
  echo "layers_check_fails: the check failed without naming auto's include of stbvh:"; echo "$out"; exit 1; }
echo "layers_check_fails: the upward include and auto's include of another kind were found"
