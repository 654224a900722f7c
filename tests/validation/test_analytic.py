"""The analytic references of postproc/analytic.py against independent published values."""
import numpy as np

from postproc import analytic


def test_consolidation_coefficient_paper_values():
    """errata.md derived check: E = 10 MPa, nu = 0.3, n = 0.3, d = 1 mm, mu = 1 mPa s give
    c_v ~ 4.12 m^2/s."""
    cv = analytic.consolidation_coefficient(10e6, 0.3, 0.3, 1e-3, 1e-3)
    assert abs(cv - 4.12) < 0.01


def test_terzaghi_degree_textbook_values():
    """Classical table (e.g. Craig's Soil Mechanics): U = 50 % at T_v = 0.197, 90 % at 0.848,
    and U = sqrt(4 T_v / pi) for small T_v."""
    assert abs(analytic.terzaghi_degree_of_consolidation(0.197) - 0.5) < 2e-3
    assert abs(analytic.terzaghi_degree_of_consolidation(0.848) - 0.9) < 1e-3
    tv = 1e-3
    assert abs(analytic.terzaghi_degree_of_consolidation(tv) - np.sqrt(4 * tv / np.pi)) < 1e-6


def test_terzaghi_pressure_limits():
    """At early time the excess pressure equals the load away from the drained boundary, and
    its depth average is consistent with the degree of consolidation."""
    z = np.linspace(0.0, 1.0, 20001)
    p = analytic.terzaghi_excess_pressure(z, 1e-4, 1e4, terms=2000)
    assert abs(p[-1] - 1e4) < 1.0 and p[0] == 0.0
    for tv in (0.05, 0.3, 1.0):
        p = analytic.terzaghi_excess_pressure(z, tv, 1.0)
        mean = np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(z))
        assert abs((1.0 - mean) - analytic.terzaghi_degree_of_consolidation(tv)) < 1e-6


def test_darcy_velocity_matches_drag_balance():
    """errata E7/E11: with F = 10 phi/(1-phi)^2 the drag coefficient 180 phi^2 mu/(d^2 (1-phi))
    balances the pressure gradient n dp/L at the pore velocity of eq. 77."""
    phi, d, mu, dp, length = 0.66, 1e-3, 1e-3, 0.5 * 101325.0, 1.0
    u = analytic.darcy_pore_velocity(phi, d, mu, dp, length)
    drag_coefficient = 180.0 * phi**2 * mu / (d**2 * (1.0 - phi))
    assert abs(drag_coefficient * u - (1.0 - phi) * dp / length) < 1e-9 * dp
