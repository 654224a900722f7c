"""Natural convection in a differentially heated square cavity (de Vahl Davis benchmark) with the
ICE scene (namelists/ice_cavity.nml).

Usage:  python -m postproc.ice_cavity [--out docs/validation] [--ra 1e3 1e4 1e5] [--n 32]
                                      [--end 100] [--nranks 1]

Mean hot-wall Nusselt number Nu = (L / dT) mean_y(-dT/dx at x = 0), the wall gradient from the
wall temperature and the first two cells, (-8 T_w + 9 T_1 - T_2) / (3 dx) (second order); printed
for every dump (to show the approach to steady state) and compared with de Vahl Davis (1983):
1.118, 2.243, 4.519. Writes ice_cavity.csv and ice_cavity.png (temperature of the last run).
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_cavity.nml")
PROPERTIES = {1e3: (0.013708, 19.394), 1e4: (0.0043349, 6.1329), 1e5: (0.0013708, 1.9394)}
BENCHMARK = {1e3: 1.118, 1e4: 2.243, 1e5: 4.519}
T_HOT, T_COLD = 303.0, 297.0


def nusselt(dump: dict) -> float:
    """Mean hot-wall Nusselt number of a dump."""
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    t = dump["cell"]["air/temperature"][:, :, 0]
    grad = (-8.0 * T_HOT + 9.0 * t[0, :] - t[1, :]) / (3.0 * dx)
    return float(np.mean(-grad) * 1.0 / (T_HOT - T_COLD))


def run(workdir: str, ra: float, n: int, end: float, nranks: int = 1) -> list[dict]:
    """All dumps of one cavity run."""
    mu, k = PROPERTIES[ra]
    out = os.path.join(workdir, f"cavity_{ra:.0e}_{n}")
    run_mpmice([NAMELIST, "--set", f"&grid ncells = {n}, {n}, 1, upper = 1.0, 1.0, {1.0 / n} /",
                "--set", f"&run output_dir = '{out}', end_time = {end}, "
                f"output_interval = {end / 10} /",
                "--set", f"&fluid name = 'air', viscosity = {mu}, conductivity = {k} /"],
               nranks=nranks, cwd=workdir, timeout=3600)
    return [read_dump(p) for p in list_dumps(out, "cavity")]


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--ra", type=float, nargs="+", default=[1e3, 1e4, 1e5])
    parser.add_argument("--n", type=int, default=32)
    parser.add_argument("--end", type=float, default=100.0)
    parser.add_argument("--nranks", type=int, default=1)
    args = parse_study_args(parser, argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for ra in args.ra:
            dumps = run(work, ra, args.n, args.end, args.nranks)
            history = [(d["time"], nusselt(d)) for d in dumps[1:]]
            print(f"Ra = {ra:.0e}, {args.n}^2 cells: Nu(t) = " +
                  ", ".join(f"{t:.0f} s: {nu:.4f}" for t, nu in history))
            nu = history[-1][1]
            rows.append((ra, args.n, nu, BENCHMARK[ra], nu / BENCHMARK[ra] - 1.0,
                         history[-1][1] - history[-2][1]))
            last = dumps[-1]
    print("      Ra   cells      Nu   benchmark   rel. difference   change over last interval")
    for ra, n, nu, ref, rel, change in rows:
        print(f"{ra:8.0e}   {n:4d}^2   {nu:.4f}   {ref:.3f}   {rel:+15.2%}   {change:+.2e}")
    with open(os.path.join(args.out, "ice_cavity.csv"), "w") as f:
        f.write("ra,cells,nu,benchmark,rel_difference,last_change\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 4.5))
    im = ax.imshow(last["cell"]["air/temperature"][:, :, 0].T, origin="lower", extent=[0, 1, 0, 1],
                   cmap="coolwarm")
    fig.colorbar(im, label="T [K]")
    ax.set_title(f"Ra = {rows[-1][0]:.0e}, Nu = {rows[-1][2]:.3f} (benchmark {rows[-1][3]})")
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "ice_cavity.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
