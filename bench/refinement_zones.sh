#!/usr/bin/env bash
# Where a fine zone's edges lie (docs/refinement.md, "The fine zone's
# symmetry"): the glass plate of case 1 (100 mm x 40 mm, a 50 mm pre-crack
# at mid-height, 1 MPa on top and bottom suddenly applied and held, PMB,
# m = 3, 80 us) meshed at dx = 1 mm with one static refinement region
# [45 mm, YMIN] x [100 mm, YMAX] at dx = 0.5 mm (pd-mesh --refine-region,
# optionally --horizon-smoothing) and run with dual horizons, against the
# uniform 0.5 mm plate (the fine run, lattice kernel). The crack runs along
# y = 20 mm: a zone from 10 to 30 mm is symmetric about it, one from 6 to
# 30 mm is not.
#
# Usage: bench/refinement_zones.sh [BUILD_DIR]
#   ZONES="YMIN:YMAX[:SMOOTHING] ..." in mm (default below)   OUT=out/refinement_zones
#   RAMP=1e-5: the tractions ramped over that time [s] instead of suddenly applied
# Prints one table row per zone (and writes OUT/zones.md): the zone, its
# edges' distances from the crack line (below / above; "plate edge" when
# the zone reaches it), the first branching (time, point) and the damage
# outside the fine run's band (pd-post --reference, band 3 mm: particles
# with damage >= 0.2 farther than a coarse horizon from the fine run's).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${OUT:-out/refinement_zones}
zones=${ZONES:-"0:40 10:30 12:28 6:34 6:40 0:34 6:30 8:30 14:30 12:40 12:40:2 6:30:4 6:30:8"}
mkdir -p "$out"
loads=(--set loads.top.y=1e6 --set loads.bottom.y=-1e6)
[ -n "${RAMP:-}" ] && loads+=(--set "loads.top.ramp_time=$RAMP" --set "loads.bottom.ramp_time=$RAMP")

# run NAME PARTICLES REFERENCE ARGS...: pd-solve and pd-post (against REFERENCE unless empty).
run() {
  local name=$1 particles=$2 reference=$3
  shift 3
  "$build/solver/pd-solve" geometries/glass_plate.toml -o "$out/$name" --quiet --set "particles=$particles" \
    "${loads[@]}" "$@" > "$out/$name.log" 2>&1 || { echo "pd-solve failed: $out/$name.log" >&2; tail -3 "$out/$name.log" >&2; exit 1; }
  local compare=()
  [ -n "$reference" ] && compare=(--reference "$out/$reference" --band 3mm)
  "$build/post/pd-post" "$out/$name" "${compare[@]}" > "$out/$name.post.log" 2>&1 ||
    { echo "pd-post failed: $out/$name.post.log" >&2; exit 1; }
}

fine="$out/glass_0.5mm.pdp"
[ -f "$fine" ] || "$build/mesher/pd-mesh" geometries/glass_plate.geo --grid uniform --spacing 0.5mm \
  --horizon 1.5mm -o "$fine" > "$out/mesh_fine.log"
run fine "$fine" ""

{
  echo "| zone y (mm) | edges from the crack line, below / above (mm) | smoothing | particles | first branching | damaged outside the fine run's band |"
  echo "| --- | --- | --- | --- | --- | --- |"
} > "$out/zones.md"
row() {  # row NAME ZONE SMOOTHING
  python3 - "$out/$1" "$2" "$3" <<'PY' | tee -a "$out/zones.md"
import csv, json, os, sys
sys.path.insert(0, "bench")
from summary_json import find, load
d, zone, smoothing = sys.argv[1:4]
s = load(os.path.join(d, "summary.json"))
post = load(os.path.join(d, "post", "summary.json"))
with open(os.path.join(d, "post", "branching_events.csv")) as f:
    events = list(csv.DictReader(f))
branching = "none"
if events:
    e = events[0]
    branching = f"{float(e['time_s']) * 1e6:.1f} us at ({float(e['x_m']) * 1e3:.1f}, {float(e['y_m']) * 1e3:.1f}) mm"
c = post.get("comparison")
outside = f"{c['area_outside_band_m2'] * 1e6:.0f} mm^2" if c else "(reference)"
if zone == "-":
    edges, zone = "-", "none (uniform 0.5 mm)"
else:
    ymin, ymax = (float(v) for v in zone.split(":"))
    below = "plate edge" if ymin <= 0 else f"{20 - ymin:g}"
    above = "plate edge" if ymax >= 40 else f"{ymax - 20:g}"
    edges, zone = f"{below} / {above}", f"{ymin:g} - {ymax:g}"
print(f"| {zone} | {edges} | {smoothing} | {find(s, 'particles')} | {branching} | {outside} |")
PY
}
row fine - -

for zone in $zones; do
  IFS=: read -r ymin ymax smoothing <<< "$zone"
  name="zone_${ymin}_${ymax}${smoothing:+_s$smoothing}"
  args=(--refine-region "45mm,${ymin}mm,100mm,${ymax}mm" --refine-factor 2)
  [ -n "$smoothing" ] && args+=(--horizon-smoothing "${smoothing}mm")
  [ -f "$out/$name.pdp" ] || "$build/mesher/pd-mesh" geometries/glass_plate.geo --grid uniform --spacing 1mm \
    --horizon 3mm "${args[@]}" -o "$out/$name.pdp" > "$out/mesh_$name.log"
  run "$name" "$out/$name.pdp" fine --set model.dual_horizon=true
  row "$name" "$ymin:$ymax" "${smoothing:+$smoothing mm}"
done
