#!/usr/bin/env bash
# MPM benchmark (2D granular collapse, 204800 particles, 1 and 2 ranks): µs per particle-step and
# per cell-step with the split per stage; writes bench/results/mpm_bench.csv and
# docs/validation/mpm_bench.png. Uses build/bin/mpmice (Release) unless MPMICE_EXE is set.
#   bench/mpm_bench.sh [--steps 100] [--ranks 1 2] [--cell 0.00125]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
exec "$root/.venv/bin/python" -m bench.mpm_bench "$@"
