"""Block balancing on the debris flow: the first steps of namelists/mpmice_debris_flow_2d.nml at a
coarse cell size on 1 rank and on 2 ranks with `&grid balance = 'cells'` and `'cost'`; per stage
the largest and the mean time over ranks, the whole run's wall time and the efficiency
t1 / (2 t2) of the timed stages.

Usage:  python -m bench.debris_balance [--cell 0.01] [--steps 200] [--particle-weight 0.5]
                                       [--runs 1 2c 2w 2y 2b 2a] [--block-cells-x N1,N2]
                                       [--restart CHECKPOINT] [--csv FILE]

Runs: `1` one rank, `2c` two ranks split evenly in x, `2w` two ranks cut in x by cost, `2y` two
ranks split evenly in y (`dims = 1, 2, 1`), `2b` two ranks cut in x at `--block-cells-x`
(`&grid block_cells_x`), `2a` two ranks cut by cost with the layout (x or y cut) chosen by the
model (`dims = 0, 0, 0`). `--restart` starts every run from a checkpoint of
the same cell size (the flow in motion; `--steps` then counts the steps of the run). With
MPMICE_CPU_TIMERS=1 the stage timers measure CPU time (the machine shared with other jobs);
on 2 ranks a rank's time then includes polling while it waits for the other.
"""
from __future__ import annotations

import argparse
import os
import re
import tempfile
import time

from postproc.run_case import ROOT, run_mpmice, stage_timers

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_debris_flow_2d.nml")
#: run label: ranks, `&grid balance`, `&grid dims`
LABELS = {"1": (1, "cells", "0, 0, 0"), "2c": (2, "cells", "2, 1, 1"),
          "2w": (2, "cost", "2, 1, 1"), "2y": (2, "cells", "1, 2, 1"),
          "2b": (2, "cells", "2, 1, 1"), "2a": (2, "cost", "0, 0, 0")}


def run_one(cell: float, steps: int, label: str, weight: float, work: str,
            restart: str = "", block_cells_x: str = "") -> dict:
    """Run `steps` steps at cell size `cell` (from `restart` when given; run `2b` cut at
    `block_cells_x`); return the stage times and the blocks."""
    nranks, balance, dims = LABELS[label]
    nx, ny = int(round(4.0 / cell)), int(round(2.0 / cell))
    cut = f", block_cells_x = {block_cells_x}" if label == "2b" else ""
    out = os.path.join(work, f"c{cell}_{label}")
    started = time.perf_counter()
    result = run_mpmice((["--restart", restart] if restart else [NAMELIST]) +
                        ["--set", f"&grid ncells = {nx}, {ny}, 1, balance = '{balance}', "
                                  f"particle_weight = {weight}, dims = {dims}{cut} /",
                         "--set", f"&run output_dir = '{out}', max_steps = {steps}, "
                                  "output_interval = 10.0, checkpoint_interval = 0.0, "
                                  "progress_interval = 0.0 /"],
                        nranks=nranks, cwd=work, timeout=3600)
    wall = time.perf_counter() - started
    blocks = re.search(r"blocks balanced by cost: (.*)", result.stdout)
    worst = stage_timers(result.stdout)
    mean = stage_timers(result.stdout, column="mean")
    keys = [k for k in worst if k != "output and checkpoint" and "of which" not in k]
    return {"label": label, "cells": nx * ny, "steps": worst["ICE advection"][0],
            "blocks": blocks.group(1) if blocks else (block_cells_x if cut else "even"),
            "max": {k: worst[k][1] for k in keys}, "mean": {k: mean[k][1] for k in keys},
            "timed": sum(worst[k][1] for k in keys), "wall": wall}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cell", type=float, default=0.01)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--particle-weight", type=float, default=0.5)
    parser.add_argument("--runs", nargs="+", default=["1", "2c", "2w"], choices=list(LABELS))
    parser.add_argument("--block-cells-x", default="",
                        help="the x cut of run 2b, e.g. 380,420 (cells of each block)")
    parser.add_argument("--restart", default="",
                        help="checkpoint of a run at the same cell size to start from")
    parser.add_argument("--csv", default="")
    args = parser.parse_args(argv)
    restart = os.path.abspath(args.restart) if args.restart else ""
    if "2b" in args.runs and not args.block_cells_x:
        parser.error("run 2b needs --block-cells-x")
    with tempfile.TemporaryDirectory() as work:
        rows = [run_one(args.cell, args.steps, r, args.particle_weight, work, restart,
                        args.block_cells_x) for r in args.runs]
    print(f"cells {rows[0]['cells']}, steps {rows[0]['steps']}")
    print(f"{'stage [s]: max / mean over ranks':>36} " + " ".join(f"{r['label']:>15}" for r in rows))
    for k in rows[0]["max"]:
        print(f"{k:>36} " + " ".join(f"{r['max'].get(k, 0):7.2f}/{r['mean'].get(k, 0):7.2f}"
                                     for r in rows))
    print(f"{'timed stages (sum of max)':>36} " + " ".join(f"{r['timed']:15.2f}" for r in rows))
    print(f"{'whole run, wall':>36} " + " ".join(f"{r['wall']:15.2f}" for r in rows))
    one = [r for r in rows if r["label"] == "1"]
    for r in rows:
        print(f"{r['label']}: blocks {r['blocks']}" + (
            f", efficiency {one[0]['timed'] / (2 * r['timed']):.1%} (timed stages), "
            f"{one[0]['wall'] / (2 * r['wall']):.1%} (whole run, wall)"
            if one and r["label"] != "1" else ""))
    if args.csv:
        with open(args.csv, "w", encoding="utf-8") as f:
            f.write("run,stage,max_s,mean_s\n")
            for r in rows:
                for k in r["max"]:
                    f.write(f"{r['label']},{k},{r['max'][k]:.6g},{r['mean'][k]:.6g}\n")
                f.write(f"{r['label']},whole run wall,{r['wall']:.6g},{r['wall']:.6g}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
