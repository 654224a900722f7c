"""Viscosity and heat conduction of the ICE scene against exact solutions
(namelists/ice_shear_layer.nml: 1D periodic gas with a velocity step or a temperature step).

Usage:  python -m postproc.ice_diffusion [--out docs/validation] [--cells 32 64 128]

The transverse velocity (+U below x = 0.5, -U above) and the temperature (T0 below, T0 + dT above)
diffuse as square waves: q(x, t) = mean + sum_{n odd} (4 a / (n pi)) sin(2 pi n x)
exp(-D (2 pi n)^2 t) with D = nu = mu / rho for the velocity and D = alpha = k / (rho c_p) for
the temperature (constant pressure; c_p = gamma cv). Two runs per resolution so the exact
solutions hold: 'velocity' (uniform T = 300 K, so rho and nu are uniform) and 'temperature'
(no velocity, T0 = 300 K, dT = 0.01 K, so rho varies by 3e-5 only). Prints the relative L2
errors at t = 1 s and the observed orders; writes ice_diffusion.png.
"""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_shear_layer.nml")
RHO = 1.0e5 / (0.4 * 717.5 * 300.0)   # ideal gas at 1e5 Pa and 300 K [kg/m^3]
NU = 0.011612 / RHO                    # mu / rho [m^2/s]
ALPHA = 11.664 / (RHO * 1.4 * 717.5)   # k / (rho c_p) [m^2/s]


def square_wave(x: np.ndarray, t: float, amplitude: float, diffusivity: float,
                dx: float, terms: int = 4000) -> np.ndarray:
    """Cell averages of the diffusing square wave (+amplitude on (0, 0.5), -amplitude above)."""
    q = np.zeros_like(x)
    for n in range(1, 2 * terms, 2):
        k = 2.0 * math.pi * n
        # cell average of sin(k x) over [x - dx/2, x + dx/2]
        avg = np.sin(k * x) * math.sin(k * dx / 2) / (k * dx / 2)
        q += 4.0 * amplitude / (n * math.pi) * avg * math.exp(-diffusivity * k * k * t)
    return q


DT = 0.01     # K, temperature step of the 'temperature' case


def run(workdir: str, n: int, case: str, nranks: int = 1) -> dict:
    """Final dump of the 'velocity' or 'temperature' case with n cells."""
    out = os.path.join(workdir, f"shear_{case}_{n}_{nranks}")
    args = [NAMELIST, "--set", f"&grid ncells = {n}, 1, 1 /",
            "--set", f"&run output_dir = '{out}' /"]
    if case == "velocity":
        args += ["--set", "&fluid name = 'air', temperature = 300.0 /"]
    else:
        args += ["--set", f"&fluid name = 'air', temperature = {300.0 + DT}, "
                 "velocity = 0.0, 0.0, 0.0 /",
                 "--set", "&region material = 'air', lower = 0.0, 0.0, 0.0, "
                 "upper = 0.5, 1.0, 1.0, volume_fraction = 1.0, pressure = 1.0e5, "
                 "temperature = 300.0, velocity = 0.0, 0.0, 0.0 /"]
    run_mpmice(args, nranks=nranks, cwd=workdir)
    return read_dump(list_dumps(out, "shear")[-1])


def exact(dump: dict, case: str) -> np.ndarray:
    """Exact cell averages of the velocity or temperature of a dump."""
    x = cell_centres(dump)[0]
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    if case == "velocity":
        return square_wave(x, dump["time"], 1.0, NU, dx)
    return 300.0 + 0.5 * DT - square_wave(x, dump["time"], 0.5 * DT, ALPHA, dx)


def error(dump: dict, case: str) -> float:
    """Relative L2 error of the velocity, or of the temperature perturbation."""
    if case == "velocity":
        q = dump["cell"]["air/velocity_y"][:, 0, 0]
        return float(np.linalg.norm(q - exact(dump, case)) / np.linalg.norm(exact(dump, case)))
    q = dump["cell"]["air/temperature"][:, 0, 0] - (300.0 + 0.5 * DT)
    e = exact(dump, case) - (300.0 + 0.5 * DT)
    return float(np.linalg.norm(q - e) / np.linalg.norm(e))


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[32, 64, 128])
    args = parse_study_args(parser, argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for n in args.cells:
            dv = run(work, n, "velocity")
            dt = run(work, n, "temperature")
            rows.append((n, error(dv, "velocity"), error(dt, "temperature")))
    print("  cells   velocity L2 error   order   temperature L2 error   order")
    for i, (n, ev, et) in enumerate(rows):
        ov = math.log(rows[i - 1][1] / ev) / math.log(n / rows[i - 1][0]) if i else float("nan")
        ot = math.log(rows[i - 1][2] / et) / math.log(n / rows[i - 1][0]) if i else float("nan")
        print(f"{n:7d}   {ev:17.3e}   {ov:5.2f}   {et:20.3e}   {ot:5.2f}")
    plt = pyplot()
    x = cell_centres(dv)[0]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    axes[0].plot(x, exact(dv, "velocity"), "k-", label="exact")
    axes[0].plot(x, dv["cell"]["air/velocity_y"][:, 0, 0], "r.", label="ICE")
    axes[0].set_title("transverse velocity [m/s]")
    axes[0].legend()
    axes[1].plot(x, exact(dt, "temperature"), "k-")
    axes[1].plot(x, dt["cell"]["air/temperature"][:, 0, 0], "r.")
    axes[1].set_title("temperature [K]")
    fig.suptitle(f"viscous shear layer and conduction, {args.cells[-1]} cells, t = 1 s")
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "ice_diffusion.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
