#!/usr/bin/env bash
# What the grid changes at a curved boundary, case C1 (docs/validation.md,
# "C1: stress at the hole per grid"): per grid (NB-NUG, uniform, free), the
# hoop stress and the strain energy density at the first ring of particles
# around the hole against a CalculiX solution on the same geometry at two
# mesh sizes, with the plate pulled through loading layers beyond its edges
# (docs/scenes.md, "Which loading to use when"). One pd-validate-c1 run for all
# spacings (one FEM pair serves them all), then bench/grid_benefit_report.py
# rewrites the generated block of docs/validation.md and docs/img/c1_hoop_stress_*.svg,
# docs/img/c1_sed_ring_*.svg.
#
# Usage: bench/grid_benefit_c1.sh [BUILD_DIR] [SPACINGS] [HORIZON_FACTORS]
#   defaults: build, "0.2mm,0.1mm,0.05mm" (0.05 mm, m = 4: the paper's C1), "4".
#   About 15 min on 2 quiet cores (the three 140,000-particle solves take
#   most); coarse spacings first, and the tables are rewritten after every
#   run, so a stopped study keeps what it finished.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
spacings=${2:-"0.2mm,0.1mm,0.05mm"}
factors=${3:-4}
work=out/grid_benefit_c1
mkdir -p "$work"
# FEM: h = 0.1 mm and 0.05 mm at the hole; the report shows how little the
# hoop stress at the ring points changes between the two.
"$build/validation/pd-validate-c1" geometries/c1_plate_hole.geo --spacing "$spacings" -m "$factors" \
  --grids nbnug,uniform,free --loading layers --hole-stress --fem-size 0.1mm --fem-refinement \
  --tolerance 1e-8 -o "$work"
python3 bench/grid_benefit_report.py "$work" docs/validation.md docs/img
