"""Time series of any run from the files it writes every step: <name>_<what>.csv in its output
directory (a header of column names, the first one time [s], then one row per step).

Usage:  python -m postproc.series RUN_DIR [--name NAME] [--files WHAT [WHAT ...]]
            [--columns COLUMN [COLUMN ...]] [--out DIR]

The files a run writes (docs/postprocessing.md): <name>_mpm_series.csv (MPM scene: time,
kinetic_energy, strain_energy [J], xmax ymax zmax xmin ymin zmin [m] of the particles) and
<name>_contact_force.csv (coupled scene with rigid solids: time, then <solid>_fx/_fy/_fz, the
contact force of the deformable solids on each rigid one, and <solid>_fluid_fx/_fy/_fz, the
fluids' pressure force on it [N]). --files picks some (by WHAT, e.g. contact_force; default
every one), --columns some columns (default all). Prints, per file, the number of rows, the time
span and each column's min, max and last value; writes <name>_<what>.png (each column against
time) into --out (default RUN_DIR/postproc). Exit status 1 with one line on stderr when the
directory holds no such file or a named file or column is missing.
"""
from __future__ import annotations

import argparse
import math
import os

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.run_files import read_step_csv, run_name, step_files


def plot(columns: dict[str, np.ndarray], names: list[str], title: str, path: str) -> str:
    """Each of ``names`` against ``columns["time"]``, one panel each."""
    plt = pyplot()
    ncols = min(3, len(names))
    nrows = math.ceil(len(names) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.5 * ncols, 2.8 * nrows), squeeze=False,
                             sharex=True)
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    for ax, key in zip(axes.flat, names):
        ax.plot(columns["time"], columns[key], "-", lw=1)
        ax.set_title(key, fontsize=9)
        ax.set_xlabel("t [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", help="output directory of a run")
    parser.add_argument("--name", default=None, help="run name (when RUN_DIR holds several)")
    parser.add_argument("--files", nargs="+", default=None, help="which <name>_<what>.csv")
    parser.add_argument("--columns", nargs="+", default=None, help="which columns")
    parser.add_argument("--out", default=None, help="where the PNGs go")
    args = parser.parse_args(argv)
    name = run_name(args.run_dir, args.name)
    files = step_files(args.run_dir, name)
    if not files:
        raise SystemExit(f"no per-step file {name}_<what>.csv in {args.run_dir}")
    if args.files:
        missing = [w for w in args.files if w not in files]
        if missing:
            raise SystemExit(f"--files {' '.join(missing)}: not in {args.run_dir} "
                             f"(there: {', '.join(files)})")
        files = {w: files[w] for w in args.files}
    tables = {}
    for what, path in files.items():
        columns = read_step_csv(path)
        if "time" not in columns:
            raise SystemExit(f"{path}: no column 'time' (header: {', '.join(columns)})")
        names = [c for c in columns if c != "time"]
        if args.columns:
            names = [c for c in args.columns if c in columns]
        tables[what] = (path, columns, names)
    if args.columns:
        known = {c for _, columns, _ in tables.values() for c in columns}
        missing = [c for c in args.columns if c not in known]
        if missing:
            raise SystemExit(f"--columns {' '.join(missing)}: in none of "
                             f"{', '.join(p for p, _, _ in tables.values())}")
    out = args.out or os.path.join(args.run_dir, "postproc")
    os.makedirs(out, exist_ok=True)
    for what, (path, columns, names) in tables.items():
        t = columns["time"]
        span = f"t = {t[0]:.6g} .. {t[-1]:.6g} s" if len(t) else "no rows yet"
        print(f"{os.path.basename(path)}: {len(t)} rows, {span}")
        if not len(t) or not names:
            continue
        for key in names:
            v = columns[key]
            print(f"  {key:>24}: min {np.min(v):13.6g}  max {np.max(v):13.6g}  last {v[-1]:13.6g}")
        png = plot(columns, names, f"{name}: {what}", os.path.join(out, f"{name}_{what}.png"))
        print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
