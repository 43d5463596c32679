#!/usr/bin/env bash
# Copies include/, src/, tools/ and embree_api/src/ of the tree in $1 and
# expects scripts/check-layers.sh to pass on the unchanged copy, then to fail
# naming the file on each of: a private kernel header included by the Embree
# API (a public-headers-only module), an include of the accel façade in a
# core header, and an include of another kind (stbvh) in auto, which may
# use only bvh's cluster tree.
set -euo pipefail
src="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/tree/scripts"
cp -r "$src/include" "$src/src" "$src/tools" "$tmp/tree/"
mkdir -p "$tmp/tree/embree_api"
cp -r "$src/embree_api/src" "$tmp/tree/embree_api/"
cp "$src/scripts/check-layers.sh" "$tmp/tree/scripts/"
bash "$tmp/tree/scripts/check-layers.sh" "$tmp/tree" > /dev/null
cp "$tmp/tree/embree_api/src/trace.h" "$tmp/trace.h"
sed -i '0,/#include "/s//#include "scene\/scene_context.h"\n#include "/' "$tmp/tree/embree_api/src/trace.h"
if out="$(bash "$tmp/tree/scripts/check-layers.sh" "$tmp/tree")"; then
  echo "layers_check_fails: a private kernel header in embree_api/src/trace.h passed the check"
  exit 1
fi
grep -q 'embree_api/src/trace.h: embree_api includes the private header "scene/scene_context.h"' <<< "$out" || {
  echo "layers_check_fails: the check failed without naming the private include:"; echo "$out"; exit 1; }
cp "$tmp/trace.h" "$tmp/tree/embree_api/src/trace.h"
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
