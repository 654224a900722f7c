"""Steady water flow through a rigid porous column (MPMICE, paper eq. 77, Fig. 4): pore velocity
against the Carman-Kozeny/Darcy solution for 5 solid fractions x 3 pressure drops.

Usage:  python -m postproc.mpmice_darcy [--out docs/validation] [--nranks 1]

Scene namelists/mpmice_darcy_1d.nml: a 2 m channel along x (20 cells) full of water, a rigid
porous column on 0.5 <= x <= 1.5 m (L = 1 m, grain size d = 1 mm, Kozeny-Carman drag), open ends
at p_ref + dp and p_ref (1 atm = 101325 Pa, errata E1). Exact steady intrinsic (pore) velocity,
eq. 77 (errata E11): U_f = (1/n) K dp / L, K = d^2 (1 - phi_s)^3 / (180 mu phi_s^2), n = 1 - phi_s
(the Darcy flux n U_f is the velocity outside the column). Runs phi_s in {0.6, 0.62, 0.66, 0.68,
0.7} x dp in {0.25, 0.5, 1} atm (--set on the solid's porosity and the x- face pressure); the
numeric U_f is the mean of /cell/water/velocity_x (the ICE velocity is the pore velocity) over the
cells whose centres lie inside the column, in the final dump; its relative change against the
previous dump measures how steady it is. Every cell is compared too (the column mean would hide
an odd-even pattern, whose pairs cancel): each cell's velocity against U_f inside the column and
n U_f outside, the largest over all cells and over the cells away from the column's two ends,
and the largest change of a cell between the last two dumps. Prints a table and the largest
relative error; writes
mpmice_darcy.png (U_f against dp, exact lines and numeric markers per phi_s) and mpmice_darcy.csv.
"""
from __future__ import annotations

import os

import numpy as np

from postproc.analytic import darcy_pore_velocity
from postproc.figures import pyplot, run_study, save_figure
from postproc.mpmice_io import cell_centres, read_run_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_darcy_1d.nml")
NAME = "darcy"
ATM = 101325.0                      # Pa (errata E1)
P_REF = 101325.0                    # Pa, the x+ face
GRAIN, MU = 1.0e-3, 1.0e-3          # m, Pa s
COLUMN = (0.5, 1.5)                 # m
LENGTH = COLUMN[1] - COLUMN[0]
FLUID, SOLID = "water", "porous"
SOLID_FRACTIONS = (0.6, 0.62, 0.66, 0.68, 0.7)
PRESSURE_DROPS_ATM = (0.25, 0.5, 1.0)
#: (phi_s, dp [atm]) of the paper's 15 cases.
CASES = tuple((phi, dp) for phi in SOLID_FRACTIONS for dp in PRESSURE_DROPS_ATM)


def exact_pore_velocity(solid_fraction: float, dp_atm: float) -> float:
    """Eq. 77: U_f [m/s] for the scene's d, mu and L at a pressure drop of dp_atm atmospheres."""
    return float(darcy_pore_velocity(solid_fraction, GRAIN, MU, dp_atm * ATM, LENGTH))


def column_cells(dump: dict) -> np.ndarray:
    """Index mask of the cells (along x) whose centres lie inside the porous column."""
    x, _, _ = cell_centres(dump)
    return (x > COLUMN[0]) & (x < COLUMN[1])


def column_velocity(dump: dict, fluid: str = FLUID) -> float:
    """Mean fluid x velocity [m/s] over the cells inside the column (a dump from read_dump)."""
    inside = column_cells(dump)
    return float(np.mean(dump["cell"][f"{fluid}/velocity_x"][inside, 0, 0]))


def cell_errors(dump: dict, solid_fraction: float, dp_atm: float) -> np.ndarray:
    """Relative error of every cell's fluid x velocity (along x): against the pore velocity U_f
    of eq. 77 in the cells inside the column, against the Darcy flux n U_f outside."""
    inside = column_cells(dump)
    u_exact = exact_pore_velocity(solid_fraction, dp_atm)
    expected = np.where(inside, u_exact, (1.0 - solid_fraction) * u_exact)
    return dump["cell"][f"{FLUID}/velocity_x"][:, 0, 0] / expected - 1.0


def column_end_cells(dump: dict) -> np.ndarray:
    """Index mask of the cells (along x) whose centres lie within one cell of a column end."""
    x, _, _ = cell_centres(dump)
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    return (np.abs(x - COLUMN[0]) < dx) | (np.abs(x - COLUMN[1]) < dx)


def analyse_case(dumps, solid_fraction: float, dp_atm: float) -> dict:
    """Result of one case from its dumps (dicts from read_dump, time order; at least one).

    Returns phi_s, dp_atm, dp (Pa), time (of the final dump), u_numeric, u_exact, rel_error
    (u_numeric / u_exact - 1), steady_change (|u_final - u_previous| / |u_final|, NaN with one
    dump), u_outside (mean fluid velocity outside the column: the Darcy flux n U_f if the solver
    is right), solid_fraction_cells (mean /cell/<solid>/volume_fraction inside, NaN if the
    dump has none), and per cell (:func:`cell_errors`): cell_error_max (largest |error| of any
    cell), cell_error_interior (the same without the cells next to the column's ends,
    :func:`column_end_cells`) and steady_change_cells (largest |u_final - u_previous| of a cell
    over the largest |u_final|, NaN with one dump).
    """
    last = dumps[-1]
    u_num = column_velocity(last)
    u_exact = exact_pore_velocity(solid_fraction, dp_atm)
    change = change_cells = float("nan")
    errors = np.abs(cell_errors(last, solid_fraction, dp_atm))
    ends = column_end_cells(last)
    if len(dumps) > 1:
        u_last = last["cell"][f"{FLUID}/velocity_x"][:, 0, 0]
        u_prev = dumps[-2]["cell"][f"{FLUID}/velocity_x"][:, 0, 0]
        change_cells = float(np.max(np.abs(u_last - u_prev)) / np.max(np.abs(u_last)))
        change = abs(u_num - column_velocity(dumps[-2])) / abs(u_num) if u_num != 0.0 \
            else float("inf")
    inside = column_cells(last)
    velocity = last["cell"][f"{FLUID}/velocity_x"][:, 0, 0]
    key = f"{SOLID}/volume_fraction"
    phi_cells = float(np.mean(last["cell"][key][inside, 0, 0])) if key in last["cell"] \
        else float("nan")
    return {
        "phi_s": solid_fraction, "dp_atm": dp_atm, "dp": dp_atm * ATM, "time": last["time"],
        "u_numeric": u_num, "u_exact": u_exact, "rel_error": u_num / u_exact - 1.0,
        "steady_change": change,
        "u_outside": float(np.mean(velocity[~inside])) if np.any(~inside) else float("nan"),
        "darcy_flux_exact": (1.0 - solid_fraction) * u_exact,
        "solid_fraction_cells": phi_cells,
        "cell_error_max": float(np.max(errors)),
        "cell_error_interior": float(np.max(errors[~ends])) if np.any(~ends) else float("nan"),
        "steady_change_cells": change_cells,
    }


def run_case(workdir: str, solid_fraction: float, dp_atm: float, nranks: int = 1,
             extra_set=()) -> dict:
    """Run one case; return :func:`analyse_case` of its dumps plus output_dir."""
    out = os.path.join(workdir, f"darcy_phi{solid_fraction}_dp{dp_atm}_r{nranks}")
    args = [NAMELIST,
            "--set", f"&solid name='{SOLID}', porosity = {1.0 - solid_fraction:.12g} /",
            "--set", f"&boundary face='x-', pressure = {P_REF + dp_atm * ATM:.12g} /",
            "--set", f"&run output_dir = '{out}' /"]
    for text in extra_set:
        args += ["--set", text]
    run_mpmice(args, nranks=nranks, cwd=workdir)
    result = analyse_case(read_run_dumps(out, NAME, last=2), solid_fraction, dp_atm)
    result["output_dir"] = out
    return result


def run_darcy(workdir: str, cases=None, nranks: int = 1, extra_set=()) -> list[dict]:
    """Run `cases` ((phi_s, dp [atm]) pairs; default: the 15 of CASES); one dict per case."""
    return [run_case(workdir, phi, dp, nranks, extra_set)
            for phi, dp in (CASES if cases is None else cases)]


def print_table(results: list[dict]) -> None:
    print(f"{'phi_s':>6} {'dp [atm]':>8} {'U_f num [m/s]':>14} {'U_f exact':>12} "
          f"{'rel error':>10} {'steady':>9} {'q out/exact':>11} {'cell max':>9} "
          f"{'interior':>9} {'cell steady':>11}")
    for r in results:
        q_ratio = r["u_outside"] / r["darcy_flux_exact"]
        print(f"{r['phi_s']:6.2f} {r['dp_atm']:8.2f} {r['u_numeric']:14.6e} "
              f"{r['u_exact']:12.6e} {r['rel_error']:10.3e} {r['steady_change']:9.2e} "
              f"{q_ratio:11.6f} {r['cell_error_max']:9.2e} {r['cell_error_interior']:9.2e} "
              f"{r['steady_change_cells']:11.2e}")
    worst = max(results, key=lambda r: abs(r["rel_error"]))
    print(f"largest |relative error| = {abs(worst['rel_error']):.3e} "
          f"(phi_s = {worst['phi_s']}, dp = {worst['dp_atm']} atm); largest steady change "
          f"{max(r['steady_change'] for r in results):.2e}")
    print(f"per cell: largest |relative error| {max(r['cell_error_max'] for r in results):.3e}, "
          f"away from the column's ends {max(r['cell_error_interior'] for r in results):.3e}; "
          f"largest steady change {max(r['steady_change_cells'] for r in results):.2e}")


def write_csv(results: list[dict], path: str) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write("phi_s,dp_atm,dp_pa,time,u_numeric,u_exact,rel_error,steady_change,u_outside,"
                "darcy_flux_exact,solid_fraction_cells,cell_error_max,cell_error_interior,"
                "steady_change_cells\n")
        for r in results:
            f.write(f"{r['phi_s']},{r['dp_atm']},{r['dp']:.10g},{r['time']:.6g},"
                    f"{r['u_numeric']:.9e},{r['u_exact']:.9e},{r['rel_error']:.6e},"
                    f"{r['steady_change']:.6e},{r['u_outside']:.9e},"
                    f"{r['darcy_flux_exact']:.9e},{r['solid_fraction_cells']:.6f},"
                    f"{r['cell_error_max']:.6e},{r['cell_error_interior']:.6e},"
                    f"{r['steady_change_cells']:.6e}\n")


def plot(results: list[dict], path: str) -> None:
    plt = pyplot()

    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    dp = np.linspace(0.0, max(PRESSURE_DROPS_ATM), 100)
    phis = sorted({r["phi_s"] for r in results})
    for k, phi in enumerate(phis):
        color = f"C{k}"
        ax.plot(dp, [exact_pore_velocity(phi, d) for d in dp], "-", color=color, lw=1)
        rows = [r for r in results if r["phi_s"] == phi]
        ax.plot([r["dp_atm"] for r in rows], [r["u_numeric"] for r in rows], "o", color=color,
                mfc="none", label=f"phi_s = {phi}")
    ax.set_xlabel("pressure drop dp [atm]")
    ax.set_ylabel("pore velocity U_f [m/s]")
    ax.set_title("Flow through a porous column, L = 1 m (lines: eq. 77, markers: MPMICE)",
                 fontsize=10)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def main(argv=None) -> int:
    return run_study(__doc__, run_darcy, print_table, plot, write_csv, "mpmice_darcy", argv)


if __name__ == "__main__":
    raise SystemExit(main())
