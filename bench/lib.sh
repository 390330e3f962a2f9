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
