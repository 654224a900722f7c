"""Logging of a run: the progress line (step, time, dt, % done, wall time, ETA)
and the per-stage timer table at the end, printed by rank 0 only.

Runs the 1D heat-conduction scene for 10 steps on 2 ranks with ``&run progress_interval = 0``
(a line every step) and checks standard output line by line.
"""
from __future__ import annotations

import pathlib
import re

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
NAMELIST_1D = str(REPO / "namelists" / "heat_conduction_1d.nml")

#: ``step N  t = T s  dt = DT s  P%  wall W s  ETA E s``
PROGRESS = re.compile(
    r"^step\s+(\d+)\s+t =\s+(\S+) s\s+dt =\s+(\S+) s\s+([\d.]+)%\s+wall\s+([\d.]+) s\s+"
    r"ETA\s+([\d.]+) s\s*$")


@pytest.mark.mpi
def test_progress_line_and_timer_table_on_rank_0_only(run_mpmice, tmp_case_dir):
    result = run_mpmice([NAMELIST_1D, "--set",
                         "&run output_dir = 'out', end_time = 0.01, progress_interval = 0 /"],
                        nranks=2, cwd=tmp_case_dir)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    progress = [PROGRESS.match(line) for line in lines]
    progress = [m for m in progress if m]
    steps = [int(m.group(1)) for m in progress]
    # dt = 1e-3 s to t = 0.01 s: 10 steps, each reported (by one rank: no step twice before the
    # last, which may be repeated by the forced final line)
    assert sorted(set(steps)) == list(range(1, 11)), steps
    for step in range(1, 10):
        assert steps.count(step) == 1, (step, steps)
    last = progress[-1]
    assert float(last.group(2)) == pytest.approx(0.01)
    assert float(last.group(3)) == pytest.approx(1.0e-3)
    assert float(last.group(4)) == pytest.approx(100.0)
    assert float(last.group(6)) == pytest.approx(0.0, abs=0.05)
    percent = [float(m.group(4)) for m in progress]
    assert percent == sorted(percent) and percent[0] == pytest.approx(10.0), percent
    # the timer table, once, with the scene's stages and the total
    headers = [i for i, line in enumerate(lines) if line.startswith("timers (wall seconds")]
    assert len(headers) == 1, result.stdout
    table = "\n".join(lines[headers[0]:])
    for stage in ("output and checkpoint", "assemble", "halo exchange",
                  "implicit solve (hypre)", "total run"):
        assert table.count(stage) == 1, (stage, table)
    assert lines.count("mpmice: finished: end time reached") == 1, result.stdout


@pytest.mark.mpi
def test_log_file_holds_progress_and_timers_and_a_restart_appends(run_mpmice, tmp_case_dir):
    """``<output_dir>/<name>.log`` gets every line rank 0 prints from the start of the run
    (progress, the timer table, the final status, warnings); a restart appends to it."""
    result = run_mpmice([NAMELIST_1D, "--set",
                         "&run output_dir = 'out', end_time = 0.01, progress_interval = 0, "
                         "checkpoint_interval = 0.005 /"],
                        nranks=2, cwd=tmp_case_dir)
    assert result.returncode == 0, result.stderr
    logs = list((tmp_case_dir / "out").glob("*.log"))
    assert len(logs) == 1, logs
    log_lines = logs[0].read_text().splitlines()
    # every progress line and the table as printed on standard output, in order
    printed = [line for line in result.stdout.splitlines() if line.startswith("mpmice: scene")]
    assert printed and log_lines[0] == printed[0]
    start = result.stdout.splitlines().index(log_lines[0])
    assert log_lines == result.stdout.splitlines()[start:], (log_lines, result.stdout)
    assert sum(bool(PROGRESS.match(line)) for line in log_lines) >= 10
    assert sum(line.startswith("timers (wall seconds") for line in log_lines) == 1
    checkpoint = sorted((tmp_case_dir / "out").glob("*_checkpoint_*.h5"))[0]
    restart = run_mpmice(["--restart", str(checkpoint)], nranks=1, cwd=tmp_case_dir)
    assert restart.returncode == 0, restart.stderr
    again = logs[0].read_text().splitlines()
    assert again[:len(log_lines)] == log_lines
    assert sum(line.startswith("timers (wall seconds") for line in again) == 2
    assert again[-1] == "mpmice: finished: end time reached"


def test_echo_shows_an_unset_table_as_unset(mpmice_exe):
    """The resolved-input echo writes an unset velocity table as a comment, not as
    ``64*-1.797e308``."""
    import subprocess
    namelist = str(REPO / "namelists" / "mpmice_debris_flow_2d.nml")
    out = subprocess.run([mpmice_exe, "--check", namelist], capture_output=True, text=True,
                         check=True).stdout
    assert "&boundary" in out and "1.797" not in out, out
    assert "  ! solid_velocity_times = unset" in out
    assert "  ! solid_velocity_history = unset" in out
