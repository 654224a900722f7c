#!/usr/bin/env bash
# hypre Struct PCG + PFMG benchmark: 2D manufactured variable-coefficient Poisson problem (L2
# error, observed order, iterations, times) and a 1000:1 coefficient-jump problem (iterations,
# times), 32^2 .. 512^2 cells, on 1 and 2 ranks. Prints the tables and writes one CSV.
#   bench/hypre_poisson.sh                 Release build in build/, CSV in bench/results/
#   BUILD_DIR=... OUT_DIR=... RANKS="1 2 4" SIZES="32 64" bench/hypre_poisson.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${BUILD_DIR:-$root/build}"
out_dir="${OUT_DIR:-$root/bench/results}"
ranks="${RANKS:-1 2}"
sizes="${SIZES:-32 64 128 256 512}"
tolerance="${TOLERANCE:-1e-10}"

if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build_dir" --target hypre_poisson -j "$(nproc)" >/dev/null
build_type="$(grep -E '^CMAKE_BUILD_TYPE:' "$build_dir/CMakeCache.txt" | cut -d= -f2)"
[ "$build_type" = "Release" ] || echo "hypre_poisson: warning: $build_dir is a $build_type build"

# Open MPI: allow root and more ranks than cores (harmless elsewhere).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

mkdir -p "$out_dir"
csv="$out_dir/hypre_poisson.csv"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
first=1
for problem in mms jump; do
  for n in $ranks; do
    part="$tmp/${problem}_np$n.csv"
    # shellcheck disable=SC2086
    mpiexec -n "$n" "$build_dir/bin/hypre_poisson" --problem "$problem" --tolerance "$tolerance" \
      --csv "$part" $sizes
    echo
    if [ $first -eq 1 ]; then cat "$part" > "$csv"; first=0; else tail -n +2 "$part" >> "$csv"; fi
  done
done
echo "hypre_poisson: wrote $csv"
