"""The measures of postproc.mpmice_crest_layer on synthetic input, without runs of mpmice (~1 s):
Byrne's densification replayed, the box's outflow from cell fluxes and from Darcy's law, the
affine shear strain, the buoyant overburden and the Kozeny-Carman conductivity."""
import math

import numpy as np
import pytest

from postproc import mpmice_crest_layer as cl


def test_replay_densification_follows_css_densify():
    """d eps_vd = a C_1 exp(-C_2 eps_vd / a) per half cycle above the threshold, C_2 = 0.4 / C_1
    by default, nothing at or below it, bounded by evd_max."""
    c1, a = 1.049, 2.0e-4
    evd = cl.replay_densification(np.array([a, a, 0.5e-4, a]), c1, threshold=1.0e-4)
    first = a * c1
    second = first + a * c1 * math.exp(-(0.4 / c1) * first / a)
    third_half = second + a * c1 * math.exp(-(0.4 / c1) * second / a)
    assert evd == pytest.approx([first, second, second, third_half], rel=1e-12)
    # per particle (rows), with a start value and a bound
    out = cl.replay_densification(np.array([[a, a], [0.5e-4, a]]), c1, threshold=1.0e-4,
                                  evd_max=2.5e-4, evd0=np.array([0.0, 1.0e-4]))
    assert out[0] == pytest.approx([first, 2.5e-4], rel=1e-12)
    second_row = 1.0e-4 + a * c1 * math.exp(-(0.4 / c1) * 1.0e-4 / a)
    assert out[1] == pytest.approx([1.0e-4, min(second_row, 2.5e-4)], rel=1e-12)


def test_box_outflow_of_cell_fluxes():
    """A uniform flux leaves nothing in an inner box; q_x = x (divergence 1) gives 1 per unit
    volume; a closed bottom (box from j = 0) under a uniform upward flux q gives q / height."""
    nx, ny, dx, dy = 12, 8, 0.1, 0.05
    x = (np.arange(nx) + 0.5) * dx
    ones = np.ones((nx, ny))
    box = (slice(3, 7), slice(2, 5))
    assert cl.box_outflow(0.3 * ones, -0.2 * ones, box, dx, dy) == pytest.approx(0.0, abs=1e-12)
    assert cl.box_outflow(x[:, None] * ones, 0.0 * ones, box, dx, dy) == pytest.approx(1.0, rel=1e-12)
    bottom = (slice(3, 7), slice(0, 3))
    assert cl.box_outflow(0.0 * ones, 2.0e-4 * ones, bottom, dx, dy) == pytest.approx(
        2.0e-4 / (3 * dy), rel=1e-12)


def test_darcy_box_outflow_and_gradient():
    """An excess pore pressure falling upward with gradient i gamma_w drives q = k i up: no net
    outflow of an inner box, k i / height from a box with a closed bottom, gradient i."""
    nx, ny, dx, dy, k, i = 10, 8, 0.1, 0.1, 1.3e-4, 0.8
    y = (np.arange(ny) + 0.5) * dy
    gw = cl.RHO_W * cl.G_ACC
    excess = np.broadcast_to(-i * gw * y[None, :], (nx, ny)).copy()
    kk = np.full((nx, ny), k)
    rate, grad = cl.darcy_box_outflow(excess, kk, (slice(2, 6), slice(2, 5)), dx, dy)
    assert rate == pytest.approx(0.0, abs=1e-15) and grad == pytest.approx(i, rel=1e-12)
    rate, grad = cl.darcy_box_outflow(excess, kk, (slice(2, 6), slice(0, 3)), dx, dy)
    assert rate == pytest.approx(k * i / (3 * dy), rel=1e-12) and grad == pytest.approx(i, rel=1e-12)


def test_affine_shear_and_half_range():
    rng = np.random.default_rng(1)
    x0, y0 = rng.uniform(0, 0.5, 50), rng.uniform(0.2, 0.5, 50)
    gamma = 3.0e-4
    assert cl.affine_shear(x0, y0, 0.01 + gamma * y0, 0.0 * y0) == pytest.approx(gamma, rel=1e-9)
    assert cl.affine_shear(x0, y0, 0.0 * x0, 0.5 * gamma * x0) == pytest.approx(0.5 * gamma, rel=1e-9)
    assert cl.half_range([1.0, -3.0, 2.0]) == pytest.approx(2.5)


def test_buoyant_overburden_and_kozeny_carman():
    """(rho_s - rho_w) phi g over the column above y_m, the cell holding y_m from y_m up; the
    conductivity of the 0.1 mm sand at n = 0.43 is docs/earthquake_liquefaction.md's 1.3e-4 m/s."""
    nx, ny, dy = 4, 10, 0.1
    attrs = {"ncells": [nx, ny, 1], "lower": [0.0, 0.0, 0.0], "dx": [0.1, dy, 0.1]}
    solid = np.zeros((nx, ny, 1))
    solid[:, :6, 0] = 0.57                        # sediment up to y = 0.6 m
    share = np.ones((nx, ny, 1))
    dump = {"attrs": attrs, "cell": {"solid_volume_fraction": solid,
                                     f"{cl.SEDIMENT}/volume_fraction": share}}
    got = cl.buoyant_overburden(dump, (slice(0, 4), slice(0, ny)), 0.35, 2650.0)
    assert got == pytest.approx((2650.0 - cl.RHO_W) * 0.57 * cl.G_ACC * 0.25, rel=1e-12)
    assert cl.kozeny_carman(1.0e-4, 0.43) == pytest.approx(1.3e-4, rel=0.03)


def test_side_shear_of_a_column():
    """tau on the right side and 0 on the left over a height H carry tau H / w off the base;
    the same tau on both sides carries nothing."""
    ys = np.arange(0.4, 2.0, 0.05)
    x = np.concatenate([np.full(ys.size, 5.0), np.full(ys.size, 5.6)])
    y = np.concatenate([ys, ys])
    tau = np.concatenate([np.zeros(ys.size), np.full(ys.size, 1000.0)])
    # bins of 0.1 m from 0.35 to 1.95 m hold particles; the one from 1.95 m holds none
    got = cl.side_shear(x, y, tau, 5.0, 5.6, 0.35, 2.05)
    assert got == pytest.approx(1000.0 * 1.6 / 0.6, rel=1e-12)
    assert cl.side_shear(x, y, np.full(x.size, 1000.0), 5.0, 5.6, 0.35, 2.05) == pytest.approx(0.0, abs=1e-9)


def _column(offset, body_gain=0.0):
    """Particles on a 0.05 m lattice across a column 0.6 m wide, 0.2 to 2.45 m high, whose total
    vertical stress follows the buoyant weight gamma' (top - y) plus a constant `offset` (a suction
    at the top when negative) plus body_gain (y_b - y) below y_b = 1.0 m; no side shear."""
    gamma, top = 9000.0, 2.45
    xs, ys = np.meshgrid(np.arange(5.525, 6.1, 0.05), np.arange(0.225, top, 0.05))
    x, y = xs.ravel(), ys.ravel()
    total = gamma * (top + 0.025 - y) + offset + body_gain * np.clip(1.0 - y, 0.0, None)
    return x, y, total, np.zeros_like(x), (lambda yy: gamma * (top + 0.025 - yy))


def test_column_balance_splits_top_and_body():
    """A column that carries its weight closes (0, 0); a suction s at its top shows as the same
    deficit at the monitor and below the top (body 0); an extra load in the body shows in the
    monitor's deficit only. Fails if the band, the weight or the split is wrong."""
    x, y, total, tau, over = _column(0.0)
    assert cl.column_balance(x, y, total, tau, 5.5, 6.1, 0.35, over) == pytest.approx((0.0, 0.0), abs=1e-6)
    x, y, total, tau, over = _column(-3000.0)
    got = cl.column_balance(x, y, total, tau, 5.5, 6.1, 0.35, over)
    assert got == pytest.approx((-3000.0, -3000.0), rel=1e-9)
    x, y, total, tau, over = _column(0.0, body_gain=-2000.0)
    dm, dt = cl.column_balance(x, y, total, tau, 5.5, 6.1, 0.35, over)
    assert dt == pytest.approx(0.0, abs=1e-6) and dm == pytest.approx(-2000.0 * 0.65, rel=1e-9)
    # shear on the sides enters as side_shear: tau on the right side only carries load off
    tau = np.where(np.abs(x - 6.075) < 0.01, -1000.0, 0.0)
    dm, _ = cl.column_balance(x, y, np.asarray(total), tau, 5.5, 6.1, 0.35, over)
    assert dm != pytest.approx(-2000.0 * 0.65, rel=1e-3)


def test_column_inertia():
    """sum m a_y over the particles above y_m between the sides per unit area."""
    x = np.array([5.6, 5.8, 6.0, 6.5, 5.8])
    y = np.array([1.0, 2.0, 0.5, 1.0, 0.1])
    m = np.array([2.0, 3.0, 4.0, 100.0, 100.0])
    a = np.array([1.0, -1.0, 0.5, 9.0, 9.0])
    got = cl.column_inertia(x, y, m, a, 5.5, 6.1, 0.35, 0.1)
    assert got == pytest.approx((2.0 - 3.0 + 2.0) / (0.6 * 0.1), rel=1e-12)
