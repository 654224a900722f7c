"""Cyclic densification of the critical-state sand (`&solid densification_c1`,
docs/soil_models.md "Cyclic densification") in the coupled scene: the undrained cyclic shear
column (namelists/mpmice_cyclic_shear_column_1d.nml) with a dense sand (porosity 0.38, phi =
0.62 > phi_m: it dilates when it yields), to 0.5 s (one cycle).

* A restart from a checkpoint written mid-run equals the uninterrupted run bit for bit: the
  per-particle cyclic state (`checkpoint/particles/<solid>/cyclic`: eps_vd, the shear strain
  and its reversal tracker) is carried; the particles have densified (eps_vd > 0), so a reset
  state would give other stresses.

* The same with a loose sand (porosity 0.43) and `tension_gap = .true.`: the per-particle gap
  (`checkpoint/particles/<solid>/gap`) is carried; at the checkpoint (step 1000) some particles
  hold a gap > 0.

Run time: ~8 s per test (three short runs of the column, 1524 steps to 0.5 s). Zeroing the
checkpoint's `cyclic` before the restart makes 23 datasets of the last dump differ, zeroing its
`gap` also 23 (measured).
"""
from __future__ import annotations

import pathlib

import h5py
import numpy as np
import pytest

from postproc import mpmice_terzaghi
from postproc.dump_compare import assert_dumps_identical
from postproc.mpmice_io import list_dumps
from postproc.run_case import run_mpmice

SHAKE = str(mpmice_terzaghi.ROOT) + "/namelists/mpmice_cyclic_shear_column_1d.nml"
SHAKE_NAME = "shake_column"
SAND = ("&solid name = 'soil', model = 'critical_state_sand', max_porosity = 0.5, "
        "porosity = 0.38, densification_c1 = 0.5 /")
LOOSE_GAP = ("&solid name = 'soil', model = 'critical_state_sand', max_porosity = 0.5, "
             "porosity = 0.43, densification_c1 = 0.5, tension_gap = .true. /")


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _restart_is_bitwise(tmp_path, sand, steps):
    """Run to 0.5 s; run `steps` steps, restart from that checkpoint and finish: every dump
    equal bit for bit. Returns the checkpoint's particle group as a dict of arrays."""
    run = "end_time = 0.5, output_interval = 0.25"
    full = tmp_path / "full"
    run_mpmice([SHAKE, "--set", sand, "--set", f"&run output_dir = '{full}', {run} /"],
               cwd=str(tmp_path), timeout=300)
    half = tmp_path / "half"
    run_mpmice([SHAKE, "--set", sand,
                "--set", f"&run output_dir = '{half}', {run}, max_steps = {steps} /"],
               cwd=str(tmp_path), timeout=300)
    checkpoint = half / f"{SHAKE_NAME}_checkpoint_{steps:06d}.h5"
    assert checkpoint.is_file()
    with h5py.File(checkpoint) as f:
        group = {k: v[...] for k, v in f["checkpoint/particles/soil"].items()}
    run_mpmice(["--restart", str(checkpoint), "--set", "&run max_steps = 0 /"],
               cwd=str(tmp_path), timeout=300)
    paths = list_dumps(str(full), SHAKE_NAME)
    assert len(paths) == 3
    for path in paths:
        assert_dumps_identical(path, half / pathlib.Path(path).name)
    return group


def test_css_densification_restart_is_bitwise_identical(solver, tmp_path):
    """The dense sand: dumps equal bit for bit, and eps_vd of the checkpoint > 0 for some
    particles."""
    cyclic = _restart_is_bitwise(tmp_path, SAND, 150)["cyclic"]
    evd = cyclic[:, 0] if cyclic.shape[1] == 5 else cyclic[0, :]
    assert np.max(evd) > 0.0, np.max(evd)


def test_css_tension_gap_restart_is_bitwise_identical(solver, tmp_path):
    """The loose sand with the gap: dumps equal bit for bit, and a gap > 0 in the checkpoint."""
    gap = _restart_is_bitwise(tmp_path, LOOSE_GAP, 1000)["gap"]
    assert np.count_nonzero(gap) > 0 and np.max(gap) > 0.0, np.max(gap)
