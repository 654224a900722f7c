"""bench.run_projection: the checkpoints it samples, the steps each sample stands for, the
seconds per step it reads from the progress lines, and a projection of a short run whose
checkpoints it restarts (the sum of the samples' steps x seconds per step)."""
import os
import re

import pytest

from bench import run_projection as dp
from postproc.run_case import ROOT, run_mpmice


def test_samples_spread_over_the_run_without_its_end():
    steps = [100 * k for k in range(1, 12)]          # 11 checkpoints, the last at step 1100
    assert dp.pick_samples(steps, 5) == [0, 2, 4, 7, 9]
    assert dp.pick_samples(steps, 1) == [0]
    assert dp.pick_samples(steps, 50) == list(range(10))
    with pytest.raises(ValueError):
        dp.pick_samples([100], 3)


def test_each_sample_stands_for_the_steps_nearest_to_it():
    weights = dp.sample_weights([100, 300, 900], 1000)
    assert weights == [200, 400, 400]
    assert sum(weights) == 1000


def test_seconds_per_step_from_the_progress_lines():
    text = "\n".join([
        "mpmice: restart from x.h5",
        "step      11  t =  1.0e-03 s  dt =  1.0e-04 s   0.1%  wall    5.00 s  ETA  100 s",
        "step      12  t =  1.1e-03 s  dt =  1.0e-04 s   0.1%  wall    5.25 s  ETA  100 s",
        "step      15  t =  1.4e-03 s  dt =  1.0e-04 s   0.2%  wall    6.50 s  ETA  100 s"])
    per_step, reached = dp.seconds_per_step(text)
    assert per_step == pytest.approx(0.375)
    assert reached == pytest.approx(1.4e-3)
    with pytest.raises(ValueError):
        dp.seconds_per_step(text.splitlines()[1])


@pytest.mark.mpi
def test_projection_of_a_short_run(tmp_path, mpmice_exe, monkeypatch, capsys):
    """The 40 mm debris flow to 6 ms with a checkpoint every 2 ms (steps 34, 51, 68): 2 samples
    of 10 steps on 1 rank, standing for the steps 0-42 and 42-68; the projection printed equals
    the CSV's sum."""
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))
    out = tmp_path / "run"
    run_mpmice([os.path.join(ROOT, "namelists", "mpmice_debris_flow_2d.nml"), "--set",
                f"&run output_dir = '{out}', end_time = 0.006, output_interval = 10.0, "
                "checkpoint_interval = 0.002 /"],
               cwd=str(tmp_path))
    csv = tmp_path / "p.csv"
    assert dp.main([str(out), "--samples", "2", "--steps", "10", "--ranks", "1",
                    "--config", "as-run", "--csv", str(csv)]) == 0
    text = capsys.readouterr().out
    rows = [line.split(",") for line in csv.read_text().splitlines()[1:]]
    assert [int(r[0]) for r in rows] == [34, 51]
    assert [int(r[1]) for r in rows] == [42, 26]
    projected = sum(int(r[1]) * float(r[3]) for r in rows)
    m = re.search(r"as-run:\s+(\d+) s", text)
    assert m and abs(int(m.group(1)) - projected) <= 1.0, text
