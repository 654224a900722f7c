#!/usr/bin/env bash
# PFMG reuse benchmark on the ICE 50^3 scene of bench/ice_bench.sh (water under air, implicit
# pressure): for each reuse value, PCG iterations per solve and ms per pressure solve (PCG solve
# timer, including the PFMG set-ups) and per step, on 1 and 2 ranks.
#   bench/solver_reuse_bench.sh [steps] [n]     (defaults: 40 steps, n = 50)
# REUSE="1 5 20" and RANKS="1 2" override the lists. The reuse value reaches the solver through
# the environment variable MPMICE_BENCH_REUSE, which only a benchmark build honours: the scenes
# do not call struct_solver_set_reuse, so add temporarily after struct_solver_init in
# ice_scene_init (modules/ice/ice_scene.f90), build, and point MPMICE_EXE at that binary:
#   block
#     character(len=16) :: env
#     integer :: n, st
#     call get_environment_variable('MPMICE_BENCH_REUSE', env, status=st)
#     if (st == 0) then
#       read(env, *) n
#       call struct_solver_set_reuse(self%solver, n)
#     end if
#   end block
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="${MPMICE_EXE:-$root/build/bin/mpmice}"
steps="${1:-40}"
n="${2:-50}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%-6s %-6s %-8s %-10s %-10s %-14s %-14s %-12s\n' ranks reuse solves its_mean its_max \
  ms_per_solve ms_pressure_step total_s
for ranks in ${RANKS:-1 2}; do
  for reuse in ${REUSE:-1 5 20}; do
    log="$work/ice_${ranks}_$reuse.log"
    (cd "$work" && MPMICE_BENCH_REUSE="$reuse" mpirun -n "$ranks" -x MPMICE_BENCH_REUSE "$exe" \
      "$root/namelists/ice_slosh.nml" \
      --set "&run output_dir = 'out_${ranks}_$reuse', max_steps = $steps, output_interval = 0.0 /" \
      --set "&grid ncells = $n, $n, $n, upper = 1.0, 1.0, 1.0 /" \
      --set "&time dt_init = 1.0e-4, dt_max = 1.0e-4 /") > "$log" 2>&1
    awk -v ranks="$ranks" -v reuse="$reuse" '
      /pressure solves, PCG iterations/ { solves = $2; mean = $(NF - 2); sub(/,/, "", mean); max = $NF }
      /of which PCG solve/ { per = $NF }
      /ICE pressure \(hypre\)/ { step = $NF }
      /total run/ { total = $NF }
      END { printf "%-6s %-6s %-8s %-10s %-10s %-14s %-14s %-12s\n", ranks, reuse, solves, mean, max, per, step, total }' "$log"
  done
done
