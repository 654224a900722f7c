"""Debris flow against an obstacle (issue 7, scene 2): the sand slide of the underwater scene
meets a rigid block on the floor, once under water (namelists/mpmice_obstacle_water_2d.nml) and
once as a saturated slide in air (namelists/mpmice_obstacle_air_2d.nml).

Usage:  python -m postproc.mpmice_obstacle --dir RUN_DIR [--dir RUN_DIR ...] [--out DIR]

Reads each run's `<name>_contact_force.csv` (the force the sand exerts through the contact on
each rigid body, per step; per 0.04 m of depth; the fluid's pressure on the body not included)
and its dumps (run-out: the largest x of the sand particles), prints the peak force on the block
and the run-out per run, and writes obstacle_force.png (force on the block and front vs time).
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump

NAME = "obstacle"
SAND = "sand"
DEPTH = 0.04  # m, the grid's depth


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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True, help="run directory")
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
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
    top.set_ylabel("force on the block, x [N/m]")
    top.legend(fontsize=8)
    bottom.set_ylabel("sand front x [m]")
    bottom.set_xlabel("t [s]")
    bottom.axhline(2.8, color="k", lw=0.8, ls="--")
    fig.tight_layout()
    path = os.path.join(args.out or args.dir[0], "obstacle_force.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
