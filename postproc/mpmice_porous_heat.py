"""Heat conduction through a rigid water-saturated porous column (MPMICE heat of both phases:
conduction in the fluid and the solid, implicit fluid-solid exchange, increments to the particles).

Usage:  python -m postproc.mpmice_porous_heat [--out docs/validation] [--cells 10 20 40 80]

Scene namelists/mpmice_porous_conduction_1d.nml: 1 m along x, both phases at T0 = 283.15 K, the
x- face held at T0 + 1 K and the x+ face at T0 from t = 0. At local thermal equilibrium the
mixture obeys (rho c)_m dT/dt = k_m d2T/dx2 with k_m = n k_f + phi_s k_s and
(rho c)_m = n rho_f c_f + phi_s rho_s c_s, whose solution is
  T = T0 + dT (1 - x/L) - sum_k (2 dT / (k pi)) sin(k pi x / L) exp(-alpha_m (k pi / L)^2 t).
Compares the fluid and the solid cell temperatures of every dump after t = 0 (max and relative
L2 error against dT; the fluid-solid difference), the observed order over the resolutions, and
writes mpmice_porous_heat.csv / .png.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_porous_conduction_1d.nml")
NAME = "porous_conduction"
FLUID, SOLID = "water", "skeleton"
T0, DT, LENGTH = 283.15, 1.0, 1.0
RHO_F, C_F, K_F = 999.8, 4181.0, 0.598
RHO_S, C_S, K_S, PHI_S = 2500.0, 835.0, 0.4, 0.6
POROSITY = 1.0 - PHI_S
K_M = POROSITY * K_F + PHI_S * K_S
RHO_C_M = POROSITY * RHO_F * C_F + PHI_S * RHO_S * C_S
ALPHA_M = K_M / RHO_C_M                                  # m^2/s


def exact(x: np.ndarray, t: float, terms: int = 2000) -> np.ndarray:
    """Mixture temperature [K] at positions x [m] and time t [s] (series above)."""
    k = np.arange(1, terms + 1)[:, None]
    series = (2.0 * DT / (k * np.pi)) * np.sin(k * np.pi * x[None, :] / LENGTH) * \
        np.exp(-ALPHA_M * (k * np.pi / LENGTH)**2 * t)
    return T0 + DT * (1.0 - x / LENGTH) - series.sum(axis=0)


def errors(dump: dict) -> dict:
    """Errors of one dump against `exact`, in units of dT."""
    x, _, _ = cell_centres(dump)
    ref = exact(x, dump["time"])
    tf = dump["cell"][f"{FLUID}/temperature"][:, 0, 0]
    ts = dump["cell"][f"{SOLID}/temperature"][:, 0, 0]
    return {"time": dump["time"],
            "max_fluid": float(np.max(np.abs(tf - ref))) / DT,
            "max_solid": float(np.max(np.abs(ts - ref))) / DT,
            "l2_fluid": float(np.sqrt(np.mean((tf - ref)**2))) / DT,
            "phase_difference": float(np.max(np.abs(tf - ts))) / DT}


def run(workdir: str, cells: int, nranks: int = 1, extra=()) -> list[dict]:
    """Dumps of one run (after t = 0) with `cells` cells."""
    out = os.path.join(workdir, f"conduction_{cells}")
    run_mpmice([NAMELIST, "--set", f"&grid ncells = {cells}, 1, 1 /",
                "--set", f"&run output_dir = '{out}' /", *extra], nranks=nranks, cwd=workdir)
    return [read_dump(p) for p in list_dumps(out, NAME)][1:]


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[10, 20, 40, 80])
    args = parse_study_args(parser, argv)
    rows, last = [], {}
    with tempfile.TemporaryDirectory() as work:
        for n in args.cells:
            dumps = run(work, n)
            for dump in dumps:
                rows.append((n, errors(dump)))
            last[n] = dumps[-1]
    print(" cells        t [s]  max err fluid  max err solid   L2 fluid  |Tf - Ts|")
    for n, e in rows:
        print(f"{n:6d} {e['time']:12.4g} {e['max_fluid']:14.3e} {e['max_solid']:14.3e} "
              f"{e['l2_fluid']:10.3e} {e['phase_difference']:10.2e}")
    final = [(n, e) for n, e in rows if e["time"] == rows[-1][1]["time"]]
    for (n1, e1), (n2, e2) in zip(final, final[1:]):
        order = np.log(e1["l2_fluid"] / e2["l2_fluid"]) / np.log(n2 / n1)
        print(f"observed order {n1} -> {n2} cells (L2, t = {e2['time']:.3g} s): {order:.2f}")
    with open(os.path.join(args.out, "mpmice_porous_heat.csv"), "w") as f:
        f.write("cells,time,max_fluid,max_solid,l2_fluid,phase_difference\n")
        for n, e in rows:
            f.write(f"{n},{e['time']:.6g},{e['max_fluid']:.6g},{e['max_solid']:.6g},"
                    f"{e['l2_fluid']:.6g},{e['phase_difference']:.6g}\n")
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    xs = np.linspace(0.0, LENGTH, 400)
    ax.plot(xs, exact(xs, last[max(last)]["time"]) - T0, "k-", lw=0.8, label="series solution")
    for n, dump in last.items():
        x, _, _ = cell_centres(dump)
        ax.plot(x, dump["cell"][f"{FLUID}/temperature"][:, 0, 0] - T0, "o", ms=3,
                label=f"{n} cells, fluid, t = {dump['time']:.3g} s")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("T - T0 [K]")
    ax.legend(fontsize=7)
    ax.set_title("porous column conduction: cells vs series solution", fontsize=9)
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpmice_porous_heat.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
