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
Both runs side by side, 64 s on the idle machine."""
import numpy as np
import pytest

from postproc import mpmice_gentle_slope as gentle
from postproc.mpmice_earthquake_slope import base_shaking
from postproc.mpmice_io import read_run_dumps
from postproc.run_case import ROOT, run_side_by_side

pytestmark = pytest.mark.slow   # two scene runs

CYCLES = 3
CREST = "layer, crest"


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


def test_loose_layer_under_the_crest_builds_up_cycle_by_cycle(tables):
    table = tables["loose"]
    assert len(table) == CYCLES
    lost = [c["lost"][CREST] for c in table]
    ru = [c["ru"][CREST] for c in table]
    assert np.all(np.diff(lost) > 0.1), lost
    assert lost[0] < 0.3 and lost[-1] > 0.55, lost
    assert np.all(np.diff(ru) > 0.03) and ru[-1] > 0.35, ru


def test_loose_bank_spreads_and_dense_bank_stands(tables):
    """The loose flanks move away from the crest by centimetres, more in every cycle; the dense
    ones by less than a millimetre."""
    left = [c["left"] for c in tables["loose"]]
    right = [c["right"] for c in tables["loose"]]
    assert np.all(np.diff(left) < -0.01) and left[-1] < -0.05, left
    assert right[-1] > 0.005, right
    for c in tables["dense"]:
        assert abs(c["left"]) < 1e-3 and abs(c["right"]) < 1e-3, (c["left"], c["right"])


def test_dense_layer_stays_far_from_liquefaction(tables):
    for c in tables["dense"]:
        assert c["lost"][CREST] < 0.15 and c["ru"][CREST] < 0.15, (c["lost"], c["ru"])
