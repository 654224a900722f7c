"""Cyclic densification of the critical-state sand (`&solid densification_c1`,
docs/soil_models.md "Cyclic densification") in the coupled scene: the undrained cyclic shear
column (namelists/mpmice_cyclic_shear_column_1d.nml) with a dense sand (porosity 0.38, phi =
0.62 > phi_m: it dilates when it yields), to 0.5 s (one cycle).

* A restart from a checkpoint written mid-run equals the uninterrupted run bit for bit: the
  per-particle cyclic state (`checkpoint/particles/<solid>/cyclic`: eps_vd, the shear strain
  and its reversal tracker) is carried; the particles have densified (eps_vd > 0), so a reset
  state would give other stresses.

Run time: ~8 s (three short runs of the column, 1524 steps to 0.5 s). Zeroing the
checkpoint's `cyclic` before the restart makes 23 datasets of the last dump differ (measured).
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


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_css_densification_restart_is_bitwise_identical(solver, tmp_path):
    """Run to 0.5 s; run 150 steps, restart from that checkpoint and finish: every dump equal
    bit for bit, and eps_vd of the checkpoint > 0 for some particles."""
    run = "end_time = 0.5, output_interval = 0.25"
    full = tmp_path / "full"
    run_mpmice([SHAKE, "--set", SAND, "--set", f"&run output_dir = '{full}', {run} /"],
               cwd=str(tmp_path), timeout=300)
    half = tmp_path / "half"
    run_mpmice([SHAKE, "--set", SAND,
                "--set", f"&run output_dir = '{half}', {run}, max_steps = 150 /"],
               cwd=str(tmp_path), timeout=300)
    checkpoint = half / f"{SHAKE_NAME}_checkpoint_000150.h5"
    assert checkpoint.is_file()
    with h5py.File(checkpoint) as f:
        cyclic = f["checkpoint/particles/soil/cyclic"][...]
    evd = cyclic[:, 0] if cyclic.shape[1] == 5 else cyclic[0, :]
    assert np.max(evd) > 0.0, np.max(evd)
    run_mpmice(["--restart", str(checkpoint), "--set", "&run max_steps = 0 /"],
               cwd=str(tmp_path), timeout=300)
    paths = list_dumps(str(full), SHAKE_NAME)
    assert len(paths) == 3
    for path in paths:
        assert_dumps_identical(path, half / pathlib.Path(path).name)
