"""A saturated sand block sliding on a rigid 45 deg slope under water (coupled scene with
`&mpm rigid_contact = 'friction'`, namelists/mpmice_slide_block_2d.nml), against the drained
rigid block: a = g (1 - rho_w / rho_sat) (sin 45 - mu cos 45), reduced by the water's added
mass (the same factor for every mu, so a(mu) / a(0) = 1 - mu cot 45 holds without it).

Usage:  python -m postproc.mpmice_slide_block [--mu 0 0.2 0.4] [--fluid water|air] [--out DIR]

With --fluid air (namelists/mpmice_slide_block_air_2d.nml) the dry block slides in air: no
buoyancy, no added mass, a = g (sin 45 - mu cos 45).

The block's displacement along the slope is its mass-weighted mean particle position projected
on t = (1, -1) / sqrt 2; the acceleration is the least-squares fit of s = a t^2 / 2 over the
dumps (it starts at rest).
"""
from __future__ import annotations

import argparse
import os
import tempfile

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELISTS = {"water": os.path.join(ROOT, "namelists", "mpmice_slide_block_2d.nml"),
             "air": os.path.join(ROOT, "namelists", "mpmice_slide_block_air_2d.nml")}
NAME = "slide"
G = 9.81
THETA = np.radians(45.0)
RHO_W = 999.8
RHO_SAT = 0.6 * 2650.0 + 0.4 * RHO_W
TANGENT = np.array([1.0, -1.0]) / np.sqrt(2.0)


def drained_acceleration(mu: float, fluid: str = "water") -> float:
    """a [m/s^2] of a drained rigid block of saturated density in still water (no added mass);
    in air, the rigid block's g (sin - mu cos)."""
    buoyancy = 1.0 - RHO_W / RHO_SAT if fluid == "water" else 1.0
    return max(0.0, G * buoyancy * (np.sin(THETA) - mu * np.cos(THETA)))


def masses(dump: dict) -> dict[str, float]:
    """Total mass [kg] of the fluid (cells) and of the block and bed (particles)."""
    dv = float(np.prod(dump["attrs"]["dx"]))
    out = {key.split("/")[0]: float(field.sum() * dv) for key, field in dump["cell"].items()
           if key.endswith("/density")}
    for name in ("block", "bed"):
        out[name] = float(dump["particles"][name]["mass"].sum())
    return out


def history(out: str) -> tuple[np.ndarray, np.ndarray, list[dict]]:
    """(time, displacement along the slope, dumps) of one run."""
    dumps = [read_dump(p) for p in list_dumps(out, NAME)]
    t, s = [], []
    x0 = None
    for d in dumps:
        b = d["particles"]["block"]
        x = np.array([np.average(b["x"], weights=b["mass"]),
                      np.average(b["y"], weights=b["mass"])])
        x0 = x if x0 is None else x0
        t.append(d["time"])
        s.append(float(np.dot(x - x0, TANGENT)))
    return np.array(t), np.array(s), dumps


def fitted_acceleration(t: np.ndarray, s: np.ndarray) -> float:
    """Least-squares a of s = a t^2 / 2."""
    q = 0.5 * t**2
    return float(np.dot(q, s) / np.dot(q, q))


def run(workdir: str, mu: float, extra=(), fluid: str = "water", nranks: int = 1) -> tuple:
    """history of one run with friction coefficient mu."""
    out = os.path.join(workdir, f"slide_{fluid}_{mu:g}_{nranks}")
    run_mpmice([NAMELISTS[fluid], "--set", f"&run output_dir = '{out}' /",
                "--set", f"&mpm contact_friction = {mu} /", *extra], nranks=nranks, cwd=workdir,
               timeout=900)
    return history(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.2, 0.4])
    parser.add_argument("--fluid", default="water", choices=sorted(NAMELISTS))
    parser.add_argument("--end", type=float, default=None, help="end time [s]")
    parser.add_argument("--out", default=None, help="keep the runs here")
    args = parser.parse_args(argv)
    work = args.out or tempfile.mkdtemp(prefix="slide_")
    os.makedirs(work, exist_ok=True)
    a0 = None
    for mu in args.mu:
        extra = ["--set", f"&run end_time = {args.end} /"] if args.end else []
        t, s, dumps = run(work, mu, extra, args.fluid)
        a = fitted_acceleration(t, s)
        m0, m1 = masses(dumps[0]), masses(dumps[-1])
        dm = max(abs(m1[k] / m0[k] - 1.0) for k in m0)
        a0 = a if mu == 0.0 else a0
        ratio = f", a/a(0) = {a / a0:.4f} (exact {1 - mu / np.tan(THETA):.4f})" if a0 else ""
        ref = drained_acceleration(mu, args.fluid)
        print(f"mu = {mu:g}: a = {a:.4f} m/s^2, drained block {ref:.4f} "
              f"({a / ref:.4f}){ratio}; s(t_end) = {s[-1]:.5f} m; "
              f"max mass change {dm:.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
