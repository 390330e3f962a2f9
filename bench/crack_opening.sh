#!/usr/bin/env bash
# The centre-cracked steel plate of docs/validation.md ("Crack opening"):
#  1. without damage, dx = 2.5 mm, m = 3: CalculiX convergence at the crack
#     centre over three tip element sizes, and the OSB opening profile
#     against the finest FEM solution (a few minutes on 2 busy cores);
#  2. with damage (G0 = 2.2e4 J/m^2), dx = 5 mm, m = 3, U = 0.1, 0.2, 0.3 mm:
#     the three OSB failure variants (theory.md Sec. 5.8), bonds broken per
#     step and the opening at the last step (tens of minutes: once bonds
#     break, every load step re-equilibrates after each round of breaking).
# Writes the tables and pictures under OUT (default out/crack) and copies the
# elastic picture to docs/img/.
# Usage: bench/crack_opening.sh [BUILD_DIR [OUT]]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/crack}
tool="$build/validation/pd-validate-crack"
geo=geometries/centre_crack_plate.geo
"$tool" "$geo" --spacing 2.5mm -m 3 --fem-tip-sizes 4mm,2mm,1mm --variants force_and_dilatation \
  --no-damage --steps 1 -o "$out/elastic"
"$tool" "$geo" --spacing 5mm -m 3 --fem-tip-sizes 2mm --displacement 0.3mm --steps 3 -o "$out/damage"
mkdir -p docs/img
cp "$out/elastic/crack_opening.png" docs/img/crack_opening_elastic.png
