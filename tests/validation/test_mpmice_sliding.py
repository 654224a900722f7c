"""Frictional contact with a rigid bed in the coupled scene (`&mpm rigid_contact = 'friction'`):
a sand block slides on a rigid 45 deg slope in air and under water
(namelists/mpmice_slide_block_air_2d.nml, mpmice_slide_block_2d.nml; postproc/
mpmice_slide_block.py; docs/applications.md). Each run: t = 0.08 s, 40 x 35 cells (2 cm) in air
and under water (~5-10 s); the slow test repeats the underwater pair on 80 x 70 cells (1 cm,
~60 s each)."""
import numpy as np
import pytest

from postproc import mpmice_slide_block as slide

END = ["--set", "&run end_time = 0.08 /"]


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _masses_kept(dumps, tolerance=2e-15):
    m0, m1 = slide.masses(dumps[0]), slide.masses(dumps[-1])
    for name in m0:
        assert abs(m1[name] / m0[name] - 1.0) < tolerance, (name, m0[name], m1[name])


@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_block_slides_in_air_as_rigid_block(tmp_path, mu):
    """In air (no buoyancy, no added mass) the block slides with a = g (sin 45 - mu cos 45)
    within 1 % (measured -0.09 % for mu = 0, +0.11 % for mu = 0.4; -2.1 / -2.3 % while nodes
    inside the bed took the round-off of their rigid mass gradient as a contact normal,
    `mpm_nodal%contact_normal`); mass kept to 2e-15 (measured 2.2e-16)."""
    t, s, dumps = slide.run(str(tmp_path), mu, END, fluid="air")
    assert t[-1] == pytest.approx(0.08)
    a = slide.fitted_acceleration(t, s)
    assert abs(a / slide.drained_acceleration(mu, "air") - 1.0) < 0.01, a
    _masses_kept(dumps)


def _underwater_pair(workdir, extra):
    """(a(0), a(0.4), dumps of mu = 0, dumps of mu = 0.4) of the block under water."""
    t0, s0, d0 = slide.run(workdir, 0.0, extra)
    t4, s4, d4 = slide.run(workdir, 0.4, extra)
    return slide.fitted_acceleration(t0, s0), slide.fitted_acceleration(t4, s4), d0, d4


def test_block_slides_under_water_with_buoyant_friction(tmp_path):
    """Under water the friction carries the buoyant weight: a(0.4) / a(0) = 1 - mu cot 45 = 0.6
    (with the full weight it would be 1 - mu rho_sat / (rho_sat - rho_w) = 0.196); on the
    scene's 40 x 35 cells (2 cm) within 0.06 (measured 0.640; the difference to 0.6 is the
    grid's, first order: 0.623 on 1 cm cells, test_block_under_water_fine). The frictionless
    block is slower than the drained rigid block's g (1 - rho_w / rho_sat) sin 45 = 3.45 m/s^2
    (the water's added mass and the pore water's drag): a(0) = 2.09 m/s^2, 0.605 of it, within
    5 % (sliding needs the buoyant weight: with the full weight it would exceed 1). Water,
    block and bed masses kept to 2e-15 (measured 2.2e-16); 2 ranks give the 1-rank slide to
    1e-9. (Before the pore water's mass flux followed the pressure equation's volume flux inside
    the soil, docs/mpmice.md departure 16: a(0.4)/a(0) 0.609.)"""
    a0, a4, d0, d4 = _underwater_pair(str(tmp_path), END)
    assert abs(a4 / a0 - 0.6) < 0.06, (a0, a4)
    assert abs(a0 / slide.drained_acceleration(0.0) / 0.605 - 1.0) < 0.05, a0
    _masses_kept(d0)
    _masses_kept(d4)
    _, s1, _ = slide.history(str(tmp_path / "slide_water_0.4_1"))
    _, s2, _ = slide.run(str(tmp_path), 0.4, END, nranks=2)
    assert np.allclose(s2, s1, rtol=1e-9, atol=1e-12), (s2, s1)
    assert s1[-1] > 0.0, s1


@pytest.mark.slow
def test_block_under_water_fine(tmp_path):
    """The same on 80 x 70 cells (1 cm, ~2 min): a(0.4) / a(0) within 0.03 of 0.6 (measured
    0.623; 0.599 before departure 16 reached inside the soil), a(0) = 2.33 m/s^2, 0.676 of the
    drained rigid block's (against 0.605 on 2 cm cells: the added mass and drag are resolved
    better), within 5 %; masses kept to 2e-15 (measured 3.3e-16)."""
    fine = END + ["--set", "&grid ncells = 80, 70, 1 /"]
    a0, a4, d0, d4 = _underwater_pair(str(tmp_path), fine)
    assert abs(a4 / a0 - 0.6) < 0.03, (a0, a4)
    assert abs(a0 / slide.drained_acceleration(0.0) / 0.676 - 1.0) < 0.05, a0
    _masses_kept(d0)
    _masses_kept(d4)
