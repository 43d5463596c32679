#!/usr/bin/env bash
# Fails when a file of the library or the command includes a header of a
# higher layer (docs/architecture.md). The allowed edges are written here and
# nowhere else.
#
#   bash scripts/check-layers.sh [ROOT]     ROOT: the source tree (default: this one)
#
# A module is a folder of src/ (its first component), tools/, or the module a
# public header include/mbrt/NAME.h belongs to (PUBLIC below). A file may
# include its own module and the modules listed for it in ALLOWED. Modules in
# PUBLIC_ONLY see other modules only through their public headers.
set -euo pipefail
root="${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}"

# Lowest layer first: core -> geometry -> scene -> leaves -> kinds -> accel -> scenes/io -> c/render/bench -> tools.
# An entry is a module (any of its headers) or a path inside one (that
# header, or the headers under that folder): a kind that uses part of
# another says exactly which part, so that e.g. auto's one tree of bvh/
# (bvh/kinds/cluster_bvh.h) does not let it include bvh's other kinds.
declare -A ALLOWED=(
  [core]=""
  [geometry]="core"
  [scene]="core geometry"
  [leaves]="core geometry scene"
  [bvh]="core geometry scene leaves decompose/fuzzy_boxes.h"
  [msbvh]="core geometry scene leaves bvh/traverse.h bvh/heuristics bvh/sah_cost.h bvh/inspect.h bvh/nodes"
  [kd]="core geometry scene leaves"
  [decompose]="core geometry scene"
  [fuzzykd]="core geometry scene leaves decompose kd bvh/traverse.h bvh/sah_cost.h bvh/nodes bvh/build"
  [embree]="core geometry scene"
  [auto]="core geometry scene decompose bvh/kinds/cluster_bvh.h"
  [accel]="core geometry scene bvh/kinds msbvh/msbvh.h kd/mbkd.h fuzzykd/fuzzykd.h embree/embree_structure.h auto/auto_kind.h"
  [scenes]="core scene"
  [io]="core scene scenes"
  [c]="core scene accel scenes io"
  [render]="core scene accel scenes io"
  [bench]="core scene accel scenes io"
  [tools]="core scene accel scenes io render bench"
)
# The module of each public header.
declare -A PUBLIC=(
  [error.h]=core [math.h]=core [quaternion.h]=core [ray.h]=core
  [build_options.h]=core [accel_stats.h]=core [camera.h]=core [splitmix.h]=core
  [scene.h]=scene
  [accel.h]=accel [accel_update.h]=accel
  [mbrt.h]=c
  [scenes.h]=scenes
  [render.h]=render [frame_renderer.h]=render
  [bench.h]=bench
)
PUBLIC_ONLY=" io render bench tools scenes c "

module_of_include() {  # "mbrt/x.h" or "dir/x.h" -> module; empty for a file of the includer's own folder
  local inc="$1"
  if [[ "$inc" == mbrt/* ]]; then
    local name="${inc#mbrt/}"
    [[ "$name" == io/* ]] && { echo io; return; }
    echo "${PUBLIC[$name]:-unknown-public:$name}"
  elif [[ "$inc" == */* ]]; then
    echo "${inc%%/*}"
  fi
}

allowed() {  # module target include -> 0 when ALLOWED[module] names the target module or the included path
  local e
  for e in ${ALLOWED[$1]}; do
    if [[ "$e" == */* ]]; then
      [[ "$3" == "$e" || "$3" == "$e"/* ]] && return 0
    elif [ "$e" = "$2" ]; then
      return 0
    fi
  done
  return 1
}

failures=0
check_file() {  # file module
  local file="$1" mod="$2" inc target
  while IFS= read -r inc; do
    target="$(module_of_include "$inc")"
    [ -z "$target" ] && continue
    [ "$target" = "$mod" ] && continue
    if [[ "$target" == unknown-public:* ]]; then
      echo "check-layers: ${file#$root/}: includes \"$inc\", a public header with no module (add it to PUBLIC in scripts/check-layers.sh)"
      failures=$((failures + 1)); continue
    fi
    if ! allowed "$mod" "$target" "$inc"; then
      echo "check-layers: ${file#$root/}: $mod includes \"$inc\" of $target, which ALLOWED[$mod] does not name"
      failures=$((failures + 1)); continue
    fi
    if [[ "$PUBLIC_ONLY" == *" $mod "* && "$inc" != mbrt/* ]]; then
      echo "check-layers: ${file#$root/}: $mod includes the private header \"$inc\" of $target (use its public header)"
      failures=$((failures + 1))
    fi
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$file")
}

count=0
while IFS= read -r -d '' f; do
  rel="${f#$root/src/}"; mod="${rel%%/*}"
  if [ -z "${ALLOWED[$mod]+x}" ]; then
    echo "check-layers: src/$rel: folder '$mod' has no layer (add it to ALLOWED in scripts/check-layers.sh)"
    failures=$((failures + 1)); continue
  fi
  check_file "$f" "$mod"; count=$((count + 1))
done < <(find "$root/src" -type f \( -name '*.h' -o -name '*.cpp' \) -print0)
while IFS= read -r -d '' f; do
  rel="${f#$root/include/mbrt/}"
  if [[ "$rel" == io/* ]]; then mod=io; else mod="${PUBLIC[$rel]:-}"; fi
  if [ -z "$mod" ]; then
    echo "check-layers: include/mbrt/$rel: a public header with no module (add it to PUBLIC)"
    failures=$((failures + 1)); continue
  fi
  check_file "$f" "$mod"; count=$((count + 1))
done < <(find "$root/include/mbrt" -type f -name '*.h' -print0)
while IFS= read -r -d '' f; do
  check_file "$f" tools; count=$((count + 1))
done < <(find "$root/tools" -type f \( -name '*.h' -o -name '*.cpp' \) -print0)

if [ "$failures" -ne 0 ]; then
  echo "check-layers: $failures upward or private includes in $count files"
  exit 1
fi
echo "check-layers: $count files, no upward include"
