#!/usr/bin/env bash
# Builds the toolchain and its tests with AddressSanitizer and
# UndefinedBehaviorSanitizer into ./build-sanitize and runs the test suite
# there (docs/robustness.md). Any sanitizer finding aborts the process that
# made it, so the test that ran it fails and its output shows the report.
# Usage: scripts/sanitize.sh [CTEST ARGUMENTS ...]
#   scripts/sanitize.sh                    # the whole suite (slow: see docs/robustness.md)
#   scripts/sanitize.sh -L 'unit|robustness'
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPD_SANITIZE=ON >/dev/null
cmake --build build-sanitize --parallel "$(nproc)"
# Leak checking is off: the third-party libraries (VTK, gmsh) keep memory
# until exit by design, and leaks are not what this run looks for.
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=0:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1"
cd build-sanitize
ctest --output-on-failure --parallel "$(nproc)" --timeout 3600 "$@"
