#!/usr/bin/env bash
# Coupled MPMICE benchmark (2D submerged sand block, 125,000 cells, 100,000 particles, 1 and 2
# ranks): µs per cell-step and per particle-step per stage; writes bench/results/mpmice_bench.csv.
# Uses build/bin/mpmice (Release) unless MPMICE_EXE is set.
#   bench/mpmice_bench.sh [--steps 40] [--ranks 1 2] [--cell 0.002]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
exec "$root/.venv/bin/python" -m bench.mpmice_bench "$@"
