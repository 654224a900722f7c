"""Earthquake-induced liquefaction of level ground (namelists/mpmice_level_ground_loose_1d.nml and
_dense_1d.nml; docs/earthquake_liquefaction.md, "Level ground: the build-up cycle by cycle").

A 2 m undrained layer of the critical-state sand with Byrne's cyclic densification on a rigid base
shaken at 0.025 g, 2 Hz (cyclic stress ratio 0.06-0.07 measured in every band), to the end of the
5th cycle. Measured (python -m postproc.mpmice_level_ground): the loose layer's deepest band
(0-0.3 m above the base) has r_u = 0.25 / 0.48 / 0.65 / 0.75 / 0.86 at the ends of cycles 1-5,
and the cell row 0.3-0.4 m above the base r_u = 1.00 at the end of cycle 5 (a liquefied band); the
dense layer's deepest band 0.02 / 0.04 / 0.05 / 0.06 / 0.07; above 1.1 m neither builds anything
(its cyclic shear strain stays below the densification's threshold). The undrained excess pore
pressure of the cells follows the skeleton's loss of vertical effective stress (within 0.02).
Both runs side by side, 17 s on the idle machine."""
import numpy as np
import pytest

from postproc import mpmice_level_ground as level
from postproc.mpmice_earthquake_slope import base_shaking
from postproc.mpmice_io import read_run_dumps
from postproc.run_case import ROOT, run_side_by_side

pytestmark = pytest.mark.slow   # two scene runs

CYCLES = 5
DEEP = 0                       # the band 0-0.3 m above the base
UPPER = 3                      # the band 1.1-1.5 m


@pytest.fixture(scope="module")
def tables(mpmice_exe, tmp_path_factory):
    """Per packing the cycle table of :func:`postproc.mpmice_level_ground.cycle_table`, both
    runs to the end of cycle CYCLES with a dump at each cycle's end."""
    def report(out):
        rows = level.analyse(read_run_dumps(out, level.NAME), base_shaking(out, level.NAME))
        return level.cycle_table(rows)

    scenes = {p: f"{ROOT}/namelists/mpmice_level_ground_{p}_1d.nml" for p in ("loose", "dense")}
    return run_side_by_side(str(tmp_path_factory.mktemp("level_ground")), scenes,
                            f"&run end_time = {0.5 * CYCLES}, output_interval = 0.5 /",
                            report=report, timeout=600, exe=str(mpmice_exe))


def test_loose_layer_builds_up_cycle_by_cycle_to_liquefaction(tables):
    table = tables["loose"]
    assert len(table) == CYCLES
    deep = [c["ru"][DEEP] for c in table]
    assert np.all(np.diff(deep) > 0.05), deep
    assert 0.1 < deep[0] < 0.4, deep
    assert deep[-1] > 0.8, deep
    # a band of cells has lost its whole effective stress by the last cycle, not by the first
    assert table[0]["cell_ru"] < 0.5 and table[-1]["cell_ru"] > 0.95, \
        [c["cell_ru"] for c in table]


def test_dense_layer_stays_far_from_liquefaction(tables):
    deep = [c["ru"][DEEP] for c in tables["dense"]]
    assert np.all(np.diff(deep) > -0.01) and deep[-1] < 0.15, deep
    assert max(c["cell_ru"] for c in tables["dense"]) < 0.15


def test_pore_pressure_follows_the_lost_effective_stress(tables):
    """Undrained: the cells' excess pressure is the skeleton's loss of sigma'_v, in both layers;
    the upper band (cyclic strain below the threshold) builds neither."""
    for packing, table in tables.items():
        for c in table:
            gap = np.abs(np.array(c["ru"][:3]) - np.array(c["lost"][:3]))
            assert np.all(gap < 0.05), (packing, c["cycle"], c["ru"], c["lost"])
            assert abs(c["ru"][UPPER]) < 0.05, (packing, c["cycle"], c["ru"])
