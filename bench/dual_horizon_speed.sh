#!/usr/bin/env bash
# Speed of a dual-horizon run against the constant-horizon run of the same
# plate (docs/performance.md, "Dual horizons: the lattice sweep for the
# constant-horizon part"): case C3-A (geometries/c3a_long.toml, damage on)
# on the NB-NUG grid at dx with horizon 4 dx, once as meshed (one horizon:
# surface correction on, as the scene has it) and once with its boxes round
# the pores meshed at dx / 2 (pd-mesh --box-spacing; horizons 4 dx / 2 in the
# boxes; model.dual_horizon = true, surface correction off: refused with dual
# horizons). A fixed number of steps of each at its own automatic step, the
# two runs alternating, PAIRS times (a shared machine's load changes). Prints
# per run the directed bond evaluations per second from summary.json (time
# loop only; the dual-horizon run counts each directed bond once, as the
# constant-horizon run does), then the means and their ratio.
#
# Usage: bench/dual_horizon_speed.sh [BUILD_DIR] [SPACING] [STEPS] [PAIRS]
#   defaults: build, 0.04mm (the paper's resolution), 300, 2.
#   A quick check of the script: bench/dual_horizon_speed.sh build 0.25mm 100 1
#   (SPACING must divide the 50 mm x 25 mm plate: pd-mesh refuses 0.16mm)
# Runs pd-mesh and pd-solve at nice 5 (the machine may be shared).
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
spacing=${2:-0.04mm}
steps=${3:-300}
pairs=${4:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

mesh_c3a_with_boxes "$build" "$spacing" "$work"

common=(geometries/c3a_long.toml --set time.step=auto --set output.snapshot_interval=0
        --set output.checkpoint_interval=0 --set "output.energy_interval=$steps" -q)
constant=(--set "particles=\"$work/plain.pdp\"")
dual=(--set "particles=\"$work/boxes.pdp\"" --set model.dual_horizon=true --set effects.surface_correction=false)

# end_time NAME ARGS...: the end time of $steps steps at the case's automatic
# step, from a run of no step.
end_time() {
  local name=$1
  shift
  nice -n 5 "$build/solver/pd-solve" "${common[@]}" "$@" --set time.end=1e-12 -o "$work/probe_$name" > /dev/null
  python3 -c "print($(summary_value "$work/probe_$name/summary.json" time_step_s) * ($steps - 0.5))"
}
constant_end=$(end_time constant "${constant[@]}")
dual_end=$(end_time dual "${dual[@]}")

# run NAME END ARGS...: one timed run; prints its rate and appends it to $work/NAME.rates.
run() {
  local name=$1 end=$2
  shift 2
  nice -n 5 "$build/solver/pd-solve" "${common[@]}" "$@" --set time.end="$end" -o "$work/$name" > "$work/$name.log"
  local rate
  rate=$(summary_value "$work/$name/summary.json" directed_bond_evaluations_per_second)
  echo "$rate" >> "$work/$name.rates"
  echo "$name: $rate directed bond evaluations/s ($(summary_value "$work/$name/summary.json" directed_bonds) directed bonds, $steps steps)"
}

for pair in $(seq 1 "$pairs"); do
  echo "== pair $pair of $pairs"
  run constant "$constant_end" "${constant[@]}"
  run dual "$dual_end" "${dual[@]}"
done
echo "== the dual-horizon run's plan:"
grep -E "^  (particles|kernel|time step):" "$work/dual.log" || true
python3 - "$work" <<'PY'
import sys
work = sys.argv[1]
def mean(name):
    rates = [float(line) for line in open(f"{work}/{name}.rates")]
    return sum(rates) / len(rates)
constant, dual = mean("constant"), mean("dual")
print(f"mean: constant horizon {constant:.4g}, dual horizon {dual:.4g} directed bond evaluations/s")
print(f"ratio dual / constant: {dual / constant:.3f}")
PY
