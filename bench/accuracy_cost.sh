#!/usr/bin/env bash
# Accuracy against cost for case C1 (docs/accuracy-cost.md): the difference
# between PD and the CalculiX plane-stress reference against wall time and
# particle count, for the three grids, horizon factors m = 3, 4, 5 and several
# spacings, with one loading: loading layers beyond the edges (default; the
# FEM moves its edge nodes) or the in-body strips (the FEM clamps them);
# docs/scenes.md, "Which loading to use when". Runs pd-validate-c1 once per
# spacing (all grids and m), collects the CSV rows, then
# bench/accuracy_cost_report.py writes docs/accuracy-cost.md and
# docs/img/accuracy_cost_*.svg.
#
# Usage: bench/accuracy_cost.sh [BUILD_DIR] [SPACINGS] [LOADING]
#   defaults: build, "0.4mm 0.2mm 0.1mm", layers  (dx = 0.05 mm takes tens of minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
spacings=${2:-"0.4mm 0.2mm 0.1mm"}
loading=${3:-layers}
work=out/accuracy_cost
mkdir -p "$work"
rows="$work/all_runs.csv"
rm -f "$rows"
for dx in $spacings; do
  echo "== C1 at dx = $dx, m = 3, 4, 5, grids uniform, free, NB-NUG, loading $loading"
  # FEM element size at the hole: dx, but at most 0.1 mm (finer changes < 5e-4 U, tests/quasistatic/test_calculix.cpp).
  fem=$(python3 -c "import sys; v=float('$dx'.replace('mm','')); print(f'{min(v, 0.1)}mm')")
  "$build/validation/pd-validate-c1" geometries/c1_plate_hole.geo --spacing "$dx" -m 3,4,5 \
    --grids uniform,free,nbnug --loading "$loading" --fem-size "$fem" --tolerance 1e-8 -o "$work/dx_${dx}" | grep -v "^FEM"
  if [ ! -f "$rows" ]; then head -1 "$work/dx_${dx}/c1_errors.csv" > "$rows"; fi
  tail -n +2 "$work/dx_${dx}/c1_errors.csv" >> "$rows"
done
python3 bench/accuracy_cost_report.py "$rows" docs/accuracy-cost.md docs/img
