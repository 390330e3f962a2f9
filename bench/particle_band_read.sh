#!/usr/bin/env bash
# Peak memory of reading C3-A's particle file whole (compact families, what
# every process of a distributed run reads today) against reading one slab's
# band of 2 and 3 slabs (docs/scaling.md, "What limits it today").
# Usage: bench/particle_band_read.sh SPACING   e.g. 0.04mm
# Needs scripts/build.sh pd-mesh pd-solve first (the libraries it links).
set -euo pipefail
cd "$(dirname "$0")/.."
spacing=${1:?spacing, e.g. 0.04mm}
niceness=${NICE:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
g++ -std=c++17 -O2 -fopenmp bench/particle_band_read.cpp -Icommon -Icommon/discretisation -Ibuild/common \
  build/common/discretisation/libpd_discretisation.a build/common/libpd_common.a -o "$work/band_read"
horizon=$(python3 -c "print(f'{4 * float(\"${spacing%mm}\"):g}mm')")
padding=$(python3 -c "print(f'{max(0.25, 4 * float(\"${spacing%mm}\")):g}mm')")
nice -n "$niceness" build/mesher/pd-mesh geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
  --padding "$padding" -o "$work/c3a.pdp" | grep -E "^grid|^families" || true
for run in "whole" "band 0 2" "band 1 2" "band 0 3" "band 1 3" "band 2 3"; do
  # shellcheck disable=SC2086
  nice -n "$niceness" "$work/band_read" "$work/c3a.pdp" $run
done
