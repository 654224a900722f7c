"""Benchmark of the coupled MPMICE step: µs per cell-step and per particle-step, split per stage,
for the 2D submerged sand block (water, air and a porous Mohr-Coulomb solid) with >= 1e5 cells and
particles, on 1 and 2 ranks.

Usage:  python -m bench.mpmice_bench [--cell 0.002] [--steps 40] [--ranks 1 2] [--csv FILE]
                                    [--balance cells|cost] [--particle-weight W]

namelists/mpmice_submerged_block_2d.nml on a finer grid: cell size 2 mm gives 500 x 250 cells;
the block is widened to 0.5 x 0.2 m, 2 x 2 particles per cell: 100,000 particles. The first
`steps` steps are timed with the run's stage timers (output excluded); per-step costs are the
maximum over ranks (wall time on 2 ranks, split along x: evenly, or with `--balance cost` where
cells + W x particles per column divides evenly, `&grid balance`). Each row also gives the mean
over ranks of every stage (`<stage> mean`) and the whole run's wall time per cell-step.
"""
from __future__ import annotations

import argparse
import os
import re
import tempfile
import time

from postproc.run_case import ROOT, run_mpmice, stage_timers

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_submerged_block_2d.nml")


def run_one(cell: float, steps: int, nranks: int, work: str, balance: str = "cells",
            weight: float = 0.5) -> dict:
    """Run `steps` steps at cell size `cell` on `nranks` ranks; return the costs per stage."""
    nx, ny = int(round(1.0 / cell)), int(round(0.5 / cell))
    out = os.path.join(work, f"c{cell}_r{nranks}")
    started = time.perf_counter()
    result = run_mpmice([NAMELIST,
                         "--set", f"&grid ncells = {nx}, {ny}, 1, dims = {nranks}, 1, 1, "
                                  f"balance = '{balance}', particle_weight = {weight} /",
                         "--set", "&solid name='sand', upper = 0.5, 0.2, 0.025 /",
                         "--set", f"&run output_dir = '{out}', max_steps = {steps}, "
                                  "output_interval = 10.0, checkpoint_interval = 0.0 /"],
                        nranks=nranks, cwd=work, timeout=1800)
    wall = time.perf_counter() - started
    stages = stage_timers(result.stdout)
    means = stage_timers(result.stdout, column="mean")
    particles = int(re.search(r"sand \(mohr_coulomb\): (\d+) particles", result.stdout).group(1))
    taken = stages["ICE advection"][0]
    timed = {k: v for k, v in stages.items() if k != "output and checkpoint"
             and not k.startswith("ICE  of which")}
    total = sum(v[1] for v in timed.values())
    row = {"ranks": nranks, "cells": nx * ny, "particles": particles, "steps": taken,
           "us_per_cell_step": 1e6 * total / (taken * nx * ny),
           "us_per_particle_step": 1e6 * total / (taken * particles)}
    for k, v in stages.items():
        if k != "output and checkpoint":
            row[k] = 1e6 * v[1] / (taken * nx * ny)
    for k, v in means.items():
        if k != "output and checkpoint":
            row[k + " mean"] = 1e6 * v[1] / (taken * nx * ny)
    row["whole run wall"] = 1e6 * wall / (taken * nx * ny)
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cell", type=float, default=0.002)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--balance", choices=["cells", "cost"], default="cells")
    parser.add_argument("--particle-weight", type=float, default=0.5)
    parser.add_argument("--csv", default=os.path.join(ROOT, "bench", "results",
                                                      "mpmice_bench.csv"))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as work:
        rows = [run_one(args.cell, args.steps, n, work, args.balance, args.particle_weight)
                for n in args.ranks]
    keys = [k for k in rows[0] if k not in ("ranks", "cells", "particles", "steps")]
    print(f"cells {rows[0]['cells']}, particles {rows[0]['particles']}, steps {rows[0]['steps']}")
    print(f"{'stage [us per cell-step]':>36} " + " ".join(f"{r['ranks']:>8} rk" for r in rows))
    for k in keys:
        print(f"{k:>36} " + " ".join(f"{r.get(k, float('nan')):11.3f}" for r in rows))
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "w", encoding="utf-8") as f:
        f.write("ranks,cells,particles,steps," + ",".join(k.replace(" ", "_").replace(",", "")
                                                          for k in keys) + "\n")
        for r in rows:
            f.write(f"{r['ranks']},{r['cells']},{r['particles']},{r['steps']}," +
                    ",".join(f"{r.get(k, float('nan')):.6g}" for k in keys) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
