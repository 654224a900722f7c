"""Shared fixtures of the validation tests: run the ``mpmice`` executable on small scenes.

* ``mpmice_exe``: path of the executable, from the environment variable ``MPMICE_EXE`` or else
  ``build/bin/mpmice``; tests that need it are skipped (with the reason) when it is missing.
* ``run_mpmice(args, nranks=1, cwd=None, timeout=300)``: run it under ``mpirun`` and return the
  ``subprocess.CompletedProcess`` (text mode, stdout and stderr captured, not checked).
* ``tmp_case_dir``: an empty directory per test, the default working directory of ``run_mpmice``.
"""

import functools
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Open MPI settings for containers and small machines: allow root, allow more ranks than cores.
OMPI_ENV = {
    'OMPI_ALLOW_RUN_AS_ROOT': '1',
    'OMPI_ALLOW_RUN_AS_ROOT_CONFIRM': '1',
    'OMPI_MCA_rmaps_base_oversubscribe': '1',
}


def mpirun_executable():
    """The MPI launcher: ``$MPIEXEC`` if set, else ``mpirun`` from the PATH."""
    return os.environ.get('MPIEXEC') or shutil.which('mpirun') or 'mpirun'


@functools.lru_cache(maxsize=None)
def is_open_mpi(launcher):
    """True when ``launcher`` belongs to Open MPI (which needs --oversubscribe beyond the cores)."""
    try:
        out = subprocess.run([launcher, '--version'], capture_output=True, text=True, timeout=30,
                             check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return 'Open MPI' in out.stdout + out.stderr or 'OpenRTE' in out.stdout + out.stderr


def mpirun_command(exe, args, nranks):
    """Command line that runs ``exe args`` on ``nranks`` ranks."""
    launcher = mpirun_executable()
    command = [launcher, '-n', str(nranks)]
    if nranks > 2 and is_open_mpi(launcher):
        command.append('--oversubscribe')
    return command + [str(exe)] + [str(a) for a in args]


@pytest.fixture(scope='session')
def mpmice_exe():
    """Path of the mpmice executable; skips the test when it has not been built."""
    path = Path(os.environ.get('MPMICE_EXE') or REPO_ROOT / 'build' / 'bin' / 'mpmice')
    if not (path.is_file() and os.access(path, os.X_OK)):
        pytest.skip(f'mpmice executable not found at {path}: build it with scripts/setup.sh '
                    'or point MPMICE_EXE at it')
    return path


@pytest.fixture
def tmp_case_dir(tmp_path):
    """An empty directory for one test's namelists and output."""
    case_dir = tmp_path / 'case'
    case_dir.mkdir()
    return case_dir


@pytest.fixture
def run_mpmice(mpmice_exe, tmp_case_dir):
    """Function running mpmice under mpirun; see the module docstring."""

    def run(args, nranks=1, cwd=None, timeout=300):
        env = os.environ.copy()
        for key, value in OMPI_ENV.items():
            env.setdefault(key, value)
        command = mpirun_command(mpmice_exe, args, nranks)
        try:
            return subprocess.run(command, cwd=str(cwd or tmp_case_dir), env=env, text=True,
                                  capture_output=True, timeout=timeout, check=False)
        except subprocess.TimeoutExpired as err:
            partial = [s.decode(errors='replace') if isinstance(s, bytes) else (s or '')
                       for s in (err.stdout, err.stderr)]
            pytest.fail(f'{" ".join(command)} did not finish within {timeout} s\n'
                        f'stdout:\n{partial[0]}\nstderr:\n{partial[1]}')

    return run
