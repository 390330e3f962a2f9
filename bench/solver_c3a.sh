#!/usr/bin/env bash
# Solver throughput on case C3-A at the paper's resolution (dx = 0.04 mm,
# delta = 0.16 mm, m = 4: 772,000 particles, 52 million directed bonds) with
# damage and surface correction on, for a fixed number of steps; then LAMMPS
# peri/pmb on a problem with about the same number of bonds, in the same run,
# and the ratio of the two. Peak memory per directed bond is reported too.
# Then the same for the ordinary state-based model (model.type = "osb",
# nu = 0.35) against LAMMPS peri/lps (bench/lammps_lps.in), printing
# osb_directed_bond_evals_per_s_per_core=<number>.
# Last line: directed_bond_evals_per_s_per_core=<number> (PMB)
#
# Usage: bench/solver_c3a.sh [BUILD_DIR] [STEPS] [MODELS]
#   defaults: build, 1000, "pmb osb" (either or both)
# C3A_PARTICLES=<file.pdp> reuses a particle file of C3-A at dx = 0.04 mm
# (pd-mesh geometries/c3a_pores.geo --spacing 0.04mm --horizon 0.16mm
# --padding 0.25mm) instead of meshing it again.
# Needs root (or sudo) once, to install the Debian package lammps.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
steps=${2:-1000}
models=${3:-pmb osb}
cores=$(nproc)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if ! command -v lmp > /dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends lammps < /dev/null > /dev/null
fi

particles=${C3A_PARTICLES:-}
if [ -z "$particles" ]; then
  echo "== pd-mesh: C3-A, dx = 0.04 mm, delta = 0.16 mm"
  particles="$work/c3a.pdp"
  "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing 0.04mm --horizon 0.16mm --padding 0.25mm \
    -o "$particles" | grep -E "^grid|^families"
else
  echo "== particles: $particles"
fi

# solve NAME [--set key=value ...]: runs pd-solve for $steps steps into
# $work/NAME; sets `rate` (directed bond evaluations/s), `bonds` (directed
# bonds), `rss_kb` (peak RSS of the whole process) and `own_peak` (pd-solve's
# own peak memory per directed bond, summary.json).
solve() {
  local name=$1
  shift
  /usr/bin/time -f "%M" -o "$work/$name.rss" \
    "$build/solver/pd-solve" geometries/c3a_long.toml --set particles="$particles" "$@" \
    --set time.end="$(python3 -c "print($steps * 2e-8)")" --set output.snapshot_interval=0 \
    --set output.checkpoint_interval=0 --set output.energy_interval=$steps -o "$work/$name" > "$work/$name.log" 2>&1
  rate=$(summary_value "$work/$name/summary.json" directed_bond_evaluations_per_second)
  bonds=$(summary_value "$work/$name/summary.json" directed_bonds)
  own_peak=$(summary_value "$work/$name/summary.json" peak_memory_bytes_per_directed_bond)
  rss_kb=$(cat "$work/$name.rss")
}

# lammps INPUT STEPS: LAMMPS on a simple cubic slab with about $bonds bonds,
# $cores MPI ranks; sets `lammps_rate` and `lammps_bonds`.
lammps() {
  local input=$1 lammps_steps=$2
  # 56 bonds per interior atom on the lattice: choose a 40-atom-thick slab of
  # the same number of bonds (surface atoms have fewer; LAMMPS reports the mean).
  local nz=40
  local nxy
  nxy=$(python3 -c "import math; print(int(round(math.sqrt($bonds / 52.0 / $nz))))")
  mpirun --allow-run-as-root --oversubscribe -np "$cores" lmp -in "$input" -log none \
    -var nx "$nxy" -var ny "$nxy" -var nz "$nz" -var steps "$lammps_steps" > "$work/lammps.log" 2>&1
  read -r lammps_rate lammps_bonds < <(python3 - "$work/lammps.log" "$lammps_steps" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
atoms = int(re.search(r"Created (\d+) atoms", text).group(1))
per_atom = float(re.search(r"bonds/atom = ([0-9.eE+-]+)", text).group(1))
loop = float(re.search(r"Loop time of ([0-9.eE+-]+)", text).group(1))
print(atoms * per_atom * int(sys.argv[2]) / loop, int(atoms * per_atom))
PY
)
}

pmb_line=""
if [[ " $models " == *" pmb "* ]]; then
  echo "== pd-solve: $steps steps of 0.02 us, damage and surface correction on, $cores threads"
  solve pmb
  ours=$rate
  echo "pd-solve: $ours directed bond evaluations/s on $cores cores; peak RSS $((rss_kb / 1024)) MB = $(python3 -c "print(f'{$rss_kb * 1024 / $bonds:.1f}')") bytes per directed bond"

  echo "== LAMMPS peri/pmb: same number of bonds, $cores MPI ranks"
  lammps_steps=$(( steps / 4 > 10 ? steps / 4 : 10 ))
  lammps bench/lammps_pmb.in "$lammps_steps"
  echo "LAMMPS: $lammps_rate directed bond evaluations/s on $cores ranks ($lammps_bonds bonds, $lammps_steps steps)"
  python3 -c "print(f'ratio pd-solve / LAMMPS: {$ours / $lammps_rate:.2f}')"
  pmb_line=$(python3 -c "print(f'directed_bond_evals_per_s_per_core={$ours / $cores:.4g}')")
fi

if [[ " $models " == *" osb "* ]]; then
  echo "== pd-solve OSB (nu = 0.35): $steps steps of 0.02 us, damage and surface correction on, $cores threads"
  solve osb --set model.type=osb --set material.poisson_ratio=0.35
  osb=$rate
  echo "pd-solve OSB: $osb directed bond evaluations/s on $cores cores; peak RSS $((rss_kb / 1024)) MB = $(python3 -c "print(f'{$rss_kb * 1024 / $bonds:.1f}')") bytes per directed bond (pd-solve's own peak: $(python3 -c "print(f'{$own_peak:.2f}')"))"

  echo "== LAMMPS peri/lps: same number of bonds, $cores MPI ranks"
  lammps_steps=$(( steps / 10 > 10 ? steps / 10 : 10 ))
  lammps bench/lammps_lps.in "$lammps_steps"
  echo "LAMMPS peri/lps: $lammps_rate directed bond evaluations/s on $cores ranks ($lammps_bonds bonds, $lammps_steps steps)"
  python3 -c "print(f'ratio pd-solve OSB / LAMMPS peri/lps: {$osb / $lammps_rate:.2f}')"
  python3 -c "print(f'osb_directed_bond_evals_per_s_per_core={$osb / $cores:.4g}')"
fi

[ -n "$pmb_line" ] && echo "$pmb_line"
exit 0
