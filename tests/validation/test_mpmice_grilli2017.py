"""The Grilli et al. (2017) test-17 scene (namelists/mpmice_grilli2017_2d.nml, issue 27 item 2):
a short run at the shipped 20 mm cells keeps the masses of the water, the beads and the bed, and
the beads, held by nothing once the gate is gone, move down the slope (~3 s). The comparison
with the gauges and shapes is not part of it."""
import numpy as np
import pytest

from postproc import mpmice_debris_flow as debris
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpmice_grilli2017_2d.nml"
NAME = "grilli"


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_grilli2017_short_run(tmp_path):
    """To t = 0.01 s: water, beads and bed masses unchanged to 1e-10 (air flows through the open
    top; measured 2e-16), the beads' centre of mass moves right and down."""
    out = str(tmp_path / "grilli")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', end_time = 0.01, "
                "output_interval = 0.005 /"], cwd=str(tmp_path), timeout=600)
    dumps = [read_dump(p) for p in list_dumps(out, NAME)]
    assert len(dumps) == 3
    m0, m1 = debris.masses(dumps[0]), debris.masses(dumps[-1])
    for name in ("water", "beads", "bed"):
        assert abs(m1[name] / m0[name] - 1.0) < 1e-10, (name, m0[name], m1[name])

    def centre(d):
        p = d["particles"]["beads"]
        return np.array([np.average(p["x"], weights=p["mass"]),
                         np.average(p["y"], weights=p["mass"])])

    move = centre(dumps[-1]) - centre(dumps[0])
    assert move[0] > 0.0 and move[1] < 0.0, move
