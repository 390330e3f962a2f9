#!/usr/bin/env bash
# What accuracy costs in time for dynamic fracture (docs/accuracy-cost.md,
# "Dynamic fracture: C3-A and C3-B"): the perforated PMMA plates C3-A and
# C3-B with the long pre-crack (geometries/c3X_long.toml as written, bond-based
# PMB, NB-NUG grid, automatic time step), run by bench/c3_side_by_side.sh at
#   - horizons delta = 0.24, 0.20, 0.16 mm with m = 4 (dx = delta / 4), and
#   - m = 3, 4, 5 at delta = 0.5 mm (dx = 0.1667, 0.125, 0.1 mm);
#   - and, where RUNS asks for them (DELTA:M:boxes2), the same plates with the
#     boxes round the pores meshed at dx / 2 and dual horizons
#     (bench/c3_side_by_side.sh's grid boxes2): what finer boxes buy.
# dx is the nearest spacing that divides the plate's 25 mm side (25 / n mm);
# the table gives the delta = m dx that ran. Then
# bench/accuracy_cost_dynamic_report.py writes the section of
# docs/accuracy-cost.md that follows its marker (the C1 part before it is
# bench/accuracy_cost.sh's) and docs/img/accuracy_cost_c3_*.svg: initiation
# time, crack speed before the first pore, trapping times, time of
# separation, branch count, against CPU time and particles.
#
# Usage: bench/accuracy_cost_dynamic.sh [BUILD_DIR [WORK]]
#   defaults: build, results/accuracy_cost_dynamic. RUNS (environment) picks
#   the (delta, m) pairs, e.g. RUNS="0.5:3 0.5:4 0.5:5"; the default is all six;
#   RUNS="0.5:4:boxes2 0.24:4:boxes2" adds the finer boxes at those two.
#   Runs whose results exist are not repeated (bench/c3_side_by_side.sh), so
#   an interrupted study resumes. Time on 2 free cores: the delta = 0.5 mm runs
#   take minutes; delta = 0.16 mm (dx = 0.04 mm, the paper's) about 5 minutes
#   of time loop per run, hours on a busy machine.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=${2:-results/accuracy_cost_dynamic}
runs=${RUNS:-"0.5:3 0.5:4 0.5:5 0.24:4 0.2:4 0.16:4"}
mkdir -p "$work"
# The machine's load average every 30 s while the study runs (WORK/load.txt,
# "HH:MM:SS 1-min 5-min 15-min"): the report says how busy the machine was,
# since the costs are only comparable within a quiet sitting.
( while true; do echo "$(date +%T) $(cut -d' ' -f1-3 /proc/loadavg)"; sleep 30; done ) >> "$work/load.txt" &
sampler=$!
trap 'kill $sampler 2>/dev/null' EXIT
for run in $runs; do
  IFS=: read -r delta m grid <<< "$run"
  variant=pmb
  [ -z "$grid" ] || variant="$grid:pmb"
  # The nearest spacing to delta / m that divides the 25 mm side.
  dx=$(python3 -c "n = round(25 / ($delta / $m)); print(f'{25 / n:.10g}mm')")
  echo "=== delta = $delta mm, m = $m: dx = $dx ${grid:+($grid)}"
  CASES="a b" VARIANTS=$variant HORIZON_FACTOR=$m bash bench/c3_side_by_side.sh "$build" "$dx" \
    "$work/delta_${delta}mm_m_$m" | grep -v "^comparison:"
done
python3 bench/accuracy_cost_dynamic_report.py "$work" docs/accuracy-cost.md docs/img
