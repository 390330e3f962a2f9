#!/usr/bin/env bash
# The paper's full case C3-A end to end, as geometries/c3a_long.toml is
# written (dx = 0.04 mm, delta = 0.16 mm, m = 4: 772,000 particles, 52 million
# directed bonds; 15,000 steps of 0.02 us, an energy row every 50 steps, a
# snapshot every 500, a checkpoint every 5000): pd-mesh, pd-solve, pd-post,
# each timed, on all cores. Prints each tool's wall time and peak memory, the
# solver's time-loop throughput, and the total.
#
# Usage: bench/full_case_c3a.sh [BUILD_DIR [KEEP_DIR]]   (default: build;
#   KEEP_DIR keeps the particle file and the results, e.g. to compare runs)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ $# -ge 2 ]; then
  work=$2
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
. bench/lib.sh
rm -f "$work/times.txt"

echo "== pd-mesh: C3-A, dx = 0.04 mm, delta = 0.16 mm"
timed "$work/times.txt" mesh "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing 0.04mm --horizon 0.16mm --padding 0.25mm \
  -o "$work/c3a.pdp" > "$work/mesh.log"
grep -E "^families|^time" "$work/mesh.log"

echo "== pd-solve: geometries/c3a_long.toml as written, $(nproc) threads"
rm -rf "$work/run"
timed "$work/times.txt" solve "$build/solver/pd-solve" geometries/c3a_long.toml --set particles="$work/c3a.pdp" -o "$work/run" -q \
  > "$work/solve.log" 2>&1 || { cat "$work/solve.log"; exit 1; }
tail -n 1 "$work/solve.log"

echo "== pd-post"
timed "$work/times.txt" post "$build/post/pd-post" "$work/run" > "$work/post.log" 2>&1 || { cat "$work/post.log"; exit 1; }

python3 - "$work/times.txt" "$work/run/summary.json" <<'PY'
import sys
sys.path.insert(0, "bench")
from summary_json import find, load
times = {}
for line in open(sys.argv[1]):
    name, wall, peak, user, system = line.split()
    times[name] = (float(wall), int(peak), float(user) + float(system))
for name, (wall, peak, cpu) in times.items():
    print(f"{name}: {wall:.1f} s wall, {cpu:.1f} s CPU, peak {peak / 1024:.0f} MB")
s = load(sys.argv[2])
rate = find(s, "directed_bond_evaluations_per_second")
bonds = find(s, "directed_bonds")
print(f"time loop: {find(s, 'steps')} steps, {rate:.3g} directed bond evaluations/s "
      f"({find(s, 'directed_bond_evaluations_per_second_per_thread'):.3g} per thread); "
      f"solver peak {times['solve'][1] * 1024 / bonds:.2f} bytes per directed bond")
total = sum(w for w, _, _ in times.values())
print(f"total (mesh + solve + post): {total:.1f} s = {total / 60:.2f} min")
PY
