"""Batch operation: SIGUSR1 (what a batch system sends before the wall-time limit) makes a run write
a checkpoint and stop with status 0 and a `stopped` status file; the restarted run finishes with
dumps bitwise identical to an uninterrupted run. `&run wall_time_limit` does the same on its own."""
import os
import signal
import subprocess
import time


from postproc.dump_compare import assert_dumps_identical
from postproc.heat_conduction import dump_files
from postproc.run_case import mpi_environment, mpirun_command, run_mpmice

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NAMELIST = os.path.join(ROOT, "namelists", "heat_conduction_2d.nml")
# 128 x 64 cells: about 2 s on a quiet machine, so that a signal sent 0.5 s after the first dump
# arrives well before the end (the namelist's 64 x 32 finishes in 0.5 s)
LONG = ["--set", "&run end_time = 1.0, output_interval = 0.25, checkpoint_interval = 0.0 /",
        "--set", "&grid ncells = 128, 64, 1 /"]


def read_status(path):
    with open(path, encoding="utf-8") as handle:
        return dict(line.split(" = ", 1) for line in handle.read().splitlines())


def assert_same_dumps(reference_dir, other_dir):
    dumps = dump_files(str(reference_dir))
    assert len(dumps) == 5  # t = 0, 0.25, 0.5, 0.75, 1
    for path in dumps:
        assert_dumps_identical(path, os.path.join(other_dir, os.path.basename(path)))


def test_sigusr1_checkpoints_and_restart_continues_identically(tmp_path, mpmice_exe):
    full = tmp_path / "full"
    run_mpmice([NAMELIST] + LONG + ["--set", f"&run output_dir = '{full}' /"], nranks=2,
               exe=str(mpmice_exe), cwd=str(tmp_path))
    assert read_status(full / "heat2d.status")["state"] == "finished"

    cut = tmp_path / "cut"
    command = mpirun_command(mpmice_exe, [NAMELIST] + LONG + ["--set", f"&run output_dir = '{cut}' /"], 2)
    process = subprocess.Popen(command, cwd=str(tmp_path), env=mpi_environment(),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while not (cut / "heat2d_000000.h5").exists() and time.time() < deadline:
        time.sleep(0.05)
    time.sleep(0.5)
    process.send_signal(signal.SIGUSR1)
    out, err = process.communicate(timeout=120)
    assert process.returncode == 0, out + err
    status = read_status(cut / "heat2d.status")
    assert status["state"] == "stopped", status
    assert "SIGUSR1" in status["reason"]
    assert 0 < int(status["step"]) < 4000
    run_mpmice(["--restart", status["checkpoint"]], nranks=2, exe=str(mpmice_exe),
               cwd=str(tmp_path))
    assert read_status(cut / "heat2d.status")["state"] == "finished"
    assert_same_dumps(full, cut)


def test_wall_time_limit_stops_with_checkpoint(tmp_path, mpmice_exe):
    out = tmp_path / "wall"
    # the limit keeps a margin of 10 s + twice the slowest step, so 10.5 s stops after ~0.5 s;
    # the run is made 20x longer than LONG so that it cannot finish before the limit
    very_long = LONG + ["--set", "&run end_time = 20.0 /"]
    run_mpmice([NAMELIST] + very_long + ["--set", f"&run output_dir = '{out}', wall_time_limit = 10.5 /"],
               nranks=1, exe=str(mpmice_exe), cwd=str(tmp_path))
    status = read_status(out / "heat2d.status")
    assert status["state"] == "stopped", status
    assert "wall_time_limit" in status["reason"]
    assert os.path.isfile(status["checkpoint"])


def test_restart_chain_script(tmp_path, mpmice_exe):
    """jobs/mpmice_chain.sh, run three times with &run max_steps = 1500, starts, continues twice
    and finishes with dumps identical to an uninterrupted run; the --set options reach the
    continuations too (a progress interval given to the continuations only is in the last
    link's resolved input)."""
    full = tmp_path / "full"
    run_mpmice([NAMELIST] + LONG + ["--set", f"&run output_dir = '{full}' /"], nranks=2,
               exe=str(mpmice_exe), cwd=str(tmp_path))
    chain = tmp_path / "chain"
    env = mpi_environment()
    env["MPMICE_EXE"] = str(mpmice_exe)
    env["MPMICE_LAUNCH"] = "mpirun -n 2"
    states = []
    for link in range(3):
        own = [] if link == 0 else ["--set", "&run progress_interval = 7.0 /"]
        result = subprocess.run(
            [os.path.join(ROOT, "jobs", "mpmice_chain.sh"), NAMELIST] + LONG
            + ["--set", f"&run output_dir = '{chain}', max_steps = 1500 /"] + own,
            cwd=str(tmp_path), env=env, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, result.stdout + result.stderr
        states.append(result.stdout.splitlines()[-1])
    assert states == ["stopped", "stopped", "finished"]
    assert_same_dumps(full, chain)
    # the continuations' own --set (a progress interval) reached the last link's resolved input
    used = (chain / "heat2d.used.nml").read_text()
    assert "progress_interval = 7.0" in used, used
