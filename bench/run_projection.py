"""Wall time of a whole run projected from short runs started at its checkpoints, per
configuration: what a change of the decomposition or of the solver settings would make of a
run that took hours, measured in minutes.

Usage:  python -m bench.run_projection RUN_DIR [--samples 5] [--steps 200] [--ranks 2]
                                          [--config LABEL [SET ...]] ... [--csv FILE]

RUN_DIR holds a finished run (its `<name>_checkpoint_<step>.h5` files; the last one gives the
run's steps). `--samples` checkpoints spread evenly over the steps (the last excluded: the run
ends there) each start `--steps` steps on `--ranks` ranks for every configuration: a label and
the `--set` groups it adds to the checkpoint's own input (default: `as-run`, none; and `cost`,
`&grid balance = 'cost', dims = 0, 0, 0 /`). The seconds per step come from the progress lines
(wall clock from the first step's line to the last one's: the start-up and the reading of the
checkpoint left out); each sample stands for the run's steps nearer to it than to the other
samples, and the projection is the sum over the samples of their steps x seconds per step. The
machine should be otherwise idle.
"""
from __future__ import annotations

import argparse
import glob
import os
import re
import tempfile

from postproc.run_case import run_mpmice

#: ``step N  t = T s  dt = DT s  P%  wall W s  ETA E s`` (the driver's progress line)
PROGRESS = re.compile(r"^step\s+(\d+)\s+t =\s+(\S+) s\s+.*\s+wall\s+([\d.]+) s")
DEFAULT_CONFIGS = [["as-run"], ["cost", "&grid balance = 'cost', dims = 0, 0, 0 /"]]


def checkpoints(run_dir: str) -> list[tuple[int, str]]:
    """(step, path) of the checkpoints of `run_dir`, by step."""
    found = []
    for path in glob.glob(os.path.join(run_dir, "*_checkpoint_*.h5")):
        m = re.search(r"_checkpoint_(\d+)\.h5$", path)
        if m:
            found.append((int(m.group(1)), path))
    return sorted(found)


def pick_samples(steps: list[int], count: int) -> list[int]:
    """Indices into `steps` (without its last entry) of `count` entries spread evenly from the
    first to the last but one."""
    usable = len(steps) - 1
    if usable < 1:
        raise ValueError("the run needs at least two checkpoints")
    count = min(count, usable)
    if count == 1:
        return [0]
    return sorted({round(k * (usable - 1) / (count - 1)) for k in range(count)})


def sample_weights(sample_steps: list[int], total: int) -> list[int]:
    """The run's steps each sample stands for: those nearer to it than to the other samples
    (boundaries half-way between neighbours, the first from step 0, the last to `total`)."""
    bounds = [0] + [(a + b) // 2 for a, b in zip(sample_steps, sample_steps[1:])] + [total]
    return [b - a for a, b in zip(bounds, bounds[1:])]


def seconds_per_step(stdout: str) -> tuple[float, float]:
    """(seconds per step from the first to the last progress line, simulated time reached)."""
    rows = [(int(m.group(1)), float(m.group(2)), float(m.group(3)))
            for m in map(PROGRESS.match, stdout.splitlines()) if m]
    if len(rows) < 2 or rows[-1][0] == rows[0][0]:
        raise ValueError("fewer than two progress lines: run more steps")
    return (rows[-1][2] - rows[0][2]) / (rows[-1][0] - rows[0][0]), rows[-1][1]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--samples", type=int, default=5)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--config", nargs="+", action="append", metavar="LABEL [SET]",
                        help="a label and the --set groups of one configuration (repeatable)")
    parser.add_argument("--csv", default="")
    args = parser.parse_args(argv)
    configs = args.config or DEFAULT_CONFIGS
    found = checkpoints(args.run_dir)
    total = found[-1][0]
    picked = [found[i] for i in pick_samples([s for s, _ in found], args.samples)]
    weights = sample_weights([s for s, _ in picked], total)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for (step, path), weight in zip(picked, weights):
            for config in configs:
                label, sets = config[0], config[1:]
                out = os.path.join(work, f"{label}_{step}")
                command = ["--restart", os.path.abspath(path)]
                for text in sets:
                    command += ["--set", text]
                command += ["--set", f"&run output_dir = '{out}', max_steps = {args.steps}, "
                                     "output_interval = 10.0, checkpoint_interval = 0.0, "
                                     "progress_interval = 0.0 /"]
                result = run_mpmice(command, nranks=args.ranks, cwd=work, timeout=3600)
                per_step, reached = seconds_per_step(result.stdout)
                blocks = re.search(r"blocks balanced by cost: ([^;(]*)", result.stdout)
                rows.append({"step": step, "weight": weight, "label": label,
                             "per_step": per_step, "reached": reached,
                             "blocks": blocks.group(1).strip() if blocks else "as run"})
                print(f"from step {step:7d} ({weight} steps) {label:>12}: {per_step:.4f} s per "
                      f"step to t = {reached:.4f} s, blocks {rows[-1]['blocks']}", flush=True)
    labels = [c[0] for c in configs]
    projected = {lab: sum(r["weight"] * r["per_step"] for r in rows if r["label"] == lab)
                 for lab in labels}
    print(f"run of {total} steps on {args.ranks} ranks, projected:")
    for lab in labels:
        print(f"{lab:>12}: {projected[lab]:9.0f} s = {projected[lab] / 3600:.2f} h"
              f"  ({projected[lab] / projected[labels[0]]:.3f} of {labels[0]})")
    if args.csv:
        with open(args.csv, "w", encoding="utf-8") as f:
            f.write("checkpoint_step,steps_represented,config,s_per_step,t_reached\n")
            for r in rows:
                f.write(f"{r['step']},{r['weight']},{r['label']},{r['per_step']:.6g},"
                        f"{r['reached']:.6g}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
