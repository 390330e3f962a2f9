#!/usr/bin/env bash
# The README's first command: installs the dependencies, builds, and runs the
# main job with defaults: case C3-A (perforated PMMA plate, 8 pores on the
# mid-line, 2 mm pre-crack) through mesh -> solve -> post.
#
# Resolution: dx = 0.125 mm, delta = 0.5 mm (m = 4), 79,000 particles and
# 5.3 million bonds, automatic time step; about a minute of solving on 2
# cores. The paper's resolution (dx = 0.04 mm, 772,000 particles) is the
# same commands with --spacing 0.04mm --horizon 0.16mm --padding 0.25mm.
#
# Results go to results/c3a_long/ (override with RESULTS=DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh pd-mesh pd-solve pd-post
results=${RESULTS:-results}
mkdir -p "$results"

echo "== mesh: C3-A NB-NUG grid"
build/mesher/pd-mesh geometries/c3a_pores.geo --spacing 0.125mm --horizon 0.5mm \
  -o "$results/c3a.pdp" --vtk "$results/c3a.vtp"

echo "== solve: C3-A, long pre-crack (geometries/c3a_long.toml)"
build/solver/pd-solve geometries/c3a_long.toml --set particles="$(realpath "$results")/c3a.pdp" \
  --set time.step=auto -o "$results/c3a_long"

echo "== post: crack tips, speeds, pictures"
build/post/pd-post "$results/c3a_long"
