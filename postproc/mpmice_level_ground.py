"""Earthquake-induced liquefaction of level ground: the build-up of excess pore pressure cycle by
cycle, by depth (namelists/mpmice_level_ground_loose_1d.nml and _dense_1d.nml,
docs/earthquake_liquefaction.md "Level ground: the build-up cycle by cycle").

Usage:  python -m postproc.mpmice_level_ground --dir output/mpmice_level_ground_loose_1d
        python -m postproc.mpmice_level_ground --compare loose=DIR1 dense=DIR2 [--out DIR]

The layer's particles are grouped by their initial height above the base's top (BANDS, cut
below the layer's top cell, which is left out). Per band
and dump: the loss of vertical effective stress 1 - sigma'_v / sigma'_v0 (the band's mean
-sigma_yy against its mean at the start), the pore-pressure ratio r_u = (mean excess pore
pressure of the band's cells, the cell pressure minus that of the first dump, hydrostatic) /
(the band's mean sigma'_v0) and the cyclic stress ratio CSR = |mean tau_xy| / mean sigma'_v0.
Undrained and with the total vertical stress unchanged, r_u and the loss of sigma'_v agree.
The table gives per shaking cycle (the base's shaking read from the run's echo level.used.nml)
r_u and the loss at the cycle's end, the largest loss within the cycle and the largest CSR.
The last column is the largest r_u of a row of cells (excess pressure over the mean sigma'_v0
of the particles that start in it) and its height: a liquefied band shows there before the
band means reach it. --compare prints each run's table and draws the base acceleration, that
largest r_u and r_u per band against time (level_ground_ru.png) and writes the per-dump
values (level_ground_ru.csv).
"""
from __future__ import annotations

import csv
import os

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.measures import by_id
from postproc.mpmice_earthquake_slope import (base_shaking, draw_base_acceleration,
                                              mark_cycle_ends, ru_axis, shaking_cycles)
from postproc.mpmice_io import cell_centres, run_or_compare

NAME = "level"
SOLID, BASE = "sand", "base"
#: bands of the layer by initial height above the base's top [m], cut at the layer's top cell,
#: which is left out (`layer_bands`: under the open boundary it takes a suction of 1-2 kPa during
#: the shaking, docs/earthquake_liquefaction.md); the shipped layer is 2 m thick
BANDS = ((0.0, 0.3), (0.3, 0.7), (0.7, 1.1), (1.1, 1.5), (1.5, 1.9))


def layer_bands(top: float, dy: float) -> list[tuple[float, float]]:
    """BANDS below the layer's top cell (heights up to ``top - dy``, ``top`` the layer's initial
    height above the base), the last one cut there; bands above it are dropped."""
    surface = top - dy
    return [(a, min(b, surface)) for a, b in BANDS if a < surface - 1e-9]


def band_labels(bands) -> list[str]:
    """'a-b m' for each band."""
    return [f"{a:g}-{b:g} m" for a, b in bands]


def base_top(dump: dict) -> float:
    """Height of the base's top [m]: midway between its highest particle and the layer's lowest
    (the two seeded with the same spacing, whatever the particles per cell)."""
    return 0.5 * float(np.max(dump["particles"][BASE]["y"]) + np.min(dump["particles"][SOLID]["y"]))


def analyse(dumps: list[dict], shaking: tuple) -> list[dict]:
    """Per dump: ``time``, and per band (lists in the order of ``bands``) ``lost`` (1 - sigma'_v /
    sigma'_v0), ``ru`` (excess cell pressure / sigma'_v0) and ``csr`` (|tau_xy| / sigma'_v0);
    ``cell_ru`` and ``cell_height``: the largest r_u of a row of cells below the layer's top cell
    (its excess pressure over the mean sigma'_v0 of the particles that start in it) and that
    row's centre height above the base [m]; ``shaking`` and ``bands`` (:func:`layer_bands`) are
    kept with every row."""
    first = by_id(dumps[0]["particles"][SOLID])
    bottom = base_top(dumps[0])
    height = first["y"] - bottom
    sv0 = -first["stress_yy"]
    dy = float(dumps[0]["attrs"]["dx"][1])
    # the layer's top: its highest particle plus half the spacing (the lowest one's height)
    bands = layer_bands(float(np.max(height) + np.min(height)), dy)
    members = [(height >= a) & (height < b) for a, b in bands]
    yc = cell_centres(dumps[0])[1] - bottom
    rows_of = [(yc >= a) & (yc < b) for a, b in bands]
    layer = np.nonzero((yc > 0.0) & (yc < bands[-1][1]))[0]
    row_sv0 = np.array([np.mean(sv0[np.abs(height - yc[j]) < 0.5 * dy]) for j in layer])
    p0 = dumps[0]["cell"]["pressure"].mean(axis=(0, 2))
    rows = []
    for dump in dumps:
        parts = by_id(dump["particles"][SOLID])
        p = dump["cell"]["pressure"].mean(axis=(0, 2)) - p0
        row = {"time": dump["time"], "shaking": shaking, "bands": bands, "lost": [], "ru": [],
               "csr": []}
        for k, cells in zip(members, rows_of):
            ref = float(np.mean(sv0[k]))
            row["lost"].append(1.0 - float(np.mean(-parts["stress_yy"][k])) / ref)
            row["ru"].append(float(np.mean(p[cells])) / ref)
            row["csr"].append(abs(float(np.mean(parts["stress_xy"][k]))) / ref)
        ru_rows = p[layer] / row_sv0
        row["cell_ru"] = float(np.max(ru_rows))
        row["cell_height"] = float(yc[layer[int(np.argmax(ru_rows))]])
        rows.append(row)
    return rows


def cycle_table(rows: list[dict]) -> list[dict]:
    """Per shaking cycle n: r_u and the loss of sigma'_v at its end, the largest loss and CSR
    within it (lists in the order of the bands)."""
    table = []
    for n, inside, end in shaking_cycles(rows, rows[0]["shaking"]):
        table.append({"cycle": n, "time": end["time"], "bands": end["bands"], "ru": end["ru"],
                      "lost": end["lost"],
                      "max_lost": list(np.max([r["lost"] for r in inside], axis=0)),
                      "cell_ru": end["cell_ru"], "cell_height": end["cell_height"],
                      "csr": list(np.max([r["csr"] for r in inside], axis=0))})
    return table


def print_cycle_table(table: list[dict]) -> None:
    """The table of :func:`cycle_table`, one line per cycle."""
    print("bands by initial height above the base: " + " / ".join(band_labels(table[0]["bands"]))
          if table else "no complete shaking cycle in the dumps")
    print("cycle  t [s]  r_u at the end | loss of sigma'_v at the end (largest) | largest CSR"
          " | largest r_u of a cell row at the end, its height [m]")
    for c in table:
        ru = " ".join(f"{v:5.2f}" for v in c["ru"])
        lost = " ".join(f"{v:5.2f} ({m:4.2f})" for v, m in zip(c["lost"], c["max_lost"]))
        csr = " ".join(f"{v:5.3f}" for v in c["csr"])
        print(f"{c['cycle']:5d} {c['time']:6.2f}  {ru} | {lost} | {csr} | {c['cell_ru']:5.2f} "
              f"{c['cell_height']:4.2f}")


def write_csv(runs: dict[str, list[dict]], path: str) -> str:
    """Per run and dump: time, r_u and the loss of sigma'_v per band."""
    with open(path, "w", newline="", encoding="utf-8") as handle:
        out = csv.writer(handle)
        labels = band_labels(next(iter(runs.values()))[0]["bands"])
        out.writerow(["run", "time_s"] + [f"ru_{b}" for b in labels]
                     + [f"lost_{b}" for b in labels])
        for label, rows in runs.items():
            for r in rows:
                out.writerow([label, f"{r['time']:.4f}"] + [f"{v:.4f}" for v in r["ru"]]
                             + [f"{v:.4f}" for v in r["lost"]])
    return path


def figure(runs: dict[str, list[dict]], out: str) -> str:
    """The base acceleration a(t)/g, the largest r_u of a cell row and r_u of each band against
    time, every run; returns the path of level_ground_ru.png."""
    plt = pyplot()
    labels = band_labels(next(iter(runs.values()))[0]["bands"])
    fig, axes = plt.subplots(len(labels) + 2, 1, figsize=(8.0, 12.0), sharex=True)
    bands = list(reversed(axes[2:]))          # the deepest band at the bottom
    draw_base_acceleration(axes[0], runs)
    for n, (label, rows) in enumerate(runs.items()):
        t = np.array([r["time"] for r in rows])
        axes[1].plot(t, [r["cell_ru"] for r in rows], "-", color=f"C{n}", marker="o", ms=2,
                     label=label)
        for b, ax in enumerate(bands):
            ax.plot(t, [r["ru"][b] for r in rows], "-", color=f"C{n}", marker="o", ms=2,
                    label=label)
    ru_axis(axes[1], "r_u, largest\nof a cell row")
    for b, ax in enumerate(bands):
        ru_axis(ax, f"r_u, {labels[b]}")
    mark_cycle_ends(axes, next(iter(runs.values()))[0]["shaking"])
    axes[-1].set_xlabel("t [s] (grey: the end of each cycle; bands by height above the base)")
    fig.tight_layout()
    path = os.path.join(out, "level_ground_ru.png")
    save_figure(fig, path, dpi=100)
    return path


def main(argv=None) -> int:
    import sys
    return run_or_compare(sys.argv[1:] if argv is None else argv, __doc__.splitlines()[0], NAME,
                          lambda dumps, path: analyse(dumps, base_shaking(path, NAME)),
                          lambda rows: print_cycle_table(cycle_table(rows)), figure,
                          lambda runs, out: write_csv(runs,
                                                      os.path.join(out, "level_ground_ru.csv")))


if __name__ == "__main__":
    raise SystemExit(main())
