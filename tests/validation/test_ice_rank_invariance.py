"""ICE scene, decomposition invariance of the two-fluid and the viscous/thermal scenes: the
water column under air (2D, 50 x 8, 100 steps) and the de Vahl Davis cavity (Ra 1e3, 16 x 16,
t = 3 s) give the same pressure, densities and temperatures on 1, 2 and 4 ranks to 1e-10
relative, and the same velocities to 1e-9 m/s absolute (the only rank-dependent operation is
hypre's PCG, converged to 1e-12 relative on a pressure of 1e5 Pa; measured: cavity velocities
differ by 1.7e-11 m/s of 0.037 m/s)."""
import os

import numpy as np
import pytest

from postproc import ice_cavity, ice_water_column
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _cavity(workdir, nranks):
    out = os.path.join(workdir, f"cavity_{nranks}")
    mu, k = ice_cavity.PROPERTIES[1e3]
    run_mpmice([ice_cavity.NAMELIST, "--set", "&grid ncells = 16, 16, 1, upper = 1.0, 1.0, 0.0625 /",
                "--set", f"&run output_dir = '{out}', end_time = 3.0, output_interval = 0.0 /",
                "--set", f"&fluid name = 'air', viscosity = {mu}, conductivity = {k} /"],
               nranks=nranks, cwd=workdir)
    return read_dump(list_dumps(out, "cavity")[-1])


def _compare(ref, other, names):
    assert other["step"] == ref["step"]
    for name in names:
        a, b = ref["cell"][name], other["cell"][name]
        if "velocity" in name:
            assert np.max(np.abs(a - b)) <= 1e-9, name
        else:
            assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(a)), name


@pytest.mark.parametrize("nranks", [2, 4])
def test_water_column_rank_invariance(tmp_path, nranks):
    ref = ice_water_column.run(str(tmp_path), ny=8, nranks=1, steps=100)[1]
    other = ice_water_column.run(str(tmp_path), ny=8, nranks=nranks, steps=100)[1]
    _compare(ref, other, ["pressure", "water/density", "air/density", "water/temperature",
                          "water/velocity_x", "air/velocity_y"])


@pytest.mark.parametrize("nranks", [2, 4])
def test_cavity_rank_invariance(tmp_path, nranks):
    ref = _cavity(str(tmp_path), 1)
    other = _cavity(str(tmp_path), nranks)
    _compare(ref, other, ["pressure", "air/temperature", "air/velocity_x", "air/velocity_y"])
