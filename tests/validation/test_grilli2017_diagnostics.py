"""The Grilli et al. (2017) diagnostic tools: every variant of
postproc/mpmice_grilli2017_cases.py is an input the program accepts (`mpmice --check`), and the
slide measures of postproc/mpmice_grilli2017_slide.py return the closed forms (~2 s)."""
import math
import subprocess

import numpy as np
import pytest

from postproc import mpmice_grilli2017_cases as cases
from postproc import mpmice_grilli2017_slide as slide


@pytest.mark.parametrize("case", sorted(cases.CASES) + ["mu025+darcy", "css+air019"])
def test_grilli2017_case_is_valid_input(case, mpmice_exe, tmp_path):
    """Each case (and two combined ones) passes the input check at 20 mm; the grid is the case's
    (the domain's height follows the air layer)."""
    text, sets = cases.case_inputs(case, 20.0)
    nml = tmp_path / "grilli.nml"
    nml.write_text(text, encoding="utf-8")
    cmd = [str(mpmice_exe), "--check", str(nml)]
    for s in sets:
        cmd += ["--set", s]
    result = subprocess.run(cmd, capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr[-2000:]
    ny = {"air007": 20, "air019": 26}.get(case.split("+")[-1], 22)
    assert f"&grid ncells = 280, {ny}, 1 /" in sets


def test_grilli2017_unknown_case_is_an_error():
    with pytest.raises(SystemExit, match="unknown case"):
        cases.case_inputs("base+nosuchcase", 20.0)


def test_grilli2017_dry_case_swaps_the_regions():
    text, _ = cases.case_inputs("dry", 20.0)
    water = text.index("material = 'water'")
    air = text.index("material = 'air'", water)
    assert "volume_fraction = 0.0" in text[water:air]
    assert "volume_fraction = 1.0" in text[air:air + 120]


def test_block_accelerations_closed_form():
    """g (sin b - mu cos b), and times 1 - rho_w / rho_b under water (rho_b = 1915 kg/m^3)."""
    b = math.atan(0.7)
    assert slide.block_acceleration(0.0, False) == pytest.approx(9.81 * math.sin(b), rel=1e-12)
    dry = 9.81 * (math.sin(b) - 0.41 * math.cos(b))
    assert slide.block_acceleration(0.41, False) == pytest.approx(dry, rel=1e-12)
    rho_b = 0.61 * 2500.0 + 0.39 * 999.8
    assert slide.block_acceleration(0.41, True) == pytest.approx(dry * (1 - 999.8 / rho_b),
                                                                 rel=1e-12)
    assert slide.block_acceleration(0.8, True) == 0.0


def test_fitted_acceleration_recovers_a_uniform_acceleration():
    """A centroid moving s = a t^2 / 2 along the slope gives a back to round-off; the dumps past
    the fit window are left out."""
    t = np.arange(0.0, 0.71, 0.02)
    s = 0.5 * 1.3 * t**2
    s[t > 0.4] = 0.0                    # outside the window: must not count
    track = {"time": t, "centroid": 0.755 + s * math.cos(math.atan(0.7))}
    assert slide.fitted_acceleration(track, 0.4) == pytest.approx(1.3, rel=1e-12)


def test_force_budget_closes_on_a_synthetic_slide(tmp_path):
    """A slide of mass M accelerating at 0.5 m/s^2 on a bed pushing back along the slope with
    0.3 M g sin b and into it with the submerged normal weight: the budget returns dv/dt, the
    bed force and the normal load to round-off, the fluids' force as the rest, and splits it
    into buoyancy, the pore water carried and the ambient water's part."""
    b, g, mass = math.atan(0.7), 9.81, 0.2
    along = np.array([math.cos(b), -math.sin(b)])
    into = -np.array([math.sin(b), math.cos(b)])
    weight = mass * g * math.sin(b)
    normal = mass * g * math.cos(b) * (1.0 - 999.8 / 2500.0)
    # the contact force on the bed: down-slope 0.3 weight (the bed holds the beads back), into it
    bed = 0.3 * weight * along + normal * into
    t = np.linspace(0.0, 0.5, 51)
    with open(tmp_path / "grilli_contact_force.csv", "w", encoding="utf-8") as f:
        f.write("time,bed_fx,bed_fy,bed_fz,bed_fluid_fx,bed_fluid_fy,bed_fluid_fz\n")
        for tn in t:
            f.write(f"{tn},{bed[0]},{bed[1]},0,0,0,0\n")
    times = np.arange(0.0, 0.51, 0.02)
    track = {"time": times, "speed": 0.5 * times}
    out = slide.force_budget(str(tmp_path), track, mass)
    assert out["accel"] == pytest.approx(0.5, rel=1e-12)
    assert out["bed"] == pytest.approx(-0.3 * weight, rel=1e-12)
    assert out["normal"] == pytest.approx(out["normal_submerged"], rel=1e-12)
    assert out["inertia"] == pytest.approx(out["weight"] + out["bed"] + out["fluid"], rel=1e-12)
    assert out["buoyancy"] == pytest.approx(-0.4 * weight * 999.8 / 1000.0, rel=1e-12)
    pore = 0.39 / 0.61 * mass / 2500.0 * 999.8 * 0.5
    assert out["pore_water"] == pytest.approx(-pore, rel=1e-12)
    assert out["ambient"] == pytest.approx(out["fluid"] - out["buoyancy"] + pore, rel=1e-12)
