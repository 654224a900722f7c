"""The coupled scene's summary says which part's stability limit set the step (docs/mpmice.md,
"Which limit sets the step"): three shipped scenes for 40 steps, each limited by another part
for a physical reason, and the counts add up to the steps the run took."""
import re

import pytest

from postproc.run_case import ROOT

LIMIT_LINE = re.compile(
    r"mpmice: step limit set by the fluids \(flow, viscosity, conduction\) in (\d+) steps .*?"
    r"the solids \(wave speed\) in (\d+) steps .*?solid conduction in (\d+) steps .*? of (\d+)")
STEPS_LINE = re.compile(r"ICE: (\d+) steps")


@pytest.mark.parametrize("scene, part", [
    # a rigid porous column: no solid wave, the water's flow sets the step
    ("mpmice_darcy_1d", 0),
    # an elastic block (E = 5 MPa, nu = 0.3: P wave 65 m/s at 1590 kg/m^3 of grains per
    # volume) sinking through still water
    ("mpmice_sinking_block_2d", 1),
    # a rigid porous column at rest conducting heat: the grains' diffusivity (1.9e-7 m^2/s)
    # exceeds the water's (1.4e-7 m^2/s), nothing flows
    ("mpmice_porous_conduction_1d", 2),
])
def test_step_limit_is_reported_for_the_part_that_sets_it(run_mpmice, tmp_path, scene, part):
    out = tmp_path / "out"
    result = run_mpmice([f"{ROOT}/namelists/{scene}.nml", "--set",
                         f"&run output_dir = '{out}', max_steps = 40 /"])
    assert result.returncode == 0, result.stdout + result.stderr
    limit = LIMIT_LINE.search(result.stdout)
    assert limit, result.stdout
    counts = [int(limit.group(k)) for k in (1, 2, 3)]
    total = int(limit.group(4))
    assert sum(counts) == total == int(STEPS_LINE.search(result.stdout).group(1)) == 40
    assert counts[part] == total, counts
