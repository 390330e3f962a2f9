# shellcheck shell=bash
# Shell functions shared by the bench scripts. Source it from the repository
# root:  . bench/lib.sh
# (bench/summary_json.py is its Python half: values out of summary.json.)

# timed TIMES_FILE NAME COMMAND...: runs COMMAND and appends the line
# "NAME wall_s peak_kB user_s system_s" to TIMES_FILE (GNU time; the
# command's own exit status is returned). CPU time (user + system) is the
# cost measure that a shared machine's load distorts least.
timed() {
  local file=$1 name=$2
  shift 2
  /usr/bin/time -f "$name %e %M %U %S" -a -o "$file" "$@"
}

# summary_value FILE KEY: prints the first value named KEY anywhere in the JSON
# file FILE (depth first, as bench/summary_json.py finds it).
summary_value() {
  python3 "$(dirname "${BASH_SOURCE[0]}")/summary_json.py" "$1" "$2"
}

# mesh_c3a_with_boxes BUILD_DIR SPACING WORK: C3-A on NB-NUG at SPACING with
# horizon 4 dx, as WORK/plain.pdp, and again with its boxes round the pores at
# dx / 2 (pd-mesh --box-spacing) as WORK/boxes.pdp; padding 0.25 mm (the
# scene's) or one horizon where that is larger (pd-mesh's minimum). Sets
# horizon and box (lengths with units) for the caller.
mesh_c3a_with_boxes() {
  local build=$1 spacing=$2 work=$3 dx_mm=${2%mm} padding
  horizon=$(python3 -c "print(f'{4 * float(\"$dx_mm\"):g}mm')")
  box=$(python3 -c "print(f'{float(\"$dx_mm\") / 2:g}mm')")
  padding=$(python3 -c "print(f'{max(0.25, 4 * float(\"$dx_mm\")):g}mm')")
  echo "== pd-mesh: C3-A, dx = $spacing, delta = $horizon, padding $padding; and its boxes at $box"
  nice -n 5 "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
    --padding "$padding" -o "$work/plain.pdp" > "$work/plain.mesh.log"
  nice -n 5 "$build/mesher/pd-mesh" geometries/c3a_pores.geo --spacing "$spacing" --horizon "$horizon" \
    --padding "$padding" --box-spacing "$box" -o "$work/boxes.pdp" > "$work/boxes.mesh.log"
  grep -hE "^grid|^horizons|^families" "$work/plain.mesh.log" "$work/boxes.mesh.log" || true
}
