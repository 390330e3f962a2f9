#!/usr/bin/env bash
# Regenerates the grid pictures of docs/mesher.md: the three grids of C1 and
# C3-A/B/C, coloured by region (zoomed on a hole) and by cell volume, and the
# NB-NUG grids of the specimens (single-edge notch, compact tension,
# Kalthoff-Winkler, L-shaped panel), and a graded free grid of C1 by horizon.
# Usage: scripts/mesher-pictures.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
mesh=${PD_MESH:-$build/mesher/pd-mesh}
post=${PD_POST:-$build/post/pd-post}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=docs/img
mkdir -p "$out"

# C1 at the paper's resolution (dx = 0.05 mm, delta = 0.2 mm).
for grid in nbnug uniform free; do
  "$mesh" geometries/c1_plate_hole.geo --spacing 0.05mm --horizon 0.2mm --grid $grid -o "$work/c1_$grid.pdp" > "$work/c1_$grid.txt"
  "$post" --particles "$work/c1_$grid.pdp" --zoom 5.5mm,8.5mm,8.5mm,11.5mm -o "$work/zoom" > /dev/null
  "$post" --particles "$work/c1_$grid.pdp" --zoom 4mm,16mm,4mm,16mm -o "$work/full" > /dev/null
  cp "$work/zoom/c1_${grid}_region.png" "$out/mesher-c1-$grid-region.png"
  cp "$work/full/c1_${grid}_volume.png" "$out/mesher-c1-$grid-volume.png"
  head -1 "$work/c1_$grid.txt"
done

# A graded free grid of C1 (docs/mesher.md, "Graded free meshes"): cells
# from 0.1 mm at the hole to dx = 0.4 mm, coloured by horizon; the whole
# plate and a zoom with the cells drawn.
"$mesh" geometries/c1_plate_hole.geo --spacing 0.4mm --horizon-factor 3 --grid free --graded-spacing 0.1mm -o "$work/c1_graded.pdp" > "$work/c1_graded.txt"
"$post" --particles "$work/c1_graded.pdp" -o "$work/full" > /dev/null
"$post" --particles "$work/c1_graded.pdp" --zoom 4mm,12mm,4mm,12mm -o "$work/zoom" > /dev/null
cp "$work/full/c1_graded_horizon.png" "$out/mesher-c1-graded-horizon.png"
cp "$work/zoom/c1_graded_horizon.png" "$out/mesher-c1-graded-horizon-zoom.png"
head -1 "$work/c1_graded.txt"

# C3 A, B, C at dx = 0.1 mm, delta = 0.4 mm (the paper's 0.04 mm gives cells
# too small to see in a picture of the plate).
for case in a b c; do
  for grid in nbnug uniform free; do
    "$mesh" geometries/c3${case}_pores.geo --spacing 0.1mm --horizon 0.4mm --grid $grid -o "$work/c3${case}_$grid.pdp" > "$work/c3${case}_$grid.txt"
    "$post" --particles "$work/c3${case}_$grid.pdp" --zoom 3.5mm,13.5mm,9mm,17mm -o "$work/zoom" > /dev/null
    "$post" --particles "$work/c3${case}_$grid.pdp" -o "$work/full" > /dev/null
    cp "$work/zoom/c3${case}_${grid}_region.png" "$out/mesher-c3${case}-$grid-region.png"
    cp "$work/full/c3${case}_${grid}_volume.png" "$out/mesher-c3${case}-$grid-volume.png"
    head -1 "$work/c3${case}_$grid.txt"
  done
done

# The specimens of geometries/ (NB-NUG grids, coloured by region): the whole
# specimen, and a zoom on the notch tip (on the rounded corner of the L).
specimen() {  # name spacing horizon zoom
  "$mesh" geometries/$1.geo --spacing $2 --horizon $3 -o "$work/$1.pdp" > "$work/$1.txt"
  "$post" --particles "$work/$1.pdp" -o "$work/full" > /dev/null
  "$post" --particles "$work/$1.pdp" --zoom $4 -o "$work/zoom" > /dev/null
  cp "$work/full/${1}_region.png" "$out/mesher-$1-region.png"
  cp "$work/zoom/${1}_region.png" "$out/mesher-$1-zoom.png"
  head -1 "$work/$1.txt"
}
specimen sen_strip 0.25mm 0.75mm 2mm,8mm,17mm,23mm
specimen compact_tension 0.5mm 1.5mm 30mm,42mm,24mm,36mm
specimen kalthoff_winkler 1mm 3mm 40mm,60mm,65mm,85mm
specimen l_panel 1mm 3mm 40mm,60mm,40mm,60mm
