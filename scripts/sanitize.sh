#!/usr/bin/env bash
# Builds the toolchain and its tests with AddressSanitizer and
# UndefinedBehaviorSanitizer (CMake option PD_SANITIZE) and runs tests
# there (docs/robustness.md). Any sanitizer finding aborts the process that
# made it, so the test that ran it fails and its output shows the report.
# Not part of CI: the instrumented build takes hours on a small machine.
# Usage: scripts/sanitize.sh [BUILD_FOLDER] [CTEST ARGUMENTS ...]
#   scripts/sanitize.sh                        # ./build-sanitize, the whole suite (slow)
#   scripts/sanitize.sh -L 'unit|robustness'   # some labels
#   scripts/sanitize.sh build-asan -L post     # another build folder
# A build folder is the first argument when it does not begin with '-'
# (relative to the folder the script is started in).
# JOBS sets the build's and the tests' parallelism (default: every core);
# the build and the tests run at low priority (nice), for a shared machine.
# ASAN_OPTIONS, UBSAN_OPTIONS and LSAN_OPTIONS already set are kept, after
# the defaults below, so that a caller's setting wins (e.g. leak checking
# with a suppressions file: ASAN_OPTIONS=detect_leaks=1
# LSAN_OPTIONS=suppressions=/path/to/lsan.supp).
set -euo pipefail
build=
if [[ $# -gt 0 && $1 != -* ]]; then
  build=$(realpath -m -- "$1")  # as named from where the script was started
  shift
fi
cd "$(dirname "$0")/.."
build=${build:-build-sanitize}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPD_SANITIZE=ON >/dev/null
nice cmake --build "$build" --parallel "$jobs"
# Leak checking is off by default: the third-party libraries (VTK, gmsh)
# keep memory until exit by design, and leaks are not what this run looks for.
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=0:strict_string_checks=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export OMP_WAIT_POLICY=passive
cd "$build"
nice ctest --output-on-failure --parallel "$jobs" --timeout 3600 "$@"
