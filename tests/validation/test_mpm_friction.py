"""Frictional contact of a deformable solid with a rigid body (`&mpm rigid_contact =
'friction'`): an elastic block on a 30 deg rigid slope against the rigid-block solution
(postproc/mpm_friction.py, docs/validation/mpm_friction.md)."""

import numpy as np
import pytest

from postproc import mpm_friction


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_exact_displacement_is_continuous_and_sticks():
    """The ramped solution joins the constant-gravity parabola smoothly; mu >= tan 30 sticks."""
    mu, ramp = 0.2, 0.05
    eps = 1e-9
    assert mpm_friction.exact_displacement(ramp - eps, mu, ramp) == \
        pytest.approx(mpm_friction.exact_displacement(ramp + eps, mu, ramp), abs=1e-9)
    assert mpm_friction.exact_displacement(0.3, mu) == \
        pytest.approx(0.5 * 9.81 * (0.5 - mu * np.cos(np.radians(30))) * 0.09, rel=1e-12)
    assert mpm_friction.exact_displacement(0.3, 0.6) == 0.0


@pytest.mark.parametrize("mu,tolerance", [(0.0, 0.005), (0.2, 0.005), (0.4, 0.01)])
def test_block_slides_as_rigid_block(tmp_path, mu, tolerance):
    """Block in contact from t = 0, gravity ramped over 0.05 s, t = 0.3 s: the displacement
    along the slope within 0.5 % (mu = 0, measured +0.04 %; mu = 0.2, -0.00 %) and 1 %
    (mu = 0.4, +0.12 %) of the rigid block's."""
    t, x, _ = mpm_friction.run(str(tmp_path), mu, 0.05)
    ref = mpm_friction.exact_displacement(t[-1], mu, 0.05)
    assert t[-1] == pytest.approx(0.3)
    assert abs(x[-1] / ref - 1.0) < tolerance, (x[-1], ref)


def test_block_sticks_above_the_friction_angle(tmp_path):
    """mu = 0.7 > tan 30: the block holds: final speed below 0.01 m/s, displacement below
    0.5 mm (measured 0.02 mm), and over the last 0.1 s only its elastic vibration (< 0.3 mm)."""
    t, x, v = mpm_friction.run(str(tmp_path), 0.7, 0.05)
    assert abs(v[-1]) < 0.01
    assert x[-1] < 5e-4
    late = t >= t[-1] - 0.1 - 1e-12
    assert np.ptp(x[late]) < 3e-4
