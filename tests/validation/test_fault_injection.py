"""Faults a run must survive in a defined way (docs/io.md, docs/batch.md):

* a NaN that first appears in the pressure equation: exit status 3 with the failed-state dump
  (`MPMICE_FAULT=nan_pressure_step:N`, modules/base/mpmice_faults.f90);
* a full disk: one line naming the file and "no space left on device", exit status 3, no partial
  file under a final name, the status file left at `running`; with the disk full before the
  start, no empty `used.nml`. On a real
  200 KiB tmpfs when this process may mount one (root); otherwise the dump's failure is injected
  (`MPMICE_FAULT=enospc_dump_step:N`) and the already-full case uses the fault as well;
* kills during dumps: every file under a dump's final name is a complete dump (dumps are
  written to `.tmp` and renamed), and `postproc.mpmice_io.list_dumps` skips unreadable files
  with a warning;
* a SIGTERM during start-up: the run stops before its first step with a checkpoint, exit 0;
* one warning repeated every step: printed 10 times, then counted and summarised at the end.

Corrupt checkpoints and existing output folders are covered with their own checks
(test_input_errors.py and the tests of the restart and output-directory rules). Each test takes
a few seconds.
"""
import contextlib
import os
import pathlib
import signal
import subprocess
import time
import warnings

import h5py
import numpy as np
import pytest

from postproc.mpmice_io import list_dumps
from postproc.run_case import mpi_environment

ROOT = pathlib.Path(__file__).resolve().parents[2]
HEAT2D = ROOT / "namelists" / "heat_conduction_2d.nml"
CAVITY = ROOT / "namelists" / "ice_cavity.nml"
TERZAGHI = ROOT / "namelists" / "mpmice_terzaghi_1d.nml"


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """No multi-line report of Open MPI's mpirun on a non-zero exit (as in test_input_errors)."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


def read_status(path):
    with open(path, encoding="utf-8") as handle:
        return dict(line.split(" = ", 1) for line in handle.read().splitlines())


def mpmice_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("mpmice:")]


# --- a NaN in the pressure equation (case 7) --------------------------------------------------

@pytest.mark.parametrize("namelist, name, nranks, only_cell, fault", [
    (CAVITY, "cavity", 1, True, "nan"),        # hypre PCG + PFMG: the system is not solved
    (CAVITY, "cavity", 2, True, "nan"),
    (TERZAGHI, "terzaghi", 1, False, "nan"),   # coupled scene; the direct line solve spreads it
    (CAVITY, "cavity", 2, False, "huge"),      # PCG overflows: hypre's error flag, NaN result
])
def test_nan_in_pressure_equation_fails_with_dump(run_mpmice, tmp_case_dir, monkeypatch,
                                                  namelist, name, nranks, only_cell, fault):
    monkeypatch.setenv("MPMICE_FAULT", f"{fault}_pressure_step:3")
    result = run_mpmice([str(namelist), "--set", "&run output_dir = 'out' /"], nranks=nranks,
                        timeout=120)
    assert result.returncode == 3, result.stdout + result.stderr
    assert "non-finite values at step 3" in result.stdout, result.stdout
    assert "hypre" not in result.stderr, result.stderr
    out = tmp_case_dir / "out"
    assert read_status(out / f"{name}.status")["state"] == "failed"
    with h5py.File(out / f"{name}_failed_000003.h5") as dump:
        pressure = dump["cell/pressure"][...]
    # the injected cell (the first cell of rank 0), and no other where hypre would have solved
    assert not np.isfinite(pressure.flat[0])
    if only_cell:
        assert np.count_nonzero(~np.isfinite(pressure)) == 1


# --- a full disk (case 8) ---------------------------------------------------------------------

@contextlib.contextmanager
def small_disk(directory: pathlib.Path, size: str = "200k"):
    """A tmpfs of `size` mounted on `directory` (yields True), or the plain directory (yields
    False) where this process may not mount."""
    directory.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs",
                              str(directory)], capture_output=True, check=False).returncode == 0
    try:
        yield mounted
    finally:
        if mounted:
            subprocess.run(["umount", str(directory)], check=False)


def assert_no_partial_files(out: pathlib.Path):
    """Every `.h5` under a final name is readable; no temporary file is left."""
    for path in out.iterdir():
        assert not path.name.endswith(".tmp"), path
        if path.suffix == ".h5":
            with h5py.File(path) as f:
                assert "time" in f.attrs, path


def test_full_disk_during_a_dump(run_mpmice, tmp_case_dir, monkeypatch):
    """128 x 64 cells: 70 KB per dump, the third does not fit in 200 KiB."""
    with small_disk(tmp_case_dir / "disk") as mounted:
        if not mounted:
            monkeypatch.setenv("MPMICE_FAULT", "enospc_dump_step:40")
        out = tmp_case_dir / "disk" / "out"
        result = run_mpmice([str(HEAT2D), "--set", f"&run output_dir = '{out}' /",
                             "--set", "&grid ncells = 128, 64, 1 /"], timeout=120)
        assert result.returncode == 3, result.stdout + result.stderr
        lines = mpmice_lines(result.stderr)
        assert len(lines) == 1, result.stderr
        assert "no space left on device" in lines[0], lines[0]
        assert "cannot write " + str(out / "heat2d_") in lines[0], lines[0]
        assert "HDF5-DIAG" not in result.stderr, result.stderr
        failed_file = lines[0].split("cannot write ")[1].split(":")[0]
        assert not os.path.exists(failed_file)
        assert_no_partial_files(out)
        assert len(list_dumps(str(out), "heat2d")) == 2, sorted(os.listdir(out))
        # no final state: a job chain must not take the run for finished or continuable
        assert read_status(out / "heat2d.status")["state"] == "running"


def test_disk_full_before_the_start(run_mpmice, tmp_case_dir, monkeypatch):
    """Nothing fits: the resolved input cannot be written, which is said in one line, and no
    empty `used.nml` is left."""
    with small_disk(tmp_case_dir / "disk") as mounted:
        out = tmp_case_dir / "disk" / "out"
        if mounted:
            out.mkdir()
            with open(tmp_case_dir / "disk" / "fill", "wb") as fill:
                with contextlib.suppress(OSError):
                    fill.write(b"\0" * 400_000)
        else:
            monkeypatch.setenv("MPMICE_FAULT", "enospc_dump_step:0")   # the first dump
        result = run_mpmice([str(HEAT2D), "--set", f"&run output_dir = '{out}' /"], timeout=120)
        assert result.returncode in (1, 3), result.stdout + result.stderr
        text = result.stdout + result.stderr
        assert "no space left on device" in text, text
        if mounted:
            assert "heat2d.used.nml" in text, text
            assert not (out / "heat2d.used.nml").exists()
        assert_no_partial_files(out)


def test_injected_full_disk_on_two_ranks(run_mpmice, tmp_case_dir, monkeypatch):
    """The fault on two ranks: exit status 3 (MPI_Abort with 3), the mpmice line once, no
    partial dump."""
    monkeypatch.setenv("MPMICE_FAULT", "enospc_dump_step:20")
    result = run_mpmice([str(HEAT2D), "--set", "&run output_dir = 'out' /"], nranks=2,
                        timeout=120)
    assert result.returncode == 3, result.stdout + result.stderr
    lines = mpmice_lines(result.stderr)
    assert len(lines) == 1, result.stderr
    assert "heat2d_000020.h5: no space left on device" in lines[0], lines[0]
    out = tmp_case_dir / "out"
    assert_no_partial_files(out)
    assert [os.path.basename(p) for p in list_dumps(str(out), "heat2d")] == ["heat2d_000000.h5"]
    assert read_status(out / "heat2d.status")["state"] == "running"


# --- kills during dumps (case 9) --------------------------------------------------------------

def test_kill_during_dumps_leaves_only_complete_dumps(tmp_case_dir, mpmice_exe):
    """A dump every step of a 512 x 256 grid (1 MB each), killed with SIGKILL as soon as the
    file of a later dump appears (under any name, so while it is being written), three times:
    every file under a dump's name opens and holds its field."""
    for attempt in range(3):
        out = tmp_case_dir / f"out{attempt}"
        command = [str(mpmice_exe), str(HEAT2D), "--set",
                   f"&run output_dir = '{out}', output_interval = 2.5e-4, "
                   "checkpoint_interval = 0.0, end_time = 0.05 /",
                   "--set", "&grid ncells = 512, 256, 1 /"]
        process = subprocess.Popen(command, cwd=str(tmp_case_dir), env=mpi_environment(),
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 60
        target = f"heat2d_{attempt + 1:06d}.h5"
        while time.time() < deadline and process.poll() is None:
            if out.is_dir() and any(name.startswith(target) for name in os.listdir(out)):
                break
            time.sleep(0.0005)
        process.kill()
        process.wait(timeout=30)
        with warnings.catch_warnings():
            warnings.simplefilter("error")   # an unreadable file under a dump's name fails here
            dumps = list_dumps(str(out), "heat2d")
        assert dumps, sorted(os.listdir(out))
        for path in dumps:
            with h5py.File(path) as dump:
                assert dump["cell/temperature"].shape == (1, 256, 512), path
        assert read_status(out / "heat2d.status")["state"] == "running"


def test_list_dumps_skips_unreadable_files(tmp_path):
    good = tmp_path / "run_000000.h5"
    with h5py.File(good, "w") as f:
        f.attrs["time"] = 0.0
        f.attrs["step"] = 0
    (tmp_path / "run_000010.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 100)  # truncated
    (tmp_path / "run_000020.h5.tmp").write_bytes(b"")
    with pytest.warns(UserWarning, match="run_000010.h5"):
        assert list_dumps(str(tmp_path), "run") == [str(good)]


# --- a signal during start-up (case 14) -------------------------------------------------------

def handles_sigterm(pid: int) -> bool:
    """True once process `pid` catches SIGTERM (bit 15 of SigCgt in /proc/<pid>/status)."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("SigCgt:"):
                    return bool(int(line.split()[1], 16) >> (signal.SIGTERM - 1) & 1)
    except OSError:
        pass
    return False


def test_sigterm_during_start_up_stops_cleanly(tmp_case_dir, mpmice_exe):
    """SIGTERM as soon as the process has its handler (before MPI_Init): the run stops before
    its first step with a checkpoint of the initial state, status file `stopped`, exit 0."""
    if not os.path.isdir("/proc/self"):
        pytest.skip("needs /proc to see when the handler is installed")
    out = tmp_case_dir / "out"
    process = subprocess.Popen([str(mpmice_exe), str(HEAT2D), "--set",
                                f"&run output_dir = '{out}' /"], cwd=str(tmp_case_dir),
                               env=mpi_environment(), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 30
    while not handles_sigterm(process.pid) and time.time() < deadline:
        time.sleep(0.001)
    process.send_signal(signal.SIGTERM)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 0, stdout + stderr
    status = read_status(out / "heat2d.status")
    assert status["state"] == "stopped", status
    assert status["reason"].startswith("stopped on SIGTERM before step 1"), status
    assert status["checkpoint"].endswith("heat2d_checkpoint_000000.h5")
    assert os.path.isfile(status["checkpoint"])


# --- repeated warnings (case 13) --------------------------------------------------------------

def test_repeated_warning_is_counted_and_summarised(run_mpmice, tmp_case_dir):
    """One PCG iteration per solve: each of the 80 steps warns twice (solver, heat scene); each
    kind is printed 10 times and summarised with its total."""
    result = run_mpmice([str(HEAT2D), "--set", "&run output_dir = 'out' /",
                         "--set", "&solver max_iterations = 1 /"], timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    lines = result.stderr.splitlines()
    assert sum("did not converge" in line and "warnings like this" not in line
               for line in lines) == 10, result.stderr
    summaries = [line for line in lines if "80 warnings like this one in all, 70 not printed"
                 in line]
    assert len(summaries) == 2, result.stderr
    assert len(lines) < 40, result.stderr
