#!/usr/bin/env bash
# Regenerates the pictures of docs/post.md:
#  1. the synthetic example (written by the pd-post test [example]; seconds);
#  2. a quasi-static run: case C2 (plate with a hole pulled apart) at a
#     coarse dx = 0.2 mm, delta = 0.8 mm, load factors 1 to 8 then steps of
#     0.1, until it separates (a few minutes on 2 cores); then pd-post with a
#     line across the hole;
#  3. C3-A and C3-C with the long (2 mm) pre-crack at dx = 0.0625 mm,
#     delta = 0.25 mm (m = 4; C3-A 316,376 particles, C3-C 312,745), the
#     paper's loading, automatic time step, then pd-post. About 2 to 4
#     minutes of solving per case on 2 free cores.
# Parts 2 and 3 are skipped with EXAMPLE_ONLY=1.
# Usage: scripts/post-pictures.sh [BUILD_DIR]   (default: build; needs the
# targets pd-mesh, pd-solve, pd-post and pd-post-tests)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=${WORK:-results/post-pictures}
mkdir -p "$work" docs/img

"$build/tests/post/pd-post-tests" "[example]" > /dev/null
example=$(ls -td "$build"/tests/post/tmp/*/example | head -1)
"$build/post/pd-post" "$example" --times 20e-6
for picture in damage_final damage_t20us strain_energy_final speed_vs_time speed_vs_x; do
  cp "$example/post/$picture.png" "docs/img/post-$picture.png"
done
[ "${EXAMPLE_ONLY:-0}" = 1 ] && exit 0

"$build/mesher/pd-mesh" geometries/c1_plate_hole.geo --spacing 0.2mm --horizon 0.8mm -o "$work/c1.pdp" | tail -1
"$build/solver/pd-solve" geometries/c2_fracture.toml --set particles="$(realpath "$work")/c1.pdp" \
  --set 'quasi_static.increments=[[8, 1.0], [40, 0.1]]' --set quasi_static.tolerance=1e-5 \
  --set output.snapshot_interval=4 -o "$work/c2" | tail -1
"$build/post/pd-post" "$work/c2" --line 10mm,2mm,10mm,18mm
for picture in displacement_x_final damage_final reactions line_profile; do
  cp "$work/c2/post/$picture.png" "docs/img/post-c2-$picture.png"
done

for case in a c; do
  "$build/mesher/pd-mesh" geometries/c3${case}_pores.geo --spacing 0.0625mm --horizon 0.25mm --padding 0.25mm \
    -o "$work/c3$case.pdp" | tail -1
  "$build/solver/pd-solve" geometries/c3${case}_long.toml --set particles="$(realpath "$work")/c3$case.pdp" \
    --set time.step=auto --set output.snapshot_interval=1000 --set output.checkpoint_interval=0 \
    -o "$work/c3${case}_long" 2>&1 | tail -1
  "$build/post/pd-post" "$work/c3${case}_long" --times 2.8e-4
  # Maps at a time are named by the snapshot drawn: the one nearest 280 us.
  rm -f docs/img/post-c3${case}-long-damage_t*us.png
  for map in $(cd "$work/c3${case}_long/post" && ls damage_t*us.png); do
    cp "$work/c3${case}_long/post/$map" "docs/img/post-c3${case}-long-$map"
  done
  for picture in damage_final strain_energy_final speed_vs_time speed_vs_x; do
    cp "$work/c3${case}_long/post/$picture.png" "docs/img/post-c3${case}-long-$picture.png"
  done
done
