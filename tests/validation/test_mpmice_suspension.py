"""The suspended particles' packing bound (`&solid suspension_cell_bound`, modules/mpmice/
mpmice_suspension.f90; docs/validation/rondon2011.md, "Crowded suspended particles"). The dense
Rondon column (namelists/mpmice_rondon_dense_2d.nml, 5 mm cells, 2 x 2 particles per cell) runs
to END_TIME with and without the bound. Without it, particles past the loosest packing that
crowd into the floor cells ahead of the column keep dilating: the summed particle volume of one
cell reaches several cell volumes (measured 8.6 at 2 s). With it, no cell holds more than
OVERLAP_MAX cell volumes of particles (measured 1.97; particles in contact overlap up to about
1.3 by the cells' crossing noise, the suspended ones at the loosest packing up to about 2), the
front is shorter (measured run-out 2.48 against 3.92 cm at 2 s; the experiment 2.2 cm) and the
base still sucks (-92 against -76 Pa at 2 s).

The settling inside suspended particles (`&solid suspension_settling`, the same module) runs
the same scene: the particles ahead of the column's initial face (x > L0) are denser, because
the grains of those held on the floor sink to the loosest packing at the drag law's hindered
settling velocity (measured mean solid fraction 0.470 against 0.368 without it at 2 s; the
loosest packing 0.53, the initial 0.60); the suction stays. About 40 s for the three runs."""
import numpy as np
import pytest

from postproc import mpmice_rondon as rondon
from postproc.mpmice_io import read_run_dumps
from postproc.mpmice_rondon_diagnose import overlap, state
from postproc.run_case import ROOT, run_into

END_TIME = 2.0       # s
OVERLAP_MAX = 2.5    # cell volumes of particles in one cell, with the bound
PHI_AHEAD = 0.42     # solid fraction between the measured means without (0.368) and with
                     # (0.470) the settling, of the particles ahead of the column's face
OPTIONS = {"free": "", "bound": "suspension_cell_bound = .true.",
           "settling": "suspension_settling = .true."}


@pytest.fixture(scope="module")
def runs(mpmice_exe, tmp_path_factory):
    """The dense scene to END_TIME, dumps every 0.5 s: as shipped, with the bound, with the
    settling."""
    base = tmp_path_factory.mktemp("suspension")
    out = {}
    for case, option in OPTIONS.items():
        run_dir = str(base / case)
        run_into(run_dir, f"{ROOT}/namelists/mpmice_rondon_dense_2d.nml",
                 f"&run end_time = {END_TIME}, output_interval = 0.5 /",
                 f"&solid name = 'beads', {option} /",
                 cwd=str(base), timeout=600, exe=str(mpmice_exe))
        out[case] = read_run_dumps(run_dir, rondon.NAME)
    return out


@pytest.mark.slow
def test_bound_keeps_suspended_particles_from_overlapping(runs):
    free = [overlap(d) for d in runs["free"]]
    bound = [overlap(d) for d in runs["bound"]]
    assert max(free) > 2.0 * OVERLAP_MAX, free
    assert max(bound) <= OVERLAP_MAX, bound


@pytest.mark.slow
def test_bound_shortens_the_dense_front_and_keeps_the_suction(runs):
    free = rondon.model_front(runs["free"][-1])
    bound = rondon.model_front(runs["bound"][-1])
    assert bound < free - 0.005, (bound, free)
    p = rondon.base_pressure(runs["bound"][-1], runs["bound"][0])
    assert p < -30.0, p


def _phi_ahead(dump: dict) -> float:
    """Mean solid fraction of the beads whose centres lie ahead of the column's initial face."""
    s = state(dump)
    ahead = s["x"] > rondon.L0
    return float(np.mean(s["phi"][ahead]))


@pytest.mark.slow
def test_settling_packs_the_run_out_material_and_keeps_the_suction(runs):
    free = _phi_ahead(runs["free"][-1])
    settled = _phi_ahead(runs["settling"][-1])
    assert free < PHI_AHEAD < settled, (free, settled)
    p = rondon.base_pressure(runs["settling"][-1], runs["settling"][0])
    assert p < -30.0, p
