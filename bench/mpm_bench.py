"""Benchmark of the explicit MPM step: µs per particle-step and per cell-step, split per stage
(P2G, nodal solve, G2P + constitutive update, migration), for the 2D granular column collapse with
>= 2e5 particles, on 1 and 2 ranks.

Usage:  python -m bench.mpm_bench [--cell 0.00125] [--steps 100] [--ranks 1 2] [--csv FILE]
        [--png FILE] [--split y|x] [--balance cells|cost] [--particle-weight W]

Uses the Release executable (build/bin/mpmice or $MPMICE_EXE). The collapse of
namelists/mpm_collapse_2d.nml (Mohr-Coulomb, GIMP, 2 x 2 particles per cell) on a finer grid:
cell size 1.25 mm gives 960 x 400 cells and 204800 particles. The first `steps` steps of the
collapse are timed (the stage timers of the run; output and checkpoint time is excluded). The
per-step costs are the maximum over ranks, so on 2 ranks they are wall time, not core time; the
ranks split the domain along y (the lower rank holds 5/8 of the particles at the start, and the
wait for it shows up in the migration stage, whose collective follows G2P). `--split x` cuts
along x instead; `--balance cost` puts the cut where the modelled step cost is least (`&grid
balance`, with `--particle-weight` W, docs/performance.md "Balancing the particles").
"""
from __future__ import annotations

import argparse
import os
import re
import tempfile

from postproc.run_case import ROOT, run_mpmice, stage_timers

NAMELIST = os.path.join(ROOT, "namelists", "mpm_collapse_2d.nml")
STAGES = ("MPM particle to grid", "MPM nodal solve", "MPM grid to particle + stress",
          "MPM migration")


def run_one(cell: float, steps: int, nranks: int, work: str, split: str = "y",
            balance: str = "cells", weight: float = 0.5) -> dict:
    """Run `steps` steps at cell size `cell` on `nranks` ranks; return the costs."""
    nx, ny = int(round(1.2 / cell)), int(round(0.5 / cell))
    out = os.path.join(work, f"c{cell}_r{nranks}")
    # split along y: the column stands in the left sixth of the domain, so an x split would leave
    # one rank without particles
    dims = f"{nranks}, 1, 1" if split == "x" else f"1, {nranks}, 1"
    grid = (f"&grid ncells = {nx}, {ny}, 1, dims = {dims}, balance = '{balance}', "
            f"particle_weight = {weight} /")
    result = run_mpmice([NAMELIST, "--set", grid,
                         "--set", f"&run output_dir = '{out}', max_steps = {steps}, "
                                  "output_interval = 10.0, checkpoint_interval = 0.0 /"],
                        nranks=nranks, cwd=work, timeout=1800)
    stages = stage_timers(result.stdout)
    particles = int(re.search(r"sand \(mohr_coulomb\): (\d+) particles", result.stdout).group(1))
    taken = stages[STAGES[0]][0]
    total = sum(stages[s][1] for s in STAGES)
    row = {"cells": nx * ny, "particles": particles, "ranks": nranks, "steps": taken,
           "us_per_particle_step": 1e6 * total / (taken * particles),
           "us_per_cell_step": 1e6 * total / (taken * nx * ny)}
    for s in STAGES:
        row[s] = 1e6 * stages[s][1] / (taken * particles)
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cell", type=float, default=0.00125)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--csv", default=os.path.join(ROOT, "bench", "results", "mpm_bench.csv"))
    parser.add_argument("--split", choices=["y", "x"], default="y")
    parser.add_argument("--balance", choices=["cells", "cost"], default="cells")
    parser.add_argument("--particle-weight", type=float, default=0.5)
    parser.add_argument("--png", default=os.path.join(ROOT, "docs", "validation", "mpm_bench.png"))
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for nranks in args.ranks:
            rows.append(run_one(args.cell, args.steps, nranks, work, args.split, args.balance,
                                args.particle_weight))
    header = ["ranks", "particles", "cells", "steps", "us_per_particle_step",
              "us_per_cell_step"] + list(STAGES)
    print(" | ".join(header))
    for r in rows:
        print(" | ".join(f"{r[k]:.3f}" if isinstance(r[k], float) else str(r[k]) for k in header))
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "w", encoding="utf-8") as f:
        f.write(",".join(h.replace(" ", "_").replace("+", "and") for h in header) + "\n")
        for r in rows:
            f.write(",".join(f"{r[k]:.6g}" if isinstance(r[k], float) else str(r[k])
                             for k in header) + "\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    bottom = [0.0] * len(rows)
    labels = [f"{r['ranks']} rank(s)" for r in rows]
    for s in STAGES:
        values = [r[s] for r in rows]
        ax.bar(labels, values, bottom=bottom, label=s)
        bottom = [b + v for b, v in zip(bottom, values)]
    ax.axhline(2.5, color="k", ls="--", lw=1, label="target 2.5 µs")
    ax.set_ylabel("µs per particle-step (wall)")
    ax.set_title(f"MPM collapse, {rows[0]['particles']} particles")
    ax.legend(fontsize=7)
    fig.tight_layout()
    os.makedirs(os.path.dirname(args.png), exist_ok=True)
    fig.savefig(args.png, dpi=120)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
