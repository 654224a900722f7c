#!/usr/bin/env bash
# Run one link of a restart chain: start the case, or continue it from the checkpoint named in
# <output_dir>/<name>.status when the previous link stopped early (signal, wall-time limit or
# &run max_steps). The --set options apply to every link, continuations included (on top of the
# input stored in the checkpoint), so a link may carry its own &run wall_time_limit. Prints the
# final state (finished | stopped | failed) as its last line and exits 0 for finished/stopped,
# 1 otherwise. Used by the Slurm and PBS templates; works anywhere.
#
#   MPMICE_LAUNCH="srun" jobs/mpmice_chain.sh case.nml [--set '...' ...]
#
# MPMICE_LAUNCH: the MPI launcher with its options (default "mpirun"); MPMICE_EXE: the executable
# (default build/bin/mpmice next to this folder).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
exe="${MPMICE_EXE:-$here/../build/bin/mpmice}"
launch="${MPMICE_LAUNCH:-mpirun}"
case_file="$1"
shift

# The resolved input tells where the run writes (the --set options apply).
resolved="$("$exe" --check "$case_file" "$@")"
output_dir="$(sed -n "s/^ *output_dir *= *['\"]\(.*\)['\"].*/\1/p" <<<"$resolved" | head -n 1)"
name="$(sed -n "s/^ *name *= *['\"]\(.*\)['\"].*/\1/p" <<<"$resolved" | head -n 1)"
status_file="$output_dir/$name.status"

state=""
[ -f "$status_file" ] && state="$(sed -n 's/^state = //p' "$status_file")"
case "$state" in
  finished)
    echo "mpmice_chain: $name already finished ($status_file)"; echo finished; exit 0 ;;
  stopped)
    checkpoint="$(sed -n 's/^checkpoint = //p' "$status_file")"
    echo "mpmice_chain: continuing $name from $checkpoint"
    $launch "$exe" --restart "$checkpoint" "$@" || true ;;
  *)
    echo "mpmice_chain: starting $name"
    $launch "$exe" "$case_file" "$@" || true ;;
esac

state="$(sed -n 's/^state = //p' "$status_file" 2>/dev/null || true)"
echo "${state:-failed}"
[ "$state" = finished ] || [ "$state" = stopped ]
