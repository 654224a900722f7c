"""Shared fixtures of the validation tests: run the ``mpmice`` executable on small scenes.

* ``mpmice_exe``: path of the executable, from the environment variable ``MPMICE_EXE`` or else
  ``build/bin/mpmice``; tests that need it are skipped (with the reason) when it is missing.
* ``unavailable(reason)``: skip the test with ``reason``, or fail it under ``MPMICE_REQUIRE_ALL=1``.

With ``MPMICE_REQUIRE_ALL=1`` (set by scripts/test.sh) nothing may skip: a missing executable, a
scene whose ``--check`` fails or a build that answers "not implemented" fails the test, and any
other skip is reported as a failure too (``pytest_runtest_makereport`` below), except
``allowed_skip(reason)``: a test whose external reference data (``../shared/reference``, not part
of the repository) are absent skips with a reason starting ``ALLOWED_SKIP``, also under
``MPMICE_REQUIRE_ALL`` (docs/testing.md).
* ``run_mpmice(args, nranks=1, cwd=None, timeout=RUN_TIMEOUT, check=False)``: run it under
  ``mpirun`` through ``postproc.run_case.run_mpmice`` (the one run helper) and return the
  ``subprocess.CompletedProcess`` (text mode, stdout and stderr captured); a time-out, and with
  ``check`` a non-zero exit status, fails the test with the output.
* ``tmp_case_dir``: an empty directory per test, the default working directory of ``run_mpmice``.
"""

import os
from pathlib import Path

import pytest

from postproc import run_case
from postproc.run_case import RUN_TIMEOUT, RunFailed

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Under the test script every test must run: a skip is a failure.
REQUIRE_ALL = os.environ.get('MPMICE_REQUIRE_ALL', '') not in ('', '0')


#: Prefix of the one kind of skip MPMICE_REQUIRE_ALL lets through: external reference data absent.
ALLOWED_SKIP = 'allowed skip, reference data absent: '


def skip_or_fail(reason):
    """Skip the current test with ``reason``, or fail it when ``MPMICE_REQUIRE_ALL`` is set."""
    if REQUIRE_ALL:
        pytest.fail(f'{reason} (MPMICE_REQUIRE_ALL=1: a test that cannot run fails)', pytrace=False)
    pytest.skip(reason)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Under ``MPMICE_REQUIRE_ALL`` report any skip (e.g. a future ``pytest.skip``) as a failure."""
    outcome = yield
    report = outcome.get_result()
    if REQUIRE_ALL and report.skipped and not hasattr(report, 'wasxfail'):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        if ALLOWED_SKIP in reason:
            return
        report.outcome = 'failed'
        report.longrepr = f'skipped under MPMICE_REQUIRE_ALL=1, which forbids skips: {reason}'


@pytest.fixture(scope='session')
def mpmice_exe():
    """Path of the mpmice executable; skips (or fails, see REQUIRE_ALL) the test when it has not
    been built."""
    path = Path(os.environ.get('MPMICE_EXE') or REPO_ROOT / 'build' / 'bin' / 'mpmice').resolve()
    if not (path.is_file() and os.access(path, os.X_OK)):
        skip_or_fail(f'mpmice executable not found at {path}: build it with scripts/setup.sh '
                    'or point MPMICE_EXE at it')
    return path


@pytest.fixture(scope='session')
def unavailable():
    """``skip_or_fail``, for tests whose scene cannot run in this build."""
    return skip_or_fail


@pytest.fixture(scope='session')
def allowed_skip():
    """``allowed_skip(what)``: skip because the external reference data ``what`` (a folder under
    ../shared/reference, never copied into the repository) is absent; allowed under
    ``MPMICE_REQUIRE_ALL``. Use it only for that reason."""

    def skip(what):
        pytest.skip(f'{ALLOWED_SKIP}{what}')

    return skip


@pytest.fixture
def tmp_case_dir(tmp_path):
    """An empty directory for one test's namelists and output."""
    case_dir = tmp_path / 'case'
    case_dir.mkdir()
    return case_dir


@pytest.fixture
def run_mpmice(mpmice_exe, tmp_case_dir):
    """Function running mpmice under mpirun; see the module docstring."""

    def run(args, nranks=1, cwd=None, timeout=RUN_TIMEOUT, check=False):
        try:
            return run_case.run_mpmice(args, nranks=nranks, cwd=str(cwd or tmp_case_dir),
                                       timeout=timeout, check=check, exe=mpmice_exe,
                                       overwrite=False)
        except RunFailed as err:
            pytest.fail(str(err), pytrace=False)

    return run
