"""Run the mpmice executable under mpirun from Python (validations, studies, benchmarks, and the
pytest fixtures in tests/validation/conftest.py)."""
from __future__ import annotations

import functools
import os
import re
import shutil
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

#: Open MPI settings for containers and small machines: allow root, allow more ranks than cores.
OMPI_ENV = {
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    "OMPI_MCA_hwloc_base_binding_policy": "none",  # concurrent runs: not all on core 0
}


def mpmice_executable() -> str:
    """Path of the executable: $MPMICE_EXE, else build/bin/mpmice in the repository, else (the
    package installed as <prefix>/share/mpmice/postproc, docs/install.md) <prefix>/bin/mpmice."""
    if os.environ.get("MPMICE_EXE"):
        return os.path.abspath(os.environ["MPMICE_EXE"])
    build = os.path.join(ROOT, "build", "bin", "mpmice")
    installed = os.path.normpath(os.path.join(ROOT, "..", "..", "bin", "mpmice"))
    if not os.path.exists(build) and os.path.exists(installed):
        return installed
    return os.path.abspath(build)


def mpirun_executable() -> str:
    """The MPI launcher: ``$MPIEXEC`` if set, else ``mpirun`` from the PATH."""
    return os.environ.get("MPIEXEC") or shutil.which("mpirun") or "mpirun"


@functools.lru_cache(maxsize=None)
def is_open_mpi(launcher: str) -> bool:
    """True when ``launcher`` belongs to Open MPI (which needs --oversubscribe beyond the cores)."""
    try:
        out = subprocess.run([launcher, "--version"], capture_output=True, text=True, timeout=30,
                             check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return "Open MPI" in out.stdout + out.stderr or "OpenRTE" in out.stdout + out.stderr


def mpirun_command(exe: str, args, nranks: int) -> list[str]:
    """Command line that runs ``exe args`` on ``nranks`` ranks."""
    launcher = mpirun_executable()
    command = [launcher, "-n", str(nranks)]
    if nranks > 2 and is_open_mpi(launcher):
        command.append("--oversubscribe")
    return command + [str(exe)] + [str(a) for a in args]


def mpi_environment() -> dict[str, str]:
    """The current environment plus OMPI_ENV (existing values win)."""
    env = dict(os.environ)
    for key, value in OMPI_ENV.items():
        env.setdefault(key, value)
    return env


#: ``--set`` text that lets a run replace the output of an earlier run in its output folder.
OVERWRITE = "&run overwrite = .true. /"

#: Wall-clock limit of one run [s] unless the caller gives another (validations, studies and
#: the tests' ``run_mpmice`` fixture alike).
RUN_TIMEOUT = 600.0


class RunFailed(RuntimeError):
    """A run ended with a non-zero exit status (``check``) or ran past its time limit."""


def _text(stream) -> str:
    return stream.decode(errors="replace") if isinstance(stream, bytes) else (stream or "")


def run_mpmice(args, nranks: int = 1, cwd: str | None = None, timeout: float = RUN_TIMEOUT,
               check: bool = True, exe: str | None = None,
               overwrite: bool = True) -> subprocess.CompletedProcess:
    """Run ``mpirun -n nranks mpmice ARGS`` (text mode, output captured) and return the
    ``subprocess.CompletedProcess``. The one way the validations, studies, benchmarks and tests
    run the program:

    * ``check``: a non-zero exit status raises ``RunFailed`` with the command and its output;
      without it the caller inspects ``returncode`` (the tests of failing runs);
    * ``timeout`` [s]: a run still going then is killed and raises ``RunFailed`` with the
      output it had written, whatever ``check`` says;
    * ``overwrite`` (the default: studies and benchmarks rerun their scenes into the same
      folders): ``--set '&run overwrite = .true. /'`` is appended, so a folder holding an earlier
      run's output is reused instead of refused;
    * ``exe``: the executable (default ``mpmice_executable()``).
    """
    args = list(args) + (["--set", OVERWRITE] if overwrite else [])
    command = mpirun_command(exe or mpmice_executable(), args, nranks)
    try:
        result = subprocess.run(command, cwd=cwd, env=mpi_environment(), capture_output=True,
                                text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired as err:
        raise RunFailed(f"{' '.join(command)} did not finish within {timeout} s\n"
                        f"stdout:\n{_text(err.stdout)}\nstderr:\n{_text(err.stderr)}") from None
    result.stderr = without_launcher_noise(result.stderr)
    if check and result.returncode != 0:
        raise RunFailed(f"{' '.join(command)} failed ({result.returncode}):\n"
                        f"{result.stdout}\n{result.stderr}")
    return result


def run_into(folder: str, namelist: str, *sets: str, **options) -> subprocess.CompletedProcess:
    """:func:`run_mpmice` of ``namelist`` with its output in ``folder`` (``&run output_dir``)
    and each text of ``sets`` as one ``--set``: the form most scene tests run; ``options``
    (``nranks``, ``cwd``, ``timeout``, ``exe``, ...) go to :func:`run_mpmice`."""
    args = [namelist, "--set", f"&run output_dir = '{folder}' /"]
    for text in sets:
        args += ["--set", text]
    return run_mpmice(args, **options)


def run_side_by_side(base: str, namelists: dict[str, str], *sets: str, report,
                     **options) -> dict:
    """:func:`run_into` of each ``namelists`` {label: path} into ``base``/label with the same
    ``sets``, two runs at a time; returns {label: ``report(folder)``} in the order given."""
    from concurrent.futures import ThreadPoolExecutor

    def one(label):
        folder = os.path.join(base, label)
        run_into(folder, namelists[label], *sets, cwd=base, **options)
        return label, report(folder)

    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(pool.map(one, namelists))


#: The warning that the event library inside Open MPI's launcher sometimes prints while a job's
#: processes exit (a race in its shutdown, open-mpi/ompi issues 2004 and 5520): not the
#: program's output.
_LAUNCHER_NOISE = re.compile(r"^\[warn\] Epoll (?:ADD|MOD|DEL)\(\d+\) on fd \d+ failed\..*(?:\n|$)",
                             re.MULTILINE)


def without_launcher_noise(stderr: str) -> str:
    """``stderr`` without the lines of ``_LAUNCHER_NOISE``, so that a test that counts the
    program's error lines counts only the program's."""
    return _LAUNCHER_NOISE.sub("", stderr or "")


#: A row of the stage-timer table a run prints at the end: stage, calls, max [s], mean [s], %,
#: per call [ms].
_TIMER_ROW = re.compile(r"\s*(.+?)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s*$")


def stage_timers(stdout: str, column: str = "max") -> dict[str, tuple[int, float]]:
    """The stage-timer table of a run's standard output: {stage: (calls, seconds)}, the seconds
    the maximum over ranks (the benchmarks' per-stage costs) or, with ``column="mean"``, the
    mean over ranks."""
    group = {"max": 3, "mean": 4}[column]
    stages = {}
    for line in stdout.splitlines():
        m = _TIMER_ROW.match(line)
        if m:
            stages[m.group(1).strip()] = (int(m.group(2)), float(m.group(group)))
    return stages
