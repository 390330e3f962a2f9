#!/usr/bin/env bash
# The set-up of pd-solve on 1, 2 and 3 MPI processes on case C3-A
# (geometries/c3a_long.toml, one time step, 1 thread per process): the peak
# resident set and the CPU seconds (user + system) of every process, for one
# or two pd-solve executables run alternately, so that a changing load
# affects both alike (docs/scaling.md, "What limits it today"). A one-step
# run is its set-up, the particle file's reading included, and one step.
#
# Usage: bench/mpi_setup.sh SPACING PD_SOLVE [PD_SOLVE_2]
#   e.g. bench/mpi_setup.sh 0.08012820513mm ../main/build/solver/pd-solve build/solver/pd-solve
# Prints one line per run: executable, processes, then per rank (rank 0
# first) "peak MiB / CPU s".
# PD_MESH: the mesher (default build/mesher/pd-mesh). NICE: a niceness for
# every run (default 5). MPIEXEC_FLAGS as bench/mpi_c3a.sh. SCENE: another
# scene of the same plate (default geometries/c3a_long.toml; e.g. a copy with
# model.type = "osb"). PROCESSES: the process counts (default "1 2 3").
# MESH_OPTIONS: more pd-mesh options (e.g. "--box-spacing 0.04mm", a file
# whose horizons differ, with a SCENE that sets model.dual_horizon).
set -euo pipefail
cd "$(dirname "$0")/.."
spacing=${1:?spacing, e.g. 0.0801mm}
shift
[ $# -ge 1 ] || { echo "bench/mpi_setup.sh: give one or two pd-solve executables" >&2; exit 1; }
solvers=("$@")
mesher=${PD_MESH:-build/mesher/pd-mesh}
niceness=${NICE:-5}
flags=${MPIEXEC_FLAGS:---oversubscribe --bind-to none}
[ "$(id -u)" -eq 0 ] && [ -z "${MPIEXEC_FLAGS:-}" ] && flags="$flags --allow-run-as-root"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

horizon=$(python3 -c "print(f'{4 * float(\"${spacing%mm}\"):g}mm')")
padding=$(python3 -c "print(f'{max(0.25, 4 * float(\"${spacing%mm}\")):g}mm')")
particles="$work/c3a.pdp"
nice -n "$niceness" "$mesher" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
  --padding "$padding" ${MESH_OPTIONS:-} -o "$particles" > "$work/mesh.log"
grep -E "^grid|^families" "$work/mesh.log" || true

scene=${SCENE:-geometries/c3a_long.toml}
common=("$scene" --set "particles=\"$particles\"" --set output.snapshot_interval=0
        --set output.checkpoint_interval=0 --set output.energy_interval=100 --set time.step=auto --threads 1 -q)
dt=$(nice -n "$niceness" "${solvers[0]}" "${common[@]}" --set time.end=1e-12 -o "$work/probe" > /dev/null &&
     python3 bench/summary_json.py "$work/probe/summary.json" time_step_s)
end=$(python3 -c "print($dt * 0.5)")  # one step

for processes in ${PROCESSES:-1 2 3}; do
  for s in "${!solvers[@]}"; do
    solver=$(realpath "${solvers[$s]}")
    out="$work/run_${s}_$processes"
    # Each rank times itself into its own file (OMPI_COMM_WORLD_RANK names it).
    nice -n "$niceness" mpiexec -n "$processes" $flags sh -c \
      '/usr/bin/time -f "%M %U %S" -o "$0.rank${OMPI_COMM_WORLD_RANK:-0}" "$@" > /dev/null' "$out" \
      "$solver" "${common[@]}" --set time.end="$end" -o "$out"
    line="${solvers[$s]} np=$processes:"
    for rank in $(seq 0 $((processes - 1))); do
      read -r kib user system < "$out.rank$rank"
      line="$line $(python3 -c "print(f'{$kib / 1024:.0f} MiB / {$user + $system:.2f} s')"),"
    done
    echo "${line%,}"
  done
done
