#!/usr/bin/env bash
# The glass plate of docs/refinement.md: 100 mm x 40 mm, a 50 mm pre-crack
# from the left edge at mid-height, tractions sigma on top and bottom applied
# suddenly and held (case 1: 1 MPa, case 2: 2 MPa), PMB, m = 3, 80 us.
# Three runs per case: the coarse plate (dx = 1 mm), adaptive refinement
# from it (dx -> dx/2 ahead of the crack, dual-horizon PD), and the fine
# plate (dx = 0.5 mm). The uniform runs use the lattice kernel (no dual
# horizons), as a user would run them.
#
# Usage: bench/refinement_glass.sh [BUILD_DIR]
#   CASES="1 2"   VARIANTS="coarse adaptive fine"   LENGTH=1 (fraction of the 80 us)
#   OUT=out/refinement_glass   LEVELS=1 (halvings of the adaptive run)
#   REGION="[0.045, 0.008, 0.1, 0.032]" (where the adaptive run may split [m]:
#   the right half around the crack's path; the loaded strips, whose
#   particles carry the tractions as body forces, stretch beyond alpha s_c
#   wherever the waves meet and would be refined for nothing)
#   CHECK=20 (steps between checks)
# Prints one table row per run and writes OUT/table.md; GNU time's wall and
# CPU seconds go to OUT/times.txt. Run it with `nice` on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
out=${OUT:-out/refinement_glass}
cases=${CASES:-"1 2"}
variants=${VARIANTS:-"coarse adaptive fine"}
length=${LENGTH:-1}
levels=${LEVELS:-1}
region=${REGION:-"[0.045, 0.008, 0.1, 0.032]"}
check=${CHECK:-20}
mkdir -p "$out"
end=$(python3 -c "print(80e-6 * $length)")

for dx in 1 0.5; do
  plate="$out/glass_${dx}mm.pdp"
  [ -f "$plate" ] || "$build/mesher/pd-mesh" geometries/glass_plate.geo --grid uniform --spacing "${dx}mm" \
    --horizon "$(python3 -c "print(3 * $dx)")mm" -o "$plate" > "$out/mesh_${dx}mm.log"
done

row() {  # case variant: one line of the table from the run's and pd-post's summary.json
  local dir="$out/case$1_$2"
  python3 - "$dir" "$1" "$2" "$out/times.txt" <<'PY'
import csv, json, os, sys
sys.path.insert(0, "bench")
from summary_json import find, load
d, case, variant, times = sys.argv[1:5]
s = load(os.path.join(d, "summary.json"))
post = load(os.path.join(d, "post", "summary.json"))
ref = s.get("refinement", {})
n0 = ref.get("particles_start", find(s, "particles"))
n1 = ref.get("particles_end", n0)
cpu = "?"
for line in open(times):
    name, wall, peak, user, system = line.split()
    if name == f"case{case}_{variant}":
        cpu = f"{float(user) + float(system):.1f}"
events = []
with open(os.path.join(d, "post", "branching_events.csv")) as f:
    events = list(csv.DictReader(f))
if events:
    e = events[0]
    branching = f"{float(e['time_s']) * 1e6:.1f} us at ({float(e['x_m']) * 1e3:.1f}, {float(e['y_m']) * 1e3:.1f}) mm, {float(e['angle_deg']):.0f} deg"
else:
    branching = "none"
print(f"| {case} | {variant} | {n0} | {n1} | {s['wall_time_s']:.1f} | {cpu} | {ref.get('seconds', 0):.1f} | "
      f"{ref.get('events', 0)} | {branching} | {ref.get('bonds_broken_by_splits', '-')} |")
PY
}

echo "| case | run | particles start | particles end | wall s | CPU s | refining s | events | first branching (time, point, angle) | bonds broken by splits |" > "$out/table.md"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |" >> "$out/table.md"
for c in $cases; do
  sigma=$(python3 -c "print($c * 1e6)")
  for v in $variants; do
    args=(--set "time.end=$end" --set "loads.top.y=$sigma" --set "loads.bottom.y=-$sigma")
    case $v in
      coarse) args+=(--set "particles=$out/glass_1mm.pdp") ;;
      fine) args+=(--set "particles=$out/glass_0.5mm.pdp") ;;
      adaptive) args+=(--set "particles=$out/glass_1mm.pdp" --set model.dual_horizon=true
                       --set "refinement.levels=$levels" --set "refinement.region=$region"
                       --set "refinement.check_interval=$check") ;;
    esac
    dir="$out/case${c}_$v"
    rm -rf "$dir"
    timed "$out/times.txt" "case${c}_$v" "$build/solver/pd-solve" geometries/glass_plate.toml -o "$dir" "${args[@]}" \
      --quiet > "$dir.log" 2>&1 || { echo "pd-solve failed: $dir.log"; tail -3 "$dir.log"; continue; }
    "$build/post/pd-post" "$dir" > "$dir.post.log" 2>&1 || { echo "pd-post failed: $dir.post.log"; continue; }
    row "$c" "$v" | tee -a "$out/table.md"
  done
done
