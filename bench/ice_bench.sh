#!/usr/bin/env bash
# ICE benchmark: two fluids (water under air, namelists/ice_slosh.nml) on a 50^3 grid, implicit
# pressure; prints µs per cell-step per stage (maximum over ranks) and PCG iterations per solve
# for 1 and 2 ranks. Uses build/bin/mpmice (build it Release) unless MPMICE_EXE is set.
#   bench/ice_bench.sh [steps] [n]      (defaults: 10 steps, n = 50)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="${MPMICE_EXE:-$root/build/bin/mpmice}"
steps="${1:-10}"
n="${2:-50}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cells=$((n * n * n))
for ranks in 1 2; do
  log="$work/ice_$ranks.log"
  (cd "$work" && mpirun -n "$ranks" "$exe" "$root/namelists/ice_slosh.nml" \
    --set "&run output_dir = 'out_$ranks', max_steps = $steps, output_interval = 0.0 /" \
    --set "&grid ncells = $n, $n, $n, upper = 1.0, 1.0, 1.0 /" \
    --set "&time dt_init = 1.0e-4, dt_max = 1.0e-4 /") > "$log" 2>&1
  echo "== $ranks rank(s), $n^3 = $cells cells, $steps steps"
  grep -E "pressure solves" "$log" | sed 's/^/   /'
  awk -v cells="$cells" -v steps="$steps" '
    /^ *ICE / { name = $0; sub(/^ */, "", name); sub(/ +[0-9].*$/, "", name)
                        n = split($0, f, " "); printf "   %-24s %8.3f us/cell-step\n", name, f[n-3] / cells / steps * 1e6 }
    /total run/ { n = split($0, f, " "); printf "   %-24s %8.3f us/cell-step\n", "total run", f[n] / cells / steps * 1e6 }' "$log"
done
