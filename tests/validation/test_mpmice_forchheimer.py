"""Forchheimer (Ergun / van Gent) drag of the coupled MPMICE scene (`&solid drag_law =
'forchheimer'`; study: postproc/mpmice_forchheimer.py, set-up of postproc/mpmice_darcy.py).

Scene runs (about 3 s in all): steady water flow through the Darcy scene's rigid column made of
gravel (d = 10 mm, phi_s = 0.6, dp = 0.5 and 0.1 atm: Re_p = rho q d / mu = 1730 and 761) against
the closed-form root of the quadratic law, and the same column of 1 mm sand at Re_p = 0.1 against
Darcy (eq. 77 with Kozeny-Carman's k; a = 180); a deformable consolidating column (Terzaghi
scene) with a = 180, b = 0 gives the Kozeny-Carman run's pressures. The analytic pieces are
tested without the solver.
"""
from __future__ import annotations

import numpy as np
import pytest

from postproc import mpmice_darcy, mpmice_forchheimer as forch, mpmice_terzaghi
from postproc.mpmice_io import read_run_dumps
from postproc.run_case import run_mpmice

#: Tolerances of the scene comparisons (measured: 1.4e-4 and 6.1e-5 on U_f, 3.8e-4 on the flux
#: outside the column at high Re; 1.5e-7 at Re_p = 0.1).
HIGH_RE_TOLERANCE = 1e-3
LOW_RE_TOLERANCE = 1e-5


# --------------------------------------------------------------------------- analytic pieces

def test_exact_flux_is_the_root_of_the_law():
    """q of exact_darcy_flux satisfies A q + B q^2 = G from Darcy to fully quadratic flow."""
    for phi, d, a, b in ((0.6, 0.01, 150.0, 1.75), (0.61, 0.004, 150.0, 1.75),
                         (0.5, 0.05, 1000.0, 1.1)):
        lin, quad = forch.law_coefficients(phi, d, a, b)
        for gradient in (1e-2, 1.0, 1e2, 1e4, 1e6):
            q = forch.exact_darcy_flux(phi, gradient, d, a, b)
            assert q > 0.0
            assert lin * q + quad * q**2 == pytest.approx(gradient, rel=1e-12)


def test_linear_term_with_a_180_is_eq77():
    """b = 0, a = 180: the pore velocity is eq. 77's (Kozeny-Carman, k = n^3 d^2 /
    (180 phi_s^2)) for the Darcy scene's 15 cases."""
    for phi, dp in mpmice_darcy.CASES:
        u = forch.exact_pore_velocity(phi, dp, mpmice_darcy.GRAIN, 180.0, 0.0)
        assert u == pytest.approx(mpmice_darcy.exact_pore_velocity(phi, dp), rel=1e-12)
        assert forch.linear_pore_velocity(phi, dp, mpmice_darcy.GRAIN, 180.0) \
            == pytest.approx(u, rel=1e-12)


def test_case_regimes():
    """The gravel cases are inertial (Re_p > 500, quadratic term > 90 % of the gradient, the
    linear law alone off by > 10x); the sand case is Darcy's to 0.2 %."""
    fake = {"u_numeric": 1.0, "u_outside": 1.0, "steady_change": 0.0}
    for case in forch.HIGH_RE_CASES:
        r = forch.analyse({**fake, "phi_s": case[1], "dp_atm": case[2]}, case)
        assert r["re_p"] > 500.0 and r["quadratic_share"] > 0.9
        assert r["u_linear"] > 10.0 * r["u_exact"]
    for case in forch.LOW_RE_CASES:
        r = forch.analyse({**fake, "phi_s": case[1], "dp_atm": case[2]}, case)
        assert r["re_p"] < 0.2 and r["quadratic_share"] < 2e-3
        darcy = mpmice_darcy.exact_pore_velocity(case[1], case[2])
        # A q + B q^2 = A q_D: q / q_D - 1 = -B q^2 / G, the quadratic share, exactly
        assert r["u_exact"] / darcy - 1.0 == pytest.approx(-r["quadratic_share"], rel=1e-9)


# --------------------------------------------------------------------------- scene runs

@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.fixture(scope="module")
def column_results(tmp_path_factory, mpmice_exe):
    """The three cases of postproc/mpmice_forchheimer.py, run once for the module."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("MPMICE_EXE", str(mpmice_exe))
        results = forch.run_forchheimer(str(tmp_path_factory.mktemp("forchheimer")))
    forch.print_table(results)
    return {r["name"]: r for r in results}


def test_gravel_column_matches_quadratic_law(column_results):
    """Re_p = 1730 and 761: steady pore velocity in the column and Darcy flux outside within
    0.1 % of the closed-form root; steady to 1e-5 between the last two dumps."""
    for case in forch.HIGH_RE_CASES:
        r = column_results[case[0]]
        assert r["steady_change"] < 1e-5, r
        assert abs(r["rel_error"]) < HIGH_RE_TOLERANCE, r
        assert abs(r["flux_ratio"] - 1.0) < HIGH_RE_TOLERANCE, r


def test_sand_column_at_low_re_is_darcy(column_results):
    """Re_p = 0.1: the quadratic law's root to 1e-5 and eq. 77 (Kozeny-Carman) to 0.2 %, the
    share of the quadratic term (0.16 %)."""
    r = column_results[forch.LOW_RE_CASES[0][0]]
    assert abs(r["rel_error"]) < LOW_RE_TOLERANCE, r
    darcy = mpmice_darcy.exact_pore_velocity(r["phi_s"], r["dp_atm"])
    assert abs(r["u_numeric"] / darcy - 1.0) < 2e-3, r
    assert abs(r["flux_ratio"] - 1.0) < LOW_RE_TOLERANCE, r


def test_deformable_column_a180_b0_is_kozeny_carman(solver, tmp_path):
    """Terzaghi consolidation (deformable soil, 50 cells, to 0.05 s): 'forchheimer' with
    a = 180, b = 0 gives the 'kozeny_carman' pressures to 1e-9 of the load; Ergun's b = 1.75
    changes them (the coefficients reach the deformable solid's drag)."""
    base = [mpmice_terzaghi.NAMELIST, "--set", "&grid ncells = 1, 50, 1 /"]
    laws = {"kc": "drag_law = 'kozeny_carman'",
            "f180": "drag_law = 'forchheimer', forchheimer_a = 180, forchheimer_b = 0",
            "ergun": "drag_law = 'forchheimer', forchheimer_a = 180, forchheimer_b = 1.75"}
    pressure = {}
    for key, text in laws.items():
        out = str(tmp_path / key)
        run_mpmice(base + ["--set", f"&solid name='soil', {text} /",
                           "--set", f"&run end_time = 0.05, output_interval = 0.025, "
                                    f"output_dir = '{out}' /"], cwd=str(tmp_path))
        pressure[key] = read_run_dumps(out, "terzaghi", last=1)[-1]["cell"]["pressure"]
    load = np.max(pressure["kc"]) - np.min(pressure["kc"])
    assert load > 1e3
    assert np.max(np.abs(pressure["f180"] - pressure["kc"])) < 1e-9 * load
    assert np.max(np.abs(pressure["ergun"] - pressure["kc"])) > 1e-6 * load
