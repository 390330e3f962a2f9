#!/usr/bin/env bash
# OSB against PMB on the perforated PMMA plates C3-A and C3-C with the long
# (2 mm) pre-crack (docs/validation.md, "OSB against PMB on C3-A and C3-C").
#
# For each case: pd-mesh at spacing DX with horizon 4 DX (m = 4) and NB-NUG
# boxes of side 2 mm around the pores (padding max(horizon, 0.25 mm): the
# main job's grid at 0.125 mm, the paper's at 0.04 mm); then pd-solve twice on
# geometries/c3X_long.toml as written (E, rho, G0, loads, pre-crack, stop at
# the right edge), with the automatic time step (theory.md Sec. 4.5 and 5.4):
#   pmb: the scene's model, bond-based PMB (plane stress, nu = 1/3);
#   osb: --set model.type=osb --set material.poisson_ratio=0.35;
# then pd-post on each. Last, bench/osb_vs_pmb_report.py writes
# WORK/comparison.md: the table of both models side by side (first crack
# growth, crack speed / c_R, trapping time at each pore, branching events,
# end of the run) and the damage pictures next to each other.
#
# Usage: bench/osb_vs_pmb_c3.sh [BUILD_DIR [DX [WORK]]]
#   defaults: build, 0.125mm (the main job's resolution; a few minutes per run
#   on 2 cores), WORK = results/osb_vs_pmb/dx_DX.
#   CASES="a c" and MODELS="pmb osb" (environment) choose the runs; a run
#   whose WORK/c3X_MODEL/summary.json exists is not repeated (delete the
#   folder to redo it), and one stopped before its end continues from its
#   last checkpoint (every 2000 steps), so an interrupted study resumes where
#   it stopped. Two invocations may share WORK only with different CASES.
#   PICTURES=DIR (e.g. docs/img) copies each run's damage_final.png and
#   speed_vs_x.png there as osb-pmb-dxDX-c3X-MODEL-NAME.png.
#   The paper's resolution, dx = 0.04 mm (772,000 particles, about 13,600
#   steps), is about 5 (PMB) and 8 (OSB) minutes of time loop per run on 2
#   free cores, hours on busy ones: bench/osb_vs_pmb_c3.sh build 0.04mm
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build}
dx=${2:-0.125mm}
work=${3:-results/osb_vs_pmb/dx_$dx}
cases=${CASES:-a c}
models=${MODELS:-pmb osb}
mkdir -p "$work"
work=$(realpath "$work")
times="$work/times.txt"

read -r horizon padding < <(python3 - "$dx" <<'PY'
import sys
dx = float(sys.argv[1].removesuffix("mm"))
print(f"{4 * dx:g}mm {max(4 * dx, 0.25):g}mm")
PY
)

model_options() {  # model_options MODEL: the pd-solve options that choose MODEL
  case $1 in
    pmb) ;;  # the scene's own model
    osb) echo "--set model.type=osb --set material.poisson_ratio=0.35" ;;
    *) echo "osb_vs_pmb_c3.sh: unknown model '$1' (expected pmb or osb)" >&2; return 1 ;;
  esac
}

for case in $cases; do
  particles="$work/c3$case.pdp"
  if [ ! -f "$particles" ]; then
    echo "== pd-mesh: C3-${case^^}, dx = $dx, delta = $horizon, padding $padding"
    timed "$times" "mesh_c3$case" "$build/mesher/pd-mesh" "geometries/c3${case}_pores.geo" --spacing "$dx" \
      --horizon "$horizon" --padding "$padding" -o "$particles.tmp" > "$work/mesh_c3$case.log"
    mv "$particles.tmp" "$particles"
    grep -E "^grid|^families" "$work/mesh_c3$case.log" || true
  fi
  for model in $models; do
    run="$work/c3${case}_$model"
    options=$(model_options "$model")
    if [ ! -f "$run/summary.json" ]; then
      # A run stopped before its end continues from its last checkpoint.
      restart=""
      [ -f "$run/checkpoint.bin" ] && restart="--restart"
      echo "== pd-solve: C3-${case^^}, $model $options $restart"
      # shellcheck disable=SC2086  # $options is a list of words
      timed "$times" "solve_c3${case}_$model" "$build/solver/pd-solve" "geometries/c3${case}_long.toml" \
        --set particles="$particles" --set time.step=auto $options --set output.snapshot_interval=0 \
        --set output.checkpoint_interval=2000 -o "$run" -q $restart >> "$work/solve_c3${case}_$model.log" 2>&1 ||
        { tail -n 20 "$work/solve_c3${case}_$model.log"; exit 1; }
      tail -n 1 "$work/solve_c3${case}_$model.log"
    fi
    echo "== pd-post: C3-${case^^}, $model"
    "$build/post/pd-post" "$run" > "$work/post_c3${case}_$model.log" 2>&1 ||
      { cat "$work/post_c3${case}_$model.log"; exit 1; }
    if [ -n "${PICTURES:-}" ]; then
      mkdir -p "$PICTURES"
      for picture in damage_final speed_vs_x; do
        cp "$run/post/$picture.png" "$PICTURES/osb-pmb-dx${dx%mm}mm-c3$case-$model-$picture.png"
      done
    fi
  done
done

python3 bench/osb_vs_pmb_report.py "$work" "$dx" > "$work/comparison.md"
echo "comparison: $work/comparison.md"
