"""Earthquake-induced submarine landslide: a saturated sediment bank on a rigid
base that shakes with a(t) = 1 g sin(2 pi 2 Hz t) (namelists/mpmice_earthquake_slope_2d.nml,
postproc/mpmice_earthquake_slope.py). A short coarse run (0.25 m cells, t = 0.15 s, ~3 s)
checks the masses, the base's prescribed motion, that the sediment is carried by the base and
yields, and the size of the surface wave. The loose / dense critical-state sand pair
(namelists/mpmice_earthquake_slope_{loose,dense}_2d.nml, the same coarse run, ~2 x 5 s): the
loose basal layer liquefies (r_u -> 1), the dense one sucks."""
import math

import numpy as np
import pytest

from postproc import mpmice_earthquake_slope as quake
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpmice_earthquake_slope_2d.nml"
END = 0.15          # s: the base has moved 5.8 cm, a(t) > tan(phi') g since t = 0.049 s
BANK_HEIGHT = 2.0   # m
GAP = 13.0 - 9.578  # m: water between two banks of the periodic row


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_shaken_bank_keeps_mass_follows_the_base_and_yields(tmp_path):
    """Masses of water, sediment and base unchanged to 1e-10 (air flows through the open top);
    every base particle moves by the exact integral of the prescribed acceleration (1e-9 m) and
    not vertically; the sediment layer on the base is carried with it (its mean displacement
    more than half the base's: stick, not sliding), while the crest lags (less than a quarter:
    the basal layer yields once a > tan(phi') g); plastic strain in the lowest sediment layer;
    the free surface within the volume bound u_base H / gap of the bank's push."""
    out = str(tmp_path / "quake")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', end_time = {END}, "
                "output_interval = 0.05 / &grid ncells = 52, 16, 1 /"],
               cwd=str(tmp_path), timeout=900)
    dumps = [read_dump(p) for p in list_dumps(out, quake.NAME)]
    assert len(dumps) == 4
    m0, m1 = quake.masses(dumps[0]), quake.masses(dumps[-1])
    for name in ("water", "sediment", "base"):
        assert abs(m1[name] / m0[name] - 1.0) < 1e-10, (name, m0[name], m1[name])

    rows = quake.analyse(dumps)
    length = quake.domain_length(dumps[0])
    b0 = quake.by_id(dumps[0]["particles"]["base"])
    for d, r in zip(dumps, rows):
        b = quake.by_id(d["particles"]["base"])
        dx = quake.unwrapped(b["x"] - b0["x"], length)
        assert np.all(np.abs(dx - r["base_dx_prescribed"]) < 1e-9), r["time"]
        assert np.all(b["y"] == b0["y"])
    last = rows[-1]
    ub = last["base_dx"]
    assert ub == pytest.approx(quake.prescribed_displacement(END), abs=1e-9)

    s0 = quake.by_id(dumps[0]["particles"]["sediment"])
    layer = s0["y"] < 0.5
    crest = s0["y"] > 2.3
    u_layer = float(np.mean(last["ux"][layer])) + ub
    u_crest = float(np.mean(last["ux"][crest])) + ub
    assert 0.5 * ub < u_layer <= 1.0 * ub + 1e-9, (u_layer, ub)
    assert u_crest < 0.25 * ub, (u_crest, ub)
    assert np.max(last["plastic"][layer]) > 1e-3
    assert np.max(np.abs(last["eta"])) < ub * BANK_HEIGHT / GAP, (last["eta_max"], last["eta_min"])


def test_pore_pressure_roughness_sees_a_single_cell_and_not_a_gradient():
    """The noise measure of the postproc on a synthetic layer: hydrostatic plus a smooth
    (linear in x, periodic wrap excluded by the sediment mask) excess gives 0; one cell 40 kPa
    above its neighbours gives 40 kPa at most and 20 kPa beside it; cells with base or without
    sediment are left out."""
    ni, nj = 12, 4
    dx = 0.5
    y = (np.arange(nj) + 0.5) * dx
    hydro = quake.P_ATM + quake.RHO_W * quake.G * (quake.STILL_LEVEL - y)
    sed = np.zeros((ni, nj, 1))
    sed[1:-1, 1:3, 0] = 1.0                      # a sediment layer, open at both x ends
    base = np.zeros((ni, nj, 1))
    base[:, 0, 0] = 1.0
    ramp = 1.0e3 * np.arange(ni)[:, None]        # 1 kPa per cell along x
    dump = {"attrs": {"ncells": [ni, nj, 1], "lower": [0.0, 0.0, 0.0], "dx": [dx, dx, dx]},
            "cell": {"pressure": (hydro[None, :] + ramp)[:, :, None],
                     "sediment/volume_fraction": sed, "base/volume_fraction": base}}
    p99, largest = quake.pore_pressure_roughness(dump)
    assert largest < 1e-6 and p99 < 1e-6, (p99, largest)
    dump["cell"]["pressure"][5, 2, 0] += 4.0e4
    dump["cell"]["pressure"][5, 0, 0] += 9.0e5   # inside the base: not counted
    p99, largest = quake.pore_pressure_roughness(dump)
    assert abs(largest - 4.0e4) < 1e-6, largest
    assert p99 > 2.0e4 - 1e-6, p99


# ------------------------------------------------------------- liquefaction: critical-state sand

LIQUEFACTION = {k: f"{ROOT}/namelists/mpmice_earthquake_slope_{k}_2d.nml" for k in ("loose", "dense")}
LAYER_MONITORS = ("layer, crest", "layer, left flank", "layer, right flank")


def liquefaction_rows(tmp_path, kind):
    """0.25 m cells, to t = 0.15 s (dumps every 0.05 s): the rows of quake.analyse."""
    out = str(tmp_path / kind)
    run_mpmice([LIQUEFACTION[kind], "--set", f"&run output_dir = '{out}', end_time = {END}, "
                "output_interval = 0.05 / &grid ncells = 52, 16, 1 /"], cwd=str(tmp_path), timeout=900)
    return quake.analyse([read_dump(p) for p in list_dumps(out, quake.NAME)])


def test_loose_sand_liquefies_dense_sand_sucks(tmp_path):
    """The critical-state sand variants of the shaken bank
    (docs/earthquake_liquefaction.md), 0.25 m cells, the first 0.15 s of the 1 g shaking.
    Loose (phi0 = 0.57 < phi_m): in the basal layer under the crest and both flanks the pore-
    pressure ratio r_u = excess pore pressure / initial sigma'_v rises from 0.05 to 0.15 s and
    reaches >= 0.6 at 0.15 s (measured 0.77 / 1.03 / 1.02), and the skeleton there has lost
    >= 90 % of its vertical effective stress (measured 100 %). Dense (phi0 = 0.62 > phi_m): the
    same points suck, r_u <= -0.3 at 0.1 and 0.15 s (measured -0.74 .. -3.9), and sigma'_v grows."""
    loose = liquefaction_rows(tmp_path, "loose")
    dense = liquefaction_rows(tmp_path, "dense")
    assert [r["time"] for r in loose] == pytest.approx([0.0, 0.05, 0.10, 0.15])
    for key in LAYER_MONITORS:
        assert loose[3]["ru"][key] > loose[1]["ru"][key], key
        assert loose[3]["ru"][key] >= 0.6, (key, loose[3]["ru"][key])
        assert loose[3]["ru_effective"][key] >= 0.9, (key, loose[3]["ru_effective"][key])
        for r in dense[2:]:
            assert r["ru"][key] <= -0.3, (key, r["time"], r["ru"][key])
            assert r["ru_effective"][key] < 0.0, (key, r["time"], r["ru_effective"][key])


def test_base_shaking_and_cycle_table(tmp_path):
    """The shaking read back from a run's echo (the base's amplitude, frequency and duration;
    the shipped 1 g, 2 Hz, 1 s without an echo), a(t) zero after the shaking, and the r_u per
    cycle on synthetic rows: at each cycle's end and the largest within it."""
    assert quake.base_shaking(str(tmp_path)) == (quake.AMPLITUDE, quake.FREQUENCY, quake.DURATION,
                                                 0.0)
    (tmp_path / "quake.used.nml").write_text(
        "&solid\n  name = 'sediment'\n  acceleration_amplitude = 0.0, 0.0, 0.0\n/\n"
        "&solid\n  name = 'base'\n  acceleration_amplitude = 1.4715, 0.0, 0.0\n"
        "  acceleration_frequency = 2.0\n  acceleration_duration = 2.5\n/\n")
    shaking = quake.base_shaking(str(tmp_path))
    assert shaking == pytest.approx((1.4715, 2.0, 2.5, 0.0))
    acc = quake.base_acceleration(np.array([0.125, 2.625]), shaking)
    assert acc[0] == pytest.approx(1.4715) and acc[1] == 0.0
    times = np.arange(0.0, 1.0 + 1e-9, 0.05)
    rows = [{"time": float(t), "ru": {k: float(t) for k in quake.RU_MONITORS}} for t in times]
    rows[3]["ru"] = {k: 0.9 for k in quake.RU_MONITORS}        # a peak inside cycle 1
    table = quake.cycle_table(rows, shaking)
    assert [c["cycle"] for c in table] == [1, 2]                # rows end at 1.0 s
    key = "layer, crest"
    assert table[0]["end"][key] == pytest.approx(0.5) and table[0]["max"][key] == pytest.approx(0.9)
    assert table[1]["end"][key] == pytest.approx(1.0) and table[1]["max"][key] == pytest.approx(1.0)


def test_cycle_diagnostics_and_shear_ratio():
    """The per-cycle cyclic stress ratio (half the range of a monitor's mean tau_xy over the
    cycle's dumps / sigma'_v0) and volume spread at the cycle's end on synthetic rows, and
    tau / p' of a K0 = 0.5 plane-strain state (sqrt(1/12) / (2/3) = 0.433) and of a pure shear."""
    shaking = (0.981, 2.0, 1.0)
    times = np.arange(0.0, 1.0 + 1e-9, 0.025)            # dumps at the peaks of sin(4 pi t)
    rows = [{"time": float(t), "sigma_v0": {k: 2.0e4 for k in quake.RU_MONITORS},
             "tau_xy": {k: 3.0e3 * math.sin(4.0 * math.pi * t) for k in quake.RU_MONITORS},
             "ev_spread": {k: 1e-3 * t for k in quake.RU_MONITORS}} for t in times]
    table = quake.cycle_diagnostics(rows, shaking)
    assert [c["cycle"] for c in table] == [1, 2]
    key = "layer, crest"
    assert table[0]["csr"][key] == pytest.approx(0.15)         # 3 kPa / 20 kPa
    assert table[1]["ev_spread"][key] == pytest.approx(1e-3)
    parts = {"stress_xx": np.array([-0.5e4, -1e4]), "stress_yy": np.array([-1e4, -1e4]),
             "stress_zz": np.array([-0.5e4, -1e4]), "stress_xy": np.array([0.0, 3e3])}
    ratio = quake.shear_ratio(parts, np.array([0, 1]))
    assert ratio[0] == pytest.approx(math.sqrt(1.0 / 12.0) * 1.5)
    assert ratio[1] == pytest.approx(0.3)


def test_shaking_start_shifts_the_cycles(tmp_path):
    """`&solid acceleration_start` read back from the echo: a(t) and the base displacement are
    zero before it, the cycles are counted from it, and the displacement is that of a shaking
    started at 0, shifted."""
    (tmp_path / "quake.used.nml").write_text(
        "&solid\n  name = 'base'\n  acceleration_amplitude = 0.4905, 0.0, 0.0\n"
        "  acceleration_frequency = 2.0\n  acceleration_duration = 1.0\n"
        "  acceleration_start = 1.5\n/\n")
    shaking = quake.base_shaking(str(tmp_path))
    assert shaking == pytest.approx((0.4905, 2.0, 1.0, 1.5))
    acc = quake.base_acceleration(np.array([0.125, 1.625, 2.625]), shaking)
    assert acc[0] == 0.0 and acc[1] == pytest.approx(0.4905) and acc[2] == 0.0
    assert quake.prescribed_displacement(1.4, *shaking) == 0.0
    assert quake.prescribed_displacement(3.2, *shaking) == pytest.approx(
        quake.prescribed_displacement(1.7, 0.4905, 2.0, 1.0), abs=1e-15)
    rows = [{"time": float(t), "ru": {k: float(t) for k in quake.RU_MONITORS}}
            for t in np.arange(0.0, 2.5 + 1e-9, 0.05)]
    table = quake.cycle_table(rows, shaking)
    assert [c["cycle"] for c in table] == [1, 2]
    assert [c["time"] for c in table] == pytest.approx([2.0, 2.5])
