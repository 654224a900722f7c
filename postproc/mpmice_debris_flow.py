"""Underwater sand slide (Rzadkiewicz et al. 1997) with the coupled scene: free surface, slide
front, slide shape and mass balance (namelists/mpmice_debris_flow_2d.nml).

Usage:  python -m postproc.mpmice_debris_flow --dir output/mpmice_debris_flow_2d [--out DIR]

Entrained air [m^2 per metre of depth]: the air's volume (sum phi_air dx dy) in the cells whose
centre lies below the shelf's level y = 1.5 m, where the tank holds water only at rest (the air
drawn into the wake over the slope, docs/mpmice.md "Known problems").

Free-surface elevation eta(x) [m above the still level 1.6 m]: in every column of cells, from the
top down, the height where the water's share of the fluid volume phi_w / (phi_w + phi_air)
first reaches 0.5 (linear between cell centres). Slide front: the largest x of the sand
particles. Mass of each fluid (sum rho_bar V) and of each solid (sum of particle masses) per
dump. Prints a line per dump and writes debris_flow.png (eta(x) and the slide's particles per
dump) in --out (default: the run directory).

This script knows the shipped scene (its slide moves toward +x, its bed outline, its still
level). For another slide use `python -m postproc.slide RUN_DIR --solid NAME` (front, run-out
and free surface in the direction the solid moves) and `python -m postproc.snapshots RUN_DIR`
(docs/postprocessing.md); both are built from postproc/measures.py, which this script uses too.
"""
from __future__ import annotations

import os

import numpy as np

from postproc import measures
from postproc.figures import pyplot, save_figure
from postproc.measures import masses  # noqa: F401  (the scene scripts and tests use it here)
from postproc.mpmice_io import cell_centres, parse_run_dir

NAME = "debris"
STILL_LEVEL = 1.6            # m
SHELF_LEVEL = 1.5            # m: the crest plateau's top
WATER, AIR, SAND = "water", "air", "sand"
VERTICAL = (1, +1)           # gravity along -y


def free_surface(dump: dict) -> tuple[np.ndarray, np.ndarray]:
    """(x of the column centres, eta) of a dump; eta is NaN where a column holds no interface
    (:func:`postproc.measures.free_surface`, method "crossing", water against air)."""
    (x,), eta = measures.free_surface(dump, WATER, [AIR], STILL_LEVEL, "crossing",
                                      vertical=VERTICAL)
    return x, eta


def entrained_air(dump: dict) -> float:
    """Air volume [m^2 per metre of depth] in the cells whose centre lies below SHELF_LEVEL."""
    _, y, _ = cell_centres(dump)
    dx = np.asarray(dump["attrs"]["dx"]).reshape(3)
    a = dump["cell"][f"{AIR}/volume_fraction"][:, :, 0]
    return float(np.sum(a[:, y < SHELF_LEVEL])) * float(dx[0] * dx[1])


def slide_front(dump: dict) -> float:
    """Largest x [m] of the sand particles (the slide moves toward +x)."""
    return measures.front(dump["particles"][SAND], 0, +1)


def main(argv=None) -> int:
    args, dumps = parse_run_dir(__doc__.splitlines()[0], NAME, argv)
    m0 = masses(dumps[0])
    print("   t [s]   front [m]   max eta [m]   min eta [m]   largest relative mass change")
    for d in dumps:
        _, eta = free_surface(d)
        m = masses(d)
        change = max(abs(m[k] / m0[k] - 1.0) for k in m0 if m0[k] > 0.0)
        print(f"{d['time']:8.3f} {slide_front(d):11.4f} {np.nanmax(eta):13.4f} "
              f"{np.nanmin(eta):13.4f} {change:14.2e}")
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for d in dumps[1:]:
        x, eta = free_surface(d)
        top.plot(x, eta * 100.0, label=f"t = {d['time']:.2f} s")
        p = d["particles"][SAND]
        bottom.plot(p["x"], p["y"], ".", ms=1)
    top.set_ylabel("eta [cm]")
    top.legend(fontsize=7)
    bed_x, bed_y = [0.0, 0.0, 1.0, 2.5, 4.0], [0.0, 1.5, 1.5, 0.0, 0.0]
    bottom.plot(bed_x, bed_y, "k-", lw=1)
    bottom.set_xlabel("x [m]")
    bottom.set_ylabel("y [m]")
    bottom.set_aspect("equal")
    fig.tight_layout()
    path = os.path.join(args.out or args.dir, "debris_flow.png")
    save_figure(fig, path)
    print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
