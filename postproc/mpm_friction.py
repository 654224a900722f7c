"""An elastic block sliding on a rigid bed with Coulomb friction (MPM, `&mpm rigid_contact =
'friction'`), against the rigid-block solution.

Usage:  python -m postproc.mpm_friction [--out docs/validation] [--mu 0 0.2 0.4 0.5 0.7] [--ramp 0.05]

Scene namelists/mpm_friction_block_2d.nml: the bed is a horizontal rigid strip, gravity is
tilted by theta = 30 deg, so the bed stands for a 30 deg slope. With gravity applied at once
(--ramp 0) a rigid block slides as x = a t^2 / 2, a = g (sin theta - mu cos theta) for
mu < tan theta, and sticks otherwise; with gravity ramped over t_r (`&mpm gravity_ramp_time`) the
acceleration grows as a t / t_r until t_r (`exact_displacement`). The numeric displacement is the
block's mass-weighted mean particle x. Prints the displacement at the end against the exact one
for each mu and writes mpm_friction.png / .csv.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpm_friction_block_2d.nml")
NAME = "friction"
G, THETA = 9.81, np.radians(30.0)


def acceleration(mu: float) -> float:
    """Sliding acceleration [m/s^2] of a rigid block on the 30 deg slope (0 when it sticks)."""
    return max(0.0, G * (np.sin(THETA) - mu * np.cos(THETA)))


def exact_displacement(t: float, mu: float, ramp: float = 0.0) -> float:
    """Displacement [m] along the slope at time t [s], gravity ramped linearly over `ramp` [s]."""
    a = acceleration(mu)
    if ramp <= 0.0:
        return 0.5 * a * t**2
    if t <= ramp:
        return a * t**3 / (6.0 * ramp)
    return a * ramp**2 / 6.0 + 0.5 * a * ramp * (t - ramp) + 0.5 * a * (t - ramp)**2


def block_history(out: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time, mean x displacement, mean x velocity) of the block over the dumps in `out`."""
    times, disp, vel = [], [], []
    x0 = None
    for path in list_dumps(out, NAME):
        d = read_dump(path)
        b = d["particles"]["block"]
        m = b["mass"]
        x = float(np.sum(m * b["x"]) / m.sum())
        x0 = x if x0 is None else x0
        times.append(d["time"])
        disp.append(x - x0)
        vel.append(float(np.sum(m * b["velocity_x"]) / m.sum()))
    return np.array(times), np.array(disp), np.array(vel)


def run(workdir: str, mu: float, ramp: float = 0.0, extra=()) -> tuple:
    """block_history of one run with friction coefficient mu."""
    out = os.path.join(workdir, f"friction_{mu:g}_{ramp:g}")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}' /",
                "--set", f"&mpm contact_friction = {mu}, gravity_ramp_time = {ramp} /",
                *extra], cwd=workdir)
    return block_history(out)


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.2, 0.4, 0.5, 0.7])
    parser.add_argument("--ramp", type=float, default=0.05)
    args = parse_study_args(parser, argv)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for mu in args.mu:
            t, x, v = run(work, mu, args.ramp)
            ts = np.linspace(0.0, t[-1], 200)
            line, = ax.plot(t, x, "o", ms=4, label=f"mu = {mu:g}")
            ax.plot(ts, [exact_displacement(s, mu, args.ramp) for s in ts], "-",
                    color=line.get_color(), lw=0.8)
            ref = exact_displacement(t[-1], mu, args.ramp)
            rows.append((mu, t[-1], x[-1], ref, v[-1]))
    print("    mu   t [s]   x MPM [m]   x exact [m]   difference   final v [m/s]")
    for mu, t, x, ref, v in rows:
        diff = f"{x / ref - 1.0:+10.2%}" if ref > 0 else f"{x - ref:+.2e} m"
        print(f"{mu:6.2f} {t:7.3f} {x:11.5f} {ref:13.5f} {diff:>12} {v:12.4f}")
    with open(os.path.join(args.out, "mpm_friction.csv"), "w") as f:
        f.write("mu,time,x_mpm,x_exact,v_final\n")
        for row in rows:
            f.write(",".join(f"{c:.6g}" for c in row) + "\n")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("displacement along the slope [m]")
    ax.set_title(f"block on a 30 deg rigid slope (lines: rigid block, gravity ramp {args.ramp} s)",
                 fontsize=8)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_friction.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
