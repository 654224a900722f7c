"""Measured strong and weak scaling of the coupled MPMICE step on the debris-flow scene
(namelists/mpmice_debris_flow_2d.nml: water, air, a Mohr-Coulomb sand wedge on a rigid bed), the
inputs of bench/scaling_model.py.

Usage:  python -m bench.scaling_bench [--steps 20] [--repeat 2] [--csv FILE]

Runs (the first `steps` steps from rest; stage timers of the run, maximum over ranks, output
excluded; the minimum over `repeat` runs of each configuration, the machine being shared):
* strong: 400 x 200 cells (10 mm) on 1, 2 and 4 ranks (4 ranks oversubscribe the 2-core
  development machine: labelled `oversubscribed`);
* weak: ~20,000 cells per rank: 200 x 100 on 1 rank, 283 x 141 on 2, 400 x 200 on 4;
* size: 1 rank at 200 x 100, 400 x 200 and 800 x 400 (5 mm, the paper's cell size) for the
  growth of the pressure solve's PCG iterations and of the per-cell costs with problem size;
* bed: 1 rank at 400 x 200 with the sand wedge shrunk to 21 particles: the cost of the rigid
  bed's particles, to split the particle stages between rigid and sand particles.
Writes one row per run: cells, particles of each solid, per-step seconds per stage, pressure
solves and PCG iterations per step.
"""
from __future__ import annotations

import argparse
import os
import re
import tempfile

from postproc.run_case import ROOT, run_mpmice, stage_timers

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_debris_flow_2d.nml")
# a rank waiting in MPI yields its core (on the shared 2-core machine a busy-polling rank took
# the core from the rank it waited for: 2 ranks measured 3x slower than 1)
os.environ.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")
#: cores of the development machine: runs on more ranks are oversubscribed
CORES = 2

STAGES = {  # short column names of the stage timers
    "ICE equilibration": "equil", "ICE face velocities": "face",
    "ICE pressure (hypre)": "pressure", "ICE  of which operator": "p_operator",
    "ICE  of which PCG solve": "p_pcg", "ICE Lagrangian values": "lagrange",
    "ICE advection": "advect", "ICE halo exchange": "ice_halo",
    "MPM particle to grid": "p2g", "MPM nodal solve": "nodal",
    "MPM grid to particle + stress": "g2p", "MPM migration": "migrate",
    "MPMICE solid cells": "solid_cells", "MPMICE faces to nodes": "faces_to_nodes",
}


#: the sand wedge shrunk to a 3 cm triangle (21 particles at 10 mm): the rigid bed's own cost
TINY_SAND = "&solid name = 'sand', polygon_x = 1.0, 1.03, 1.03, polygon_y = 1.5, 1.5, 1.47 /"


def run_one(nx: int, ny: int, nranks: int, steps: int, work: str, kind: str) -> dict:
    """`steps` steps of the debris flow on an nx x ny grid and `nranks` ranks (kind 'bed':
    the sand shrunk to TINY_SAND)."""
    out = os.path.join(work, f"{kind}_{nx}x{ny}_r{nranks}")
    extra = ["--set", TINY_SAND] if kind == "bed" else []
    result = run_mpmice([NAMELIST] + extra + [
                         "--set", f"&grid ncells = {nx}, {ny}, 1 /",
                         "--set", f"&run output_dir = '{out}', max_steps = {steps}, "
                                  "output_interval = 100.0, checkpoint_interval = 0.0, "
                                  "progress_interval = 1000.0 /"],
                        nranks=nranks, cwd=work, timeout=1800)
    stages = stage_timers(result.stdout)
    taken = stages["ICE advection"][0]
    parts = {name: int(n) for name, n in
             re.findall(r"mpm: solid (\w+) \(\w+\): (\d+) particles", result.stdout)}
    solves = int(re.search(r"ICE: (\d+) pressure solves", result.stdout).group(1))
    pcg = float(re.search(r"PCG iterations mean ([\d.]+)", result.stdout).group(1))
    dims = re.search(r"blocks (\d+) x (\d+) x (\d+)", result.stdout).groups()
    row = {"kind": kind, "ranks": nranks, "oversubscribed": int(nranks > CORES),
           "dims": "x".join(dims), "nx": nx, "ny": ny, "cells": nx * ny,
           "sand_particles": parts.get("sand", 0), "bed_particles": parts.get("bed", 0),
           "steps": taken, "solves_per_step": solves / taken, "pcg_per_solve": pcg}
    total = 0.0
    for stage, short in STAGES.items():
        sec = stages.get(stage, (0, 0.0))[1] / taken
        row[f"{short}_s"] = sec
        if not short.startswith("p_"):
            total += sec
    row["step_s"] = total
    return row


CONFIGS = [("strong", 400, 200, 1), ("strong", 400, 200, 2), ("strong", 400, 200, 4),
           ("weak", 200, 100, 1), ("weak", 283, 141, 2),
           ("size", 800, 400, 1), ("bed", 400, 200, 1)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--csv", default=os.path.join(ROOT, "bench", "results",
                                                      "scaling_bench.csv"))
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for kind, nx, ny, nranks in CONFIGS:
            runs = [run_one(nx, ny, nranks, args.steps, work, kind) for _ in range(args.repeat)]
            best = min(runs, key=lambda r: r["step_s"])
            rows.append(best)
            times = ", ".join(f"{r['step_s'] * 1e3:.2f}" for r in runs)
            print(f"{kind:6s} {nx}x{ny} {nranks} rank(s) [{best['dims']}]: "
                  f"{best['step_s'] * 1e3:8.2f} ms per step (runs: {times}), "
                  f"{best['pcg_per_solve']:.1f} PCG its x {best['solves_per_step']:.2f} solves",
                  flush=True)
    # the weak series shares the 4-rank 400 x 200 run, the size series the 1-rank runs
    extra = [dict(r, kind="weak") for r in rows if r["kind"] == "strong" and r["ranks"] == 4]
    extra += [dict(r, kind="size") for r in rows
              if (r["kind"] in ("strong", "weak")) and r["ranks"] == 1]
    rows += extra
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    keys = list(rows[0])
    with open(args.csv, "w", encoding="utf-8") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(f"{r[k]:.6g}" if isinstance(r[k], float) else str(r[k])
                             for k in keys) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
