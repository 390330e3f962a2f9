#!/usr/bin/env bash
# pd-solve on 2 MPI processes x 1 thread against 1 process x 2 threads on case
# C3-A (long pre-crack, damage and surface correction on), for a fixed number
# of steps (docs/solver.md, "Running on several processes (MPI)";
# docs/scaling.md uses the figures). Prints per configuration: directed bond
# evaluations per second per core, the parallel efficiency of the 2-process
# run (its rate per core over the threaded run's: below 1 also because every
# bond of a distributed run runs on the neighbour lists, the threaded one on
# the lattice sweep), the ghost bytes sent per step (all processes) and the
# time in the ghost exchange (slowest process, waiting included).
#
# Usage: bench/mpi_c3a.sh [BUILD_DIR] [SPACING] [STEPS]
#   defaults: build, 0.04mm (the paper's resolution: 772,000 particles), 500.
#   A quick check of the script: bench/mpi_c3a.sh build 0.3125mm 200
# C3A_PARTICLES=<file.pdp> reuses a particle file of that spacing.
# MPIEXEC_FLAGS: extra mpiexec flags (default: --oversubscribe, and
# --allow-run-as-root when run as root).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
spacing=${2:-0.04mm}
steps=${3:-500}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=${MPIEXEC_FLAGS:---oversubscribe}
[ "$(id -u)" -eq 0 ] && [ -z "${MPIEXEC_FLAGS:-}" ] && flags="$flags --allow-run-as-root"

particles=${C3A_PARTICLES:-}
if [ -z "$particles" ]; then
  horizon=$(python3 -c "print(f'{4 * float(\"${spacing%mm}\"):g}mm')")
  echo "== pd-mesh: C3-A, dx = $spacing, delta = $horizon"
  particles="$work/c3a.pdp"
  "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" --padding 0.25mm \
    -o "$particles" | grep -E "^grid|^families" || true
fi

# A fixed number of steps: the end time is steps x the automatic step, which
# the first (1-step) run reports.
common=(geometries/c3a_long.toml --set "particles=\"$(realpath "$particles")\"" --set time.step=auto
        --set output.snapshot_interval=0 --set output.checkpoint_interval=0 --set output.energy_interval=100 -q)
"$build/solver/pd-solve" "${common[@]}" --set time.end=1e-12 -o "$work/probe" > /dev/null
dt=$(python3 bench/summary_json.py "$work/probe/summary.json" time_step_s)
end=$(python3 -c "print($dt * ($steps - 0.5))")

value() { python3 bench/summary_json.py "$1/summary.json" "$2"; }
run_case() {  # name, launcher..., then pd-solve arguments after --
  local name=$1; shift
  local launch=()
  while [ "$1" != "--" ]; do launch+=("$1"); shift; done
  shift
  echo "== $name"
  "${launch[@]}" "$build/solver/pd-solve" "${common[@]}" --set time.end="$end" -o "$work/$name" "$@" > "$work/$name.log"
  grep -E "^  (kernel|threads):" "$work/$name.log" || true
}

run_case threads2 env -- --threads 2
run_case mpi2 mpiexec -n 2 $flags -- --threads 1
python3 - "$work" <<'PY'
import json, sys
sys.path.insert(0, "bench")
from summary_json import load, find
work = sys.argv[1]
def rate(name):
    s = load(f"{work}/{name}/summary.json")
    return find(s, "directed_bond_evaluations_per_second"), find(s, "threads") * (find(s, "processes") or 1), s
t2, cores_t2, _ = rate("threads2")
m2, cores_m2, s = rate("mpi2")
mpi = find(s, "mpi") or {}
print(f"1 process x 2 threads (lattice sweep): {t2 / cores_t2:.4g} directed bond evaluations/s per core")
print(f"2 processes x 1 thread (neighbour lists): {m2 / cores_m2:.4g} directed bond evaluations/s per core")
print(f"parallel efficiency, 2 x 1 against 1 x 2 (rate per core): {(m2 / cores_m2) / (t2 / cores_t2):.3f}")
print(f"ghost bytes sent per step (all processes): {mpi.get('ghost_bytes_per_step')}")
print(f"ghost exchange time, slowest process: {mpi.get('ghost_update_seconds_max')} s "
      f"of {find(s, 'wall_time_s')} s wall")
PY
