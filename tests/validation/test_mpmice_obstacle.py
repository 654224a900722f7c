"""Debris flow against an obstacle: the saturated slide in air meets a rigid
block on the floor (namelists/mpmice_obstacle_air_2d.nml, postproc/mpmice_obstacle.py). A short
coarse run (40 mm, t = 0.02 s, ~10 s) keeps the pore water's, the sand's, the bed's and the
block's mass and records the contact force and the fluids' pressure force on each rigid body
every step."""
import numpy as np
import pytest

from postproc import mpmice_obstacle as obstacle
from postproc.mpmice_debris_flow import masses
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpmice_obstacle_air_2d.nml"
G = 9.81


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_obstacle_scene_keeps_mass_and_records_the_contact_force(tmp_path):
    """Masses of the pore water, the sand, the bed and the block unchanged to 1e-10 (air flows
    through the open top); the force series has a row per step with the bed's and the block's
    columns, all finite; the block, 1.15 m ahead of the toe, feels nothing yet; the sand presses
    on the 45 deg bed downwards with between 1/4 and 1 of the normal load of its saturated
    weight's vertical part, W_sat cos^2 45 (82 N: measured 57 N at t = 0.04 s, between the
    buoyant 41 N of a hydrostatic pore pressure and the saturated 82 N of a draining one). The
    air presses the block (on the floor: no fluid below) down with p w D, p = 1 atm plus the
    weight of 1.9 m of air (1.17 kg/m^3), -405.39 N, to 1e-3 every step (measured: within 2e-4,
    median 1e-6),
    and not sideways (|F_x| below 1e-3 of it; measured 5e-5)."""
    out = str(tmp_path / "obstacle")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', end_time = 0.02, "
                "output_interval = 0.02 /"], cwd=str(tmp_path), timeout=900)
    dumps = [read_dump(p) for p in list_dumps(out, obstacle.NAME)]
    assert len(dumps) == 2
    m0, m1 = masses(dumps[0]), masses(dumps[-1])
    for name in ("water", "sand", "bed", "block"):
        assert abs(m1[name] / m0[name] - 1.0) < 1e-10, (name, m0[name], m1[name])
    f = obstacle.contact_force(out)
    assert set(f) >= {"time", "bed_fx", "bed_fy", "block_fx", "block_fy", "bed_fluid_fx",
                      "bed_fluid_fy", "block_fluid_fx", "block_fluid_fy"}
    assert len(f["time"]) == dumps[-1]["step"]
    assert f["time"][-1] == pytest.approx(0.02)
    for key, values in f.items():
        assert np.all(np.isfinite(values)), key
    assert np.all(f["block_fx"] == 0.0) and np.all(f["block_fy"] == 0.0)
    air = -(101325.0 + 1.17 * G * 1.9) * 0.1 * 0.04
    assert np.all(np.abs(f["block_fluid_fy"] / air - 1.0) < 1e-3), (f["block_fluid_fy"], air)
    assert np.all(np.abs(f["block_fluid_fx"]) < 1e-3 * abs(air))
    w_sat = 1990.0 * G * 0.5 * 0.65**2 * 0.04
    late = f["time"] > 0.01
    fy = np.median(f["bed_fy"][late])
    assert -w_sat * 0.5 < fy < -0.25 * w_sat * 0.5, (fy, w_sat)
    # the report: force plot and snapshots (the nearest dump to each requested time)
    plots = tmp_path / "plots"
    assert obstacle.main(["--dir", out, "--out", str(plots), "--times", "0.0", "0.02"]) == 0
    assert (plots / "obstacle_force.png").stat().st_size > 0
    assert (plots / "obstacle_snapshots_obstacle.png").stat().st_size > 0
