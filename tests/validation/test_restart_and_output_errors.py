"""Errors that come from the machine, the output folder or a checkpoint rather than from the
namelist (docs/batch.md "Before a run writes"): each is an input
error, i.e. exit status 1, one line on standard error naming what is wrong and why, no HDF5
error stack, and nothing written or overwritten.

* a grid that cannot fit in the node's memory is refused before anything is allocated, also by
  ``--check`` (the estimate per rank and the available memory are in the line);
* an output folder that cannot be created or written is reported with the reason;
* a truncated or corrupt checkpoint, a dump given to ``--restart``, and a ``--set`` that changes
  what the checkpoint holds (``&grid ncells``, ``lower``, ``upper``, physics) are refused;
* a restart continues in the checkpoint's own folder, wherever it is started from;
* an output folder that holds another run's output (same ``&run name``) is refused unless
  ``&run overwrite = .true.``.

Every scene here is a 16-cell heat-conduction case of 10 steps (well under a second a run).
"""
from __future__ import annotations

import os
import pathlib
import shutil
import subprocess

import h5py
import pytest

from postproc.run_case import mpi_environment, mpirun_command

#: 16 cells, 10 steps, checkpoints at steps 5 and 10; output in ``out/``.
CASE = """&run
  name = 'good'
  output_dir = 'out'
  end_time = 0.01
  checkpoint_interval = 0.005
/
&grid
  ncells = 16, 1, 1
  upper = 2.0, 1.0, 1.0
/
&time
  dt_init = 1.0e-3
  dt_max = 1.0e-3
/
&heat
  amplitude = 0.5
/
"""


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """No multi-line report from Open MPI's mpirun when a rank exits with a non-zero status (as
    in test_input_errors.py): standard error holds only what mpmice prints."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


def error_lines(result):
    """Non-empty lines of standard error."""
    return [line for line in (result.stderr or "").splitlines() if line.strip()]


def assert_one_line_error(result, pieces, prefix="mpmice: input error: "):
    """Exit status 1, exactly one line on standard error holding every piece, no HDF5 stack."""
    lines = error_lines(result)
    assert result.returncode == 1, result.stdout + result.stderr
    assert len(lines) == 1, f"expected one error line, got:\n{result.stderr}"
    assert lines[0].startswith(prefix), lines[0]
    for piece in pieces:
        assert piece in lines[0], f"{piece!r} missing from: {lines[0]}"
    assert "HDF5-DIAG" not in result.stdout + result.stderr


def snapshot(folder: pathlib.Path) -> dict:
    """{name: (size, mtime_ns, content)} of every file below `folder`."""
    return {str(p.relative_to(folder)): (p.stat().st_size, p.stat().st_mtime_ns, p.read_bytes())
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture
def finished_run(run_mpmice, tmp_case_dir):
    """The case run to its end in ``tmp_case_dir/out``: (case dir, output dir, checkpoint at
    step 5, final dump)."""
    (tmp_case_dir / "case.nml").write_text(CASE)
    result = run_mpmice(["case.nml"], cwd=tmp_case_dir)
    assert result.returncode == 0, result.stdout + result.stderr
    out = tmp_case_dir / "out"
    checkpoint = out / "good_checkpoint_000005.h5"
    assert checkpoint.is_file(), sorted(p.name for p in out.iterdir())
    return tmp_case_dir, out, checkpoint, out / "good_000010.h5"


# ------------------------------------------------------------------------ case 2: memory

@pytest.mark.parametrize("nranks", [1, 2])
@pytest.mark.parametrize("check", [True, False], ids=["check", "run"])
def test_grid_beyond_memory_is_refused(run_mpmice, tmp_case_dir, nranks, check):
    """10^15 cells need about 3e8 GiB per rank: refused before allocation, also by --check."""
    (tmp_case_dir / "case.nml").write_text(CASE)
    args = (["--check"] if check else []) + [
        "case.nml", "--set", "&grid ncells = 100000, 100000, 100000 /"]
    result = run_mpmice(args, nranks=nranks, cwd=tmp_case_dir, timeout=120)
    assert_one_line_error(result, ["&grid ncells = 100000, 100000, 100000", "GiB of memory per rank",
                                   f"{nranks} ranks of a node", "available"])
    assert result.stdout.strip() == ""
    assert sorted(p.name for p in tmp_case_dir.iterdir()) == ["case.nml"]


def test_memory_estimate_lets_a_small_case_run(run_mpmice, tmp_case_dir):
    """The estimate does not refuse an ordinary case (--check prints the input, exit 0)."""
    (tmp_case_dir / "case.nml").write_text(CASE)
    result = run_mpmice(["--check", "case.nml", "--set", "&grid ncells = 200, 200, 1 /"],
                        cwd=tmp_case_dir)
    assert result.returncode == 0, result.stderr


# ------------------------------------------------------------------------ case 3: output folder

LONG_NAME = "a" * 300


@pytest.mark.parametrize("output_dir, reason", [
    ("/proc/mpmice_test_out", "cannot create the folder '/proc/mpmice_test_out': "),
    ("afile", "'afile' exists and is a file, not a folder"),
    ("afile/sub", "'afile' is a file, not a folder"),
    (f"x/{LONG_NAME}/y", "is longer than 255 characters"),
], ids=["proc", "existing_file", "below_a_file", "long_component"])
def test_unusable_output_dir_is_reported_with_the_reason(run_mpmice, tmp_case_dir, output_dir,
                                                         reason):
    (tmp_case_dir / "case.nml").write_text(CASE)
    (tmp_case_dir / "afile").write_text("user data\n")
    result = run_mpmice(["case.nml", "--set", f"&run output_dir = '{output_dir}' /"],
                        cwd=tmp_case_dir)
    assert_one_line_error(result, [f"&run output_dir = '{output_dir}'", reason],
                          prefix="mpmice: error: cannot write to &run output_dir")
    assert result.stdout.strip() == ""
    assert sorted(p.name for p in tmp_case_dir.iterdir()) == ["afile", "case.nml"]
    assert (tmp_case_dir / "afile").read_text() == "user data\n"
    assert not os.path.exists("/proc/mpmice_test_out")


# ------------------------------------------------------------------------ case 4: checkpoints

def truncated(checkpoint, target):
    data = checkpoint.read_bytes()
    target.write_bytes(data[:len(data) // 2])


def corrupt_superblock_area(checkpoint, target):
    """Bytes 100-599 (root group and its attributes' headers) replaced by a fixed pattern."""
    data = bytearray(checkpoint.read_bytes())
    for i in range(100, 600):
        data[i] = (i * 37 + 11) % 256
    target.write_bytes(bytes(data))


def corrupt_dataset_header(checkpoint, target):
    """The object header of the checkpoint's temperature dataset overwritten with 0xff."""
    with h5py.File(checkpoint) as f:
        address = h5py.h5o.get_info(f["checkpoint/cell/temperature"].id).addr
    data = bytearray(checkpoint.read_bytes())
    data[address:address + 140] = b"\xff" * 140
    target.write_bytes(bytes(data))


@pytest.mark.parametrize("damage, pieces, nranks", [
    (truncated, ["truncated or corrupt"], 1),
    (truncated, ["truncated or corrupt"], 2),
    (corrupt_superblock_area, ["corrupt"], 1),
    (corrupt_dataset_header, ["corrupt checkpoint"], 2),
], ids=["truncated-1", "truncated-2", "corrupt_root-1", "corrupt_dataset-2"])
def test_damaged_checkpoint_is_an_input_error(run_mpmice, finished_run, nranks, damage, pieces):
    case_dir, out, checkpoint, _ = finished_run
    bad = out / "good_checkpoint_000007.h5"
    damage(checkpoint, bad)
    before = snapshot(case_dir)
    result = run_mpmice(["--restart", str(bad)], nranks=nranks, cwd=case_dir)
    assert_one_line_error(result, [str(bad), "cannot restart from it"] + pieces)
    assert snapshot(case_dir) == before


def test_restart_from_a_dump_is_an_input_error(run_mpmice, finished_run):
    case_dir, out, _, dump = finished_run
    before = snapshot(case_dir)
    result = run_mpmice(["--restart", str(dump)], cwd=case_dir)
    assert_one_line_error(result, [str(dump), "not a checkpoint", "_checkpoint_"])
    assert snapshot(case_dir) == before


# ------------------------------------------------------------------------ case 5: what may change

@pytest.mark.parametrize("change, pieces, nranks", [
    ("&grid ncells = 32, 1, 1 /", ["&grid ncells = 32, 1, 1", "written with 16, 1, 1"], 2),
    ("&grid lower = -1.0, 0.0, 0.0 /", ["&grid lower = -1.0, 0.0, 0.0",
                                        "written with 0.0, 0.0, 0.0"], 1),
    ("&grid upper = 4.0, 1.0, 1.0 /", ["&grid upper = 4.0, 1.0, 1.0",
                                       "written with 2.0, 1.0, 1.0"], 2),
    ("&heat conductivity = 2.0 /", ["&heat conductivity = 2.0", "written with 1.0"], 1),
    ("&run name = 'other' /", ["&run name = 'other'", "written with 'good'"], 1),
], ids=["ncells", "lower", "upper", "physics", "name"])
def test_restart_refuses_changes_the_checkpoint_cannot_honour(run_mpmice, finished_run, nranks,
                                                              change, pieces):
    """Refused by --check and by the run, which then writes nothing: the original run's
    used.nml, status and dumps keep their content and times."""
    case_dir, _, checkpoint, _ = finished_run
    before = snapshot(case_dir)
    for check in (["--check"], []):
        result = run_mpmice(check + ["--restart", str(checkpoint), "--set", change],
                            nranks=nranks, cwd=case_dir)
        assert_one_line_error(result, ["--set", "a restart cannot change it",
                                       "a restart accepts changes only to"] + pieces)
        assert snapshot(case_dir) == before


def test_restart_accepts_run_control_changes(run_mpmice, finished_run):
    """A later end time, other intervals, dt limits and a decomposition are accepted."""
    case_dir, out, checkpoint, _ = finished_run
    result = run_mpmice(["--restart", str(checkpoint), "--set",
                         "&run end_time = 0.012, output_interval = 0.004, progress_interval = 0 /",
                         "--set", "&time dt_init = 5.0e-4, dt_max = 5.0e-4 /", "--set", "&grid dims = 2, 1, 1 /"],
                        nranks=2, cwd=case_dir)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "state = finished" in (out / "good.status").read_text()
    times = []
    for path in sorted(out.glob("good_0*.h5")):
        with h5py.File(path) as f:
            times.append(round(float(f.attrs["time"]), 9))
    assert times[-1] == 0.012, times


# ------------------------------------------------------------------------ case 6: where it writes

def test_restart_continues_in_the_checkpoint_folder(run_mpmice, tmp_path):
    """A run in A with the relative output_dir 'out' stops at step 5; restarted from another
    working directory B it writes into A/out (the checkpoint's folder), never into B/out."""
    a, b = tmp_path / "A", tmp_path / "B"
    a.mkdir()
    b.mkdir()
    (a / "case.nml").write_text(CASE)
    first = run_mpmice(["case.nml", "--set", "&run max_steps = 5 /"], cwd=a)
    assert first.returncode == 0, first.stdout + first.stderr
    assert "state = stopped" in (a / "out" / "good.status").read_text()
    assert not (a / "out" / "good_000010.h5").exists()
    restart = run_mpmice(["--restart", "../A/out/good_checkpoint_000005.h5"], cwd=b)
    assert restart.returncode == 0, restart.stdout + restart.stderr
    assert sorted(p.name for p in b.iterdir()) == []
    assert (a / "out" / "good_000010.h5").is_file()
    assert "state = finished" in (a / "out" / "good.status").read_text()


# ------------------------------------------------------------------------ case 10: used folders

def test_output_dir_of_another_run_is_refused(run_mpmice, finished_run):
    """Running the case again into the same folder is refused and changes nothing."""
    case_dir, _, _, _ = finished_run
    before = snapshot(case_dir)
    result = run_mpmice(["case.nml"], nranks=2, cwd=case_dir)
    assert_one_line_error(result, ["&run output_dir = 'out'", "already holds the output of a "
                                   "run named 'good'", "good.used.nml", "overwrite = .true."])
    assert snapshot(case_dir) == before


@pytest.mark.parametrize("marker", ["good.status", "good.xmf", "good_000000.h5"])
def test_any_file_of_the_run_marks_the_folder_as_used(run_mpmice, finished_run, marker):
    """The echo alone is not what marks a used folder: the status file, the time series or
    the first dump do too (e.g. after the user removed good.used.nml)."""
    case_dir, out, _, _ = finished_run
    for path in out.iterdir():
        if path.name != marker:
            path.unlink()
    result = run_mpmice(["case.nml"], cwd=case_dir)
    assert_one_line_error(result, ["already holds the output", marker])


def test_simultaneous_runs_into_one_folder(mpmice_exe, tmp_case_dir):
    """Two runs of the same case started together into one empty folder: exactly one runs, the
    other is refused (the echo is created exclusively, so even overlapping checks cannot both
    pass)."""
    (tmp_case_dir / "case.nml").write_text(CASE)
    env = mpi_environment()
    env["OMPI_MCA_orte_execute_quiet"] = "1"
    processes = [subprocess.Popen(mpirun_command(mpmice_exe, ["case.nml"], 1),
                                  cwd=str(tmp_case_dir), env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [(p.wait(timeout=120), p.communicate()[1]) for p in processes]
    assert sorted(code for code, _ in results) == [0, 1], results
    refused = [err for code, err in results if code == 1][0]
    assert "already holds the output of a run named 'good'" in refused, refused
    assert "state = finished" in (tmp_case_dir / "out" / "good.status").read_text()


def test_overwrite_replaces_the_earlier_run(run_mpmice, finished_run):
    case_dir, out, _, dump = finished_run
    old = dump.stat().st_mtime_ns
    result = run_mpmice(["case.nml", "--set", "&run overwrite = .true. /"], cwd=case_dir)
    assert result.returncode == 0, result.stdout + result.stderr
    assert dump.stat().st_mtime_ns > old
    assert "overwrite = .true." in (out / "good.used.nml").read_text()


def test_another_name_may_share_the_folder(run_mpmice, finished_run):
    """Only output of the same &run name counts: a differently named run may write beside it."""
    case_dir, out, _, _ = finished_run
    result = run_mpmice(["case.nml", "--set", "&run name = 'second' /"], cwd=case_dir)
    assert result.returncode == 0, result.stdout + result.stderr
    assert (out / "second_000010.h5").is_file() and (out / "good_000010.h5").is_file()


def test_restart_into_a_used_other_folder_is_refused(run_mpmice, finished_run):
    """A restart continues its own run in its own folder; sent with --set to a folder holding
    another run of the same name it is refused like a fresh run."""
    case_dir, out, checkpoint, _ = finished_run
    other = case_dir / "other"
    shutil.copytree(out, other)
    before = snapshot(case_dir)
    result = run_mpmice(["--restart", str(checkpoint), "--set", "&run output_dir = 'other' /"],
                        cwd=case_dir)
    assert_one_line_error(result, ["&run output_dir = 'other'", "already holds the output"])
    assert snapshot(case_dir) == before
