"""ICE scene, Sod shock tube (namelists/ice_sod.nml) against the exact Riemann solution
(postproc.riemann): accuracy at 100 and 200 cells, rank invariance, bitwise-identical restart.

Tolerances are fixed up front from the measured values (docs/validation/ice_sod.md):
relative L1 density error 0.94 % at 200 cells (acoustic CFL 0.5, time_theta 0.5; 0.77 % since the
face velocities are time-centred), post-shock plateau pressure
within 0.1 % of the exact p* = 0.30313 on average (total-energy-conservative update)."""
import os

import numpy as np
import pytest

from postproc import ice_sod, riemann
from postproc.dump_compare import assert_dumps_identical
from postproc.mpmice_io import cell_centres, list_dumps
from postproc.run_case import run_mpmice


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_sod_accuracy(tmp_path):
    """Relative L1 density error < 1.0 % at 200 cells (measured 0.94 %, 0.77 % now), smaller
    than at 100 cells; pressure between contact and shock: mean within 0.1 % of the exact p*,
    every cell within 0.2 % (the post-shock overshoot, 0.6 %, is left out of the window)."""
    rows, dump = ice_sod.study(str(tmp_path), [100, 200])
    assert rows[1][1] < 0.010, rows
    assert rows[1][1] < 0.8 * rows[0][1], rows
    x = cell_centres(dump)[0]
    p_star, _ = riemann.star_state(riemann.SOD_LEFT, riemann.SOD_RIGHT)
    # between contact (x = 0.685) and shock (x = 0.850), 10 cells clear of the shock's overshoot
    plateau = dump["cell"]["pressure"][(x > 0.72) & (x < 0.80), 0, 0]
    assert abs(np.mean(plateau) / p_star - 1.0) < 1e-3, plateau
    assert np.max(np.abs(plateau / p_star - 1.0)) < 2e-3, plateau


def test_sod_issue_target_250_cells(tmp_path):
    """The target: relative L1 density error <= 0.6 % at 250 cells with the namelist
    settings (measured 0.580 % with the time-centred face velocities; 0.729 % before)."""
    rows, _ = ice_sod.study(str(tmp_path), [250])
    assert rows[0][1] <= 0.006, rows


def test_sod_rank_invariance(tmp_path):
    """Density, velocity and pressure on 2 and 4 ranks equal the 1-rank run to 1e-10 relative
    (the only rank-dependent step is hypre's PCG, converged to 1e-12)."""
    ref = ice_sod.run(str(tmp_path), 200, nranks=1)
    for nranks in (2, 4):
        other = ice_sod.run(str(tmp_path), 200, nranks=nranks)
        assert other["step"] == ref["step"]
        for name in ("gas/density", "gas/velocity_x", "pressure"):
            a, b = ref["cell"][name], other["cell"][name]
            scale = np.max(np.abs(a))
            assert np.max(np.abs(a - b)) <= 1e-10 * scale, (nranks, name)


@pytest.mark.parametrize("nranks", [1, 2])
def test_sod_restart_is_bitwise_identical(tmp_path, nranks):
    """Run to the end; run 110 of ~200 steps (checkpoint at max_steps), restart (110 more allowed): identical dumps."""
    full = tmp_path / "full"
    half = tmp_path / "half"
    common = [ice_sod.NAMELIST, "--set", "&grid ncells = 200, 1, 1 /",
              "--set", "&run output_interval = 0.05 /"]
    run_mpmice(common + ["--set", f"&run output_dir = '{full}' /"], nranks=nranks,
               cwd=str(tmp_path))
    run_mpmice(common + ["--set", f"&run output_dir = '{half}', max_steps = 110 /"],
               nranks=nranks, cwd=str(tmp_path))
    checkpoint = half / "sod_checkpoint_000110.h5"
    assert checkpoint.is_file()
    run_mpmice(["--restart", str(checkpoint)], nranks=nranks, cwd=str(tmp_path))
    full_dumps = list_dumps(str(full), "sod")
    assert len(full_dumps) == 5  # t = 0, 0.05, 0.1, 0.15, 0.2
    for path in full_dumps:
        assert_dumps_identical(path, half / os.path.basename(path))
