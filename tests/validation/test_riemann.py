"""The exact Riemann solver of postproc/riemann.py (the reference of the Sod tests) checked
against independent values: Toro's star states for his five standard tests, the shock speeds
against the Rankine-Hugoniot conditions, and the rarefaction fans against their isentropic
invariants. No solver runs (~1 s)."""
import math

import numpy as np
import pytest

from postproc import riemann

GAMMA = 1.4

#: Toro, Riemann Solvers and Numerical Methods for Fluid Dynamics, 3rd ed., Table 4.1 (data:
#: left and right (rho, u, p)) and Table 4.3 (exact star values: p*, u*, rho*_L, rho*_R).
TORO_TESTS = {
    1: ((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), ("0.30313", "0.92745", "0.42632", "0.26557")),
    2: ((1.0, -2.0, 0.4), (1.0, 2.0, 0.4), ("0.00189", "0.00000", "0.02185", "0.02185")),
    3: ((1.0, 0.0, 1000.0), (1.0, 0.0, 0.01), ("460.894", "19.5975", "0.57506", "5.99924")),
    4: ((1.0, 0.0, 0.01), (1.0, 0.0, 100.0), ("46.0950", "-6.19633", "5.99242", "0.57511")),
    5: ((5.99924, 19.5975, 460.894), (5.99242, -6.19633, 46.0950),
        ("1691.64", "8.68975", "14.2823", "31.0426")),
}


def star_densities(left, right, gamma=GAMMA):
    """rho*_L and rho*_R: the sampled states just left and right of the contact."""
    _, u_star = riemann.star_state(left, right, gamma)
    eps = 1e-9 * max(1.0, abs(u_star))
    rho, _, _ = riemann.sample(left, right, np.array([u_star - eps, u_star + eps]), gamma)
    return rho[0], rho[1]


def printed_tolerance(text):
    """Half a unit in the last printed digit of a table value."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0**-decimals


@pytest.mark.parametrize("test", sorted(TORO_TESTS))
def test_star_state_matches_toro_table(test):
    """p*, u*, rho*_L, rho*_R of Toro's tests 1-5 to half a unit in the table's last printed
    digit (5 or 6 significant figures; test 5's data are themselves the rounded star states of
    tests 3 and 4, which moves its answers by up to 3e-6 relative: 5e-6 more there)."""
    left, right, expected = TORO_TESTS[test]
    p_star, u_star = riemann.star_state(left, right, GAMMA)
    rho_l, rho_r = star_densities(left, right)
    rel = 5e-6 if test == 5 else 0.0
    for name, value, text in zip(("p*", "u*", "rho*_L", "rho*_R"),
                                 (p_star, u_star, rho_l, rho_r), expected):
        ref = float(text)
        assert abs(value - ref) <= printed_tolerance(text) + rel * abs(ref), \
            (test, name, value, text)


def test_sod_star_state_module_check():
    """The module's own command-line check (Sod = Toro test 1) passes."""
    assert riemann.main() == 0


def conserved(rho, u, p, gamma=GAMMA):
    """(mass, momentum, energy) densities and their fluxes of a state."""
    energy = p / (gamma - 1.0) + 0.5 * rho * u * u
    return (np.array([rho, rho * u, energy]),
            np.array([rho * u, rho * u * u + p, u * (energy + p)]))


def locate_jump(left, right, lo, hi, gamma=GAMMA):
    """Similarity coordinate of the single discontinuity of the sampled density in (lo, hi),
    by bisection to round-off."""
    rho_lo = riemann.sample(left, right, np.array([lo]), gamma)[0][0]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if riemann.sample(left, right, np.array([mid]), gamma)[0][0] == rho_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("test", [1, 3, 4, 5])
def test_shock_speed_satisfies_rankine_hugoniot(test):
    """Every shock of tests 1, 3, 4, 5: the speed S where the sampled solution jumps satisfies
    S (U_pre - U_post) = F(U_pre) - F(U_post) for mass, momentum and energy (relative 1e-9 of
    the flux scale); the post-shock state is the star state."""
    left, right, _ = TORO_TESTS[test]
    p_star, u_star = riemann.star_state(left, right, GAMMA)
    shocks = []
    if p_star > right[2]:
        c_r = math.sqrt(GAMMA * right[2] / right[0])
        shocks.append((right, u_star, right[1] + 2.0 * (c_r + abs(right[1]) + abs(u_star)) + 10))
    if p_star > left[2]:
        c_l = math.sqrt(GAMMA * left[2] / left[0])
        shocks.append((left, left[1] - 2.0 * (c_l + abs(left[1]) + abs(u_star)) - 10, u_star))
    assert shocks, test
    for pre, lo, hi in shocks:
        speed = locate_jump(left, right, lo + 1e-12, hi - 1e-12)
        side = 1e-7 * max(1.0, abs(speed))
        probe = np.array([speed - side, speed + side])
        rho, u, p = riemann.sample(left, right, probe, GAMMA)
        k_post = 0 if pre is right else 1
        k_pre = 1 - k_post
        assert (rho[k_pre], u[k_pre], p[k_pre]) == pytest.approx(pre, rel=1e-12)
        assert p[k_post] == pytest.approx(p_star, rel=1e-12)
        assert u[k_post] == pytest.approx(u_star, rel=1e-12, abs=1e-12)
        q_pre, f_pre = conserved(rho[k_pre], u[k_pre], p[k_pre])
        q_post, f_post = conserved(rho[k_post], u[k_post], p[k_post])
        scale = np.abs(f_pre) + np.abs(f_post) + abs(speed) * (np.abs(q_pre) + np.abs(q_post))
        residual = speed * (q_pre - q_post) - (f_pre - f_post)
        assert np.all(np.abs(residual) <= 1e-9 * scale), (test, speed, residual / scale)


def test_rankine_hugoniot_check_detects_a_wrong_speed():
    """The check above fails for a shock speed 1 % off (Sod's right shock)."""
    left, right, _ = TORO_TESTS[1]
    speed = locate_jump(left, right, 1.0, 3.0)
    rho, u, p = riemann.sample(left, right, np.array([speed - 1e-7, speed + 1e-7]), GAMMA)
    q_pre, f_pre = conserved(rho[1], u[1], p[1])
    q_post, f_post = conserved(rho[0], u[0], p[0])
    wrong = 1.01 * speed
    residual = wrong * (q_pre - q_post) - (f_pre - f_post)
    scale = np.abs(f_pre) + np.abs(f_post) + abs(wrong) * (np.abs(q_pre) + np.abs(q_post))
    assert np.max(np.abs(residual) / scale) > 1e-3


@pytest.mark.parametrize("test", [1, 2, 3, 4])
def test_rarefaction_fan_is_isentropic(test):
    """Inside every rarefaction fan of tests 1-4 (200 points): the entropy p / rho^gamma and the
    Riemann invariant carried across the fan (u + 2c/(gamma-1) for a left fan, u - 2c/(gamma-1)
    for a right fan) equal their values ahead of the fan to 1e-12, the fan is self-similar
    (u - c = x/t in a left fan, u + c = x/t in a right fan), and its tail meets the star state."""
    left, right, _ = TORO_TESTS[test]
    p_star, u_star = riemann.star_state(left, right, GAMMA)
    fans = []
    if p_star <= left[2]:
        c_l = math.sqrt(GAMMA * left[2] / left[0])
        c_star = c_l * (p_star / left[2]) ** ((GAMMA - 1.0) / (2.0 * GAMMA))
        fans.append((left, -1.0, left[1] - c_l, u_star - c_star))
    if p_star <= right[2]:
        c_r = math.sqrt(GAMMA * right[2] / right[0])
        c_star = c_r * (p_star / right[2]) ** ((GAMMA - 1.0) / (2.0 * GAMMA))
        fans.append((right, 1.0, u_star + c_star, right[1] + c_r))
    assert fans, test
    for ahead, sign, head_or_tail_lo, hi in fans:
        s = np.linspace(head_or_tail_lo, hi, 202)[1:-1]
        rho, u, p = riemann.sample(left, right, s, GAMMA)
        c = np.sqrt(GAMMA * p / rho)
        c_ahead = math.sqrt(GAMMA * ahead[2] / ahead[0])
        entropy = ahead[2] / ahead[0] ** GAMMA
        assert np.max(np.abs(p / rho**GAMMA / entropy - 1.0)) < 1e-12, test
        invariant = ahead[1] - sign * 2.0 * c_ahead / (GAMMA - 1.0)
        scale = abs(ahead[1]) + c_ahead
        assert np.max(np.abs(u - sign * 2.0 * c / (GAMMA - 1.0) - invariant)) < 1e-12 * scale
        assert np.max(np.abs(u + sign * c - s)) < 1e-12 * scale
        assert np.all(np.diff(p) * sign > 0.0)      # pressure falls towards the star region
    # the fan's tail is continuous with the star state (test 1, left fan)
    if test == 1:
        _, tail = fans[0][2], fans[0][3]
        rho, u, p = riemann.sample(left, right, np.array([tail - 1e-9, tail + 1e-9]), GAMMA)
        assert p[0] == pytest.approx(p[1], rel=1e-7) and u[0] == pytest.approx(u[1], rel=1e-7)


def test_contact_carries_pressure_and_velocity():
    """Across the contact of tests 1-5 pressure and velocity are continuous (the star values)."""
    for left, right, _ in TORO_TESTS.values():
        p_star, u_star = riemann.star_state(left, right, GAMMA)
        eps = 1e-9 * max(1.0, abs(u_star))
        _, u, p = riemann.sample(left, right, np.array([u_star - eps, u_star + eps]), GAMMA)
        assert p == pytest.approx([p_star, p_star], rel=1e-14)
        assert u == pytest.approx([u_star, u_star], rel=1e-14, abs=1e-14)


def test_cell_average_of_a_uniform_region_is_the_state():
    """cell_average over cells entirely ahead of Sod's waves returns the initial states."""
    edges = np.array([0.0, 0.05, 0.1, 0.9, 0.95, 1.0])
    rho, u, p = riemann.cell_average(riemann.SOD_LEFT, riemann.SOD_RIGHT, 0.5, 0.1, edges)
    assert rho[0] == 1.0 and p[0] == 1.0 and u[0] == 0.0
    assert rho[-1] == 0.125 and p[-1] == pytest.approx(0.1, rel=1e-14) and u[-1] == 0.0
