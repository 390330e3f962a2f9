#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the whole test suite (CTest).
# This is the README's second command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest --output-on-failure --parallel "$(nproc)" --timeout 1500
