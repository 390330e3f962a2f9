#!/usr/bin/env bash
# Installs every build and test dependency from Debian 12 packages.
# Idempotent, non-interactive, needs root (or sudo). Only apt-get, no other network.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libgmsh-dev gmsh              # meshing (C++ API); gmsh CLI for debugging .geo files
  libcgal-dev                   # exact geometry (polygon checks in tests)
  libeigen3-dev                 # small dense linear algebra
  libnanoflann-dev              # k-d tree neighbour search
  libvtk9-dev                   # .vtp/.pvd output, PNG pictures (offscreen)
  libboost-program-options-dev  # command-line options
  catch2                        # unit tests (v2 in Debian 12)
  libtomlplusplus-dev           # scene files (TOML)
  calculix-ccx                  # FEM reference solutions for validation tests
  python3                       # C4 pore generator (standard library only)
  time                          # /usr/bin/time for peak memory in bench/
  libopenmpi-dev openmpi-bin    # MPI: pd-solve on several processes (optional in CMake)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" </dev/null
echo "install-deps: done"
