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
# Usage: bench/accuracy_cost.sh [BUILD_DIR] [SPACINGS] [LOADING] [PARTS]
#   defaults: build, "0.4mm 0.2mm 0.1mm", layers  (dx = 0.05 mm takes tens of minutes on 2 cores),
#   PARTS "grids boxes": grids = the three grids above; boxes = box_spacing_rows
#   below (BOX_SPACINGS, default "0.4mm 0.2mm", the coarse spacings of that study).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
spacings=${2:-"0.4mm 0.2mm 0.1mm"}
loading=${3:-layers}
parts=${4:-"grids boxes"}
work=out/accuracy_cost
mkdir -p "$work"

# ---- Finer NB-NUG boxes (pd-mesh --box-spacing) -------------------------------
# C1 with the boxes meshed 2x and 4x finer than the squares (dx / 2, dx / 4),
# against the uniform grid of the same finest spacing and the NB-NUG grid of
# constant spacing dx; m = 3. Horizons vary on the boxed grids, so every row of
# this study is solved the same way: dual-horizon PD (model.dual_horizon), by
# the linear solution of validation/dual_horizon_statics.hpp, without surface
# correction (not available with dual horizons). FEM element size 0.1 mm at
# the hole; "near hole" = within 1 mm of it for every row. Writes $work/box_spacing_runs.csv and the section between the
# box-spacing markers of docs/accuracy-cost.md.
box_spacing_rows() {
  local rows="$work/box_spacing_runs.csv" dx fine f
  local common=(-m 3 --no-surface-correction --dual-horizon --fem-size 0.1mm --near-hole-band 1mm --tolerance 1e-8)
  rm -f "$rows"
  for dx in ${BOX_SPACINGS:-0.4mm 0.2mm}; do
    echo "== C1 boxes: NB-NUG dx = $dx with boxes at dx, dx/2, dx/4"
    "$build/validation/pd-validate-c1" geometries/c1_plate_hole.geo --spacing "$dx" --grids nbnug \
      --box-refinement 2,4 "${common[@]}" -o "$work/boxes_${dx}" | grep -v "^FEM"
  done
  # The uniform grids of every finest spacing above, each once.
  fine=$(python3 -c "print(','.join(sorted({f'{float(d[:-2]) / k:g}mm' for d in '${BOX_SPACINGS:-0.4mm 0.2mm}'.split() for k in (2, 4)})))")
  echo "== C1 boxes: uniform at $fine"
  "$build/validation/pd-validate-c1" geometries/c1_plate_hole.geo --spacing "$fine" --grids uniform "${common[@]}" \
    -o "$work/boxes_uniform" | grep -v "^FEM"
  for f in ${BOX_SPACINGS:-0.4mm 0.2mm} uniform; do
    f="$work/boxes_$f/c1_errors.csv"
    if [ ! -f "$rows" ]; then head -1 "$f" > "$rows"; fi
    tail -n +2 "$f" >> "$rows"
  done
  python3 bench/accuracy_cost_report.py --box-spacing "$rows" docs/accuracy-cost.md docs/img
}
# ---- end of finer NB-NUG boxes -------------------------------------------------

grid_rows() {
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
}

for part in $parts; do
  case $part in
    grids) grid_rows ;;
    boxes) box_spacing_rows ;;
    *) echo "bench/accuracy_cost.sh: unknown part '$part' (use grids, boxes)" >&2; exit 2 ;;
  esac
done
