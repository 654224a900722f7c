"""The suspended particles' packing bound (`&solid suspension_cell_bound`, modules/mpmice/
mpmice_suspension.f90; docs/validation/rondon2011.md, "Crowded suspended particles"). The dense
Rondon column (namelists/mpmice_rondon_dense_2d.nml, 5 mm cells, 2 x 2 particles per cell) runs
to END_TIME with and without the bound. Without it, particles past the loosest packing that
crowd into the floor cells ahead of the column keep dilating: the summed particle volume of one
cell reaches several cell volumes (measured 8.6 at 2 s). With it, no cell holds more than
OVERLAP_MAX cell volumes of particles (measured 1.97; particles in contact overlap up to about
1.3 by the cells' crossing noise, the suspended ones at the loosest packing up to about 2), the
front is shorter (measured run-out 2.48 against 3.92 cm at 2 s; the experiment 2.2 cm) and the
base still sucks (-92 against -76 Pa at 2 s). About 25 s for the pair."""
import pytest

from postproc import mpmice_rondon as rondon
from postproc.mpmice_io import read_run_dumps
from postproc.mpmice_rondon_diagnose import overlap
from postproc.run_case import ROOT, run_into

END_TIME = 2.0       # s
OVERLAP_MAX = 2.5    # cell volumes of particles in one cell, with the bound


@pytest.fixture(scope="module")
def runs(mpmice_exe, tmp_path_factory):
    """The dense scene to END_TIME, dumps every 0.5 s, without and with the bound."""
    base = tmp_path_factory.mktemp("suspension")
    out = {}
    for bound in (False, True):
        run_dir = str(base / f"bound_{bound}")
        run_into(run_dir, f"{ROOT}/namelists/mpmice_rondon_dense_2d.nml",
                 f"&run end_time = {END_TIME}, output_interval = 0.5 /",
                 f"&solid name = 'beads', suspension_cell_bound = {'.true.' if bound else '.false.'} /",
                 cwd=str(base), timeout=600, exe=str(mpmice_exe))
        out[bound] = read_run_dumps(run_dir, rondon.NAME)
    return out


@pytest.mark.slow
def test_bound_keeps_suspended_particles_from_overlapping(runs):
    free = [overlap(d) for d in runs[False]]
    bound = [overlap(d) for d in runs[True]]
    assert max(free) > 2.0 * OVERLAP_MAX, free
    assert max(bound) <= OVERLAP_MAX, bound


@pytest.mark.slow
def test_bound_shortens_the_dense_front_and_keeps_the_suction(runs):
    free = rondon.model_front(runs[False][-1])
    bound = rondon.model_front(runs[True][-1])
    assert bound < free - 0.005, (bound, free)
    p = rondon.base_pressure(runs[True][-1], runs[True][0])
    assert p < -30.0, p
