"""2D granular column collapse, aspect ratio 2 (postproc/mpm_collapse.py): the deposit comes to
rest, no particle is lost, mass is conserved and the column spreads. The comparison with the
experimental run-out scaling is a report (docs/validation/mpm_collapse.md), not asserted here."""
import numpy as np
import pytest

from postproc import mpm_collapse


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.mark.slow
def test_collapse_comes_to_rest(tmp_path):
    """a = 2 at t = 1 s: kinetic energy < 1e-5 of the initial potential energy (measured 3e-7),
    all 3200 particles kept, final height below the initial one, run-out > 1 L0 (measured 2.7)."""
    r = mpm_collapse.run_collapse(str(tmp_path), 2.0)
    assert r["particles"] == 3200
    assert r["kinetic_ratio"] < 1.0e-5, r["kinetic_ratio"]
    assert r["height"] < 2.0, r["height"]
    assert r["runout"] > 1.0, r["runout"]
    assert np.all(r["y"] >= 0.0)
