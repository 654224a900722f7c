"""The Grilli et al. (2017) test-17 scene (namelists/mpmice_grilli2017_2d.nml):
a short run at the shipped 20 mm cells keeps the masses of the water, the beads and the bed, and
the beads, held by nothing once the gate is gone, move down the slope (~3 s). A slow test runs
the scene on 40 mm cells to the first trough at WG1 and checks its sign, order and time against
the digitised record (skipped when the reference folder is absent); the full comparison is
postproc/mpmice_grilli2017.py (docs/validation/grilli2017.md)."""
import os

import numpy as np
import pytest

from postproc import mpmice_debris_flow as debris
from postproc import mpmice_grilli2017 as grilli
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


#: the digitised records (../shared/reference beside the repository or $MPMICE_REFERENCE)
REFERENCE = grilli.DEFAULT_REFERENCE


@pytest.mark.slow
def test_grilli2017_first_trough_at_wg1_coarse(tmp_path, allowed_skip):
    """40 mm cells (the wedge 2 to 3 cells high, 12 bead particles), beads E = 1 MPa, to model
    t = 1.35 s (record 1.65 s with the gauges' shift of 0.3 s): at WG1 the model's first wave
    has the record's order and signs, a leading crest (> 0) and then a trough (< 0) of at least
    half the record's depth (measured on 1 rank: +5.9 mm at 1.08 s and -6.6 mm at 1.60 s against
    +4.1 mm at 0.93 s and -9.4 mm at 1.46 s), its time within 0.25 s of the record's (measured
    +0.14 s);
    the beads' mass kept to 1e-10, the water's loss through the open top below 2e-4. A
    coarse-grid guard of the sign and order, not the 20 % / 0.1 s targets
    (docs/validation/grilli2017.md). 187 s on 2 loaded cores."""
    if not os.path.isdir(REFERENCE):
        allowed_skip(f"grilli2017 digitised records not found at {REFERENCE} (set "
                     "MPMICE_REFERENCE to the shared reference folder)")
    out = str(tmp_path / "grilli40")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', end_time = 1.35 /",
                "--set", "&grid ncells = 140, 11, 1 /",
                "--set", "&solid name = 'beads', youngs_modulus = 1.0e6 /"],
               nranks=2, cwd=str(tmp_path), timeout=1200)
    dumps = [read_dump(p) for p in list_dumps(out, NAME)]
    t_model, model = grilli.gauge_series(dumps)
    ref = grilli.reference_gauges(REFERENCE)
    (_, lead_rec), (t_trough_rec, trough_rec), _ = grilli.extrema(*ref["WG1"], 2.05)
    (_, lead), (t_trough, trough), _ = grilli.extrema(t_model + 0.3, model["WG1"], 2.05)
    assert lead_rec > 0.0 and trough_rec < 0.0
    assert lead > 0.0, lead
    assert trough < 0.5 * trough_rec, (trough, trough_rec)
    assert abs(t_trough - t_trough_rec) < 0.25, (t_trough, t_trough_rec)
    m0, m1 = debris.masses(dumps[0]), debris.masses(dumps[-1])
    assert abs(m1["beads"] / m0["beads"] - 1.0) < 1e-10, (m0["beads"], m1["beads"])
    # the 0.12 m of air are 3 cells here: water's volume fraction diffuses up to the open top
    # and leaves (measured 8.5e-5 of the water by 1.34 s; 1.3e-7 by 2.8 s at 20 mm)
    assert 0.0 <= 1.0 - m1["water"] / m0["water"] < 2e-4, (m0["water"], m1["water"])
