#!/usr/bin/env bash
# Solver throughput on case C3-A at the paper's resolution (dx = 0.04 mm,
# delta = 0.16 mm, m = 4: 772,000 particles, 52 million directed bonds) with
# damage and surface correction on, for a fixed number of steps; then LAMMPS
# peri/pmb on a problem with about the same number of bonds, in the same run,
# and the ratio of the two. Peak memory per directed bond is reported too.
# Last line: directed_bond_evals_per_s_per_core=<number>
#
# Usage: bench/solver_c3a.sh [BUILD_DIR] [STEPS]   (defaults: build, 1000)
# Needs root (or sudo) once, to install the Debian package lammps.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-1000}
cores=$(nproc)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. bench/lib.sh

if ! command -v lmp > /dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends lammps < /dev/null > /dev/null
fi

echo "== pd-mesh: C3-A, dx = 0.04 mm, delta = 0.16 mm"
"$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing 0.04mm --horizon 0.16mm --padding 0.25mm \
  -o "$work/c3a.pdp" | grep -E "^grid|^families"

echo "== pd-solve: $steps steps of 0.02 us, damage and surface correction on, $cores threads"
/usr/bin/time -f "%M" -o "$work/rss.txt" \
  "$build/solver/pd-solve" geometries/c3a_long.toml --set particles="$work/c3a.pdp" \
  --set time.end="$(python3 -c "print($steps * 2e-8)")" --set output.snapshot_interval=0 \
  --set output.checkpoint_interval=0 --set output.energy_interval=$steps -o "$work/run" > "$work/solve.log" 2>&1
ours=$(summary_value "$work/run/summary.json" directed_bond_evaluations_per_second)
bonds=$(summary_value "$work/run/summary.json" directed_bonds)
rss_kb=$(cat "$work/rss.txt")
echo "pd-solve: $ours directed bond evaluations/s on $cores cores; peak RSS $((rss_kb / 1024)) MB = $(python3 -c "print(f'{$rss_kb * 1024 / $bonds:.1f}')") bytes per directed bond"

echo "== LAMMPS peri/pmb: same number of bonds, $cores MPI ranks"
# 56 bonds per interior atom on the lattice: choose a 40-atom-thick slab of
# the same number of bonds (surface atoms have fewer; LAMMPS reports the mean).
nz=40
nxy=$(python3 -c "import math; print(int(round(math.sqrt($bonds / 52.0 / $nz))))")
lammps_steps=$(( steps / 4 > 10 ? steps / 4 : 10 ))
mpirun --allow-run-as-root --oversubscribe -np "$cores" lmp -in bench/lammps_pmb.in -log none \
  -var nx "$nxy" -var ny "$nxy" -var nz "$nz" -var steps "$lammps_steps" > "$work/lammps.log" 2>&1
lammps=$(python3 - "$work/lammps.log" "$lammps_steps" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
atoms = int(re.search(r"Created (\d+) atoms", text).group(1))
per_atom = float(re.search(r"bonds/atom = ([0-9.eE+-]+)", text).group(1))
loop = float(re.search(r"Loop time of ([0-9.eE+-]+)", text).group(1))
print(atoms * per_atom * int(sys.argv[2]) / loop, int(atoms * per_atom))
PY
)
read -r lammps_rate lammps_bonds <<< "$lammps"
echo "LAMMPS: $lammps_rate directed bond evaluations/s on $cores ranks ($lammps_bonds bonds, $lammps_steps steps)"
python3 -c "print(f'ratio pd-solve / LAMMPS: {$ours / $lammps_rate:.2f}')"
python3 -c "print(f'directed_bond_evals_per_s_per_core={$ours / $cores:.4g}')"
