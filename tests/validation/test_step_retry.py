"""A rejected step leaves the state it started from (driver_loop, ice_scene, mpmice_scene).

A step is rejected when the equilibration or the pressure's outer iteration fails; the loop then
retries it with half the step. The retry must start from the accepted state: if the cell
pressure kept the failed attempt's values (up to 1e32 Pa, the next equilibration's initial
guess) and the coupled scene's porous face predictor read the failed attempt's face velocities,
every retry of the 5 mm debris flow at t = 0.714 s would fail again (docs/accuracy.md, "Failure
detection in the run loop").

Scene: the submerged sand block (namelists/mpmice_submerged_block_2d.nml: water, air, a porous
Mohr-Coulomb block, 40 x 20 cells). `&ice max_outer_iterations = 1` with an outer tolerance no
single solve reaches rejects every attempt, so the run fails at the first step after 9 attempts
and dumps its state: that dump must equal the initial dump in every dataset, bit for bit.
"""
from __future__ import annotations

import pathlib

import h5py
import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
BLOCK = str(REPO / "namelists" / "mpmice_submerged_block_2d.nml")


def datasets(path: pathlib.Path, group: str) -> dict[str, np.ndarray]:
    """Every dataset under `group` of an HDF5 file, by its path."""
    found = {}
    with h5py.File(path, "r") as f:
        f[group].visititems(lambda name, obj: found.__setitem__(name, obj[()])
                            if isinstance(obj, h5py.Dataset) else None)
    return found


def test_rejected_steps_leave_the_initial_state(run_mpmice, tmp_case_dir):
    """Every attempt of step 1 rejected: the failed dump is the initial state, bit for bit."""
    result = run_mpmice([BLOCK, "--set", "&ice max_outer_iterations = 1, "
                         "outer_tolerance = 1.0e-30 /", "--set",
                         "&run output_dir = 'out', output_interval = 0.0 /"], timeout=120)
    assert result.returncode == 3, result.stdout + result.stderr
    assert "step 1 rejected 9 times" in result.stdout, result.stdout
    assert result.stderr.count("pressure constraint worst in the cell at") == 9, result.stderr
    out = tmp_case_dir / "out"
    initial, failed = out / "block2d_000000.h5", out / "block2d_failed_000000.h5"
    for group in ("cell", "particles"):
        start, end = datasets(initial, group), datasets(failed, group)
        assert start.keys() == end.keys()
        assert len(start) > 10, sorted(start)
        for name, values in start.items():
            assert np.array_equal(values, end[name]), (group, name)
