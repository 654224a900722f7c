"""2D granular column collapse (dry sand, Mohr-Coulomb phi' = 30 deg) at aspect ratios a = H0/L0
of 0.5 and 2: normalised run-out (L_inf - L0)/L0 and final height H_inf/L0 against the
experimental scaling of two-dimensional collapses, as compiled by Lagree, Staron & Popinet (2011,
J. Fluid Mech. 686, 378, eqs. 3.1-3.2) from Lube et al. (2005, Phys. Rev. E 72, 041301) and
Lajeunesse et al. (2005, Phys. Fluids 17, 103302); see docs/validation/mpm_collapse.md:
    (L_inf - L0)/L0 = lambda a below the transition (a0 = 1.8-3), lambda = 1.2 (Lube) to 1.8
    (Lajeunesse): the band [1.2 a, 1.8 a];
    H_inf/L0 = a (a < 1.15, the top is not reached), a^0.4 (a > 1.15, Lube).
L_inf is the largest particle x and H_inf the largest particle y of the deposit at t = 1 s
(kinetic energy checked to have decayed). Also printed: the extent of the deposit where it is at
least 0.1 H0 thick (`body`, less sensitive to the thin front) and the height beyond the first
cell column at the wall (a one-cell sliver of particles can stay on the smooth wall).

Usage:  python -m postproc.mpm_collapse [--out docs/validation] [--nranks 1] [--cell 0.01]
Writes mpm_collapse.png and mpm_collapse.csv.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.measures import front, top
from postproc.mpm_common import particles, series
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpm_collapse_2d.nml")
L0 = 0.2


def scaling(a: float) -> tuple[float, float, float]:
    """Experimental (L_inf - L0)/L0 band (low: 1.2 a, high: 1.8 a) and H_inf/L0 for aspect
    ratio a (see module notes)."""
    height = a if a < 1.15 else a ** 0.4
    return 1.2 * a, 1.8 * a, height


def body_extent(x: np.ndarray, y: np.ndarray, thickness: float, width: float = 0.005) -> float:
    """Right end [m] of the columns of `width` whose highest particle is at least `thickness` m
    above the base."""
    edges = np.arange(0.0, x.max() + 2.0 * width, width)
    top = np.zeros(len(edges))
    np.maximum.at(top, np.digitize(x, edges) - 1, y)
    thick = np.nonzero(top >= thickness)[0]
    return float(edges[thick.max()] + width) if len(thick) else 0.0


def run_collapse(workdir: str, a: float, nranks: int = 1, cell: float = 0.01, extra=(),
                 timeout: float = 3600) -> dict:
    """Run the collapse of aspect ratio a with cells of `cell` m (further `--set` arguments in
    `extra`); return the deposit measures."""
    out = os.path.join(workdir, f"collapse_a{a}_c{cell}")
    grid = f"&grid ncells = {int(round(1.2 / cell))}, {int(round(0.5 / cell))}, 1 /"
    run_mpmice([NAMELIST, "--set", f"&solid name = 'sand', upper = {L0}, {a * L0!r}, 1.0 /",
                "--set", grid, "--set", f"&run output_dir = '{out}' /", *extra], nranks=nranks,
               cwd=workdir, timeout=timeout)
    paths = list_dumps(out, "collapse2d")
    _, p0 = particles(paths[0], "sand")
    time, p1 = particles(paths[-1], "sand")
    s = series(out, "collapse2d")
    potential = float(np.sum(p0["mass"] * 9.81 * p0["y"]))
    runout = (front(p1, 0, +1) - L0) / L0
    height = top(p1, (1, +1)) / L0
    expected = scaling(a)
    return {"a": a, "time": time, "x0": p0["x"], "y0": p0["y"], "x": p1["x"], "y": p1["y"],
            "runout": runout, "height": height, "runout_low": expected[0],
            "runout_high": expected[1], "height_expected": expected[2],
            "body": (body_extent(p1["x"], p1["y"], 0.1 * a * L0) - L0) / L0,
            "height_off_wall": float(np.max(p1["y"][p1["x"] > cell])) / L0,
            "kinetic_ratio": float(s["kinetic_energy"][-1]) / potential,
            "particles": len(p1["x"]), "potential": potential,
            "kinetic_max": float(np.max(s["kinetic_energy"])),
            "strain_energy_min": float(np.min(s["strain_energy"])),
            "end_time": float(s["time"][-1])}


def main(argv=None) -> int:
    parser = study_parser(__doc__, nranks=True)
    parser.add_argument("--cell", type=float, default=0.01, help="cell size [m] (0.01)")
    args = parse_study_args(parser, argv)
    plt = pyplot()

    rows = []
    with tempfile.TemporaryDirectory() as work:
        for a in (0.5, 2.0):
            r = run_collapse(work, a, args.nranks, args.cell)
            rows.append(r)
            print(f"a = {a}: run-out (L-L0)/L0 = {r['runout']:.3f} (scaling band "
                  f"{r['runout_low']:.2f}-{r['runout_high']:.2f}, "
                  f"{100 * (r['runout'] / r['runout_low'] - 1):+.1f} % from the low edge), "
                  f"body (>= 0.1 H0 thick) {r['body']:.3f}, H/L0 = {r['height']:.3f} (beyond the "
                  f"first cell column {r['height_off_wall']:.3f}; scaling "
                  f"{r['height_expected']:.3f}, "
                  f"{100 * (r['height'] / r['height_expected'] - 1):+.1f} %), kinetic/potential "
                  f"at t = {r['time']:.2f} s: {r['kinetic_ratio']:.1e}")
    fig, axes = plt.subplots(2, 1, figsize=(9, 6))
    for ax, r in zip(axes, rows):
        ax.plot(r["x0"], r["y0"], ".", ms=1, color="0.75", label="initial")
        ax.plot(r["x"], r["y"], ".", ms=1, label=f"MPM, t = {r['time']:.2f} s")
        ax.axvspan(L0 * (1 + r["runout_low"]), L0 * (1 + r["runout_high"]), color="0.85",
                   label="run-out scaling 1.2 a - 1.8 a")
        ax.axhline(L0 * r["height_expected"], color="k", ls=":", lw=1, label="final height scaling")
        ax.set_aspect("equal")
        ax.set_xlim(0.0, 1.2)
        ax.set_ylim(0.0, max(0.45, 1.1 * L0 * r["a"]))
        ax.set_title(f"a = {r['a']}, {args.cell * 1000:g} mm cells")
        ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("x [m]")
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_collapse.png"), dpi=120)
    with open(os.path.join(args.out, "mpm_collapse.csv"), "w", encoding="utf-8") as f:
        f.write("a,cell,runout,runout_scaling_low,runout_scaling_high,body,height,"
                "height_off_wall,height_scaling,kinetic_ratio\n")
        for r in rows:
            f.write(f"{r['a']},{args.cell},{r['runout']:.6f},{r['runout_low']:.6f},"
                    f"{r['runout_high']:.6f},{r['body']:.6f},{r['height']:.6f},"
                    f"{r['height_off_wall']:.6f},{r['height_expected']:.6f},"
                    f"{r['kinetic_ratio']:.3e}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
