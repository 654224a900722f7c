"""Earthquake-induced liquefaction of a gentle submarine bank
(namelists/mpmice_gentle_slope_loose_2d.nml and _dense_2d.nml; docs/earthquake_liquefaction.md,
"A gentle bank: build-up, spreading and flow").

A bank 1 m high with 10 deg flanks on a 1 m layer of the critical-state sand with Byrne's cyclic
densification and the memory of the apex (`tension_gap`), undrained (10 um grains), on a rigid
base shaken at 0.025 g, 2 Hz, here for 3 cycles (1.5 s) and then 1 s of rest. Measured (python -m
postproc.mpmice_gentle_slope, dumps every 0.25 s): the loose layer under the crest loses 0.05 /
0.36 / 0.45 of its vertical effective stress at the ends of cycles 1-3 (r_u 0.04 / 0.28 / 0.33);
the loose left flank's surface moves to -x by 1.0 / 7.3 / 14.7 cm, and after the shaking the
flanks move apart by 8.9 and then 12.3 cm in the two half-seconds (flow; the same run without
`tension_gap`: 5.0 and then 1.8 cm, the spreading dies out); the right flank is 9.8 cm out at
2.5 s. The dense layer under the crest loses at most 0.12 and the dense flanks move less than
1 mm.
Both runs side by side, about 120 s on the idle machine. Without runs (not slow): the report finds
a bank's levels, crest and flanks wherever it lies in the periodic row, across x = 0 too."""
import numpy as np
import pytest

from postproc import mpmice_gentle_slope as gentle
from postproc.mpmice_earthquake_slope import base_shaking
from postproc.mpmice_io import read_run_dumps
from postproc.run_case import ROOT, run_side_by_side

CYCLES = 3
REST = 1.0      # s of rest after the shaking
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
    """Per packing the cycle table of :func:`postproc.mpmice_gentle_slope.cycle_table` and the
    flanks after the shaking (:func:`postproc.mpmice_gentle_slope.after_shaking`), both runs
    shaken for CYCLES cycles and then REST s at rest, with a dump every 0.25 s."""
    def report(out):
        rows = gentle.analyse(read_run_dumps(out, gentle.NAME), base_shaking(out, gentle.NAME))
        return {"cycles": gentle.cycle_table(rows)[:CYCLES],
                "after": gentle.after_shaking(rows)}

    scenes = {p: f"{ROOT}/namelists/mpmice_gentle_slope_{p}_2d.nml" for p in ("loose", "dense")}
    return run_side_by_side(str(tmp_path_factory.mktemp("gentle_slope")), scenes,
                            f"&run end_time = {0.5 * CYCLES + REST}, output_interval = 0.25 /",
                            f"&solid name = 'base', acceleration_duration = {0.5 * CYCLES} /",
                            report=report, timeout=900, exe=str(mpmice_exe))


@pytest.mark.slow   # two scene runs
def test_loose_layer_under_the_crest_builds_up_cycle_by_cycle(tables):
    table = tables["loose"]["cycles"]
    assert len(table) == CYCLES
    lost = [c["lost"][CREST] for c in table]
    ru = [c["ru"][CREST] for c in table]
    assert np.all(np.diff(lost) > 0.03), lost
    assert lost[0] < 0.3 and lost[-1] > 0.35, lost
    assert np.all(np.diff(ru) > 0.03) and ru[-1] > 0.2, ru


@pytest.mark.slow   # two scene runs
def test_loose_bank_spreads_and_dense_bank_stands(tables):
    """The loose left flank moves away from the crest by centimetres in every cycle, the right
    one follows; the dense ones move by less than a millimetre."""
    left = [c["left"] for c in tables["loose"]["cycles"]]
    assert np.all(np.diff(left) < -0.01) and left[-1] < -0.10, left
    right = tables["loose"]["after"][-1][2]
    assert right > 0.02, right
    for c in tables["dense"]["cycles"]:
        assert abs(c["left"]) < 1e-3 and abs(c["right"]) < 1e-3, (c["left"], c["right"])
    for _, left_end, right_end in tables["dense"]["after"]:
        assert abs(left_end) < 1e-3 and abs(right_end) < 1e-3, (left_end, right_end)


@pytest.mark.slow   # two scene runs
def test_loose_bank_flows_after_the_shaking(tables):
    """After the shaking the loose flanks move apart by more than 5 cm in each half-second, the
    second no slower than 0.8 of the first: a flow, not a spreading that dies out (without
    `tension_gap` the second half-second's 1.8 cm is a third of the first's)."""
    marks = tables["loose"]["after"]
    assert len(marks) == 3, marks
    apart = [(r1 - l1) - (r0 - l0) for (_, l0, r0), (_, l1, r1) in zip(marks, marks[1:])]
    assert min(apart) > 0.05 and apart[1] > 0.8 * apart[0], apart


@pytest.mark.slow   # two scene runs
def test_dense_layer_stays_far_from_liquefaction(tables):
    for c in tables["dense"]["cycles"]:
        assert c["lost"][CREST] < 0.15 and c["ru"][CREST] < 0.15, (c["lost"], c["ru"])
