"""Blocks cut by the modelled cost (`&grid balance = 'cost'`): the submerged sand block, whose
particles sit in the lower left corner of the tank, on 2 ranks with the cut moved into the sand
(in x where `dims = 2, 1, 1` fixes the layout, in y where the model chooses it) equals the
1-rank run to the rank-invariance tolerances; a restart counts the particles in its
checkpoint: the same blocks while they have not moved (bitwise continuation), new blocks after
the sliding block moved right (the uninterrupted run's end to the rank-invariance tolerances);
with `&grid rebalance` the blocks follow the particles within one run (the run ends where the
run on fixed blocks does); an unknown value, or rebalance without its prerequisites, is one
input-error line."""
import os
import re

import h5py
import numpy as np
import pytest

from postproc.dump_compare import (assert_dumps_identical, assert_field_close,
                                   assert_particles_close)
from postproc.mpm_common import particles
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_into, run_mpmice

BLOCK = os.path.join(ROOT, "namelists", "mpmice_submerged_block_2d.nml")
#: 40 x 20 cells; the block (x < 0.2 m, 2 x 2 particles per cell) fills 8 columns of 8 cells,
#: 32 particles per column and per row. A cut at column c costs F = 20 (40 - c) + 4 x 32
#: max(c, 8 - c) for c <= 8 (least, 1232, at c = 4: the particles halved) and 20 max(c, 40 - c) +
#: 4 x 256 beyond (least, 1424, at the even cut): with weight 4 the cut goes through the sand, at
#: column 4. A cut at row r costs 40 (20 - r) + 4 x 32 max(r, 8 - r) for r <= 8 (least, 1152, at
#: r = 4): with the layout free the model takes the y cut at row 4
COST = "&grid balance = 'cost', particle_weight = 4.0 /"
BLOCKS = ("y", 4, 16)
#: 4 ranks: 2 x 2 (MPI_Dims_create), 1 x 4 and 4 x 1 compared; the y strips 3, 3, 6, 8 put 8 x 3
#: x 4 = 96 particles and at most 40 x 8 = 320 cells in a block: F = 320 + 4 x 96 = 704
CASES = {"x": (2, "&grid balance = 'cost', particle_weight = 4.0, dims = 2, 1, 1 /",
               ("x", 4, 36), "modelled cost 1232 cells per step"),
         "free": (2, COST, BLOCKS, "modelled cost 1152 cells per step, the least of 2 layouts "
                                  "(2 x 1 x 1: 1232)"),
         "free4": (4, COST, ("y", 3, 3, 6, 8), "modelled cost 704 cells per step, the least of "
                                              "3 layouts (2 x 2 x 1: 832)")}
SETS = ("&run end_time = 0.02, output_interval = 0.01 /",)


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _run(tmp_path, label, nranks, *sets):
    out = str(tmp_path / label)
    return out, run_into(out, BLOCK, *sets, nranks=nranks, cwd=str(tmp_path))


def _blocks(stdout, restart=False, report=None):
    """(axis, cells of each block) from the log line of a run cut along one axis."""
    m = re.search(r"blocks balanced by cost: ([xyz]) ([\d,]+)(.*)", stdout)
    assert m, stdout
    assert ("particles counted in the checkpoint" in m.group(3)) == restart, m.group(0)
    if report is not None:
        assert m.group(3).endswith("; " + report), m.group(0)
    return (m.group(1),) + tuple(int(c) for c in m.group(2).split(","))


def _fields(path):
    with h5py.File(path) as f:
        cells = {k: f[k][...] for k in ("cell/pressure", "cell/water/velocity_x",
                                        "cell/water/velocity_y", "cell/solid_volume_fraction")}
        order = np.lexsort((f["particles/sand/x"][...], f["particles/sand/y"][...]))
        parts = {k: f[f"particles/sand/{k}"][...][order] for k in ("x", "y", "velocity_y",
                                                                  "stress_yy")}
    return cells, parts


@pytest.mark.mpi
@pytest.mark.parametrize("case", sorted(CASES))
def test_cost_blocks_equal_one_rank(tmp_path, case):
    """2 ranks cut through the sand (at column 4 of 40 with the x layout fixed, at row 4 of 20
    where the model compares the layouts) and 4 ranks in y strips through it, each with the
    modelled cost the log line reports, equal 1 rank: pressure to 1e-9 of its range, water
    velocity to 1e-9 of its largest value, particle positions to 1e-12 m, stress to 1e-9 of its
    largest value (the tolerances of test_mpmice_parallel's submerged block)."""
    nranks, cost, blocks, report = CASES[case]
    one = list_dumps(_run(tmp_path, "r1", 1, *SETS)[0], "block2d")
    out, result = _run(tmp_path, "cost", nranks, *SETS, cost)
    assert _blocks(result.stdout, report=report) == blocks
    two = list_dumps(out, "block2d")
    assert [os.path.basename(p) for p in one] == [os.path.basename(p) for p in two]
    c1, p1 = _fields(one[-1])
    c2, p2 = _fields(two[-1])
    prange = np.ptp(c1["cell/pressure"])
    assert prange > 100.0   # the hydrostatic column: the comparison is not of zeros
    assert np.max(np.abs(c1["cell/pressure"] - c2["cell/pressure"])) < 1e-9 * prange
    for key in ("cell/water/velocity_x", "cell/water/velocity_y"):
        scale = np.max(np.abs(c1[key]))
        assert scale > 0.0
        assert np.max(np.abs(c1[key] - c2[key])) < 1e-9 * scale, key
    assert np.array_equal(c1["cell/solid_volume_fraction"] > 0, c2["cell/solid_volume_fraction"] > 0)
    assert np.max(np.abs(p1["x"] - p2["x"])) < 1e-12
    assert np.max(np.abs(p1["y"] - p2["y"])) < 1e-12
    stress = np.max(np.abs(p1["stress_yy"]))
    assert stress > 0.0
    assert np.max(np.abs(p1["stress_yy"] - p2["stress_yy"])) < 1e-9 * stress


@pytest.mark.mpi
def test_restart_keeps_blocks_while_particles_stay(tmp_path):
    """A 2-rank run with balance = 'cost' stopped after 10 steps and continued from its
    checkpoint: the sand has not moved across a cut, so the particles counted in the checkpoint
    give the same blocks, and the continuation ends bitwise equal to the uninterrupted run."""
    sets = ("&run end_time = 0.005, output_interval = 0.005 /", COST)   # ~48 steps
    full, _ = _run(tmp_path, "full", 2, *sets)
    half, first = _run(tmp_path, "half", 2, *sets, "&run max_steps = 10 /")
    checkpoint = os.path.join(half, "block2d_checkpoint_000010.h5")
    assert os.path.isfile(checkpoint)
    cont = run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 0 /"], nranks=2,
                      cwd=str(tmp_path))
    assert _blocks(cont.stdout, restart=True) == _blocks(first.stdout) == BLOCKS
    a = list_dumps(full, "block2d")[-1]
    b = list_dumps(half, "block2d")[-1]
    assert os.path.basename(a) == os.path.basename(b)
    assert_dumps_identical(a, b)


SLIDE = os.path.join(ROOT, "namelists", "mpm_slide_2d.nml")


@pytest.mark.mpi
def test_restart_follows_moved_particles(tmp_path):
    """The sliding block (mpm_slide_2d: 20 x 20 cells, 4 m/s to the right; solids alone, w =
    20) on 2 ranks cut in x (`dims = 2, 1, 1`): the seeding gives the cut at column 10; after 60 steps (t = 0.025 s) the
    block has moved 0.1 m, and the restart from that checkpoint cuts at column 11. The
    continuation ends where the uninterrupted run on the seeding's blocks ends, to the MPM
    rank-invariance tolerances (test_mpm_parallel: positions 1e-14 m, velocities 3e-13 m/s,
    stresses 3e-13 of the largest)."""
    cost = "&grid balance = 'cost', particle_weight = 20.0, dims = 2, 1, 1 /"
    out_full = str(tmp_path / "full")
    first = run_mpmice([SLIDE, "--set", f"&run output_dir = '{out_full}' /", "--set", cost],
                       nranks=2, cwd=str(tmp_path))
    assert _blocks(first.stdout) == ("x", 10, 10)
    out_half = str(tmp_path / "half")
    run_mpmice([SLIDE, "--set", f"&run output_dir = '{out_half}', max_steps = 60 /",
                "--set", cost], nranks=2, cwd=str(tmp_path))
    checkpoint = os.path.join(out_half, "slide2d_checkpoint_000060.h5")
    cont = run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 0 /"], nranks=2,
                      cwd=str(tmp_path))
    assert _blocks(cont.stdout, restart=True) == ("x", 11, 9)
    a = list_dumps(out_full, "slide2d")[-1]
    b = list_dumps(out_half, "slide2d")[-1]
    assert os.path.basename(a) == os.path.basename(b)
    _, ref = particles(a, "block")
    _, other = particles(b, "block")
    assert np.array_equal(ref["id"], other["id"])
    scale = max(np.max(np.abs(ref[f"stress_{c}"])) for c in ("xx", "yy", "xy"))
    assert scale > 0.0
    for c in ("x", "y"):
        assert np.max(np.abs(other[c] - ref[c])) < 1e-14, c
        assert np.max(np.abs(other[f"velocity_{c}"] - ref[f"velocity_{c}"])) < 3e-13, c
    for c in ("xx", "yy", "zz", "xy"):
        assert np.max(np.abs(other[f"stress_{c}"] - ref[f"stress_{c}"])) < 3e-13 * scale, c


@pytest.mark.mpi
def test_rebalance_within_the_run(tmp_path):
    """`&grid rebalance = .true.` on the sliding block (2 ranks cut in x, a checkpoint every 5
    ms): the blocks follow the block to the right within one run (x 10,10 at the start, 11,9
    at the first move, ending further right), and the run ends where the run on the seeding's
    blocks ends, to the MPM rank-invariance tolerances; the history CSV has the same rows, the
    status file says finished; the log has the scene's summary of each segment before a move.
    With `&run max_steps = 100` the steps count over the segments: the run stops at step 100."""
    cost = ("&grid balance = 'cost', particle_weight = 20.0, dims = 2, 1, 1 /",
            "&run checkpoint_interval = 0.005 /")
    runs = {}
    for label, extra in (("fixed", ()), ("moving", ("&grid rebalance = .true. /",))):
        out = str(tmp_path / label)
        command = [SLIDE, "--set", f"&run output_dir = '{out}' /"]
        for text in cost + extra:
            command += ["--set", text]
        runs[label] = (out, run_mpmice(command, nranks=2, cwd=str(tmp_path)))
    moves = re.findall(r"blocks rebalanced at \S+_checkpoint_(\d+)\.h5: x (\d+),(\d+)",
                       runs["moving"][1].stdout)
    assert len(moves) >= 2, runs["moving"][1].stdout
    assert (int(moves[0][1]), int(moves[0][2])) == (11, 9)
    assert int(moves[-1][1]) > 11
    assert runs["moving"][1].stdout.count("mpmice: the steps on these blocks, to ") == len(moves)
    assert "blocks rebalanced" not in runs["fixed"][1].stdout
    a = list_dumps(runs["fixed"][0], "slide2d")[-1]
    b = list_dumps(runs["moving"][0], "slide2d")[-1]
    assert os.path.basename(a) == os.path.basename(b)
    assert_particles_close(a, b, "block", 1e-14, 3e-13, 3e-13, ("xx", "yy", "zz", "xy"))
    rows = [np.loadtxt(os.path.join(out, "slide2d_mpm_series.csv"), delimiter=",", skiprows=1)
            for out, _ in runs.values()]
    assert rows[0].shape == rows[1].shape
    assert np.max(np.abs(rows[0] - rows[1])) < 1e-9 * np.max(np.abs(rows[0]))
    with open(os.path.join(runs["moving"][0], "slide2d.status"), encoding="utf-8") as f:
        assert "state = finished" in f.read()

    out = str(tmp_path / "limited")
    command = [SLIDE, "--set", f"&run output_dir = '{out}', max_steps = 100 /"]
    for text in cost + ("&grid rebalance = .true. /",):
        command += ["--set", text]
    result = run_mpmice(command, nranks=2, cwd=str(tmp_path))
    assert "blocks rebalanced" in result.stdout
    with open(os.path.join(out, "slide2d.status"), encoding="utf-8") as f:
        status = f.read()
    assert "state = stopped" in status and "step = 100" in status, status


SLIDE_BLOCK = os.path.join(ROOT, "namelists", "mpmice_slide_block_2d.nml")


@pytest.mark.mpi
def test_rebalance_within_a_coupled_run(tmp_path):
    """The coupled sliding block (water, a porous block sliding on the rigid bed; 2 ranks cut
    in x, w = 5, a checkpoint every 20 ms): the cut moves with the block (x 12,28 -> 13,27) and
    the run continues in the same process exactly as `mpmice --restart` of that checkpoint
    does (bitwise), and it ends where the run on the first blocks ends: pressure to 1e-9 of its
    largest value, block particle positions to 1e-12 m, velocities to 1e-10 m/s, stresses to
    1e-9 of the largest (measured 8e-13, 3e-16 m, 7e-14 m/s, 3e-12)."""
    sets = ("&grid dims = 2, 1, 1, balance = 'cost', particle_weight = 5.0, rebalance = .true. /",
            "&run checkpoint_interval = 0.02 /")
    out = str(tmp_path / "moving")
    command = [SLIDE_BLOCK, "--set", f"&run output_dir = '{out}' /"]
    for text in sets:
        command += ["--set", text]
    result = run_mpmice(command, nranks=2, cwd=str(tmp_path))
    moves = re.findall(r"blocks rebalanced at (\S+): x (\d+),(\d+)", result.stdout)
    assert moves, result.stdout
    checkpoint, first, second = moves[0]
    assert (int(first), int(second)) == (13, 27)
    # `mpmice --restart` of that checkpoint cuts its blocks from the particles there too
    restarted = str(tmp_path / "restarted")
    again_run = run_mpmice(["--restart", checkpoint, "--set",
                            f"&run output_dir = '{restarted}' /"], nranks=2, cwd=str(tmp_path))
    assert _blocks(again_run.stdout, restart=True)[1:] == (int(first), int(second))
    moving = list_dumps(out, "slide")[-1]
    again = list_dumps(restarted, "slide")[-1]
    assert os.path.basename(moving) == os.path.basename(again)
    assert_dumps_identical(moving, again)
    fixed_out = str(tmp_path / "fixed")
    command = [SLIDE_BLOCK, "--set", f"&run output_dir = '{fixed_out}' /", "--set",
               "&grid dims = 2, 1, 1, balance = 'cost', particle_weight = 5.0 /",
               "--set", "&run checkpoint_interval = 0.02 /"]
    run_mpmice(command, nranks=2, cwd=str(tmp_path))
    fixed = list_dumps(fixed_out, "slide")[-1]
    assert os.path.basename(fixed) == os.path.basename(moving)
    assert_field_close(fixed, moving, "cell/pressure", 1e-9)
    assert_particles_close(fixed, moving, "block", 1e-12, 1e-10, 1e-9)


@pytest.mark.parametrize("sets, rule", [
    (("&grid rebalance = .true. /",), "balance = 'cost'"),
    (("&grid balance = 'cost', rebalance = .true. /", "&run checkpoint_interval = 0.0 /"),
     "checkpoint_interval > 0")])
def test_rebalance_needs_cost_and_checkpoints(tmp_path, monkeypatch, sets, rule):
    """`&grid rebalance` without `balance = 'cost'` or without checkpoints: one error line
    naming the variable and what it needs; exit status 1, nothing written."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")
    out = tmp_path / "bad"
    command = [SLIDE, "--set", f"&run output_dir = '{out}' /"]
    for text in sets:
        command += ["--set", text]
    result = run_mpmice(command, cwd=str(tmp_path), check=False)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 1
    assert len(lines) == 1, result.stderr
    assert "&grid rebalance = .true." in lines[0] and rule in lines[0], lines[0]
    assert not out.exists()


COLUMN = os.path.join(ROOT, "namelists", "mpm_column_2d.nml")


@pytest.mark.mpi
def test_cost_takes_a_layout_that_fits(tmp_path, monkeypatch):
    """3 ranks on the 4 x 50 cells of mpm_column_2d: MPI_Dims_create's 3 x 1 leaves blocks of 1
    cell, below the ghost width 2. With the even split that is one input-error line that names
    the layout that fits (1, 3, 1), exit status 1, nothing written; `balance = 'cost'` runs on
    that layout (y strips)."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")
    bad = tmp_path / "cells"
    result = run_mpmice([COLUMN, "--set", f"&run output_dir = '{bad}', max_steps = 2 /"],
                        nranks=3, cwd=str(tmp_path), check=False)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 1
    assert len(lines) == 1, result.stderr
    assert "3 ranks split 3 x 1 x 1" in lines[0], lines[0]
    assert "set &grid dims = 1, 3, 1, or balance = 'cost'" in lines[0], lines[0]
    assert not bad.exists()
    good = tmp_path / "cost"
    result = run_mpmice([COLUMN, "--set", f"&run output_dir = '{good}', max_steps = 2 /",
                         "--set", "&grid balance = 'cost' /"], nranks=3, cwd=str(tmp_path))
    axis, *cells = _blocks(result.stdout)
    assert axis == "y" and len(cells) == 3 and sum(cells) == 50 and min(cells) >= 2, cells


def test_unknown_balance_is_an_input_error(tmp_path, monkeypatch):
    """`&grid balance = 'particles'`: one error line naming the group, variable, value and the
    allowed values; exit status 1, nothing written."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")   # no launcher report on stderr
    out = tmp_path / "bad"
    result = run_mpmice([BLOCK, "--set", f"&run output_dir = '{out}' /",
                         "--set", "&grid balance = 'particles' /"], cwd=str(tmp_path),
                        check=False)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.returncode == 1
    assert len(lines) == 1, result.stderr
    for piece in ("&grid", "balance", "particles", "cells", "cost"):
        assert piece in lines[0], lines[0]
    assert not out.exists()
