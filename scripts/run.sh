#!/usr/bin/env bash
# Run a scene (default: the README's default scene), setting up and building first if needed, then
# compare it with its reference solution and write the comparison plot.
#
#   scripts/run.sh                         default scene on 2 ranks
#   scripts/run.sh namelists/X.nml [N]     scene X on N ranks (default 2), extra mpmice
#                                          arguments after N (e.g. --set '&grid ncells=...')
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

case_file="${1:-namelists/mpmice_terzaghi_1d.nml}"
nranks="${2:-2}"
shift $(( $# > 2 ? 2 : $# )) || true

"$root/scripts/setup.sh"

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# no core binding: each mpirun binds its rank 0 to core 0, so concurrent runs (ctest -j2, several
# scenes at once) would all share one core (docs/testing.md)
export OMPI_MCA_hwloc_base_binding_policy="${OMPI_MCA_hwloc_base_binding_policy:-none}"
# ROMIO for MPI-IO: Open MPI 4.1 OMPIO collective writes corrupted data here (docs/io.md)
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"

# a rerun replaces the scene's earlier output (without it mpmice refuses a used output folder)
mpirun -n "$nranks" "$root/build/bin/mpmice" "$case_file" "$@" --set '&run overwrite = .true. /'

# Postprocess: the output directory and scene come from the resolved input.
output_dir=$("$root/build/bin/mpmice" --check "$case_file" "$@" | \
  sed -n "s/^ *output_dir *= *['\"]\(.*\)['\"].*/\1/p" | head -n 1)
scene=$("$root/build/bin/mpmice" --check "$case_file" "$@" | \
  sed -n "s/^ *scene *= *['\"]\(.*\)['\"].*/\1/p" | head -n 1)
case "$scene" in
  heat_conduction)
    PYTHONPATH="$root" "$root/.venv/bin/python" -m postproc.heat_conduction "$output_dir" ;;
  mpmice)
    if grep -q "name *= *'terzaghi'" "$output_dir/"*.used.nml 2>/dev/null; then
      PYTHONPATH="$root" "$root/.venv/bin/python" -m postproc.mpmice_terzaghi --dir "$output_dir"
    else
      echo "run.sh: no postprocessing script for this mpmice case; output is in $output_dir"
    fi ;;
  *)
    echo "run.sh: no postprocessing script for scene '$scene'; output is in $output_dir" ;;
esac
