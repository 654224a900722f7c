"""Earthquake-induced liquefaction of a gentle submarine bank
(namelists/mpmice_gentle_slope_loose_2d.nml and _dense_2d.nml; docs/earthquake_liquefaction.md,
"A gentle bank: build-up and spreading").

A bank 1 m high with 10 deg flanks on a 1 m layer of the critical-state sand with Byrne's cyclic
densification, undrained (10 um grains), on a rigid base shaken at 0.025 g, 2 Hz, to the end of
the 3rd cycle. Measured (python -m postproc.mpmice_gentle_slope): the loose layer under the crest
loses 0.23 / 0.62 / 0.76 of its vertical effective stress at the ends of cycles 1-3 (r_u 0.19 /
0.51 / 0.60), and the loose flanks' surface moves away from the crest, the left one by 1.1 / 4.7
/ 8.6 cm, the right one by 0.0 / 0.3 / 1.6 cm; the dense layer under the crest loses 0.01 / 0.06
/ 0.08 and the dense flanks move less than 0.5 mm.
Both runs side by side, 64 s on the idle machine. Without runs (not slow): the report finds a bank's
levels, crest and flanks wherever it lies in the periodic row, across x = 0 too."""
import numpy as np
import pytest

from postproc import mpmice_gentle_slope as gentle
from postproc.mpmice_earthquake_slope import base_shaking
from postproc.mpmice_io import read_run_dumps
from postproc.run_case import ROOT, run_side_by_side

CYCLES = 3
CREST = "layer, crest"


def synthetic_bank(crest_x: float, length: float = 20.0, dx: float = 0.05):
    """Particles of a 1 m layer (0.2-1.2 m) and a bank 1 m high with 10 deg flanks and a 2 m
    crest centred at ``crest_x`` (periodic over ``length``), and of the base below, on a
    lattice of spacing ``dx`` as the seeding places them."""
    run = 1.0 / np.tan(np.radians(10.0))
    x = (np.arange(int(round(length / dx))) + 0.5) * dx
    d = np.abs((x - crest_x + 0.5 * length) % length - 0.5 * length)   # distance to the crest
    top = 1.2 + np.clip((1.0 + run - d) / run, 0.0, 1.0)
    sx, sy = [], []
    for xi, ti in zip(x, top):
        ys = np.arange(0.2 + 0.5 * dx, ti, dx)
        sx += [xi] * len(ys)
        sy += list(ys)
    base = {"x": x, "y": np.full_like(x, 0.2 - 0.5 * dx)}
    return {"x": np.array(sx), "y": np.array(sy)}, base


@pytest.mark.parametrize("crest_x", [10.0, 0.4, 19.0])
def test_bank_geometry_found_anywhere_in_the_periodic_row(crest_x):
    """The report finds the levels, the crest and the flanks' mid-points of a bank wherever it
    lies, across x = 0 too."""
    parts, base = synthetic_bank(crest_x)
    g = gentle.bank_geometry(parts, base, 0.05, 20.0)
    assert abs(g["base_top"] - 0.2) < 1e-9 and abs(g["layer_top"] - 1.2) < 0.03
    assert abs(g["crest_top"] - 2.2) < 0.03
    half = 1.0 + 0.5 / np.tan(np.radians(10.0))        # crest centre to the flanks' mid-height
    # a flank's mid-point is the first column of the top nearest the middle height: the tops
    # step by one particle spacing, i.e. 0.05 / tan 10 deg = 0.28 m along the flank; the
    # crest's edge columns within one spacing
    step = 0.05 / np.tan(np.radians(10.0))
    for key, want, tol in (("crest", crest_x, 0.05), ("left", crest_x - half, step),
                           ("right", crest_x + half, step)):
        gap = (g[key] - want + 10.0) % 20.0 - 10.0
        assert abs(gap) < tol, (key, g[key], want % 20.0)
    flank = gentle.surface_members(parts, g, g["left"], 20.0)
    gaps = (parts["x"][flank] - g["left"] + 10.0) % 20.0 - 10.0
    assert flank.size > 0 and np.all(np.abs(gaps) <= gentle.FLANK_HALF_WIDTH)


@pytest.fixture(scope="module")
def tables(mpmice_exe, tmp_path_factory):
    """Per packing the cycle table of :func:`postproc.mpmice_gentle_slope.cycle_table`, both
    runs to the end of cycle CYCLES with a dump every 0.25 s."""
    def report(out):
        rows = gentle.analyse(read_run_dumps(out, gentle.NAME), base_shaking(out, gentle.NAME))
        return gentle.cycle_table(rows)

    scenes = {p: f"{ROOT}/namelists/mpmice_gentle_slope_{p}_2d.nml" for p in ("loose", "dense")}
    return run_side_by_side(str(tmp_path_factory.mktemp("gentle_slope")), scenes,
                            f"&run end_time = {0.5 * CYCLES}, output_interval = 0.25 /",
                            report=report, timeout=900, exe=str(mpmice_exe))


@pytest.mark.slow   # two scene runs
def test_loose_layer_under_the_crest_builds_up_cycle_by_cycle(tables):
    table = tables["loose"]
    assert len(table) == CYCLES
    lost = [c["lost"][CREST] for c in table]
    ru = [c["ru"][CREST] for c in table]
    assert np.all(np.diff(lost) > 0.1), lost
    assert lost[0] < 0.3 and lost[-1] > 0.55, lost
    assert np.all(np.diff(ru) > 0.03) and ru[-1] > 0.35, ru


@pytest.mark.slow   # two scene runs
def test_loose_bank_spreads_and_dense_bank_stands(tables):
    """The loose flanks move away from the crest by centimetres, more in every cycle; the dense
    ones by less than a millimetre."""
    left = [c["left"] for c in tables["loose"]]
    right = [c["right"] for c in tables["loose"]]
    assert np.all(np.diff(left) < -0.01) and left[-1] < -0.05, left
    assert right[-1] > 0.005, right
    for c in tables["dense"]:
        assert abs(c["left"]) < 1e-3 and abs(c["right"]) < 1e-3, (c["left"], c["right"])


@pytest.mark.slow   # two scene runs
def test_dense_layer_stays_far_from_liquefaction(tables):
    for c in tables["dense"]:
        assert c["lost"][CREST] < 0.15 and c["ru"][CREST] < 0.15, (c["lost"], c["ru"])
