"""The underwater sand slide scene (namelists/mpmice_debris_flow_2d.nml, issue 7): a short
coarse run keeps the mass of the water, the sand and the bed, and the sand moves down the slope
(postproc/mpmice_debris_flow.py)."""
import numpy as np
import pytest

from postproc import mpmice_debris_flow as debris
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpmice_debris_flow_2d.nml"


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_debris_flow_short_run(tmp_path):
    """40 mm cells to t = 0.04 s: water, sand and bed masses unchanged to 1e-10 (air flows
    through the open top), the sand's centre of mass moves right and down, the free surface
    stays within 2 cm of the still level."""
    out = str(tmp_path / "debris")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', end_time = 0.04, "
                "output_interval = 0.02 /"], cwd=str(tmp_path), timeout=900)
    dumps = [read_dump(p) for p in list_dumps(out, debris.NAME)]
    assert len(dumps) == 3
    m0, m1 = debris.masses(dumps[0]), debris.masses(dumps[-1])
    for name in ("water", "sand", "bed"):
        assert abs(m1[name] / m0[name] - 1.0) < 1e-10, (name, m0[name], m1[name])

    def centre(d):
        p = d["particles"][debris.SAND]
        return np.array([np.average(p["x"], weights=p["mass"]),
                         np.average(p["y"], weights=p["mass"])])

    move = centre(dumps[-1]) - centre(dumps[0])
    assert move[0] > 0.0 and move[1] < 0.0, move
    _, eta = debris.free_surface(dumps[-1])
    assert np.nanmax(np.abs(eta)) < 0.02
