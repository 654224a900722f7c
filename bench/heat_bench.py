"""Benchmark of the implicit heat-conduction step (hypre PCG + PFMG): µs per cell-step, split per
pipeline stage, and PCG iterations per solve, on 1 and 2 ranks.

Usage:  python -m bench.heat_bench [--cells 256 512] [--steps 50] [--ranks 1 2] [--csv FILE]

Uses the Release executable (build/bin/mpmice or $MPMICE_EXE). Crank-Nicolson, fixed dt, no
output between the first and last dump (output time is reported separately).
"""
from __future__ import annotations

import argparse
import os
import re
import tempfile

from postproc.run_case import ROOT, run_mpmice, stage_timers

NAMELIST = os.path.join(ROOT, "namelists", "heat_conduction_2d.nml")


def run_one(n: int, steps: int, nranks: int, work: str) -> dict:
    dt = 0.016 / n
    out = os.path.join(work, f"n{n}_r{nranks}")
    result = run_mpmice([NAMELIST, "--set", f"&grid ncells = {n}, {n}, 1, upper = 1.0, 1.0, 1.0 /",
                         "--set", f"&time dt_init = {dt!r}, dt_max = {dt!r} /",
                         "--set", f"&run output_dir = '{out}', end_time = {steps * dt!r}, "
                                  "output_interval = 0.0, checkpoint_interval = 0.0 /"],
                        nranks=nranks, cwd=work)
    stages = {name: seconds for name, (_, seconds) in stage_timers(result.stdout).items()}
    iterations = float(re.search(r"PCG iterations mean ([\d.]+)", result.stdout).group(1))
    cell_steps = n * n * steps
    return {"cells": n * n, "ranks": nranks, "steps": steps, "iterations": iterations,
            "stages_us": {k: 1e6 * v / cell_steps for k, v in stages.items()}}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[256, 512])
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--csv", default=os.path.join(ROOT, "bench", "results", "heat_bench.csv"))
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for n in args.cells:
            for r in args.ranks:
                rows.append(run_one(n, args.steps, r, work))
    stages = ["assemble", "halo exchange", "implicit solve (hypre)", "output and checkpoint"]
    header = "cells,ranks,pcg_iterations," + ",".join(s.replace(" ", "_") + "_us" for s in stages) \
        + ",step_us_without_output"
    lines = [header]
    print(f"{'cells':>8} {'ranks':>5} {'PCG it':>7} " + " ".join(f"{s[:14]:>15}" for s in stages)
          + f" {'step (no output)':>17}   [µs per cell-step]")
    for row in rows:
        values = [row["stages_us"].get(s, 0.0) for s in stages]
        step = sum(values[:3])
        print(f"{row['cells']:8d} {row['ranks']:5d} {row['iterations']:7.2f} "
              + " ".join(f"{v:15.4f}" for v in values) + f" {step:17.4f}")
        lines.append(f"{row['cells']},{row['ranks']},{row['iterations']:.2f},"
                     + ",".join(f"{v:.5f}" for v in values) + f",{step:.5f}")
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")
    print(f"wrote {args.csv}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
