"""A geostatic settle before the shaking (`&solid densification_start`,
docs/earthquake_liquefaction.md "Shaking from a settled bank"): the cyclic densification counts only
from the given time.

The undrained cyclic shear column (namelists/mpmice_cyclic_shear_column_1d.nml, one cycle per
0.5 s) with the dense sand of test_mpmice_css_densification.py (densification_c1 = 0.5), to
0.75 s, three times: densification from 0 s, from 0.3 s, and off (C_1 = 0).

* Before the start, the run equals the run without densification bit for bit (the dump at
  0.25 s), and its particles' cyclic state is untouched (all zero in the checkpoint at 0.25 s).
* After it, the particles densify (eps_vd > 0 at 0.75 s, the dump at 0.75 s differs from the
  run without densification) and count fewer reversals than the run densifying from 0 s.

Run time: ~8 s (three runs of the column to 0.75 s).
"""
from __future__ import annotations

import glob
import os

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
        "porosity = 0.38, densification_c1 = {c1}, densification_start = {start} /")
RUN = "end_time = 0.75, output_interval = 0.25, checkpoint_interval = 0.25"


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def cyclic_at(out, time: float) -> np.ndarray:
    """The soil's cyclic state (rows: eps_vd, gamma, gamma_rev, gamma_ext, reversals) in the
    checkpoint written at `time`."""
    for path in sorted(glob.glob(os.path.join(out, f"{SHAKE_NAME}_checkpoint_*.h5"))):
        with h5py.File(path) as f:
            if abs(float(f.attrs["time"]) - time) < 1e-9:
                c = f["checkpoint/particles/soil/cyclic"][...]
                return c.T if c.shape[1] == 5 else c
    raise AssertionError(f"no checkpoint at {time} s in {out}")


def test_densification_counts_from_its_start(solver, tmp_path):
    outs = {}
    for label, c1, start in (("from0", 0.5, 0.0), ("late", 0.5, 0.3), ("off", 0.0, 0.0)):
        out = tmp_path / label
        run_mpmice([SHAKE, "--set", SAND.format(c1=c1, start=start),
                    "--set", f"&run output_dir = '{out}', {RUN} /"], cwd=str(tmp_path), timeout=300)
        outs[label] = out
    late = list_dumps(str(outs["late"]), SHAKE_NAME)
    off = list_dumps(str(outs["off"]), SHAKE_NAME)
    assert len(late) == len(off) == 4
    assert_dumps_identical(off[1], late[1])   # 0.25 s: before the start, as without it
    assert np.all(cyclic_at(outs["late"], 0.25) == 0.0)
    end_late = cyclic_at(outs["late"], 0.75)
    end_from0 = cyclic_at(outs["from0"], 0.75)
    assert np.max(end_late[0]) > 0.0
    assert np.sum(end_late[4]) < np.sum(end_from0[4]), (np.sum(end_late[4]), np.sum(end_from0[4]))
    with pytest.raises(AssertionError):
        assert_dumps_identical(off[3], late[3])
