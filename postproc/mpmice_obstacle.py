"""Debris flow against an obstacle (issue 7, scene 2): the sand slide of the underwater scene
meets a rigid block on the floor, once under water (namelists/mpmice_obstacle_water_2d.nml) and
once as a saturated slide in air (namelists/mpmice_obstacle_air_2d.nml).

Usage:  python -m postproc.mpmice_obstacle --dir RUN_DIR [--dir RUN_DIR ...] [--out DIR]

Reads each run's `<name>_contact_force.csv` (the force the sand exerts through the contact on
each rigid body, per step; per 0.04 m of depth; the fluid's pressure on the body not included)
and its dumps (run-out: the largest x of the sand particles), prints the peak force on the block
and the run-out per run, and writes obstacle_force.png (force on the block and front vs time)
and, per run, obstacle_snapshots_<run>.png (the water's volume fraction, the sand's particles
coloured by their excess pore pressure and the block at --times, default 0.5 1.0 1.5 2.0 s:
the nearest dump of each).
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc.mpmice_io import cell_centres, list_dumps, read_dump

NAME = "obstacle"
SAND = "sand"
DEPTH = 0.04  # m, the grid's depth
BLOCK = (2.8, 2.9, 0.0, 0.1)  # m, the rigid block: x from, x to, y from, y to
BED = ([0.0, 0.0, 1.0, 2.5, 4.0], [0.0, 1.5, 1.5, 0.0, 0.0])  # m, the bed's outline
P_ATM, RHO_W, G, LEVEL = 101325.0, 999.8, 9.81, 1.6  # Pa, kg/m^3, m/s^2, m (still water)


def contact_force(run_dir: str) -> dict[str, np.ndarray]:
    """Columns of `<name>_contact_force.csv`: time [s] and `<solid>_fx/_fy/_fz` [N]."""
    data = np.genfromtxt(os.path.join(run_dir, f"{NAME}_contact_force.csv"), delimiter=",",
                         names=True)
    return {key: np.atleast_1d(data[key]) for key in data.dtype.names}


def front_history(run_dir: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, largest x of the sand particles) over the dumps of a run."""
    t, x = [], []
    for path in list_dumps(run_dir, NAME):
        d = read_dump(path)
        t.append(d["time"])
        x.append(float(np.max(d["particles"][SAND]["x"])))
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
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return [dumps_t[i] for i in chosen]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True, help="run directory")
    parser.add_argument("--out", default=None)
    parser.add_argument("--times", type=float, nargs="+", default=[0.5, 1.0, 1.5, 2.0])
    args = parser.parse_args(argv)
    out = args.out or args.dir[0]
    os.makedirs(out, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for run_dir in args.dir:
        f = contact_force(run_dir)
        t, front = front_history(run_dir)
        fx = f["block_fx"] / DEPTH
        label = os.path.basename(os.path.normpath(run_dir))
        print(f"{label}: peak horizontal force on the block {np.max(np.abs(fx)):.1f} N/m "
              f"(t = {f['time'][np.argmax(np.abs(fx))]:.3f} s); run-out (front) "
              f"{front[-1]:.3f} m at t = {t[-1]:.2f} s")
        top.plot(f["time"], fx, label=label)
        bottom.plot(t, front, "o-", label=label)
        shot = os.path.join(out, f"obstacle_snapshots_{label}.png")
        shown = snapshots(run_dir, args.times, shot, plt)
        print(f"snapshots at t = {', '.join(f'{t_s:.2f}' for t_s in shown)} s: {shot}")
    top.set_ylabel("force on the block, x [N/m]")
    top.legend(fontsize=8)
    bottom.set_ylabel("sand front x [m]")
    bottom.set_xlabel("t [s]")
    bottom.axhline(2.8, color="k", lw=0.8, ls="--")
    fig.tight_layout()
    path = os.path.join(out, "obstacle_force.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
