#!/usr/bin/env bash
# pd-solve on 2 MPI processes x 1 thread against 1 process x 2 threads on case
# C3-A (long pre-crack, damage and surface correction on), for a fixed number
# of steps (docs/solver.md, "Running on several processes (MPI)";
# docs/scaling.md and docs/performance.md use the figures). Both run the
# lattice sweep for the squares (each process on its slab). The two
# configurations run alternately, PAIRS times, so that a machine whose load
# changes affects both alike. Prints per run and as medians: directed bond
# evaluations per second per core, the parallel efficiency of the 2-process
# run (its rate per core over the threaded run's of the same pair), the
# ghost bytes sent per step (all processes, the communicator's counters) and
# the time in the ghost exchange (slowest process, waiting for the
# neighbour included, measured around the exchange) against the run's wall time.
#
# Usage: bench/mpi_c3a.sh [BUILD_DIR] [SPACING] [STEPS] [PAIRS]
#   defaults: build, 0.04mm (the paper's resolution: 772,000 particles), 500, 2.
#   A quick check of the script: bench/mpi_c3a.sh build 0.3125mm 200 2
# C3A_PARTICLES=<file.pdp> reuses a particle file of that spacing.
# MPIEXEC_FLAGS: extra mpiexec flags (default: --oversubscribe --bind-to none,
# and --allow-run-as-root when run as root). NICE: a niceness for every run (default 0).
# MODEL: the scene's model.type, pmb (default) or osb (ordinary state-based PD:
# a second ghost exchange per step, theta / m after the dilatation pass).
#   MODEL=osb bench/mpi_c3a.sh build 0.08mm 300 2
# BASELINE=<another build directory>: each pair also runs that build's pd-solve
# on 2 processes right after this one's (before/after a change on a machine
# whose load drifts: the same pair, one after the other), and prints its
# efficiency against the same threaded run.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
spacing=${2:-0.04mm}
steps=${3:-500}
pairs=${4:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=${MPIEXEC_FLAGS:---oversubscribe --bind-to none}
[ "$(id -u)" -eq 0 ] && [ -z "${MPIEXEC_FLAGS:-}" ] && flags="$flags --allow-run-as-root"
niceness=${NICE:-0}
model=${MODEL:-pmb}
case "$model" in
  pmb|osb) ;;
  *) echo "bench/mpi_c3a.sh: MODEL=$model: expected pmb or osb" >&2; exit 1 ;;
esac

particles=${C3A_PARTICLES:-}
if [ -z "$particles" ]; then
  horizon=$(python3 -c "print(f'{4 * float(\"${spacing%mm}\"):g}mm')")
  # The boxes' padding: 0.25 mm (the paper's resolution), at least one horizon (pd-mesh's rule).
  padding=$(python3 -c "print(f'{max(0.25, 4 * float(\"${spacing%mm}\")):g}mm')")
  echo "== pd-mesh: C3-A, dx = $spacing, delta = $horizon"
  particles="$work/c3a.pdp"
  nice -n "$niceness" "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
    --padding "$padding" -o "$particles" | grep -E "^grid|^families" || true
fi

# A fixed number of steps: the end time is steps x the automatic step, which
# the first (1-step) run reports.
common=(geometries/c3a_long.toml --set "particles=\"$(realpath "$particles")\"" --set "model.type=\"$model\""
        --set time.step=auto
        --set output.snapshot_interval=0 --set output.checkpoint_interval=0 --set output.energy_interval=100 -q)
"$build/solver/pd-solve" "${common[@]}" --set time.end=1e-12 -o "$work/probe" > /dev/null
dt=$(python3 bench/summary_json.py "$work/probe/summary.json" time_step_s)
end=$(python3 -c "print($dt * ($steps - 0.5))")

run_case() {  # name, launcher..., then pd-solve arguments after --
  local name=$1; shift
  local launch=()
  while [ "$1" != "--" ]; do launch+=("$1"); shift; done
  shift
  echo "== $name, model $model (load: $(cut -d' ' -f1-3 /proc/loadavg))"
  nice -n "$niceness" "${launch[@]}" "$build/solver/pd-solve" "${common[@]}" --set time.end="$end" \
    -o "$work/$name" "$@" > "$work/$name.log"
  grep -E "^  (kernel|threads):" "$work/$name.log" || true
}

baseline=${BASELINE:-}
for pair in $(seq 1 "$pairs"); do
  run_case "threads2_$pair" env -- --threads 2
  run_case "mpi2_$pair" mpiexec -n 2 $flags -- --threads 1
  if [ -n "$baseline" ]; then
    saved=$build
    build=$baseline
    run_case "baseline_mpi2_$pair" mpiexec -n 2 $flags -- --threads 1
    build=$saved
  fi
done
python3 - "$work" "$pairs" "$baseline" <<'PY'
import statistics, sys
sys.path.insert(0, "bench")
from summary_json import load, find
work, pairs, baseline = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def per_core(name):
    s = load(f"{work}/{name}/summary.json")
    cores = find(s, "threads") * (find(s, "processes") or 1)
    return find(s, "directed_bond_evaluations_per_second") / cores, s
threaded, distributed, efficiency, exchange_share, baseline_efficiency = [], [], [], [], []
for p in range(1, pairs + 1):
    t, _ = per_core(f"threads2_{p}")
    m, s = per_core(f"mpi2_{p}")
    mpi = find(s, "mpi") or {}
    wall = find(s, "wall_time_s")
    steps = find(s, "steps_this_run")
    seconds = mpi.get("ghost_update_seconds_max", 0.0)
    waiting = mpi.get("ghost_wait_seconds_max")  # the finishing halves (builds that split the exchange)
    threaded.append(t)
    distributed.append(m)
    efficiency.append(m / t)
    exchange_share.append(seconds / wall)
    print(f"pair {p}: 1 x 2 threads {t:.4g}, 2 processes x 1 thread {m:.4g} directed bond evaluations/s per core; "
          f"efficiency {m / t:.3f}; ghost bytes per step {mpi.get('ghost_bytes_per_step')} "
          f"in {mpi.get('ghost_exchanges_per_step', 1)} exchanges; "
          f"ghost exchange {seconds:.3g} s of {wall:.3g} s wall ({1e6 * seconds / steps:.1f} us per step"
          + (f", of which finishing {1e6 * waiting / steps:.1f} us" if waiting is not None else "") + "); "
          f"lattice particles {find(s, 'lattice_particles')} of {find(s, 'particles') or '?'}")
    if baseline:
        b, bs = per_core(f"baseline_mpi2_{p}")
        bmpi = find(bs, "mpi") or {}
        bseconds = bmpi.get("ghost_update_seconds_max", 0.0)
        baseline_efficiency.append(b / t)
        print(f"        baseline 2 processes x 1 thread {b:.4g} per core; efficiency {b / t:.3f}; "
              f"ghost exchange {bseconds:.3g} s of {find(bs, 'wall_time_s'):.3g} s wall "
              f"({1e6 * bseconds / find(bs, 'steps_this_run'):.1f} us per step)")
median = statistics.median
print(f"median of {pairs} pairs:")
print(f"  1 process x 2 threads:   {median(threaded):.4g} directed bond evaluations/s per core")
print(f"  2 processes x 1 thread:  {median(distributed):.4g} directed bond evaluations/s per core")
print(f"  parallel efficiency (2 x 1 over 1 x 2, per core): {median(efficiency):.3f}")
print(f"  time in the ghost exchange: {100 * median(exchange_share):.2f} % of the wall time")
if baseline_efficiency:
    print(f"  baseline build, 2 processes: parallel efficiency {median(baseline_efficiency):.3f}")
PY
