"""The critical-state sand's compaction at low effective stress (`&solid compaction_index`,
`css_compaction` in modules/mpm/mpm_critical_state_sand.f90; docs/soil_models.md and
docs/validation/rondon2011.md, "Compaction at low effective stress") in the loose Rondon column
(namelists/mpmice_rondon_loose_2d.nml, 5 mm cells).

Without it the loose column's base excess pore pressure is positive only while the column
collapses, and from about 1 s on it is near zero or negative (measured +0.8 / -11.8 / -12.9 Pa at
1 / 1.5 / 2 s; the experiment +133 Pa at 1.1 s, +144 Pa at 2 s): the particles, elastic at rest, take their load back within an
elastic strain as the liquid drains. With it (lambda_c = 0.01, p_a = 5 Pa) the liquefied packing
reconsolidates along its soft compaction line and the base pressure stays positive (measured
+189 / +163 / +136 Pa). The restart test runs the option 150 steps, restarts from the checkpoint and
finishes: the dumps equal the uninterrupted run's bit for bit, and with the checkpoint's
compaction pressures zeroed they do not, so p_c (`checkpoint/particles/beads/hardening`) is
carried. About 40 s in all."""
import shutil

import numpy as np
import pytest

from postproc import mpmice_rondon as rondon
from postproc.dump_compare import assert_dumps_identical, dump_differences
from postproc.mpmice_io import list_dumps, read_run_dumps
from postproc.run_case import ROOT, run_into, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpmice_rondon_loose_2d.nml"
COMPACTION = "&solid name = 'beads', compaction_index = 0.01, compaction_pressure = 5.0 /"
END_TIME = 2.0       # s
HELD = 80.0          # Pa: the base pressure with the option at 1, 1.5 and 2 s is above it
DRAINED = 20.0       # Pa: without it, at 1.5 and 2 s below it


@pytest.fixture(scope="module")
def runs(mpmice_exe, tmp_path_factory):
    """The loose scene to END_TIME, dumps every 0.5 s, without and with the compaction."""
    base = tmp_path_factory.mktemp("compaction")
    out = {}
    for case, option in (("off", "&solid name = 'beads' /"), ("on", COMPACTION)):
        run_dir = str(base / case)
        run_into(run_dir, NAMELIST, f"&run end_time = {END_TIME}, output_interval = 0.5 /",
                 option, cwd=str(base), timeout=600, exe=str(mpmice_exe))
        out[case] = read_run_dumps(run_dir, rondon.NAME)
    return out


def _base_pressures(dumps: list[dict]) -> dict[float, float]:
    """Base excess pore pressure [Pa] at the probe per dump time [s]."""
    return {round(float(d["time"]), 3): rondon.base_pressure(d, dumps[0]) for d in dumps}


@pytest.mark.slow
def test_compaction_keeps_the_loose_base_pressure(runs):
    off = _base_pressures(runs["off"])
    on = _base_pressures(runs["on"])
    assert all(on[t] > HELD for t in (1.0, 1.5, 2.0)), on
    assert all(off[t] < DRAINED for t in (1.5, 2.0)), off


@pytest.mark.slow
def test_restart_carries_the_compaction_pressure(mpmice_exe, tmp_path):
    import h5py
    sets = ("&run end_time = 0.3, output_interval = 0.1 /", COMPACTION)
    full = str(tmp_path / "full")
    run_into(full, NAMELIST, *sets, cwd=str(tmp_path), exe=str(mpmice_exe))
    half = tmp_path / "half"
    run_into(str(half), NAMELIST, *sets, "&run max_steps = 150 /", cwd=str(tmp_path),
             exe=str(mpmice_exe))
    checkpoint = half / f"{rondon.NAME}_checkpoint_000150.h5"
    assert checkpoint.is_file()
    zeroed = tmp_path / "zeroed"
    zeroed.mkdir()
    shutil.copy(checkpoint, zeroed / checkpoint.name)
    with h5py.File(zeroed / checkpoint.name, "r+") as f:
        pc = f["checkpoint/particles/beads/hardening"]
        assert np.max(pc[...]) > 0.0
        pc[...] = 0.0
    for start in (checkpoint, zeroed / checkpoint.name):
        run_mpmice(["--restart", str(start), "--set", "&run max_steps = 0 /"],
                   cwd=str(tmp_path), exe=str(mpmice_exe))
    paths = list_dumps(full, rondon.NAME)
    assert len(paths) == 4
    for path in paths[1:]:
        name = path.split("/")[-1]
        assert_dumps_identical(path, half / name)
    last = paths[-1].split("/")[-1]
    assert dump_differences(paths[-1], str(zeroed / last))
