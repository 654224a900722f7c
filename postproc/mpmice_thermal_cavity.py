"""Thermally driven flow in a square cavity of rigid water-saturated porous medium (MPMICE, paper
section "Thermal induced cavity flow") and the Darcy-Rayleigh benchmarks.

Usage:  python -m postproc.mpmice_thermal_cavity [--out docs/validation] [--ra 10 100 1000]
                                                 [--n 20 40] [--end-thermal 1.0] [--nranks 1]
        python -m postproc.mpmice_thermal_cavity --paper [--n 10 20 40]
        python -m postproc.mpmice_thermal_cavity --summary CSV [CSV ...]   (Nu against cells)

Scene namelists/mpmice_thermal_cavity_2d.nml: H = 1 m, left wall T0 + dT/2, right wall T0 - dT/2,
dT = 1 K, adiabatic top and bottom, the paper's water and skeleton (phi_s = 0.6). The Darcy-
Rayleigh number Ra = alpha_f g K dT H / (mu alpha_m) (alpha_f = 0.18 kg/m^3/K the water's density
change per kelvin, alpha_m = k_m / (rho_f c_f), k_m = n k_f + phi_s k_s) is set through the grain
size: K = Ra mu alpha_m / (alpha_f g dT H), d = sqrt(180 phi_s^2 K / n^3) (Kozeny-Carman, the
scene's drag law). The paper's d = 1 mm gives Ra = 15.2 (--paper).

Mean hot-wall Nusselt number Nu = q H / (k_m dT) with q the heat flux the scheme conducts through
the wall, the mean over the wall of 2 (phi_f k_f (T_w - T_f,1) + phi_s k_s (T_w - T_s,1)) / dx
(both phases: the wall face carries the conductance of its inner cell). The cold wall's Nu is
printed too: at steady state the two agree (energy balance). Benchmarks (Darcy model, square
cavity): about 1.08 (Ra 10), 3.1 (Ra 100), 13.4 (Ra 1000); published values spread over
3.10-3.16 at Ra 100 and 12.96-14.06 at Ra 1000 (Walker & Homsy 1978, Gross et al. 1986, Manole &
Lage 1992, Baytas & Pop 1999). Writes <tag>.csv and <tag>.png (temperature and velocity of the
finest run of each Ra); --summary draws Nu against the cell count for every Ra of the given CSVs
with the benchmarks and their 3 % band (mpmice_thermal_cavity_nusselt.png).
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_thermal_cavity_2d.nml")
NAME = "cavity"
FLUID, SOLID = "water", "skeleton"
H, DT = 1.0, 1.0                         # m, K
T_HOT, T_COLD = 283.65, 282.65           # K
RHO_F, C_F, K_F, MU, ALPHA_F = 999.8, 4181.0, 0.598, 1.0e-3, 0.18
RHO_S, C_S, K_S, PHI_S = 2500.0, 835.0, 0.4, 0.6
G = 9.81
POROSITY = 1.0 - PHI_S
K_M = POROSITY * K_F + PHI_S * K_S       # W/m/K
ALPHA_M = K_M / (RHO_F * C_F)            # m^2/s
SIGMA = (POROSITY * RHO_F * C_F + PHI_S * RHO_S * C_S) / (RHO_F * C_F)
THERMAL_TIME = SIGMA * H**2 / ALPHA_M    # s
BENCHMARK = {10.0: 1.08, 100.0: 3.1, 1000.0: 13.4}
PAPER_GRAIN = 1.0e-3                     # m


def permeability(grain: float) -> float:
    """Kozeny-Carman permeability [m^2] of the skeleton with grain size `grain` [m]."""
    return grain**2 * POROSITY**3 / (180.0 * PHI_S**2)


def rayleigh(grain: float) -> float:
    """Darcy-Rayleigh number of the cavity with grain size `grain` [m]."""
    return ALPHA_F * G * permeability(grain) * DT * H / (MU * ALPHA_M)


def grain_for(ra: float) -> float:
    """Grain size [m] that gives Darcy-Rayleigh number `ra`."""
    k = ra * MU * ALPHA_M / (ALPHA_F * G * DT * H)
    return float(np.sqrt(180.0 * PHI_S**2 * k / POROSITY**3))


def wall_nusselt(dump: dict) -> tuple[float, float]:
    """Mean Nusselt numbers (hot wall x = 0, cold wall x = H) of a dump."""
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    cell = dump["cell"]
    tf = cell[f"{FLUID}/temperature"][:, :, 0]
    ts = cell[f"{SOLID}/temperature"][:, :, 0]
    phi_f = cell[f"{FLUID}/volume_fraction"][:, :, 0]
    phi_s = 1.0 - phi_f

    def flux(i: int, wall: float) -> np.ndarray:
        return 2.0 * (phi_f[i, :] * K_F * (wall - tf[i, :]) + phi_s[i, :] * K_S *
                      (wall - ts[i, :])) / dx

    hot = float(np.mean(flux(0, T_HOT))) * H / (K_M * DT)
    cold = float(np.mean(-flux(-1, T_COLD))) * H / (K_M * DT)
    return hot, cold


def run(workdir: str, grain: float, n: int, end: float, nranks: int = 1,
        ppc: int = 2) -> list[dict]:
    """All dumps of one cavity run (n x n cells, grain size [m], end time [s])."""
    out = os.path.join(workdir, f"cavity_{grain:.4e}_{n}")
    run_mpmice([NAMELIST,
                "--set", f"&grid ncells = {n}, {n}, 1, upper = 1.0, 1.0, {1.0 / n} /",
                "--set", f"&run output_dir = '{out}', end_time = {end}, "
                f"output_interval = {end / 10} /",
                "--set", f"&solid name = '{SOLID}', grain_size = {grain}, upper = 1.0, 1.0, "
                f"{1.0 / n}, particles_per_cell = {ppc}, {ppc}, 1 /"],
               nranks=nranks, cwd=workdir, timeout=7200)
    return [read_dump(p) for p in list_dumps(out, NAME)]


def plot(runs: list[tuple[str, dict]], path: str) -> None:
    """Temperature with velocity arrows, one panel per (title, dump)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(runs), figsize=(4.2 * len(runs), 4.0), squeeze=False)
    for ax, (title, dump) in zip(axes[0], runs):
        t = dump["cell"][f"{FLUID}/temperature"][:, :, 0]
        u = dump["cell"][f"{FLUID}/velocity_x"][:, :, 0]
        v = dump["cell"][f"{FLUID}/velocity_y"][:, :, 0]
        n = t.shape[0]
        xc = (np.arange(n) + 0.5) / n * H
        im = ax.contourf(xc, xc, t.T - 0.5 * (T_HOT + T_COLD), levels=21, cmap="coolwarm")
        step = max(1, n // 16)
        ax.quiver(xc[::step], xc[::step], u[::step, ::step].T, v[::step, ::step].T)
        speed = float(np.max(np.hypot(u, v)))
        ax.set_title(f"{title}\nlargest pore speed {speed:.2e} m/s", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        fig.colorbar(im, ax=ax, label="T - T0 [K]", shrink=0.8)
    axes[0][0].set_ylabel("y [m]")
    fig.tight_layout()
    save_figure(fig, path)


def plot_summary(csv_paths: list[str], path: str) -> None:
    """Nu against cells per Ra from the CSVs written by main, with the benchmarks (3 % band)."""
    plt = pyplot()
    rows = []
    for csv in csv_paths:
        data = np.genfromtxt(csv, delimiter=",", names=True)
        rows.extend(np.atleast_1d(data).tolist())
    ras = sorted({r[0] for r in rows})
    fig, axes = plt.subplots(1, len(ras), figsize=(3.6 * len(ras), 3.4), squeeze=False)
    for ax, ra in zip(axes[0], ras):
        pts = sorted((r[2], r[3]) for r in rows if r[0] == ra)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label="MPMICE, hot wall")
        ref = BENCHMARK.get(round(ra, 6))
        if ref:
            ax.axhline(ref, color="k", lw=0.8, label=f"benchmark {ref}")
            ax.axhspan(0.97 * ref, 1.03 * ref, color="0.85", label="+-3 %")
        ax.set_xscale("log", base=2)
        ax.set_xlabel("cells per side")
        ax.set_title(f"Ra = {ra:.4g}", fontsize=9)
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("mean Nusselt number")
    fig.tight_layout()
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--ra", type=float, nargs="+", default=[10.0, 100.0, 1000.0])
    parser.add_argument("--paper", action="store_true", help="the paper's d = 1 mm only")
    parser.add_argument("--n", type=int, nargs="+", default=[20, 40])
    parser.add_argument("--end-thermal", type=float, default=1.0,
                        help="end time in thermal times sigma H^2 / alpha_m (6.1e6 s)")
    parser.add_argument("--nranks", type=int, default=1)
    parser.add_argument("--tag", default="mpmice_thermal_cavity")
    parser.add_argument("--summary", nargs="+", metavar="CSV",
                        help="only draw Nu against cells from these CSVs")
    args = parse_study_args(parser, argv)
    if args.summary:
        plot_summary(args.summary, os.path.join(args.out, "mpmice_thermal_cavity_nusselt.png"))
        return 0
    cases = [(rayleigh(PAPER_GRAIN), PAPER_GRAIN)] if args.paper else \
        [(ra, grain_for(ra)) for ra in args.ra]
    rows, panels = [], []
    end = args.end_thermal * THERMAL_TIME
    with tempfile.TemporaryDirectory() as work:
        for ra, grain in cases:
            for n in args.n:
                dumps = run(work, grain, n, end, args.nranks)
                history = [wall_nusselt(d)[0] for d in dumps[1:]]
                hot, cold = wall_nusselt(dumps[-1])
                ref = BENCHMARK.get(ra, float("nan"))
                change = abs(history[-1] - history[-2]) / abs(history[-1])
                rows.append((ra, grain, n, hot, cold, ref, hot / ref - 1.0, change))
                print(f"Ra = {ra:7.2f} (d = {grain * 1e3:.3f} mm), {n}^2: Nu(t) = " +
                      ", ".join(f"{nu:.4f}" for nu in history), flush=True)
                if n == args.n[-1]:
                    panels.append((f"Ra = {ra:.4g}, {n}x{n}: Nu = {hot:.3f}", dumps[-1]))
    print("      Ra   d [mm]  cells   Nu hot  Nu cold  benchmark  rel. diff  last change")
    for ra, grain, n, hot, cold, ref, rel, change in rows:
        print(f"{ra:8.2f} {grain * 1e3:8.3f} {n:4d}^2 {hot:8.4f} {cold:8.4f} {ref:9.3f} "
              f"{rel:+10.2%} {change:10.1e}")
    with open(os.path.join(args.out, f"{args.tag}.csv"), "w") as f:
        f.write("ra,grain_m,cells,nu_hot,nu_cold,benchmark,rel_difference,last_change\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    plot(panels, os.path.join(args.out, f"{args.tag}.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
