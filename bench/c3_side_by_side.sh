#!/usr/bin/env bash
# The perforated PMMA plates C3 with the long (2 mm) pre-crack run side by
# side in several variants (model and grid) with everything else the same
# (docs/validation.md, "OSB against PMB on C3-A and C3-C" and "What the grid
# changes on C3 at the paper's resolution").
#
# A variant is MODEL or GRID:MODEL:
#   MODEL pmb: the scene's model, bond-based PMB (plane stress, nu = 1/3);
#         osb: --set model.type=osb --set material.poisson_ratio=0.35;
#   GRID  nbnug (default): squares, with free gmsh meshes in boxes of side
#         2 mm around the pores (padding max(horizon, 0.25 mm): the main
#         job's grid at 0.125 mm, the paper's at 0.04 mm);
#         uniform: squares everywhere, cut by the pores;
#         boxes2: NB-NUG with the boxes meshed at DX / 2 (pd-mesh --box-spacing;
#         horizons m DX / 2 there), run with dual horizons
#         (model.dual_horizon = true; surface correction off, which dual
#         horizons refuse).
# For each case: pd-mesh per grid at spacing DX with horizon m DX (m = 4, or
# HORIZON_FACTOR from the environment);
# then pd-solve per variant on geometries/c3X_long.toml as written (E, rho,
# G0, loads, pre-crack, stop at the right edge), with the automatic time step
# (theory.md Sec. 4.5 and 5.4); then pd-post on each. Last,
# bench/c3_side_by_side_report.py writes WORK/comparison.md: one table per
# case, one column per variant (first crack growth, crack speed / c_R,
# trapping time at each pore, branching events, end of the run) and the
# damage pictures next to each other.
#
# Usage: bench/c3_side_by_side.sh [BUILD_DIR [DX [WORK]]]
#   defaults: build, 0.125mm (the main job's resolution; a few minutes per run
#   on 2 cores), WORK = results/c3_side_by_side/dx_DX.
#   CASES="a c" and VARIANTS="pmb osb" (environment) choose the runs, e.g.
#   CASES="a b" VARIANTS="pmb uniform:pmb" for the grids. A run whose
#   WORK/c3X_VARIANT/summary.json exists is not repeated (delete the folder to
#   redo it; VARIANT with ':' written '_', nbnug left out: c3a_pmb,
#   c3a_uniform_pmb), and one stopped before its end continues from its last
#   checkpoint (every 2000 steps), so an interrupted study resumes where it
#   stopped. Two invocations may share WORK only with different CASES.
#   PICTURES=DIR (e.g. docs/img) copies each run's damage_final.png and
#   speed_vs_x.png there as c3-dxDX-c3X-VARIANT-NAME.png.
#   The paper's resolution, dx = 0.04 mm (772,000 particles, about 13,600
#   steps), is about 5 (PMB) and 8 (OSB) minutes of time loop per run on 2
#   free cores, hours on busy ones: bench/c3_side_by_side.sh build 0.04mm
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
dx=${2:-0.125mm}
work=${3:-results/c3_side_by_side/dx_$dx}
cases=${CASES:-a c}
variants=${VARIANTS:-pmb osb}
mkdir -p "$work"
work=$(realpath "$work")
times="$work/times.txt"

read -r horizon padding < <(python3 - "$dx" "${HORIZON_FACTOR:-4}" <<'PY'
import sys
dx, m = float(sys.argv[1].removesuffix("mm")), float(sys.argv[2])
print(f"{m * dx:.10g}mm {max(m * dx, 0.25):.10g}mm")
PY
)

model_options() {  # model_options MODEL: the pd-solve options that choose MODEL
  case $1 in
    pmb) ;;  # the scene's own model
    osb) echo "--set model.type=osb --set material.poisson_ratio=0.35" ;;
    *) echo "c3_side_by_side.sh: unknown model '$1' in VARIANTS (expected pmb or osb)" >&2; return 1 ;;
  esac
}

particle_file() {  # particle_file CASE GRID: meshes C3-CASE on GRID once; prints the file
  local case=$1 grid=$2 name="c3$1"
  [ "$grid" = nbnug ] || name="c3${case}_$grid"
  local particles="$work/$name.pdp"
  if [ ! -f "$particles" ]; then
    local mesh_grid=$grid extra=()
    case $grid in
      nbnug) extra=(--padding "$padding") ;;
      uniform) ;;  # (no boxes to pad: pd-mesh refuses --padding there)
      boxes2) mesh_grid=nbnug extra=(--padding "$padding" --box-spacing "$(python3 -c "print(f'{float(\"${dx%mm}\") / 2:g}mm')")") ;;
      *) echo "c3_side_by_side.sh: unknown grid '$grid' in VARIANTS (expected nbnug, uniform or boxes2)" >&2
         return 1 ;;
    esac
    echo "== pd-mesh: C3-${case^^} on $grid, dx = $dx, delta = $horizon, padding $padding" >&2
    timed "$times" "mesh_$name" "$build/mesher/pd-mesh" "geometries/c3${case}_pores.geo" --grid "$mesh_grid" \
      --spacing "$dx" --horizon "$horizon" "${extra[@]}" -o "$particles.tmp" > "$work/mesh_$name.log"
    mv "$particles.tmp" "$particles"
    grep -E "^grid|^families" "$work/mesh_$name.log" >&2 || true
  fi
  echo "$particles"
}

for case in $cases; do
  for variant in $variants; do
    grid=nbnug model=$variant
    if [[ $variant == *:* ]]; then grid=${variant%%:*} model=${variant#*:}; fi
    name=$model
    [ "$grid" = nbnug ] || name="${grid}_$model"
    options=$(model_options "$model")
    [ "$grid" = boxes2 ] && options+=" --set model.dual_horizon=true --set effects.surface_correction=false"
    particles=$(particle_file "$case" "$grid")
    run="$work/c3${case}_$name"
    if [ ! -f "$run/summary.json" ]; then
      # A run stopped before its end continues from its last checkpoint.
      restart=""
      [ -f "$run/checkpoint.bin" ] && restart="--restart"
      echo "== pd-solve: C3-${case^^}, $grid, $model $options $restart"
      # shellcheck disable=SC2086  # $options is a list of words
      timed "$times" "solve_c3${case}_$name" "$build/solver/pd-solve" "geometries/c3${case}_long.toml" \
        --set particles="$particles" --set time.step=auto $options --set output.snapshot_interval=0 \
        --set output.checkpoint_interval=2000 -o "$run" -q $restart >> "$work/solve_c3${case}_$name.log" 2>&1 ||
        { tail -n 20 "$work/solve_c3${case}_$name.log"; exit 1; }
      tail -n 1 "$work/solve_c3${case}_$name.log"
    fi
    echo "== pd-post: C3-${case^^}, $grid, $model"
    "$build/post/pd-post" "$run" > "$work/post_c3${case}_$name.log" 2>&1 ||
      { cat "$work/post_c3${case}_$name.log"; exit 1; }
    if [ -n "${PICTURES:-}" ]; then
      mkdir -p "$PICTURES"
      for picture in damage_final speed_vs_x; do
        cp "$run/post/$picture.png" "$PICTURES/c3-dx${dx%mm}mm-c3$case-$name-$picture.png"
      done
    fi
  done
done

python3 bench/c3_side_by_side_report.py "$work" "$dx" > "$work/comparison.md"
echo "comparison: $work/comparison.md"
