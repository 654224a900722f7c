#!/usr/bin/env bash
# Install what MPMICE needs on a fresh Debian 12 machine (idempotent), create the Python
# virtual environment and configure + build with CMake.
#   scripts/setup.sh            Release build in build/
#   BUILD_TYPE=Debug scripts/setup.sh   Debug build (-fcheck=all, FPE traps) in build-debug/
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

apt_packages=(gfortran cmake make libopenmpi-dev openmpi-bin libhypre-dev libhdf5-mpi-dev
              liblapack-dev python3-venv python3-dev pkg-config)
missing=()
for p in "${apt_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -q "${missing[@]}"
fi

venv="$root/.venv"
if [ ! -x "$venv/bin/python" ]; then
  echo "setup: creating Python virtual environment in .venv"
  python3 -m venv "$venv"
fi
# fypp expands the Fortran templates (modules/**/*.fypp) at build time
if ! "$venv/bin/python" -c "import numpy, h5py, matplotlib, pytest, fypp" 2>/dev/null; then
  "$venv/bin/pip" install -q --upgrade pip
  "$venv/bin/pip" install -q numpy h5py matplotlib pytest fypp
fi

build_type="${BUILD_TYPE:-Release}"
if [ "$build_type" = "Debug" ]; then build_dir="$root/build-debug"; else build_dir="$root/build"; fi
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
echo "setup: build ready in $build_dir"
