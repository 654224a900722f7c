"""Run the mpmice executable from Python (validations, studies, benchmarks)."""
from __future__ import annotations

import os
import shutil
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def mpmice_executable() -> str:
    """Path of the executable: $MPMICE_EXE, else build/bin/mpmice in the repository."""
    return os.path.abspath(os.environ.get("MPMICE_EXE", os.path.join(ROOT, "build", "bin", "mpmice")))


def mpi_environment() -> dict[str, str]:
    """Environment for mpirun as root and oversubscribed on small machines."""
    env = dict(os.environ)
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    return env


def run_mpmice(args: list[str], nranks: int = 1, cwd: str | None = None,
               timeout: float = 600, check: bool = True) -> subprocess.CompletedProcess:
    """Run ``mpirun -n nranks mpmice ARGS`` and return the completed process."""
    mpirun = shutil.which("mpirun") or "mpirun"
    command = [mpirun, "-n", str(nranks)]
    if nranks > 2:
        command.append("--oversubscribe")
    command += [mpmice_executable()] + list(args)
    result = subprocess.run(command, cwd=cwd, env=mpi_environment(), capture_output=True,
                            text=True, timeout=timeout)
    if check and result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({result.returncode}):\n"
                           f"{result.stdout}\n{result.stderr}")
    return result
