#!/usr/bin/env bash
# Case C2 (geometries/c2_fracture.toml: the plate with a hole pulled apart
# quasi-statically with damage, docs/validation.md "C2") on the lattice
# kernels at a given spacing, m = 4, to separation: meshes, runs pd-solve and
# prints wall and CPU time, NCG/CG iterations and minimisations, pairs
# broken, the cracks at the hole (pd-validate-c2 --count-cracks), the peak
# reaction, and the peak memory per directed bond (docs/performance.md,
# "Quasi-static on the fast kernels").
#
# Usage: bench/c2_quasi_static.sh SPACING [THREADS] [BUILD_DIR] [pd-solve options...]
#   e.g. nice -n 5 bench/c2_quasi_static.sh 0.05mm 2
#        bench/c2_quasi_static.sh 0.2mm 1 build --set 'quasi_static.increments=[[4,1.0],[30,0.1]]'
# GRID=free (or uniform) meshes that grid instead of NB-NUG (pd-mesh --grid;
# a free mesh has no lattice squares: the kernel's general particles' lists
# do all, docs/solver.md "Fast kernels").
# Output folder: out/bench_c2_SPACING (or $C2_OUT). CPU time is user +
# system: the measure a loaded machine distorts least (on 2 free cores the
# wall time is about CPU / 2).
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
spacing=${1:?usage: bench/c2_quasi_static.sh SPACING [THREADS] [BUILD_DIR] [pd-solve options...]}
threads=${2:-2}
build=${3:-build}
shift $(( $# < 3 ? $# : 3 ))
out=${C2_OUT:-out/bench_c2_$spacing}
grid=${GRID:-nbnug}
horizon=$(python3 -c "import sys; s = sys.argv[1]; print(f'{4 * float(s[:-2]):g}mm')" "$spacing")
mkdir -p "$out"
rm -f "$out/times.txt"
"$build/mesher/pd-mesh" geometries/c1_plate_hole.geo --spacing "$spacing" --horizon "$horizon" --grid "$grid" -o "$out/c1.pdp" >"$out/mesh.log"
timed "$out/times.txt" c2 "$build/solver/pd-solve" geometries/c2_fracture.toml --set "particles=\"$out/c1.pdp\"" \
  --set 'quasi_static.kernels="lattice"' --set 'output.snapshot_interval=0' --threads "$threads" -o "$out/run" "$@" \
  2>"$out/progress.log" >"$out/solve.log"
read -r _ wall peak_kb user sys <"$out/times.txt"
steps="$out/run/load_steps.csv"
python3 - "$steps" "$out/run/summary.json" "$wall" "$user" "$sys" "$peak_kb" <<'PY'
import csv, json, sys
steps, summary, wall, user, sys_s, peak_kb = sys.argv[1:]
rows = list(csv.DictReader(open(steps)))
reaction = [abs(float(r["right_reaction_x_N"])) for r in rows]
s = json.load(open(summary))
def find(d, key):
    if isinstance(d, dict):
        if key in d: return d[key]
        for v in d.values():
            x = find(v, key)
            if x is not None: return x
    if isinstance(d, list):
        for v in d:
            x = find(v, key)
            if x is not None: return x
    return None
print(f"load steps: {len(rows)}, minimisations: {sum(int(r['minimisations']) for r in rows)}, "
      f"iterations: {sum(int(r['iterations']) for r in rows)}")
print(f"pairs broken: {sum(int(r['pairs_broken']) for r in rows)}, directed bonds broken: {rows[-1]['broken_bonds']}")
print(f"peak reaction: {max(reaction):.6g} N, last: {reaction[-1]:.6g} N at load factor {rows[-1]['load_factor']}")
print(f"stop: {find(s, 'stop_reason')}")
print(f"wall: {float(wall):.0f} s, CPU: {float(user) + float(sys_s):.0f} s (user {user}, system {sys_s})")
print(f"peak memory: {int(peak_kb) / 1024:.0f} MiB, {find(s, 'peak_memory_bytes_per_directed_bond'):.1f} bytes per directed bond")
PY
"$build/validation/pd-validate-c2" geometries/c1_plate_hole.geo --spacing "$spacing" --count-cracks "$out/run"
