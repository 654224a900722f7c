"""Exact solution of the Riemann problem for the 1D Euler equations of an ideal gas.

Follows E. F. Toro, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, 3rd ed., ch. 4:
the star-region pressure is the root of f(p) = f_L(p) + f_R(p) + (u_R - u_L) (eqs. 4.5-4.7),
found by Newton iteration from the two-rarefaction guess (eq. 4.46); the solution is then sampled
along x/t (section 4.5, Fig. 4.14). States are (rho, u, p).

Usage:  python -m postproc.riemann   (prints the Sod star state and a self-check)
"""
from __future__ import annotations

import math

import numpy as np


def _f_and_df(p: float, rho: float, pk: float, ck: float, gamma: float) -> tuple[float, float]:
    """Toro eq. 4.6/4.7 (shock branch for p > pk, rarefaction branch otherwise) and its derivative."""
    if p > pk:
        a = 2.0 / ((gamma + 1.0) * rho)
        b = (gamma - 1.0) / (gamma + 1.0) * pk
        root = math.sqrt(a / (p + b))
        return (p - pk) * root, root * (1.0 - 0.5 * (p - pk) / (b + p))
    ratio = p / pk
    f = 2.0 * ck / (gamma - 1.0) * (ratio ** ((gamma - 1.0) / (2.0 * gamma)) - 1.0)
    df = 1.0 / (rho * ck) * ratio ** (-(gamma + 1.0) / (2.0 * gamma))
    return f, df


def star_state(left, right, gamma: float = 1.4, tol: float = 1e-14) -> tuple[float, float]:
    """Pressure and velocity in the star region (Toro eqs. 4.5, 4.9) for states (rho, u, p)."""
    rl, ul, pl = left
    rr, ur, pr = right
    cl = math.sqrt(gamma * pl / rl)
    cr = math.sqrt(gamma * pr / rr)
    if 2.0 * (cl + cr) / (gamma - 1.0) <= ur - ul:
        raise ValueError("vacuum is generated: the exact solver does not handle it")
    z = (gamma - 1.0) / (2.0 * gamma)
    p = ((cl + cr - 0.5 * (gamma - 1.0) * (ur - ul)) / (cl / pl ** z + cr / pr ** z)) ** (1.0 / z)
    for _ in range(100):
        fl, dfl = _f_and_df(p, rl, pl, cl, gamma)
        fr, dfr = _f_and_df(p, rr, pr, cr, gamma)
        p_new = max(p - (fl + fr + ur - ul) / (dfl + dfr), tol)
        change = 2.0 * abs(p_new - p) / (p_new + p)
        p = p_new
        if change < tol:
            break
    fl, _ = _f_and_df(p, rl, pl, cl, gamma)
    fr, _ = _f_and_df(p, rr, pr, cr, gamma)
    return p, 0.5 * (ul + ur) + 0.5 * (fr - fl)


def sample(left, right, s: np.ndarray, gamma: float = 1.4):
    """(rho, u, p) arrays at the similarity coordinates ``s = (x - x0)/t`` (Toro section 4.5)."""
    rl, ul, pl = left
    rr, ur, pr = right
    cl = math.sqrt(gamma * pl / rl)
    cr = math.sqrt(gamma * pr / rr)
    ps, us = star_state(left, right, gamma)
    g1 = (gamma - 1.0) / (gamma + 1.0)
    s = np.asarray(s, dtype=float)
    rho = np.empty_like(s)
    u = np.empty_like(s)
    p = np.empty_like(s)
    for n, x in enumerate(s.flat):
        if x <= us:  # left of the contact
            if ps > pl:  # left shock
                rs = rl * (ps / pl + g1) / (g1 * ps / pl + 1.0)
                speed = ul - cl * math.sqrt((gamma + 1.0) / (2.0 * gamma) * ps / pl
                                            + (gamma - 1.0) / (2.0 * gamma))
                state = (rl, ul, pl) if x <= speed else (rs, us, ps)
            else:  # left rarefaction
                cs = cl * (ps / pl) ** ((gamma - 1.0) / (2.0 * gamma))
                head, tail = ul - cl, us - cs
                if x <= head:
                    state = (rl, ul, pl)
                elif x >= tail:
                    state = (rl * (ps / pl) ** (1.0 / gamma), us, ps)
                else:
                    c = 2.0 / (gamma + 1.0) * (cl + 0.5 * (gamma - 1.0) * (ul - x))
                    state = (rl * (c / cl) ** (2.0 / (gamma - 1.0)),
                             2.0 / (gamma + 1.0) * (cl + 0.5 * (gamma - 1.0) * ul + x),
                             pl * (c / cl) ** (2.0 * gamma / (gamma - 1.0)))
        else:  # right of the contact
            if ps > pr:  # right shock
                rs = rr * (ps / pr + g1) / (g1 * ps / pr + 1.0)
                speed = ur + cr * math.sqrt((gamma + 1.0) / (2.0 * gamma) * ps / pr
                                            + (gamma - 1.0) / (2.0 * gamma))
                state = (rr, ur, pr) if x >= speed else (rs, us, ps)
            else:  # right rarefaction
                cs = cr * (ps / pr) ** ((gamma - 1.0) / (2.0 * gamma))
                head, tail = ur + cr, us + cs
                if x >= head:
                    state = (rr, ur, pr)
                elif x <= tail:
                    state = (rr * (ps / pr) ** (1.0 / gamma), us, ps)
                else:
                    c = 2.0 / (gamma + 1.0) * (cr - 0.5 * (gamma - 1.0) * (ur - x))
                    state = (rr * (c / cr) ** (2.0 / (gamma - 1.0)),
                             2.0 / (gamma + 1.0) * (-cr + 0.5 * (gamma - 1.0) * ur + x),
                             pr * (c / cr) ** (2.0 * gamma / (gamma - 1.0)))
        rho.flat[n], u.flat[n], p.flat[n] = state
    return rho, u, p


def cell_average(left, right, x0: float, t: float, edges: np.ndarray, gamma: float = 1.4,
                 points: int = 64):
    """Cell averages of (rho, u, p) over cells with the given edges (midpoint rule, ``points``
    sub-samples per cell), for the comparison of finite-volume results."""
    edges = np.asarray(edges, dtype=float)
    frac = (np.arange(points) + 0.5) / points
    xs = edges[:-1, None] + frac[None, :] * np.diff(edges)[:, None]
    rho, u, p = sample(left, right, (xs - x0) / t, gamma)
    return rho.mean(axis=1), u.mean(axis=1), p.mean(axis=1)


SOD_LEFT = (1.0, 0.0, 1.0)
SOD_RIGHT = (0.125, 0.0, 0.1)


def main() -> int:
    ps, us = star_state(SOD_LEFT, SOD_RIGHT)
    print(f"Sod star state: p* = {ps:.6f}, u* = {us:.6f} (Toro Table 4.3: 0.30313, 0.92745)")
    return 0 if abs(ps - 0.30313) < 1e-5 and abs(us - 0.92745) < 1e-5 else 1


if __name__ == "__main__":
    raise SystemExit(main())
