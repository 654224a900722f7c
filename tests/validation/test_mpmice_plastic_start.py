"""Elastic gravity loading (`&solid plastic_start`, docs/earthquake_liquefaction.md "Elastic gravity
loading"): before the given time a plastic model's stress follows its elastic law only.

The undrained cyclic shear column (namelists/mpmice_cyclic_shear_column_1d.nml, one cycle per
0.5 s) with the dense critical-state sand of test_mpmice_settle_start.py, to 0.75 s, three
times: plastic from 0 s, plastic from 0.3 s, and the linear elastic model with the same E and
nu.

* Before the start, the sand's run equals the linear elastic run bit for bit (the dump at
  0.25 s: the column stays in compression, so the sand's no-tension apex never acts), while the
  sand plastic from 0 s has yielded by then (the test can fail).
* After it, the sand yields (plastic strain > 0 at 0.75 s) and its dump differs from the
  elastic one.

Run time: ~8 s (three runs of the column to 0.75 s).
"""
from __future__ import annotations

import h5py
import numpy as np
import pytest

from postproc import mpmice_terzaghi
from postproc.dump_compare import assert_dumps_identical
from postproc.mpmice_io import list_dumps
from postproc.run_case import run_mpmice

SHAKE = str(mpmice_terzaghi.ROOT) + "/namelists/mpmice_cyclic_shear_column_1d.nml"
SHAKE_NAME = "shake_column"
SAND = "&solid name = 'soil', model = 'critical_state_sand', max_porosity = 0.5, porosity = 0.38, "
#: the same skeleton, linear elastic (no loosest packing: the column stays far denser than it)
ELASTIC = "&solid name = 'soil', model = 'linear_elastic', porosity = 0.38 /"
RUN = "end_time = 0.75, output_interval = 0.25"


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def plastic_strain(path) -> np.ndarray:
    """The soil particles' equivalent plastic strain in the dump `path`."""
    with h5py.File(path) as f:
        return f["particles/soil/plastic_strain"][...]


def test_elastic_before_plastic_start(solver, tmp_path):
    dumps = {}
    for label, solid in (("plastic", SAND + "plastic_start = 0.0 /"),
                         ("late", SAND + "plastic_start = 0.3 /"), ("elastic", ELASTIC)):
        out = tmp_path / label
        run_mpmice([SHAKE, "--set", solid,
                    "--set", f"&run output_dir = '{out}', {RUN} /"], cwd=str(tmp_path), timeout=300)
        dumps[label] = list_dumps(str(out), SHAKE_NAME)
        assert len(dumps[label]) == 4
    assert np.max(plastic_strain(dumps["plastic"][1])) > 0.0   # 0.25 s: yielded without the start
    assert np.all(plastic_strain(dumps["late"][1]) == 0.0)
    assert_dumps_identical(dumps["elastic"][1], dumps["late"][1])
    assert np.max(plastic_strain(dumps["late"][3])) > 0.0     # 0.75 s: plastic from 0.3 s
    with pytest.raises(AssertionError):
        assert_dumps_identical(dumps["elastic"][3], dumps["late"][3])
