"""Sod shock tube with the ICE scene against the exact Riemann solution (postproc.riemann).

Usage:  python -m postproc.ice_sod [--out docs/validation] [--cells 100 200 400 800]
                                   [--cfl 0.5] [--sound-speed-factor 0] [--order 2] [--nranks 1]

Runs namelists/ice_sod.nml at each resolution (t = 0.2), prints the relative L1 density error
sum |rho - rho_exact| / sum |rho_exact| (exact cell averages) and the observed order between
successive resolutions, and writes ice_sod.csv and ice_sod.png (density, velocity and pressure of
the finest run against the exact solution) into --out.
"""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from postproc import riemann
from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_sod.nml")
X0 = 0.5      # diaphragm position
T_END = 0.2   # s


def run(workdir: str, n: int, cfl: float = 0.5, sound_speed_factor: float | None = None,
        order: int = 2, nranks: int = 1, extra=()) -> dict:
    """Run the Sod namelist with n cells; return the final dump."""
    out = os.path.join(workdir, f"sod_{n}_{nranks}")
    args = [NAMELIST, "--set", f"&grid ncells = {n}, 1, 1 /",
            "--set", f"&run output_dir = '{out}' /",
            "--set", f"&time cfl = {cfl} /",
            "--set", f"&numerics advection_order = {order} /"]
    if sound_speed_factor is not None:
        args += ["--set", f"&ice sound_speed_factor = {sound_speed_factor} /"]
    args += list(extra)
    run_mpmice(args, nranks=nranks, cwd=workdir)
    return read_dump(list_dumps(out, "sod")[-1])


def exact(dump: dict):
    """Exact cell averages (rho, u, p) on the dump's cells at the dump's time."""
    x = cell_centres(dump)[0]
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    edges = np.concatenate([x - 0.5 * dx, [x[-1] + 0.5 * dx]])
    return riemann.cell_average(riemann.SOD_LEFT, riemann.SOD_RIGHT, X0, dump["time"], edges)


def density_error(dump: dict) -> float:
    """Relative L1 density error of a final dump."""
    rho = dump["cell"]["gas/density"][:, 0, 0]
    rho_exact = exact(dump)[0]
    return float(np.sum(np.abs(rho - rho_exact)) / np.sum(np.abs(rho_exact)))


def study(workdir: str, cells, **kwargs) -> tuple[list[tuple[int, float, float]], dict]:
    """(n, error, observed order) per resolution and the finest dump."""
    rows = []
    dump = None
    for n in cells:
        dump = run(workdir, n, **kwargs)
        err = density_error(dump)
        order = math.log(rows[-1][1] / err) / math.log(n / rows[-1][0]) if rows else float("nan")
        rows.append((n, err, order))
    return rows, dump


def plot(dump: dict, path: str, title: str) -> None:
    """Density, velocity and pressure of a dump against the exact solution."""
    plt = pyplot()
    x = cell_centres(dump)[0]
    fine = np.linspace(0.0, 1.0, 2001)
    ex = riemann.sample(riemann.SOD_LEFT, riemann.SOD_RIGHT, (fine - X0) / dump["time"])
    pressure = dump["cell"]["pressure"][:, 0, 0]
    num = (dump["cell"]["gas/density"][:, 0, 0], dump["cell"]["gas/velocity_x"][:, 0, 0], pressure)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, q, e, label in zip(axes, num, ex, ("density", "velocity", "pressure")):
        ax.plot(fine, e, "k-", lw=1, label="exact")
        ax.plot(x, q, "r.", ms=3, label="ICE")
        ax.set_xlabel("x")
        ax.set_title(label)
    axes[0].legend()
    fig.suptitle(title)
    fig.tight_layout()
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[100, 200, 400, 800])
    parser.add_argument("--cfl", type=float, default=0.5)
    parser.add_argument("--sound-speed-factor", type=float, default=None)
    parser.add_argument("--order", type=int, default=2)
    parser.add_argument("--nranks", type=int, default=1)
    parser.add_argument("--tag", default="ice_sod")
    args = parse_study_args(parser, argv)
    with tempfile.TemporaryDirectory() as work:
        rows, dump = study(work, args.cells, cfl=args.cfl,
                           sound_speed_factor=args.sound_speed_factor, order=args.order,
                           nranks=args.nranks)
        print(f"Sod shock tube, t = {dump['time']:.4f}, cfl = {args.cfl}, sound-speed factor = "
              f"{args.sound_speed_factor}, advection order {args.order}")
        print("   cells   rel. L1 density error   observed order")
        for n, err, order in rows:
            print(f"{n:8d}   {err:20.4e}   {order:14.3f}")
        with open(os.path.join(args.out, f"{args.tag}.csv"), "w") as f:
            f.write("cells,rel_l1_density_error,observed_order\n")
            for n, err, order in rows:
                f.write(f"{n},{err:.6e},{order:.4f}\n")
        plot(dump, os.path.join(args.out, f"{args.tag}.png"),
             f"Sod shock tube, {args.cells[-1]} cells, t = {dump['time']:.3f}: "
             f"rel. L1 density error {rows[-1][1]:.3%}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
