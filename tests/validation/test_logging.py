"""Logging of a run (issue 3, item 8): the progress line (step, time, dt, % done, wall time, ETA)
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
