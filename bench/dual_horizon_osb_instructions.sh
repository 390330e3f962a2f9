#!/usr/bin/env bash
# Instructions per step of dual-horizon OSB against constant-horizon OSB
# (docs/performance.md, "Dual-horizon OSB"): case C3-A
# (geometries/c3a_long.toml with model.type = "osb", surface correction
# off, a fixed step of 1e-8 s) meshed at dx with horizon 4 dx, and again with
# its boxes round the pores at dx / 2 (pd-mesh --box-spacing). Three runs
# under callgrind, one thread, STEPS steps each: the plain plate with one
# horizon (lattice sweep and lists), the same plate with
# model.dual_horizon = true, the boxes with model.dual_horizon = true (both
# with the lattice split of theory.md Sec. 6.8: the squares at the stencil's
# horizon on the sweep, the others on dual-horizon rows; the plan's kernel
# line says how many). Prints per run the inclusive instructions of
# Simulation::step divided by STEPS, and per directed bond, then each
# dual-horizon run's ratio to the constant-horizon run. Instruction counts
# do not depend on the machine's load; callgrind is some 50 times slower
# than a native run.
#
# Usage: bench/dual_horizon_osb_instructions.sh [BUILD_DIR] [SPACING] [STEPS]
#   defaults: build, 0.25mm, 10 (about 30 min on a shared 2-core machine).
#   A quick check of the script: bench/dual_horizon_osb_instructions.sh build 1mm 3
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
spacing=${2:-0.25mm}
steps=${3:-10}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mesh_c3a_with_boxes "$build" "$spacing" "$work"

end=$(python3 -c "print(($steps - 0.5) * 1e-8)")
common=(geometries/c3a_long.toml --set 'model.type="osb"' --set effects.surface_correction=false
        --set time.step=1e-8 --set time.end="$end" --set output.snapshot_interval=0
        --set output.checkpoint_interval=0 --set output.energy_interval=1000000 -q --threads 1)

# run NAME ARGS...: one run under callgrind; prints its instructions per
# step and keeps them in per_step[NAME].
declare -A per_step
run() {
  local name=$1
  shift
  nice -n 5 valgrind --tool=callgrind --callgrind-out-file="$work/$name.out" "$build/solver/pd-solve" \
    "${common[@]}" "$@" -o "$work/$name" > "$work/$name.log" 2> "$work/$name.err"
  local step bonds
  # The first (inclusive) line of Simulation::step; awk reads to the end, so
  # that no early close of the pipe fails it.
  step=$(callgrind_annotate --inclusive=yes "$work/$name.out" |
         awk '/Simulation::step\(/ && !found { found = 1; value = $1 } END { gsub(",", "", value); print value }')
  bonds=$(summary_value "$work/$name/summary.json" directed_bonds)
  per_step[$name]=$(python3 -c "print($step / $steps)")
  python3 -c "print(f'$name: {$step / $steps / 1e6:.1f} M instructions per step, ' \
f'{$step / $steps / $bonds:.1f} per directed bond ({$bonds} directed bonds)')"
  grep -E "^  kernel:" "$work/$name.log" || true
}

run constant --set "particles=\"$work/plain.pdp\""
run dual_plain --set "particles=\"$work/plain.pdp\"" --set model.dual_horizon=true
run dual_boxes --set "particles=\"$work/boxes.pdp\"" --set model.dual_horizon=true
for name in dual_plain dual_boxes; do
  python3 -c "print(f'$name / constant: {${per_step[$name]} / ${per_step[constant]}:.2f} per step')"
done
