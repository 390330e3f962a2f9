#!/usr/bin/env bash
# The cases of docs/refinement.md: coarse, adaptive and fine runs side by
# side, one table per specimen.
#
# glass: the glass plate, 100 mm x 40 mm, a 50 mm pre-crack from the left
#   edge at mid-height, tractions sigma on top and bottom applied suddenly
#   and held (case 1: 1 MPa, case 2: 2 MPa), PMB, m = 3, 80 us; uniform grids.
# hole: the 50 mm x 50 mm glass plate with a hole of radius 5 mm and a 15 mm
#   pre-crack below it, the top edge pulled by 1.2 MPa suddenly applied and
#   held, the bottom edge fixed, 60 us; on NB-NUG (the hole's boundary
#   followed by gmsh cells) and on a uniform grid (a staircase hole).
#
# Runs: coarse (dx = 1 mm), adaptive from it (dx -> dx/2 ahead of the crack,
# dual-horizon PD; only squares split, so on NB-NUG the hole's gmsh cells
# stay coarse), fine (the uniform plate at the adaptive run's finest
# spacing: dx = 0.5 mm, 0.25 mm with LEVELS=2). Coarse and fine runs use the lattice
# kernel (no dual horizons), as a user would run them. Each run's damage is
# compared with the fine run's (pd-post --reference: particles with damage
# >= 0.2 farther than one coarse horizon, 3 mm, from the fine run's damage
# (a crack's damage reaches about a horizon to each side of it);
# for the hole, the fine NB-NUG run is the reference of both grids).
#
# Usage: bench/refinement.sh [BUILD_DIR]
#   SPECIMENS="glass hole"   CASES="1 2" (glass)   GRIDS="nbnug uniform" (hole)
#   VARIANTS="fine coarse adaptive" (the fine run first: the others compare with it);
#   an adaptive variant may name [refinement] keys after '+', e.g.
#   adaptive+strain=normal+spread=none+strain_fraction=1.0 (run adaptive_strain-normal_...)
#   LENGTH=1 (fraction of the end time)   OUT=out/refinement
#   REUSE=1: keep the runs that finished (OUT/NAME/summary.json) and redo pd-post and the tables
#   STEPS="auto 1.15e-7": the time steps, one row set each. "auto": each run its
#   own stable step (the coarse run twice the fine one's; an adaptive run the
#   refined set's from its first event on). A number [s]: every run of the set
#   at that one fixed step, below the fine and the refined sets' stable limits
#   (1.48e-7 s and 1.53e-7 s here), as a comparison at one step for all runs
#   is made; rows "VARIANT, dt = STEP s", runs OUT/NAME_dtSTEP.
#   LEVELS=1 (halvings of the adaptive run)   CHECK=20 (steps between checks)
#   THREADS=$(nproc): every run's --threads (under CALLGRIND, 1)
#   CALLGRIND=1: every pd-solve runs on one thread under valgrind's callgrind
#   (some 50 times slower); OUT/instructions.txt gets a line "NAME total
#   events set-up steps" (instructions of the whole run, of the refinement
#   events, of their simulations' set-up, of the time steps; inclusive), and
#   `python3 bench/refinement_instructions.py OUT` prints the cost ratios
#   of docs/refinement.md ("Cost") from it. Instruction counts do not depend
#   on the machine's load.
#   Where the adaptive run may split [m]. The region must hold the whole crack
#   path: a crack that leaves the refined zone runs along its edge and damages
#   the coarse side (docs/refinement.md). The glass plate's branches reach the
#   right edge near y = 8 and 32 mm, so its region is the whole height right of
#   the pre-crack's tip. The hole plate's leaves out the loaded and the fixed
#   strips (the loaded particles carry the tractions as body forces and stretch
#   beyond alpha s_c wherever the waves meet; no crack runs there):
#   GLASS_REGION="[0.045, 0.0, 0.1, 0.04]"   HOLE_REGION="[0.0, 0.006, 0.05, 0.044]"
# Prints one table row per run and writes OUT/glass.md and OUT/hole.md
# (with adaptive variants, `python3 bench/refinement_variants.py OUT VARIANT...`
# makes the criteria table of docs/refinement.md from the runs); GNU
# time's wall and CPU seconds go to OUT/times.txt. Run it with `nice` on a
# shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
out=${OUT:-out/refinement}
specimens=${SPECIMENS:-"glass hole"}
cases=${CASES:-"1 2"}
grids=${GRIDS:-"nbnug uniform"}
variants=${VARIANTS:-"fine coarse adaptive"}
length=${LENGTH:-1}
levels=${LEVELS:-1}
check=${CHECK:-20}
# Every run on the same thread count (pd-solve left to choose runs the 1 mm
# plates on one thread and the others on two: docs/performance.md).
threads=${THREADS:-$(nproc)}
# The fine runs are the uniform plates at the adaptive runs' finest spacing.
fine_dx=$(python3 -c "print(1 / 2**$levels)")
glass_region=${GLASS_REGION:-"[0.045, 0.0, 0.1, 0.04]"}
hole_region=${HOLE_REGION:-"[0.0, 0.006, 0.05, 0.044]"}
band=3mm
steps=${STEPS:-"auto 1.15e-7"}
mkdir -p "$out"

plate() {  # plate GEOMETRY GRID DX: meshes once, prints the particle file
  local file="$out/$1_$2_$3mm.pdp"
  [ -f "$file" ] || "$build/mesher/pd-mesh" "geometries/$1.geo" --grid "$2" --spacing "$3mm" \
    --horizon "$(python3 -c "print(3 * $3)")mm" -o "$file" > "$out/mesh_$1_$2_$3mm.log"
  echo "$file"
}

row() {  # row NAME LABEL: one line of the table from the run's and pd-post's summary.json
  python3 - "$out/$1" "$2" "$1" "$out/times.txt" <<'PY'
import csv, json, os, sys
sys.path.insert(0, "bench")
from summary_json import find, load
d, label, name, times = sys.argv[1:5]
s = load(os.path.join(d, "summary.json"))
post = load(os.path.join(d, "post", "summary.json"))
ref = s.get("refinement", {})
n0 = ref.get("particles_start", find(s, "particles"))
n1 = ref.get("particles_end", n0)
cpu = "?"
for line in open(times):
    run, wall, peak, user, system = line.split()
    if run == name:
        cpu = f"{float(user) + float(system):.1f}"
with open(os.path.join(d, "post", "branching_events.csv")) as f:
    events = list(csv.DictReader(f))
if events:
    e = events[0]
    branching = (f"{float(e['time_s']) * 1e6:.1f} us at ({float(e['x_m']) * 1e3:.1f}, "
                 f"{float(e['y_m']) * 1e3:.1f}) mm, {float(e['angle_deg']):.0f} deg")
else:
    branching = "none"
c = post.get("comparison")
outside = f"{c['damaged_outside_band']} ({c['area_outside_band_m2'] * 1e6:.0f} mm^2)" if c else "-"
print(f"| {label} | {n0} | {n1} | {s['wall_time_s']:.1f} | {cpu} | {ref.get('seconds', 0):.1f} | "
      f"{ref.get('events', 0)} | {branching} | {ref.get('bonds_broken_by_splits', '-')} | {outside} |")
PY
}

header() {  # header FILE FIRST_COLUMN: the table's two header lines
  echo "| $2 | run | particles start | particles end | wall s | CPU s | refining s | events | first branching (time, point, angle) | bonds broken by splits | damaged outside the fine run's band |" > "$1"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |" >> "$1"
}

# instructions NAME CALLGRIND_FILE: "NAME total events set-up steps", each
# inclusive (callgrind_annotate --inclusive=yes; 0 where the run has no such part).
instructions() {
  callgrind_annotate --inclusive=yes "$2" 2>/dev/null | awk -v name="$1" '
    function count(v) { gsub(",", "", v); return v + 0 }
    /PROGRAM TOTALS/ { total = count($1) }
    /AdaptiveRefinement::check\(/ && !events { events = count($1) }
    /AdaptiveRefinement::set_up\(/ && !setup { setup = count($1) }
    /Simulation::step\(bool\) \[/ && !steps { steps = count($1) }
    END { printf "%s %.0f %.0f %.0f %.0f\n", name, total, events, setup, steps }'
}

# solve NAME SCENE REFERENCE ARGS...: one run, pd-post on it (against REFERENCE
# when it is another run), its table row printed.
solve() {
  local name=$1 scene=$2 reference=$3
  shift 3
  local dir="$out/$name"
  if [ "${REUSE:-0}" != 1 ] || [ ! -f "$dir/summary.json" ]; then
    rm -rf "$dir"
    local profiler=()
    local run_threads=$threads
    [ "${CALLGRIND:-0}" = 1 ] && profiler=(valgrind --tool=callgrind --callgrind-out-file="$dir.callgrind") &&
      run_threads=1
    timed "$out/times.txt" "$name" "${profiler[@]}" "$build/solver/pd-solve" "$scene" -o "$dir" "$@" --quiet \
      --threads "$run_threads" > "$dir.log" 2>&1 ||
      { echo "pd-solve failed: $dir.log" >&2; tail -3 "$dir.log" >&2; return 1; }
    [ "${CALLGRIND:-0}" = 1 ] && instructions "$name" "$dir.callgrind" >> "$out/instructions.txt"
  fi
  local compare=()
  [ "$reference" != "$name" ] && [ -f "$out/$reference/arrival.vtp" ] &&
    compare=(--reference "$out/$reference" --band "$band")
  "$build/post/pd-post" "$dir" "${compare[@]}" > "$dir.post.log" 2>&1 ||
    { echo "pd-post failed: $dir.post.log" >&2; return 1; }
}

# A fixed time step's part of a run's name, arguments and row label (nothing for "auto").
step_suffix() { [ "$1" = auto ] || echo "_dt$1"; }
step_args() { [ "$1" = auto ] || echo "--set time.step=$1"; }
step_label() { [ "$1" = auto ] || echo ", dt = $1 s"; }

adaptive_args() {  # adaptive_args REGION VARIANT: the keys of an adaptive run, the variant's after its '+'
  # (A variant's key replaces the default one: pd-solve refuses a key set twice.)
  local variant_keys variant_names key name
  variant_keys=$(tr '+' ' ' <<< "${2#adaptive}")
  variant_names=" $(sed 's/=[^ ]*//g' <<< "$variant_keys") "
  for key in model.dual_horizon=true "refinement.levels=$levels" "refinement.region=$1" \
             "refinement.check_interval=$check"; do
    name=${key%%=*}
    [[ $variant_names == *" ${name#refinement.} "* ]] || echo "$key"
  done
  for key in $variant_keys; do echo "refinement.$key"; done
}
run_name() { tr '+=' '_-' <<< "$1"; }  # run_name VARIANT: the variant in a run's name

for specimen in $specimens; do
  case $specimen in
    glass)
      table="$out/glass.md"
      header "$table" case
      end=$(python3 -c "print(80e-6 * $length)")
      for step in $steps; do
      suffix=$(step_suffix "$step")
      for c in $cases; do
        sigma=$(python3 -c "print($c * 1e6)")
        for v in $variants; do
          args=(--set "time.end=$end" --set "loads.top.y=$sigma" --set "loads.bottom.y=-$sigma" $(step_args "$step"))
          case $v in
            coarse) args+=(--set "particles=$(plate glass_plate uniform 1)") ;;
            fine) args+=(--set "particles=$(plate glass_plate uniform "$fine_dx")") ;;
            adaptive|adaptive+*) args+=(--set "particles=$(plate glass_plate uniform 1)")
                      for a in $(adaptive_args "${glass_region// /}" "$v"); do args+=(--set "$a"); done ;;
            *) echo "refinement.sh: unknown variant '$v' (expected fine, coarse or adaptive)" >&2; exit 1 ;;
          esac
          name="glass_case${c}_$(run_name "$v")$suffix"
          solve "$name" geometries/glass_plate.toml "glass_case${c}_fine$suffix" "${args[@]}" || continue
          row "$name" "$c ($c MPa) | $v$(step_label "$step")" | tee -a "$table"
        done
      done
      done ;;
    hole)
      table="$out/hole.md"
      header "$table" grid
      end=$(python3 -c "print(60e-6 * $length)")
      # The fine NB-NUG run is every run's reference: it goes first.
      runs=(nbnug:fine)
      for g in $grids; do
        for v in $variants; do [ "$g:$v" = nbnug:fine ] || runs+=("$g:$v"); done
      done
      for step in $steps; do
      suffix=$(step_suffix "$step")
      for run in "${runs[@]}"; do
        g=${run%%:*} v=${run#*:}
        args=(--set "time.end=$end" $(step_args "$step"))
        case $v in
          coarse) args+=(--set "particles=$(plate hole_plate "$g" 1)") ;;
          fine) args+=(--set "particles=$(plate hole_plate "$g" "$fine_dx")") ;;
          adaptive|adaptive+*) args+=(--set "particles=$(plate hole_plate "$g" 1)")
                    for a in $(adaptive_args "${hole_region// /}" "$v"); do args+=(--set "$a"); done ;;
          *) echo "refinement.sh: unknown variant '$v' (expected fine, coarse or adaptive)" >&2; exit 1 ;;
        esac
        name="hole_${g}_$(run_name "$v")$suffix"
        solve "$name" geometries/hole_plate.toml "hole_nbnug_fine$suffix" "${args[@]}" || continue
        row "$name" "$g | $v$(step_label "$step")" | tee -a "$table"
      done
      done ;;
    *) echo "refinement.sh: unknown specimen '$specimen' (expected glass or hole)" >&2; exit 1 ;;
  esac
done
