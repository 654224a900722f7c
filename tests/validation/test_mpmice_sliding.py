"""Frictional contact with a rigid bed in the coupled scene (`&mpm rigid_contact = 'friction'`,
issue 7): a sand block slides on a rigid 45 deg slope in air and under water
(namelists/mpmice_slide_block_air_2d.nml, mpmice_slide_block_2d.nml; postproc/
mpmice_slide_block.py; docs/applications.md). Each run: t = 0.08 s, 40 x 35 cells in air (~5-10 s),
80 x 70 under water (~40 s)."""
import numpy as np
import pytest

from postproc import mpmice_slide_block as slide

END = ["--set", "&run end_time = 0.08 /"]


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _masses_kept(dumps):
    m0, m1 = slide.masses(dumps[0]), slide.masses(dumps[-1])
    for name in m0:
        assert abs(m1[name] / m0[name] - 1.0) < 1e-10, (name, m0[name], m1[name])


@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_block_slides_in_air_as_rigid_block(tmp_path, mu):
    """In air (no buoyancy, no added mass) the block slides with a = g (sin 45 - mu cos 45)
    within 4 % (measured -2.1 % for mu = 0, -2.4 % for mu = 0.4; the same block in scene `mpm`
    is 1.7 % slow: the staircase of the rigid polygon's particles); mass kept to 1e-10."""
    t, s, dumps = slide.run(str(tmp_path), mu, END, fluid="air")
    assert t[-1] == pytest.approx(0.08)
    a = slide.fitted_acceleration(t, s)
    assert abs(a / slide.drained_acceleration(mu, "air") - 1.0) < 0.04, a
    _masses_kept(dumps)


def test_block_slides_under_water_with_buoyant_friction(tmp_path):
    """Under water the friction carries the buoyant weight: a(0.4) / a(0) = 1 - mu cot 45 = 0.6
    (with the full weight it would be 1 - mu rho_sat / (rho_sat - rho_w) = 0.196); within 0.03
    on 80 x 70 cells (1 cm), measured 0.622. The difference to 0.6 is the grid's, first order:
    0.641 on the scene's 40 x 35 cells (2 cm). (Before the pore water's mass flux followed the
    pressure equation's volume flux inside the soil, docs/mpmice.md departure 16: 0.609 and
    0.599.) The frictionless block is slower than the drained rigid block's
    g (1 - rho_w / rho_sat) sin 45 = 3.45 m/s^2 (the water's added mass and the pore water's
    drag; measured 0.67 of it), and sliding needs the buoyant weight: a(0) between 0.4 and 1.0
    of it. Water, block and bed masses kept to 1e-10; 2 ranks give the 1-rank slide to 1e-9
    (on the scene's own 40 x 35 cells: the split does not depend on the cell size, and the
    fine grid's 2-rank run cost a minute)."""
    fine = END + ["--set", "&grid ncells = 80, 70, 1 /"]
    for sub in ("fine", "coarse"):
        (tmp_path / sub).mkdir()
    t0, s0, d0 = slide.run(str(tmp_path / "fine"), 0.0, fine)
    t4, s4, d4 = slide.run(str(tmp_path / "fine"), 0.4, fine)
    a0, a4 = slide.fitted_acceleration(t0, s0), slide.fitted_acceleration(t4, s4)
    assert abs(a4 / a0 - 0.6) < 0.03, (a0, a4)
    assert 0.4 < a0 / slide.drained_acceleration(0.0) < 1.0, a0
    _masses_kept(d0)
    _masses_kept(d4)
    _, s1, _ = slide.run(str(tmp_path / "coarse"), 0.4, END)
    _, s2, _ = slide.run(str(tmp_path / "coarse"), 0.4, END, nranks=2)
    assert np.allclose(s2, s1, rtol=1e-9, atol=1e-12), (s2, s1)
    assert s1[-1] > 0.0, s1
