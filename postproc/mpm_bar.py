"""Axial vibration of a fixed-free elastic bar in its first mode (1D MPM): period, amplitude and
energy against the exact solution at three resolutions, linear and GIMP shape functions.

Usage:  python -m postproc.mpm_bar [--out docs/validation] [--cells 10 20 40]

Exact (small strain): u(x, t) = (v0 / w) sin(pi x / (2L)) sin(w t), w = pi c / (2L), c =
sqrt(E / rho), period T = 4L/c. The tip is the particle with the largest x (at L - l_p); its
displacement comes from the scene's per-step series file. Printed per run (n = cells over the
bar): relative period error (mean spacing of the upward zero crossings over 10 periods), relative
amplitude error (largest |u_tip| vs v0/w sin(pi x_tip / 2L)), largest |u_tip - exact| over the 10
periods relative to the amplitude, and the total-energy drift (E(10 T) - E(0)) / E(0) with E =
kinetic + elastic strain energy of the particles. A second pair of runs at v0 = 2 m/s (tip
amplitude about half a cell, so particles cross cell boundaries) prints the energy drift of
linear and GIMP shape functions. Writes mpm_bar.png and mpm_bar.csv.
"""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpm_common import particles, series
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpm_bar_1d.nml")
L, E, RHO, V0 = 1.0, 1.0e7, 1000.0, 0.01
C = math.sqrt(E / RHO)
OMEGA = math.pi * C / (2.0 * L)
PERIOD = 4.0 * L / C
CROSSING_V0 = 2.0   # m/s: tip amplitude about half a cell at 40 cells, particles cross cells


def upward_crossings(t: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Times where u crosses zero upwards (linear interpolation)."""
    i = np.nonzero((u[:-1] < 0.0) & (u[1:] >= 0.0))[0]
    return t[i] - u[i] * (t[i + 1] - t[i]) / (u[i + 1] - u[i])


def run_bar(workdir: str, cells: int, shape: str, nranks: int = 1, v0: float = V0) -> dict:
    """Run the bar with `cells` cells over its length (initial amplitude v0 [m/s]); return the
    error measures (the exact solution is the small-strain one: meaningful for small v0)."""
    out = os.path.join(workdir, f"bar_{shape}_{cells}_{v0}")
    run_mpmice([NAMELIST, "--set", f"&grid ncells = {int(round(1.25 * cells))}, 1, 1 /",
                "--set", f"&numerics shape_function = '{shape}' /",
                "--set", f"&solid name = 'bar', velocity = {v0!r}, 0.0, 0.0 /",
                "--set", f"&run output_dir = '{out}' /"], nranks=nranks, cwd=workdir)
    _, p0 = particles(list_dumps(out, "bar1d")[0], "bar")
    x_tip = float(np.max(p0["x"]))
    s = series(out, "bar1d")
    t = np.concatenate([[0.0], s["time"]])
    u = np.concatenate([[0.0], s["xmax"] - x_tip])
    energy = s["kinetic_energy"] + s["strain_energy"]
    amplitude = v0 / OMEGA * math.sin(math.pi * x_tip / (2.0 * L))
    crossings = upward_crossings(t[1:], u[1:])   # skip the start at u = 0
    period = float(np.mean(np.diff(crossings)))
    exact = amplitude * np.sin(OMEGA * t)
    return {
        "cells": cells, "shape": shape, "t": t, "u": u, "amplitude": amplitude,
        "period_error": abs(period - PERIOD) / PERIOD,
        "amplitude_error": abs(np.max(np.abs(u)) - amplitude) / amplitude,
        "history_error": float(np.max(np.abs(u - exact)) / amplitude),
        "energy_drift": float((energy[-1] - energy[0]) / energy[0]),
        "periods": len(crossings) + 1,
    }


def order(rows: list[dict], key: str) -> list[float]:
    """Observed orders of `key` between successive resolutions."""
    return [math.log(a[key] / b[key], b["cells"] / a["cells"]) for a, b in zip(rows, rows[1:])]


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[10, 20, 40])
    args = parse_study_args(parser, argv)
    plt = pyplot()

    results = {}
    with tempfile.TemporaryDirectory() as work:
        for shape in ("linear", "gimp"):
            results[shape] = [run_bar(work, n, shape) for n in args.cells]
        crossing = {shape: run_bar(work, 40, shape, v0=CROSSING_V0) for shape in ("linear", "gimp")}
    print(f"exact period {PERIOD:.6f} s, c = {C:.1f} m/s")
    print("shape   cells  period_err  amplitude_err  history_err  energy_drift")
    for shape, rows in results.items():
        for r in rows:
            print(f"{shape:7s} {r['cells']:5d}  {r['period_error']:.3e}   {r['amplitude_error']:.3e}"
                  f"      {r['history_error']:.3e}    {r['energy_drift']:+.3e}")
        print(f"{shape}: observed order of the period error {order(rows, 'period_error')}")
    for shape, r in crossing.items():
        print(f"cell crossing (v0 = {CROSSING_V0} m/s, tip amplitude {r['amplitude'] * 1e3:.1f} mm"
              f" = {r['amplitude'] * 40:.2f} cells, 40 cells): {shape} energy drift over 10 periods "
              f"{r['energy_drift']:+.3e}")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    mid = len(args.cells) // 2
    for shape, rows in results.items():
        r = rows[mid]
        axes[0].plot(r["t"] / PERIOD, r["u"] * 1e6, lw=1, label=f"MPM {shape}, {r['cells']} cells")
    t = np.linspace(0.0, 10.0 * PERIOD, 2000)
    r = results["gimp"][mid]
    axes[0].plot(t / PERIOD, r["amplitude"] * np.sin(OMEGA * t) * 1e6, "k:", lw=1, label="exact")
    axes[0].set_xlim(8.0, 10.0)
    axes[0].set_xlabel("t / T")
    axes[0].set_ylabel("tip displacement [um]")
    axes[0].legend(fontsize=8)
    for shape, rows in results.items():
        n = [r["cells"] for r in rows]
        axes[1].loglog(n, [r["period_error"] for r in rows], "o-", label=f"period, {shape}")
        axes[1].loglog(n, [r["history_error"] for r in rows], "s--", label=f"u_tip(t) max, {shape}")
    axes[1].set_xlabel("cells over the bar")
    axes[1].set_ylabel("relative error")
    axes[1].legend(fontsize=8)
    fig.suptitle("Fixed-free elastic bar, first mode, 10 periods")
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_bar.png"), dpi=120)
    with open(os.path.join(args.out, "mpm_bar.csv"), "w", encoding="utf-8") as f:
        f.write("shape,cells,period_error,amplitude_error,history_error,energy_drift\n")
        for shape, rows in results.items():
            for r in rows:
                f.write(f"{shape},{r['cells']},{r['period_error']:.6e},{r['amplitude_error']:.6e},"
                        f"{r['history_error']:.6e},{r['energy_drift']:.6e}\n")
        f.write("# cell crossing, v0 = 2 m/s, 40 cells: shape,energy_drift\n")
        for shape, r in crossing.items():
            f.write(f"# {shape},{r['energy_drift']:.6e}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
