#!/usr/bin/env bash
# Times pd-mesh on case C3-A at the paper's resolution (dx = 0.04 mm,
# delta = 0.16 mm, box padding 0.25 mm -> 2 mm boxes): grid, families and file.
# Prints pd-mesh's own per-stage summary, wall time and peak memory.
# Usage: bench/mesh_c3a.sh [BUILD_DIR [PD-MESH OPTIONS ...]]   (default: build)
#   e.g. bench/mesh_c3a.sh build --bonds-across-voids keep   (bonds by distance only)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
/usr/bin/time -f "wall %e s, peak RSS %M kB" \
  "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing 0.04mm --horizon 0.16mm --padding 0.25mm \
  -o "$out/c3a.pdp" "$@"
ls -l "$out/c3a.pdp" | awk '{printf "particle file: %.0f MB\n", $5 / 1e6}'
