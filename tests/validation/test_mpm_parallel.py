"""MPM scene on several ranks: decomposition invariance with particles crossing block boundaries
(1, 2, 4 ranks; PIC, FLIP and APIC, whose affine velocity migrates with the particle), and
bitwise-identical continuation from a checkpoint (FLIP; APIC, whose checkpoint carries the
affine velocity: without it the continued run differs)."""
import os

import h5py
import numpy as np
import pytest

from postproc.dump_compare import assert_dumps_identical
from postproc.mpm_common import particles, series
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpm_slide_2d.nml")


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _transfer(flip):
    """The `&mpm` setting of a velocity update: a FLIP fraction, or 'apic'."""
    if flip == "apic":
        return "&mpm velocity_transfer = 'apic' /"
    return f"&mpm flip_fraction = {flip} /"


def _run(tmp_path, nranks, flip, extra=()):
    out = tmp_path / f"r{nranks}_f{flip}"
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}' /",
                "--set", _transfer(flip), *extra], nranks=nranks,
               cwd=str(tmp_path))
    return out


@pytest.mark.parametrize("flip", [0.0, 0.99, "apic"])
def test_rank_invariance_with_crossing_particles(tmp_path, flip):
    """Final particle positions, velocities and stresses on 2 and 4 ranks equal the 1-rank run
    to round-off: |dx| < 1e-14 m, |dv| < 3e-13 m/s, |d sigma| < 3e-13 max|sigma| (measured at
    most 1.0e-15 m, 4.9e-14 m/s, 3.0e-14: docs/validation/mpm_parallel.md); more than 50 particles cross x = 0.5 and more than 10 cross
    y = 0.5 (the block boundaries of 2 and 4 ranks), and the block hits the x+ wall."""
    ref_dir = _run(tmp_path, 1, flip)
    paths = list_dumps(str(ref_dir), "slide2d")
    _, start = particles(paths[0], "block")
    _, ref = particles(paths[-1], "block")
    assert np.sum((start["x"] < 0.5) & (ref["x"] > 0.5)) > 50
    assert np.sum((start["y"] > 0.5) & (ref["y"] < 0.5)) > 10
    assert np.max(series(str(ref_dir), "slide2d")["xmax"]) > 0.97  # reached the wall
    scale = max(np.max(np.abs(ref[f"stress_{c}"])) for c in ("xx", "yy", "xy"))
    for nranks in (2, 4):
        _, other = particles(list_dumps(str(_run(tmp_path, nranks, flip)), "slide2d")[-1], "block")
        assert np.array_equal(ref["id"], other["id"])
        # cell averages: the particle volume per cell sums to the total particle volume
        with h5py.File(list_dumps(str(tmp_path / f"r{nranks}_f{flip}"), "slide2d")[-1]) as f:
            fraction = f["cell/block/volume_fraction"][...]
            assert abs(fraction.sum() * 0.05 ** 2 - np.sum(other["volume"])) < 1e-12
        for c in ("x", "y"):
            assert np.max(np.abs(other[c] - ref[c])) < 1e-14, (nranks, c)
            assert np.max(np.abs(other[f"velocity_{c}"] - ref[f"velocity_{c}"])) < 3e-13
        for c in ("xx", "yy", "zz", "xy"):
            diff = np.max(np.abs(other[f"stress_{c}"] - ref[f"stress_{c}"]))
            assert diff < 3e-13 * scale, (nranks, c, diff / scale)


@pytest.mark.parametrize("nranks,flip", [(1, 0.99), (2, 0.99), (2, "apic")])
def test_restart_is_bitwise_identical(tmp_path, nranks, flip):
    """Run to the end; run 60 steps (checkpoint at the stop), restart, finish: every dump of the
    continued run equals the uninterrupted one bit for bit."""
    full = _run(tmp_path, nranks, flip)
    half = tmp_path / "half"
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{half}', max_steps = 60 /",
                "--set", _transfer(flip)], nranks=nranks, cwd=str(tmp_path))
    checkpoint = half / "slide2d_checkpoint_000060.h5"
    assert checkpoint.is_file()
    run_mpmice(["--restart", str(checkpoint), "--set", "&run max_steps = 0 /"], nranks=nranks,
               cwd=str(tmp_path))
    full_dumps = list_dumps(str(full), "slide2d")
    assert len(full_dumps) == 3  # t = 0, 0.06, 0.12
    for path in full_dumps:
        assert_dumps_identical(path, half / os.path.basename(path))


def test_apic_checkpoint_carries_the_affine_velocity(tmp_path):
    """APIC on the collapsing column (namelists/mpm_collapse_2d.nml to 0.05 s, 392 steps): the
    checkpoint after 200 steps holds `affine` (9 per particle); a restart from it with `affine`
    zeroed ends elsewhere than the uninterrupted run (largest velocity difference > 1e-4 of
    the largest speed: the state is needed), and without the dataset the restart is refused:
    exit status 1, one input-error line naming it, nothing written."""
    collapse = os.path.join(ROOT, "namelists", "mpm_collapse_2d.nml")
    run = "end_time = 0.05, output_interval = 0.025"
    full = tmp_path / "full"
    run_mpmice([collapse, "--set", f"&run output_dir = '{full}', {run} /",
                "--set", _transfer("apic")], cwd=str(tmp_path))
    half = tmp_path / "half"
    run_mpmice([collapse, "--set", f"&run output_dir = '{half}', {run}, max_steps = 200 /",
                "--set", _transfer("apic")], cwd=str(tmp_path))
    checkpoint = half / "collapse2d_checkpoint_000200.h5"
    with h5py.File(checkpoint, "a") as f:
        affine = f["checkpoint/particles/sand/affine"]
        assert 9 in affine.shape and np.max(np.abs(affine[...])) > 0.0
        affine[...] = 0.0
    run_mpmice(["--restart", str(checkpoint), "--set", "&run max_steps = 0 /"],
               cwd=str(tmp_path))
    last = list_dumps(str(full), "collapse2d")[-1]
    _, ref = particles(last, "sand")
    _, zeroed = particles(str(half / os.path.basename(last)), "sand")
    speed = np.max(np.hypot(ref["velocity_x"], ref["velocity_y"]))
    assert np.max(np.abs(zeroed["velocity_x"] - ref["velocity_x"])) > 1e-4 * speed
    with h5py.File(checkpoint, "a") as f:
        del f["checkpoint/particles/sand/affine"]
    bad = tmp_path / "bad"
    bad.mkdir()
    os.replace(checkpoint, bad / checkpoint.name)
    result = run_mpmice(["--restart", str(bad / checkpoint.name), "--set",
                         "&run max_steps = 0 /"], cwd=str(tmp_path), check=False,
                        overwrite=False)
    assert result.returncode == 1, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("mpmice:")]
    assert len(lines) == 1, result.stderr
    assert "input error" in lines[0] and "checkpoint/particles/sand/affine" in lines[0]
    assert sorted(os.listdir(bad)) == [checkpoint.name]


def test_rank_without_particles(tmp_path):
    """Collapse on 2 ranks split along x: the right rank seeds no particle; 5 steps, the dumps and
    the checkpoint (collective particle writes) complete and hold all 3200 particles."""
    namelist = os.path.join(ROOT, "namelists", "mpm_collapse_2d.nml")
    out = tmp_path / "empty_rank"
    run_mpmice([namelist, "--set", f"&run output_dir = '{out}', max_steps = 5 /",
                "--set", "&grid dims = 2, 1, 1 /"], nranks=2, cwd=str(tmp_path), timeout=120)
    with h5py.File(out / "collapse2d_checkpoint_000005.h5") as f:
        assert f["checkpoint/particles/sand/id"].shape == (3200,)
        assert list(f["checkpoint/particles/sand/rank_counts"][...]) == [3200, 0]


def test_apic_warns_of_an_unused_flip_fraction(tmp_path):
    """APIC takes the PIC velocity: a `flip_fraction` other than the default (the bar's 1.0)
    is named in one warning line; the default (the sliding block) gives none."""
    bar = os.path.join(ROOT, "namelists", "mpm_bar_1d.nml")
    for namelist, warned in ((bar, True), (NAMELIST, False)):
        out = tmp_path / os.path.basename(namelist)
        result = run_mpmice([namelist, "--set", _transfer("apic"),
                             "--set", f"&run output_dir = '{out}', max_steps = 2 /"],
                            cwd=str(tmp_path))
        text = result.stdout + result.stderr
        lines = [line for line in text.splitlines() if "flip_fraction" in line]
        assert len(lines) == (1 if warned else 0), lines
        if warned:
            assert "warning" in lines[0] and "not used with velocity_transfer = 'apic'" in lines[0]
