"""Water column at rest under air, under gravity (ICE scene, namelists/ice_water_column.nml).

Usage:  python -m postproc.ice_water_column [--out docs/validation] [--ny 1] [--nranks 1]

Runs 1000 steps of 1 ms (1D: 50 cells along the vertical x axis; --ny 8 gives the 2D version),
prints the largest velocity of each fluid after the run, the largest relative difference of the
pressure from the exact hydrostatic profile (isothermal ideal-gas air over linear water, errata
E3) at t = 0 and at the end, and writes ice_water_column.png (pressure and its error).
"""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_water_column.nml")
G = 9.81
P_TOP = 101325.0
INTERFACE = 0.6          # m
TOP = 1.0                # m
T = 293.15               # K
R_AIR = 0.4 * 717.5      # (gamma - 1) cv
RHO_REF, T_REF, K_WATER, ALPHA = 999.8, 283.15, 2.0e9, 0.18


def exact_pressure(x: np.ndarray) -> np.ndarray:
    """Hydrostatic pressure [Pa] at heights x: isothermal air above the interface, linear water
    (rho = rho_ref - alpha (T - T_ref) + (p - p_ref) rho_ref / K) below it."""
    x = np.asarray(x, dtype=float)
    p_air = P_TOP * np.exp(G * (TOP - x) / (R_AIR * T))
    p_i = P_TOP * math.exp(G * (TOP - INTERFACE) / (R_AIR * T))
    c = RHO_REF / K_WATER
    rho0 = RHO_REF - ALPHA * (T - T_REF)
    q_i = rho0 + (p_i - P_TOP) * c
    p_water = P_TOP + (q_i * np.exp(c * G * (INTERFACE - x)) - rho0) / c
    return np.where(x > INTERFACE, p_air, p_water)


def run(workdir: str, ny: int = 1, nranks: int = 1, steps: int = 1000) -> tuple[dict, dict]:
    """First and last dump of a run of `steps` steps of 1 ms."""
    out = os.path.join(workdir, f"column_{ny}_{nranks}")
    run_mpmice([NAMELIST, "--set", f"&grid ncells = 50, {ny}, 1 /",
                "--set", f"&run output_dir = '{out}', end_time = {steps * 1e-3} /"],
               nranks=nranks, cwd=workdir)
    dumps = list_dumps(out, "column")
    return read_dump(dumps[0]), read_dump(dumps[-1])


def measures(first: dict, last: dict) -> dict:
    """Largest speed per fluid and relative pressure errors against the exact profile."""
    x = cell_centres(last)[0][:, None, None]
    exact = exact_pressure(x)
    result = {"steps": last["step"]}
    for fluid in ("air", "water"):
        speed = np.zeros_like(last["cell"][f"{fluid}/velocity_x"])
        for comp in ("x", "y", "z"):
            speed = np.maximum(speed, np.abs(last["cell"][f"{fluid}/velocity_{comp}"]))
        result[f"max_speed_{fluid}"] = float(np.max(speed))
    for name, dump in (("initial", first), ("final", last)):
        result[f"pressure_error_{name}"] = float(np.max(np.abs(dump["cell"]["pressure"] / exact
                                                               - 1.0)))
    result["pressure_change"] = float(np.max(np.abs(last["cell"]["pressure"]
                                                    / first["cell"]["pressure"] - 1.0)))
    return result


def plot(last: dict, path: str, title: str) -> None:
    """Pressure profile and its relative error against the exact profile."""
    plt = pyplot()
    x = cell_centres(last)[0]
    p = last["cell"]["pressure"][:, 0, 0]
    fine = np.linspace(0.0, 1.0, 1001)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    axes[0].plot(exact_pressure(fine), fine, "k-", lw=1, label="exact")
    axes[0].plot(p, x, "r.", ms=4, label="ICE")
    axes[0].set_xlabel("pressure [Pa]")
    axes[0].set_ylabel("height x [m]")
    axes[0].legend()
    axes[1].plot(p / exact_pressure(x) - 1.0, x, "b.-", ms=3)
    axes[1].set_xlabel("relative pressure error")
    fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--ny", type=int, default=1)
    parser.add_argument("--nranks", type=int, default=1)
    args = parse_study_args(parser, argv)
    with tempfile.TemporaryDirectory() as work:
        first, last = run(work, args.ny, args.nranks)
    m = measures(first, last)
    for key, value in m.items():
        print(f"{key:24s} {value:.3e}" if isinstance(value, float) else f"{key:24s} {value}")
    tag = "ice_water_column" if args.ny == 1 else "ice_water_column_2d"
    plot(last, os.path.join(args.out, f"{tag}.png"),
         f"water under air at rest, 50 x {args.ny} cells, {m['steps']} steps: "
         f"max speed {max(m['max_speed_air'], m['max_speed_water']):.1e} m/s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
