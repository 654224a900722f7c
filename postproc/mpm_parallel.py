"""MPM decomposition invariance: the elastic block of namelists/mpm_slide_2d.nml, thrown against
the x+ wall so that its particles cross the block boundaries of 2 and 4 ranks (x = 0.5,
y = 0.5), run on 1, 2 and 4 ranks with PIC and FLIP 0.99; prints the largest difference of the
final particle positions, velocities and stresses from the 1-rank run and writes
mpm_parallel.png / mpm_parallel.csv.

Usage:  python -m postproc.mpm_parallel [--out docs/validation]
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpm_common import particles
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpm_slide_2d.nml")


def run(workdir: str, nranks: int, flip: float) -> tuple[dict, dict]:
    """(first dump, last dump) particle fields of one run."""
    out = os.path.join(workdir, f"r{nranks}_f{flip}")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}' /",
                "--set", f"&mpm flip_fraction = {flip} /"], nranks=nranks, cwd=workdir)
    paths = list_dumps(out, "slide2d")
    return particles(paths[0], "block")[1], particles(paths[-1], "block")[1]


def differences(ref: dict, other: dict) -> dict:
    """Largest |difference| of positions [m], velocities [m/s] and stresses (relative to the
    largest stress magnitude of `ref`)."""
    if not np.array_equal(ref["id"], other["id"]):
        raise RuntimeError("particle sets differ")
    scale = max(np.max(np.abs(ref[f"stress_{c}"])) for c in ("xx", "yy", "zz", "xy"))
    return {
        "position": max(np.max(np.abs(other[c] - ref[c])) for c in ("x", "y")),
        "velocity": max(np.max(np.abs(other[f"velocity_{c}"] - ref[f"velocity_{c}"]))
                        for c in ("x", "y")),
        "stress": max(np.max(np.abs(other[f"stress_{c}"] - ref[f"stress_{c}"]))
                      for c in ("xx", "yy", "zz", "xy")) / scale,
    }


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    args = parse_study_args(parser, argv)
    plt = pyplot()

    rows = []
    with tempfile.TemporaryDirectory() as work:
        for flip in (0.0, 0.99):
            start, ref = run(work, 1, flip)
            crossed_x = int(np.sum((start["x"] < 0.5) & (ref["x"] > 0.5)))
            crossed_y = int(np.sum((start["y"] > 0.5) & (ref["y"] < 0.5)))
            for nranks in (2, 4):
                d = differences(ref, run(work, nranks, flip)[1])
                rows.append((flip, nranks, d["position"], d["velocity"], d["stress"],
                             crossed_x, crossed_y))
            if flip > 0.0:
                final = ref
    print(" flip  ranks  max|dx| [m]  max|dv| [m/s]  max|dsigma|/max|sigma|  crossed x=0.5 / "
          "y=0.5")
    for flip, n, dx, dv, ds, cx, cy in rows:
        print(f"{flip:5.2f} {n:6d} {dx:12.2e} {dv:14.2e} {ds:23.2e}   {cx} / {cy}")
    with open(os.path.join(args.out, "mpm_parallel.csv"), "w", encoding="utf-8") as f:
        f.write("flip,ranks,max_dx,max_dv,max_dstress_rel,crossed_x,crossed_y\n")
        for row in rows:
            f.write(",".join(f"{c:.6g}" for c in row) + "\n")
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4.2))
    ax0.plot(start["x"], start["y"], ".", ms=2, color="0.6", label="t = 0")
    ax0.plot(final["x"], final["y"], ".", ms=2, label="end (1 rank, FLIP 0.99)")
    ax0.axvline(0.5, color="k", lw=0.8, ls="--", label="block boundaries (2, 4 ranks)")
    ax0.axhline(0.5, color="k", lw=0.8, ls="--")
    ax0.set_xlim(0, 1)
    ax0.set_ylim(0, 1)
    ax0.set_aspect("equal")
    ax0.legend(fontsize=7, loc="lower left")
    ax0.set_title("elastic block thrown at the x+ wall", fontsize=9)
    labels = [f"{'PIC' if r[0] == 0 else 'FLIP'}\n{r[1]} ranks" for r in rows]
    pos = np.arange(len(rows))
    floor = 1e-18
    for k, (name, col) in enumerate((("position [m]", 2), ("velocity [m/s]", 3),
                                     ("stress (relative)", 4))):
        ax1.bar(pos + (k - 1) * 0.25, [max(r[col], floor) for r in rows], 0.25, label=name)
    ax1.set_yscale("log")
    ax1.set_xticks(pos)
    ax1.set_xticklabels(labels, fontsize=8)
    ax1.set_ylabel("largest difference from 1 rank")
    ax1.set_title(f"decomposition invariance (bars at {floor:g}: identical)", fontsize=9)
    ax1.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_parallel.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
