"""Mohr-Coulomb element tests through the postproc script (src/mc_element.f90,
postproc/mpm_mohr_coulomb.py): drained triaxial peak and dilation, plane-strain simple shear
(Davis 1968). The same checks on the Fortran side are in tests/unit/test_mpm_constitutive.pf."""
import pytest

from postproc import mpm_mohr_coulomb


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_element_tests_match_the_analytic_values(tmp_path):
    """Peak axial stress to 1e-8 relative (measured 3e-16), lateral stress held to 1e-8 p0,
    dilation ratio to 1e-8 (7e-13), Davis ratios to 1e-8 (1e-11), d eps_yy / d gamma = tan psi
    to 1e-6 (1e-11)."""
    errors = mpm_mohr_coulomb.run(str(tmp_path))["errors"]
    assert errors["peak"] < 1e-8
    assert errors["lateral"] < 1e-8
    assert errors["dilation"] < 1e-8
    for key in ("davis_30_0", "davis_35_10"):
        assert errors[key] < 1e-8, (key, errors[key])
    for key in ("dilation_30_0", "dilation_35_10"):
        assert errors[key] < 1e-6, (key, errors[key])
