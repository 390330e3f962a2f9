#!/usr/bin/env bash
# Instructions per step of the lattice kernel's general particles' bonds
# (docs/performance.md, "The general particles' pairs in float"): two builds
# of pd-solve, BEFORE (double neighbour lists, each direction on its own)
# and AFTER (each pair once in float), on case C3-A meshed at SPACING with
# horizon 4 dx (geometries/c3a_long.toml, the command of "Where the time
# goes"), PMB and OSB, one thread, under callgrind: the inclusive
# instructions of Simulation::step divided by the steps, and the functions
# with the most instructions. Then `perf stat -e instructions,cycles` of the
# same runs natively, BEFORE and AFTER interleaved (cycles follow the
# machine's load; instructions do not). Instruction counts do not depend on
# the load; callgrind is some 50 times slower than a native run.
#
# Usage: bench/general_pairs_instructions.sh BEFORE_BUILD AFTER_BUILD [SPACING] [STEPS]
#   defaults: 0.125mm, 20 (about 10 min on a shared 2-core machine).
set -euo pipefail
cd "$(dirname "$0")/.."
before=$1
after=$2
spacing=${3:-0.125mm}
steps=${4:-20}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

dx_mm=${spacing%mm}
horizon=$(python3 -c "print(f'{4 * float(\"$dx_mm\"):g}mm')")
nice -n 5 "$after/mesher/pd-mesh" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
  -o "$work/c3a.pdp" > "$work/mesh.log"
end=$(python3 -c "print(($steps) * 2e-8)")
common=(geometries/c3a_long.toml --set "particles=\"$work/c3a.pdp\"" --set material.poisson_ratio=0.35
        --set time.step=2e-8 --set output.snapshot_interval=0
        --set output.checkpoint_interval=0 --set output.energy_interval=100 -q --threads 1)

# profile NAME BUILD ARGS...: one run under callgrind; prints its
# instructions per step and the functions above 2 % of the step.
profile() {
  local name=$1 build=$2
  shift 2
  nice -n 5 valgrind --tool=callgrind --toggle-collect='pd::solver::Simulation::step(bool)' \
    --callgrind-out-file="$work/$name.out" "$build/solver/pd-solve" "${common[@]}" --set time.end="$end" "$@" \
    -o "$work/$name" > "$work/$name.log" 2> "$work/$name.err"
  local total
  total=$(callgrind_annotate "$work/$name.out" | awk '/PROGRAM TOTALS/ { gsub(",", "", $1); print $1 }')
  python3 -c "print(f'$name: {$total / $steps / 1e6:.2f} M instructions per step')"
  callgrind_annotate "$work/$name.out" | awk -v total="$total" -v steps="$steps" '
    /^ *[0-9,]+ .*\(/ { v = $1; gsub(",", "", v); if (v > 0.02 * total) {
      $1 = ""; printf "  %8.2f M  %s\n", v / steps / 1e6, substr($0, 1, 150) } }'
}

for model in pmb osb; do
  profile "before_$model" "$before" --set "model.type=\"$model\""
  profile "after_$model" "$after" --set "model.type=\"$model\""
done

# perf stat, natively: runs of 100 and 300 steps, whose difference is 200
# steps of the time loop without the set-up; BEFORE and AFTER interleaved
# (the cycles of runs made at different moments are not comparable).
perf_run() {  # perf_run BUILD MODEL STEPS: prints "instructions cycles" of the whole run
  local build=$1 model=$2 n=$3
  nice -n 5 perf stat -x, -e instructions,cycles -o "$work/perf.txt" "$build/solver/pd-solve" "${common[@]}" \
    --set "model.type=\"$model\"" --set time.end="$(python3 -c "print($n * 2e-8)")" -o "$work/perf_run" \
    > /dev/null 2>&1
  awk -F, '$3 ~ /^instructions/ { ins = $1 } $3 ~ /^cycles/ { cyc = $1 } END { print ins, cyc }' "$work/perf.txt"
}
for model in pmb osb; do
  for which in before after before after; do
    build=$before
    [ "$which" = after ] && build=$after
    read -r i1 c1 < <(perf_run "$build" "$model" 100)
    read -r i3 c3 < <(perf_run "$build" "$model" 300)
    python3 -c "print(f'perf $model $which: {($i3 - $i1) / 200 / 1e6:.2f} M instructions per step, ' \
f'{($c3 - $c1) / 200 / 1e6:.2f} M cycles per step, IPC {($i3 - $i1) / ($c3 - $c1):.2f}')"
  done
done
