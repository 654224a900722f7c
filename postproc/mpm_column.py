"""Elastic column under self-weight (1D and 2D), gravity ramped over 0.5 s, local damping 0.1.

Usage:  python -m postproc.mpm_column [--out docs/validation] [--nranks 1]

Exact static solution (uniaxial strain, M = lambda + 2 mu, column height H, base fixed):
    sigma_yy = -rho g (H - y),   u_y = -(rho g / M)(H y - y^2 / 2),   sigma_xx = nu/(1-nu) sigma_yy.
Prints, at t = 1 s: the largest |sigma_yy - exact| over all particles relative to rho g H, the
largest |u_y - exact| relative to the exact top displacement, the ratio sigma_xx / sigma_yy, and
the residual oscillation of the top (half peak-to-peak of the top position over the last 0.1 s)
relative to the exact top displacement. The 1D column is also run without damping: its residual
oscillation after the linear ramp is compared with the single-mode estimate
|sin(w t_r / 2)| / (w t_r / 2), w = pi c / (2 H), c = sqrt(M / rho). Writes mpm_column.png/.csv.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.analytic import oedometer_modulus
from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpm_common import particles, series
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELISTS = os.path.join(ROOT, "namelists")
RHO, G, E, NU, H, RAMP = 2000.0, 9.81, 1.0e7, 0.3, 1.0, 0.5


def ramp_residual() -> float:
    """Residual oscillation / static displacement of the first mode after a linear ramp."""
    c = np.sqrt(oedometer_modulus(E, NU) / RHO)
    half = 0.5 * np.pi * c / (2.0 * H) * RAMP
    return float(abs(np.sin(half)) / half)


def run_column(workdir: str, dim: int, nranks: int = 1, shape: str = "gimp",
               damping: float = 0.1) -> dict:
    """Run the 1D or 2D column; return the errors and the profiles."""
    name = f"column{dim}d"
    out = os.path.join(workdir, f"{name}_{shape}_r{nranks}_a{damping}")
    run_mpmice([os.path.join(NAMELISTS, f"mpm_column_{dim}d.nml"),
                "--set", f"&run output_dir = '{out}' /",
                "--set", f"&mpm local_damping = {damping!r} /",
                "--set", f"&numerics shape_function = '{shape}' /"], nranks=nranks, cwd=workdir)
    paths = list_dumps(out, name)
    _, p0 = particles(paths[0], "soil")
    time, p1 = particles(paths[-1], "soil")
    y0 = p0["y"]
    u = p1["y"] - y0
    m = oedometer_modulus(E, NU)
    u_exact = -(RHO * G / m) * (H * y0 - 0.5 * y0 ** 2)
    s_exact = -RHO * G * (H - y0)
    utop = RHO * G * H ** 2 / (2.0 * m)
    s = series(out, name)
    window = s["time"] > (RAMP + 0.05 if damping == 0.0 else s["time"][-1] - 0.1)
    top = s["ymax"][window]
    return {
        "dim": dim, "shape": shape, "damping": damping, "time": time, "y": y0, "syy": p1["stress_yy"],
        "sxx": p1["stress_xx"], "u": u, "u_exact": u_exact, "s_exact": s_exact,
        "stress_error": float(np.max(np.abs(p1["stress_yy"] - s_exact)) / (RHO * G * H)),
        "disp_error": float(np.max(np.abs(u - u_exact)) / utop),
        "k0_ratio": float(np.median(p1["stress_xx"] / p1["stress_yy"])),
        "oscillation": float(0.5 * (top.max() - top.min()) / utop),
    }


def main(argv=None) -> int:
    parser = study_parser(__doc__, nranks=True)
    args = parse_study_args(parser, argv)
    plt = pyplot()

    rows = []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    with tempfile.TemporaryDirectory() as work:
        for dim in (1, 2):
            r = run_column(work, dim, args.nranks)
            rows.append(r)
            print(f"{dim}D: max |sigma_yy - exact| / (rho g H) = {r['stress_error']:.3e}, "
                  f"max |u - exact| / u_top = {r['disp_error']:.3e}, sigma_xx/sigma_yy = "
                  f"{r['k0_ratio']:.6f} (exact {NU / (1 - NU):.6f}), residual oscillation / "
                  f"u_top = {r['oscillation']:.3e}")
            order = np.argsort(r["y"])
            axes[0].plot(-r["syy"][order] / 1e3, r["y"][order], ".", ms=3, label=f"MPM {dim}D")
            axes[1].plot(-r["u"][order] * 1e3, r["y"][order], ".", ms=3, label=f"MPM {dim}D")
        r = run_column(work, 1, args.nranks, damping=0.0)
        rows.append(r)
        print(f"1D undamped: residual oscillation after the ramp / u_top = {r['oscillation']:.3e} "
              f"(single-mode estimate {ramp_residual():.3e})")
        y = np.linspace(0.0, H, 200)
        axes[0].plot(RHO * G * (H - y) / 1e3, y, "k-", lw=1, label="exact")
        m = oedometer_modulus(E, NU)
        axes[1].plot((RHO * G / m) * (H * y - 0.5 * y ** 2) * 1e3, y, "k-", lw=1, label="exact")
    axes[0].set_xlabel("-sigma_yy [kPa]")
    axes[1].set_xlabel("-u_y [mm]")
    for ax in axes:
        ax.set_ylabel("y [m]")
        ax.legend()
    fig.suptitle("Elastic column under self-weight, t = 1 s (gravity ramped over 0.5 s, "
                 "local damping 0.1)")
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_column.png"), dpi=120)
    with open(os.path.join(args.out, "mpm_column.csv"), "w", encoding="utf-8") as f:
        f.write("dim,damping,stress_error,disp_error,k0_ratio,oscillation\n")
        for r in rows:
            f.write(f"{r['dim']},{r['damping']},{r['stress_error']:.6e},{r['disp_error']:.6e},"
                    f"{r['k0_ratio']:.9f},{r['oscillation']:.6e}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
