"""Heat-conduction validation study: spatial convergence (1D and 2D) and rank invariance.

Usage:  python -m postproc.heat_convergence [--out docs/validation] [--quick]

Runs the scene at three (four) resolutions with dt proportional to dx (Crank-Nicolson, so the
error is second order in dx), prints the relative L2 error of the temperature perturbation and the
observed order, runs the 2D case on 1, 2 and 4 ranks and prints the largest relative difference,
and writes CSV + PNG into --out.
"""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.heat_conduction import dump_files, read_temperature, relative_error
from postproc.run_case import ROOT, run_mpmice

NAMELISTS = os.path.join(ROOT, "namelists")


def run_resolution(workdir: str, dim: int, n: int, nranks: int = 1) -> dict:
    """Run the 1D or 2D scene with n cells along x (n/2 along y in 2D); return the final dump."""
    extra = []
    if dim == 1:
        nml = os.path.join(NAMELISTS, "heat_conduction_1d.nml")
        cells = f"{n}, 1, 1"
        dt = 0.064 / n            # 1e-3 s at 64 cells
    elif dim == 3:                # unit cube, walls everywhere, t = 0.01 s
        nml = os.path.join(NAMELISTS, "heat_conduction_1d.nml")
        cells = f"{n}, {n}, {n}"
        dt = 0.016 / n
        extra = ["--set", "&run end_time = 0.01, output_interval = 0.0 /"]
    else:
        nml = os.path.join(NAMELISTS, "heat_conduction_2d.nml")
        cells = f"{n}, {n // 2}, 1"
        dt = 0.016 / n            # 2.5e-4 s at 64 x 32 cells
    out = os.path.join(workdir, f"d{dim}_n{n}_r{nranks}")
    run_mpmice([nml, "--set", f"&grid ncells = {cells} /",
                "--set", f"&time dt_init = {dt!r}, dt_max = {dt!r} /",
                "--set", f"&run output_dir = '{out}', checkpoint_interval = 0.0 /"] + extra,
               nranks=nranks, cwd=workdir)
    return read_temperature(dump_files(out)[-1])


def convergence(workdir: str, dim: int, resolutions: list[int]) -> list[tuple[int, float, float]]:
    """(n, error, observed order vs the previous resolution) per resolution."""
    rows = []
    for n in resolutions:
        error = relative_error(run_resolution(workdir, dim, n))
        order = math.log(rows[-1][1] / error, 2) if rows else float("nan")
        rows.append((n, error, order))
    return rows


def rank_difference(workdir: str, n: int = 64, ranks=(1, 2, 4)) -> dict[int, float]:
    """Largest |T_r - T_1| / max|T_1| for the 2D scene on each rank count."""
    reference = run_resolution(workdir, 2, n, ranks[0])["T"]
    scale = np.max(np.abs(reference))
    return {r: float(np.max(np.abs(run_resolution(workdir, 2, n, r)["T"] - reference)) / scale)
            for r in ranks[1:]}


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--quick", action="store_true", help="three coarse resolutions only")
    args = parse_study_args(parser, argv)
    res = [16, 32, 64] if args.quick else [32, 64, 128, 256]
    with tempfile.TemporaryDirectory() as work:
        studies = {dim: convergence(work, dim, res) for dim in (1, 2)}
        studies[3] = convergence(work, 3, [r // 4 for r in res])
        diffs = rank_difference(work)
    lines = ["dimension,cells_x,relative_l2_error,observed_order"]
    for dim, rows in studies.items():
        print(f"{dim}D heat conduction (Crank-Nicolson, dt ~ dx):")
        for n, err, order in rows:
            print(f"  {n:5d} cells along x: error {err:.4e}  order {order:.3f}")
            lines.append(f"{dim},{n},{err:.6e},{order:.4f}")
    for r, diff in diffs.items():
        print(f"2D, 64 x 32 cells: max |T({r} ranks) - T(1 rank)| / max|T| = {diff:.3e}")
    with open(os.path.join(args.out, "heat_convergence.csv"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for dim, rows in studies.items():
        n = np.array([r[0] for r in rows], dtype=float)
        e = np.array([r[1] for r in rows])
        ax.loglog(n, e, "o-", label=f"{dim}D")
    n = np.array([r[0] for r in studies[1]], dtype=float)
    ax.loglog(n, studies[1][0][1] * (n[0] / n) ** 2, "k--", label="slope 2")
    ax.set_xlabel("cells along x")
    ax.set_ylabel("relative L2 error of T - T_base")
    ax.set_title("Heat conduction vs exact solution")
    ax.legend()
    fig.tight_layout()
    png = os.path.join(args.out, "heat_convergence.png")
    save_figure(fig, png)
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
