"""The rigid-bed contact on a slope that is not aligned with the grid: the nodal contact normals'
angle error and a sliding block's acceleration (MPM, `&mpm rigid_contact = 'friction'`).

Usage:  python -m postproc.mpm_slope_contact [--cells 0.02 0.01 0.005] [--mu 0 0.41]
            [--angle 35] [--end 0.2] [--out DIR]

Scene (written here, dry, vertical gravity 9.81 m/s^2): a rigid bed seeded as the polygon below
the line y = y0 - tan(b) x (b = --angle, 35 deg as the Grilli test-17 slope, the bed's particles
a staircase along it, as `namelists/mpmice_grilli2017_2d.nml` seeds its bed), and an elastic
block 0.12 m long and 0.04 m thick (E = 1 MPa, 2000 kg/m^3, 2 x 2 particles per cell) seeded
as the rectangle lying on the line. A rigid block slides from rest at
a = g (sin b - mu cos b); the run's acceleration is the slope of a least-squares line through
the block's mass-weighted velocity along the slope over the dumps from t = 0.05 s (after the
first contact settles) to --end, and mu_eff = tan b - a / (g cos b) the friction the contact
acted with.

Normals: from the first dump's bed particles, grad m_i = sum_p m_p grad S_i(x_p) with the uGIMP
functions of the run (l_p = h/4), as `mpm_p2g` deposits it; the node's raw normal grad m / |grad m|
and the contact's normal (grad m smoothed over the node's 3 x 3 neighbours with the weights (1, 2,
1), `mpm_nodal.contact_normal`), each against the true outward normal (sin b, cos b), at the
contact nodes (both the bed and the block have mass there, as `mpm_nodal` applies the contact),
weighted by the block's nodal mass: the RMS, the mean and the largest of the signed error e
(negative: the normal tilted up-slope, so that a velocity along the true slope approaches the bed
at that node, with dv . n = |dv| sin e), the mean of |sin e| (the share of a sliding velocity the
contact sees as normal at a node) and the block mass share on approaching nodes (e < 0).
Prints one line per cell size and mu.
"""
from __future__ import annotations

import argparse
import math
import os
import tempfile

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice

G = 9.81
NAME = "slope"
LX, LY = 0.6, 0.5          # m: domain
Y0 = 0.45                  # m: the bed's surface at x = 0
X_BLOCK = 0.08             # m: the block's upper end along x on the line
LENGTH, THICK = 0.12, 0.04  # m


def namelist(h: float, mu: float, angle: float, end: float, out: str) -> str:
    """The scene's namelist text (module notes)."""
    t = math.tan(math.radians(angle))
    s, c = math.sin(math.radians(angle)), math.cos(math.radians(angle))
    x_toe = Y0 / t
    nx, ny = round(LX / h), round(LY / h)
    # block: the rectangle on the line from (xa, ya) down-slope by LENGTH, THICK along the normal
    xa, ya = X_BLOCK, Y0 - t * X_BLOCK
    xb, yb = xa + LENGTH * c, ya - LENGTH * s
    nxv, nyv = s * THICK, c * THICK
    px = [xa, xb, xb + nxv, xa + nxv]
    py = [ya, yb, yb + nyv, ya + nyv]
    fmt = lambda v: ", ".join(f"{x:.6f}" for x in v)  # noqa: E731
    return f"""&run
  name = '{NAME}'
  scene = 'mpm'
  output_dir = '{out}'
  end_time = {end}
  output_interval = 0.01
/
&grid
  ncells = {nx}, {ny}, 1
  lower = 0.0, 0.0, 0.0
  upper = {LX}, {LY}, {h}
/
&time
  cfl = 0.4
  dt_init = 1.0e-5
  dt_max = 1.0e-3
/
&numerics
  shape_function = 'gimp'
/
&physics
  gravity = 0.0, -{G}, 0.0
/
&mpm
  flip_fraction = 1.0
  rigid_contact = 'friction'
  contact_friction = {mu}
  contact_normal = 'smoothed'
/
&solid
  name = 'block'
  model = 'linear_elastic'
  density = 2000.0
  youngs_modulus = 1.0e6
  poisson_ratio = 0.3
  shape = 'polygon'
  npoints = 4
  polygon_x = {fmt(px)}
  polygon_y = {fmt(py)}
  lower = 0.0, 0.0, 0.0
  upper = {LX}, {LY}, {h}
  particles_per_cell = 2, 2, 1
/
&solid
  name = 'bed'
  model = 'rigid'
  density = 2650.0
  shape = 'polygon'
  npoints = 3
  polygon_x = 0.0, 0.0, {x_toe:.6f}
  polygon_y = 0.0, {Y0}, 0.0
  lower = 0.0, 0.0, 0.0
  upper = {LX}, {LY}, {h}
  particles_per_cell = 2, 2, 1
/
&boundary
  face = 'x+'
  solid = 'free'
/
&boundary
  face = 'y+'
  solid = 'free'
/
"""


def gimp(r: np.ndarray, h: float, lp: float) -> tuple[np.ndarray, np.ndarray]:
    """uGIMP weight and derivative d/dx_p at offsets r = x_p - x_i (modules/mpm/mpm_shape_gimp)."""
    a, s = np.abs(r), np.sign(r)
    w = np.zeros_like(r)
    dw = np.zeros_like(r)
    m1 = a < lp
    m2 = (a >= lp) & (a < h - lp)
    m3 = (a >= h - lp) & (a < h + lp)
    w[m1] = 1 - (r[m1] ** 2 + lp**2) / (2 * h * lp)
    dw[m1] = -r[m1] / (h * lp)
    w[m2] = 1 - a[m2] / h
    dw[m2] = -s[m2] / h
    w[m3] = (h + lp - a[m3]) ** 2 / (4 * h * lp)
    dw[m3] = -s[m3] * (h + lp - a[m3]) / (2 * h * lp)
    return w, dw


def deposit(x, y, m, h, nx, ny):
    """(nodal mass, grad m x, grad m y) on the (nx+1, ny+1) nodes from particles at (x, y)."""
    lp = h / 4
    mass = np.zeros((nx + 1, ny + 1))
    gx = np.zeros_like(mass)
    gy = np.zeros_like(mass)
    i0 = np.rint(x / h).astype(int)
    j0 = np.rint(y / h).astype(int)
    for di in (-1, 0, 1):
        i = i0 + di
        wx, dwx = gimp(x - i * h, h, lp)
        for dj in (-1, 0, 1):
            j = j0 + dj
            wy, dwy = gimp(y - j * h, h, lp)
            ok = (i >= 0) & (i <= nx) & (j >= 0) & (j <= ny)
            np.add.at(mass, (i[ok], j[ok]), (m * wx * wy)[ok])
            np.add.at(gx, (i[ok], j[ok]), (m * dwx * wy)[ok])
            np.add.at(gy, (i[ok], j[ok]), (m * wx * dwy)[ok])
    return mass, gx, gy


def normal_errors(dump: dict, h: float, angle: float, smoothed: bool) -> dict[str, float]:
    """Angle errors [deg] of the bed's node normals where the block has mass (module notes), of
    the nodal grad m or (`smoothed`) of the contact's normal, grad m smoothed over 3 x 3 nodes."""
    nx, ny = round(LX / h), round(LY / h)
    b, k = dump["particles"]["bed"], dump["particles"]["block"]
    mb, gx, gy = deposit(b["x"], b["y"], b["mass"], h, nx, ny)
    mk, _, _ = deposit(k["x"], k["y"], k["mass"], h, nx, ny)
    if smoothed:
        gx, gy = smooth(gx), smooth(gy)
    on = (mk > 0) & (mb > 0) & (np.hypot(gx, gy) > 0)
    w = mk[on] / mk[on].sum()
    true = math.radians(angle)
    # signed angle of the node normal from the true one, positive toward +x (down-slope)
    err = np.angle(np.exp(1j * (np.arctan2(gx[on], gy[on]) - true)))
    return {"rms": math.degrees(math.sqrt(np.sum(w * err**2))),
            "mean": math.degrees(np.sum(w * err)),
            "max": math.degrees(np.max(np.abs(err))),
            "sin": float(np.sum(w * np.abs(np.sin(err)))),
            "approach": float(np.sum(w[err < 0])),
            "nodes": int(on.sum())}


def smooth(g: np.ndarray) -> np.ndarray:
    """g summed over each node's 3 x 3 neighbours with the weights (1, 2, 1) per direction, the
    neighbours outside the grid left out (`mpm_nodal.contact_normal`)."""
    p = np.pad(g, 1)
    out = np.zeros_like(g)
    wts = (1.0, 2.0, 1.0)
    for a in range(3):
        for b in range(3):
            out += wts[a] * wts[b] * p[a:a + g.shape[0], b:b + g.shape[1]]
    return out


def acceleration(dumps: list[dict], angle: float, t0: float = 0.05) -> float:
    """Slope of the block's mass-weighted velocity along the slope against time, t >= t0."""
    a = math.radians(angle)
    along = np.array([math.cos(a), -math.sin(a)])
    ts, vs = [], []
    for d in dumps:
        if d["time"] < t0 - 1e-9:
            continue
        k = d["particles"]["block"]
        m = k["mass"]
        ts.append(d["time"])
        v = along[0] * k["velocity_x"] + along[1] * k["velocity_y"]
        vs.append(float(np.sum(m * v) / m.sum()))
    return float(np.polyfit(ts, vs, 1)[0])


def measure(work: str, h: float, mu: float, angle: float = 35.0, end: float = 0.2) -> dict:
    """Run the scene in `work` and return {raw, contact (normal_errors), a, exact, mu_eff}."""
    b = math.radians(angle)
    out = os.path.join(work, f"slope_{h:g}_{mu:g}")
    nml = os.path.join(work, f"slope_{h:g}_{mu:g}.nml")
    os.makedirs(work, exist_ok=True)
    with open(nml, "w", encoding="utf-8") as f:
        f.write(namelist(h, mu, angle, end, out))
    run_mpmice([nml], cwd=work)
    dumps = [read_dump(p) for p in list_dumps(out, NAME)]
    a = acceleration(dumps, angle)
    return {"raw": normal_errors(dumps[0], h, angle, smoothed=False),
            "contact": normal_errors(dumps[0], h, angle, smoothed=True),
            "a": a, "exact": G * (math.sin(b) - mu * math.cos(b)),
            "mu_eff": math.tan(b) - a / (G * math.cos(b))}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cells", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    parser.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.41])
    parser.add_argument("--angle", type=float, default=35.0)
    parser.add_argument("--end", type=float, default=0.2)
    parser.add_argument("--out", default=None, help="keep the runs under this folder")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        work = args.out or tmp
        print(f"{'':19} {'grad m (raw)':-^33} {'contact normal':-^27}")
        print(f"{'h [m]':>7} {'mu':>5} {'nodes':>5} {'rms':>6} {'mean':>6} {'max':>6} {'|sin|':>6}"
              f" {'appr':>5} {'rms':>6} {'mean':>6} {'max':>6} {'|sin|':>6}"
              f" {'a [m/s2]':>9} {'exact':>7} {'mu_eff':>7}")
        for h in args.cells:
            for mu in args.mu:
                r = measure(work, h, mu, args.angle, args.end)
                e, es = r["raw"], r["contact"]
                print(f"{h:7.3f} {mu:5.2f} {e['nodes']:5d} {e['rms']:6.2f} {e['mean']:6.2f}"
                      f" {e['max']:6.1f} {e['sin']:6.3f} {e['approach']:5.2f}"
                      f" {es['rms']:6.2f} {es['mean']:6.2f} {es['max']:6.1f} {es['sin']:6.3f}"
                      f" {r['a']:9.3f} {r['exact']:7.3f} {r['mu_eff']:7.3f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
