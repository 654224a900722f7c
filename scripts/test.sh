#!/usr/bin/env bash
# MPMICE test command: set up whatever is missing, build, run every test.
#
#   scripts/test.sh            set up + build (scripts/setup.sh, incremental), ctest, pytest
#   scripts/test.sh --unit     set up + build, ctest only (unit, MPI and harness tests)
#   scripts/test.sh --quick    as the default, but skip ctest tests labelled `slow` and
#                              pytest tests marked `slow`
#   scripts/test.sh -- ARGS    pass ARGS on to pytest (e.g. -- -k heat -x)
#
# Exit status: 0 when every test passed, 1 otherwise (2 for a usage error). Nothing may pass by
# not running: a missing executable ($MPMICE_EXE) fails, pytest's "no tests collected" (exit 5)
# fails, and MPMICE_REQUIRE_ALL=1 turns every pytest skip into a failure. See docs/testing.md.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

unit_only=0
quick=0
pytest_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --unit) unit_only=1 ;;
    --quick) quick=1 ;;
    --) shift; pytest_args=("$@"); break ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "test.sh: unknown option $1 (try --help)" >&2; exit 2 ;;
  esac
  shift
done

# Open MPI: allow running as root (containers, CI) and more ranks than cores (MPI tests use 4).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# no core binding: each mpirun binds its rank 0 to core 0, so concurrent runs (ctest -j2, several
# scenes at once) would all share one core (docs/testing.md)
export OMPI_MCA_hwloc_base_binding_policy="${OMPI_MCA_hwloc_base_binding_policy:-none}"
# ROMIO for MPI-IO: Open MPI 4.1 OMPIO collective writes corrupted data here (docs/io.md)
export OMPI_MCA_io="${OMPI_MCA_io:-^ompio}"
# launch latency (about a thousand runs in the suite, docs/testing.md): the ob1 messaging layer
# starts 0.25 s faster than UCX on one node, and a run that exits non-zero is reaped at once
# instead of after the launcher's 1 s grace before SIGKILL (2.2 s per input-error run)
export OMPI_MCA_pml="${OMPI_MCA_pml:-ob1}"
export OMPI_MCA_odls_base_sigkill_timeout="${OMPI_MCA_odls_base_sigkill_timeout:-0}"
export MPMICE_EXE="${MPMICE_EXE:-$root/build/bin/mpmice}"
# validation tests that cannot run (no executable, a scene that fails --check) fail, never skip
export MPMICE_REQUIRE_ALL=1

start=$(date +%s)
echo "== test.sh: set up and build (scripts/setup.sh)"
if ! "$root/scripts/setup.sh"; then
  echo "test.sh: FAILED (set-up or build, see above)"
  exit 1
fi

if [ "$unit_only" -eq 0 ] && [ ! -x "$MPMICE_EXE" ]; then
  echo "test.sh: FAILED: no mpmice executable at MPMICE_EXE=$MPMICE_EXE"
  exit 1
fi

ctest_args=(--test-dir "$root/build" --output-on-failure --no-tests=error -j2)
[ "$quick" -eq 1 ] && ctest_args+=(-LE slow)
echo "== test.sh: ctest ${ctest_args[*]}"
ctest_status=0
ctest "${ctest_args[@]}" || ctest_status=$?

pytest_status=0
if [ "$unit_only" -eq 0 ]; then
  marker=()
  [ "$quick" -eq 1 ] && marker=(-m "not slow")
  echo "== test.sh: pytest tests/validation"
  # --durations: the slowest tests at the end of the log (the suite's time budget, docs/testing.md)
  "$root/.venv/bin/python" -m pytest "$root/tests/validation" -q --durations=15 \
    "${marker[@]}" "${pytest_args[@]}" || pytest_status=$?
  if [ "$pytest_status" -eq 5 ]; then
    echo "test.sh: pytest collected no tests (a failure: check the arguments after --)"
  fi
fi

elapsed=$(( $(date +%s) - start ))
echo "== test.sh: ctest exit ${ctest_status}, pytest exit ${pytest_status}, ${elapsed} s in all"
if [ "$ctest_status" -ne 0 ] || [ "$pytest_status" -ne 0 ]; then
  echo "test.sh: FAILED"
  exit 1
fi
echo "test.sh: all tests passed"
