#!/usr/bin/env bash
# The Griffith study of docs/validation.md ("Griffith"): a centre crack of
# length 2a in a plate W wide and 1.5 W high, pulled apart quasi-statically
# by its top and bottom grips in load steps 2.5 % apart; the gross stress at
# which the crack first grows half a horizon beyond a tip, against
# sqrt(E G0 / (pi a)) with Tada's finite-width factor
# (tests/quasistatic/test_griffith.cpp). Each line: model, m, a and W in
# cells, the onset bracket and its ratio to the Griffith stress, run time.
# PMB runs on the lattice kernels (a few minutes each on 2 busy cores), OSB
# on neighbour lists with Hessian products by differences (tens of minutes).
# Usage: bench/griffith.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tests="$build/tests/quasistatic/pd-quasistatic-tests"
run() {  # model nu m a_cells W_cells first_load_factor
  GRIFFITH_MODEL=$1 GRIFFITH_NU=$2 GRIFFITH_M=$3 GRIFFITH_A=$4 GRIFFITH_W=$5 GRIFFITH_FIRST=$6 \
    "$tests" "Griffith study" 2>/dev/null | sed -n '/warning:/,/^$/p' | grep -v "warning:" | tr -s ' \n' ' '
  echo
}
run pmb 0.3333333333 3 15 75 1.0
run pmb 0.3333333333 3 20 100 1.0
run pmb 0.3333333333 4 20 100 1.0
run osb 0.25 3 15 75 1.0
run osb 0.25 4 20 100 1.1
