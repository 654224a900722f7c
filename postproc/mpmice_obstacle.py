"""Debris flow against an obstacle: the sand slide of the underwater scene
meets a rigid block on the floor, once under water (namelists/mpmice_obstacle_water_2d.nml) and
once as a saturated slide in air (namelists/mpmice_obstacle_air_2d.nml).

Usage:  python -m postproc.mpmice_obstacle --dir RUN_DIR [--dir RUN_DIR ...] [--out DIR]

Reads each run's `<name>_contact_force.csv` (per step and rigid body, N per 0.04 m of depth:
the force the sand exerts through the contact, `<solid>_fx/_fy/_fz`, and the fluids' pressure
force, `<solid>_fluid_fx/_fy/_fz`; files written before the fluid force have no such columns,
read as zero) and its dumps (run-out: the largest x of the sand particles), prints per run the
horizontal force on the block - contact, fluid pressure and total: first contact, largest 10 ms
mean, impulse over the run and over --window - and the run-out, and writes obstacle_force.png
(horizontal force on the block, contact, fluid and total, 10 ms means, and the front vs time)
and, per run, obstacle_snapshots_<run>.png (the water's volume fraction, the sand's particles
coloured by their excess pore pressure and the block at --times, default 0.5 1.0 1.5 2.0 s:
the nearest dump of each).
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.measures import front
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_files import read_step_csv

NAME = "obstacle"
SAND = "sand"
DEPTH = 0.04  # m, the grid's depth
BLOCK = (2.8, 2.9, 0.0, 0.1)  # m, the rigid block: x from, x to, y from, y to
BED = ([0.0, 0.0, 1.0, 2.5, 4.0], [0.0, 1.5, 1.5, 0.0, 0.0])  # m, the bed's outline
P_ATM, RHO_W, G, LEVEL = 101325.0, 999.8, 9.81, 1.6  # Pa, kg/m^3, m/s^2, m (still water)


def contact_force(run_dir: str) -> dict[str, np.ndarray]:
    """Columns of `<name>_contact_force.csv`: time [s] and `<solid>_fx/_fy/_fz` [N]."""
    return read_step_csv(os.path.join(run_dir, f"{NAME}_contact_force.csv"))


def block_forces(f: dict[str, np.ndarray], component: str = "fx") -> dict[str, np.ndarray]:
    """The block's contact, fluid-pressure and total force component [N per 0.04 m] per step
    (the fluid part zero where the file has no fluid columns)."""
    contact = f[f"block_{component}"]
    fluid = f.get(f"block_fluid_{component}", np.zeros_like(contact))
    return {"contact": contact, "fluid": fluid, "total": contact + fluid}


def impulse(time: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Cumulative impulse [N s] at the rows' times: each row's force held over its step (the
    step from the previous row's time, the first from 0)."""
    dt = np.diff(np.concatenate(([0.0], time)))
    return np.cumsum(force * dt)


def running_mean(time: np.ndarray, force: np.ndarray, width: float = 0.01) -> np.ndarray:
    """Mean of `force` over the `width` seconds up to each row's time (by its impulse)."""
    cum = impulse(time, force)
    return (cum - np.interp(time - width, time, cum, left=0.0)) / width


def largest_mean(time: np.ndarray, force: np.ndarray, width: float = 0.01) -> tuple[float, float]:
    """Largest mean of `force` over a window of `width` seconds (by its impulse) and the
    window's end time [s]."""
    mean = running_mean(time, force, width)
    valid = time >= time[0] + width
    if not np.any(valid):
        return float("nan"), float("nan")
    index = int(np.argmax(np.where(valid, mean, -np.inf)))
    return float(mean[index]), float(time[index])


def impulse_between(time: np.ndarray, force: np.ndarray, t0: float, t1: float) -> float:
    """Impulse [N s] over [t0, t1]."""
    cum = impulse(time, force)
    return float(np.interp(t1, time, cum, left=0.0) - np.interp(t0, time, cum, left=0.0))


def front_history(run_dir: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, largest x of the sand particles) over the dumps of a run (the slide moves toward
    +x, :func:`postproc.measures.front`)."""
    t, x = [], []
    for path in list_dumps(run_dir, NAME):
        d = read_dump(path)
        t.append(d["time"])
        x.append(front(d["particles"][SAND], 0, +1))
    return np.array(t), np.array(x)


def snapshots(run_dir: str, times: list[float], path: str, plt) -> list[float]:
    """Write the snapshots of a run at the dumps nearest to `times` to `path`; returns the
    dumps' times [s]."""
    paths = list_dumps(run_dir, NAME)
    dumps_t = [read_dump(p)["time"] for p in paths]
    chosen = sorted({int(np.argmin(np.abs(np.array(dumps_t) - t))) for t in times})
    fig, axes = plt.subplots(len(chosen), 1, figsize=(8, 3.6 * len(chosen)), squeeze=False)
    for ax, index in zip(axes[:, 0], chosen):
        d = read_dump(paths[index])
        x, y, _ = cell_centres(d)
        water = d["cell"]["water/volume_fraction"][:, :, 0]
        ax.pcolormesh(x, y, water.T, cmap="Blues", vmin=0.0, vmax=1.0, shading="nearest")
        p = d["particles"][SAND]
        excess = (p["pore_pressure"] - (P_ATM + RHO_W * G * np.maximum(LEVEL - p["y"], 0.0)))
        sc = ax.scatter(p["x"], p["y"], c=excess / 1e3, s=1, cmap="coolwarm", vmin=-20, vmax=20)
        ax.plot(*BED, "k-", lw=1)
        x0, x1, y0, y1 = BLOCK
        ax.fill([x0, x1, x1, x0], [y0, y0, y1, y1], color="k")
        ax.set_aspect("equal")
        ax.set_ylim(0.0, 2.0)
        ax.set_title(f"t = {d['time']:.2f} s", fontsize=9)
        fig.colorbar(sc, ax=ax, label="excess pore pressure [kPa]", fraction=0.03)
    fig.tight_layout()
    save_figure(fig, path, dpi=100)
    return [dumps_t[i] for i in chosen]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True, help="run directory")
    parser.add_argument("--out", default=None)
    parser.add_argument("--times", type=float, nargs="+", default=[0.5, 1.0, 1.5, 2.0])
    parser.add_argument("--window", type=float, nargs=2, default=[1.3, 2.0],
                        help="impulse window [s] (default 1.3 2.0: the impact under water)")
    args = parser.parse_args(argv)
    out = args.out or args.dir[0]
    os.makedirs(out, exist_ok=True)
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for run_dir in args.dir:
        f = contact_force(run_dir)
        t, front = front_history(run_dir)
        time = f["time"]
        parts = block_forces(f)
        label = os.path.basename(os.path.normpath(run_dir))
        touched = np.nonzero(parts["contact"] != 0.0)[0]
        first = f"{time[touched[0]]:.3f} s" if touched.size else "none"
        print(f"{label}: horizontal force on the block [N per {DEPTH} m of depth], first contact "
              f"{first}")
        t0, t1 = args.window
        for name, fx in parts.items():
            peak, end = largest_mean(time, fx)
            print(f"  {name:8s} largest 10 ms mean {peak:9.2f} N ({end - 0.01:.3f}-{end:.3f} s), "
                  f"single-step peak {fx[np.argmax(np.abs(fx))]:9.2f} N, impulse "
                  f"{impulse(time, fx)[-1]:7.3f} N s ({t0}-{t1} s: "
                  f"{impulse_between(time, fx, t0, t1):7.3f} N s)")
        print(f"  run-out (front) {front[-1]:.3f} m at t = {t[-1]:.2f} s")
        # the fluid force's step-to-step noise (sound waves) hides everything: 10 ms means
        for name, style in (("total", "-"), ("contact", "--"), ("fluid", ":")):
            top.plot(time, running_mean(time, parts[name]) / DEPTH, style, lw=1,
                     label=f"{label} {name}")
        bottom.plot(t, front, "o-", label=label)
        shot = os.path.join(out, f"obstacle_snapshots_{label}.png")
        shown = snapshots(run_dir, args.times, shot, plt)
        print(f"snapshots at t = {', '.join(f'{t_s:.2f}' for t_s in shown)} s: {shot}")
    top.set_ylabel("force on the block, x [N/m]\n(10 ms means)")
    top.legend(fontsize=8)
    bottom.set_ylabel("sand front x [m]")
    bottom.set_xlabel("t [s]")
    bottom.axhline(2.8, color="k", lw=0.8, ls="--")
    fig.tight_layout()
    path = os.path.join(out, "obstacle_force.png")
    save_figure(fig, path)
    print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
