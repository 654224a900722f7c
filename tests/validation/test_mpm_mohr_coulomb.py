"""Mohr-Coulomb element tests through the postproc script (tools/mc_element.f90,
postproc/mpm_mohr_coulomb.py): drained triaxial peak and dilation, plane-strain simple shear
(Davis 1968). The same checks on the Fortran side are in tests/unit/test_mpm_constitutive.pf."""
import pytest

from postproc import mpm_mohr_coulomb


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_element_tests_match_the_analytic_values(tmp_path):
    """Round-off against the closed forms, each bound ~10x its measurement (round-off moves
    with the compiler): peak axial stress to 5e-15 relative (measured 3.3e-16), lateral stress
    held to 5e-15 p0 (2.9e-16), dilation ratio to 1e-11 (6.9e-13), Davis ratios to 2e-10
    (1.8e-13, 1.1e-11), d eps_yy / d gamma = tan psi to 2e-10 (1.1e-13, 1.4e-11)."""
    errors = mpm_mohr_coulomb.run(str(tmp_path))["errors"]
    assert errors["peak"] < 5e-15, errors["peak"]
    assert errors["lateral"] < 5e-15, errors["lateral"]
    assert errors["dilation"] < 1e-11, errors["dilation"]
    for key in ("davis_30_0", "davis_35_10", "dilation_30_0", "dilation_35_10"):
        assert errors[key] < 2e-10, (key, errors[key])
