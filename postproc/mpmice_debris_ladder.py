"""Resolution study of the underwater sand slide (Rzadkiewicz et al. 1997; scene
namelists/mpmice_debris_flow_2d.nml, docs/applications.md section 1): several runs of the scene
at different cell sizes compared at given times.

Usage:  python -m postproc.mpmice_debris_ladder --dir RUN1 --dir RUN2 [--dir RUN3 ...]
            [--times 0.4 0.8] [--out DIR]

Each run is the output directory of one run (dumps debris_<step>.h5; checkpoints are ignored).
For every requested time the nearest dump of each run is used (the table names its time); a run
whose nearest dump is more than half an output interval away has not reached that time and is
left out of that time's comparison. Per run and time it prints:

* eta max / min [cm] and their x (free surface of postproc.mpmice_debris_flow.free_surface);
* the slide front x (largest x of the sand particles, mpmice_debris_flow.slide_front) and its
  advance since the first dump (the seeding puts the first front h/4 inside the wedge, an
  offset that depends on the cell size h);
* the largest relative mass change of water, sand and bed since the first dump
  (mpmice_debris_flow.masses);
* the air entrained below the shelf's level y = 1.5 m [m^2 per metre of depth]
  (mpmice_debris_flow.entrained_air);
* against the next coarser run (runs ordered by cell size): the difference of eta(x), the coarser
  eta interpolated linearly onto the finer run's column centres where both are defined, as an
  RMS ("L2": sqrt of the mean square over those columns) and a max norm, in cm;
* the excess pore pressure of the sand particles, pore_pressure - p_hyd with
  p_hyd = p_atm + rho_w g (1.6 - y) below the still level y = 1.6 m and p_atm above it,
  min / 1st percentile / median / 99th percentile / max [kPa] (single particles of a moving
  porous body carry its pore-pressure noise, docs/mpmice.md; the percentiles show the bulk).

With three or more runs, the observed convergence order p of eta(x) from every three successive
runs (cell sizes h1 > h2 > h3, differences e12, e23): (h1^p - h2^p) / (h2^p - h3^p) = e12 / e23,
i.e. p = ln(e12 / e23) / ln(r) for a constant refinement ratio r; also of the front's advance
from its successive differences.

Writes debris_ladder_eta.png (eta(x) and the slide's particles of every run, one column per
time), debris_ladder_front.png (front x(t) of every run, every dump) and debris_ladder_pore.png
(the sand particles coloured by their excess pore pressure, a row per time and a column per run)
into --out (default: the first run's directory).

Published numbers: no value of eta(x) at 0.4 s or 0.8 s for this experiment is stated in the
text or a table of the sources consulted (the MPMICE paper, ../shared/paper/mpmice-paper.md,
section "Underwater debris flow", compares eta(x) in its Figure 10 only; Rzadkiewicz et al.
1997 and Dai et al. 2021, Water 13:2276, show eta(x) as curves in figures); see
docs/applications.md section 1, "Published numbers". No comparison is printed.
"""
from __future__ import annotations

import argparse
import math
import os

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.mpmice_debris_flow import (NAME, SAND, STILL_LEVEL, entrained_air, free_surface,
                                         masses, slide_front)
from postproc.mpmice_io import list_dumps, read_attrs, read_dump

P_ATM = 101325.0             # Pa
RHO_W = 999.8                # kg/m^3
G = 9.81                     # m/s^2
CONSERVED = ("water", "sand", "bed")
BED_X, BED_Y = [0.0, 0.0, 1.0, 2.5, 4.0], [0.0, 1.5, 1.5, 0.0, 0.0]


def nearest_index(times, t: float) -> int:
    """Index of the entry of `times` nearest to t (the first one on a tie)."""
    return int(np.argmin(np.abs(np.asarray(times, dtype=float) - t)))


def eta_difference(x_fine, eta_fine, x_coarse, eta_coarse) -> tuple[float, float, int]:
    """(RMS, max |.|, number of columns) of eta_fine - eta_coarse, the coarser eta interpolated
    linearly onto x_fine; only columns where both are defined (finite, and x_fine inside the
    coarser run's span of finite values without a NaN neighbour) count. NaN, NaN, 0 when none."""
    x_fine, eta_fine = np.asarray(x_fine, float), np.asarray(eta_fine, float)
    x_coarse, eta_coarse = np.asarray(x_coarse, float), np.asarray(eta_coarse, float)
    on_coarse = np.interp(x_fine, x_coarse, eta_coarse, left=np.nan, right=np.nan)
    both = np.isfinite(on_coarse) & np.isfinite(eta_fine)
    if not np.any(both):
        return math.nan, math.nan, 0
    diff = eta_fine[both] - on_coarse[both]
    return float(np.sqrt(np.mean(diff**2))), float(np.max(np.abs(diff))), int(np.count_nonzero(both))


def observed_order(h, e) -> float:
    """Observed order p from cell sizes h = (h1, h2, h3), h1 > h2 > h3, and the differences
    e = (e12, e23) between successive solutions: (h1^p - h2^p) / (h2^p - h3^p) = e12 / e23.
    Closed form ln(e12/e23) / ln(r) for a constant ratio r = h1/h2 = h2/h3 (negative: the
    differences grow); otherwise bisection on 0 < p <= 20. NaN when undefined."""
    h1, h2, h3 = (float(v) for v in h)
    e12, e23 = (float(v) for v in e)
    if not (e12 > 0.0 and e23 > 0.0 and h1 > h2 > h3 > 0.0):
        return math.nan
    ratio = e12 / e23
    r1, r2 = h1 / h2, h2 / h3
    if abs(r1 / r2 - 1.0) < 1e-9:
        return math.log(ratio) / math.log(r1)

    def excess(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - ratio

    low, high = 1e-6, 20.0
    if excess(low) * excess(high) > 0.0:
        return math.nan
    for _ in range(200):
        mid = 0.5 * (low + high)
        if excess(low) * excess(mid) <= 0.0:
            high = mid
        else:
            low = mid
    return 0.5 * (low + high)


def excess_pore_pressure(y, pore_pressure) -> np.ndarray:
    """Pore pressure [Pa] minus the hydrostatic p_atm + rho_w g (1.6 - y) (p_atm above 1.6 m)."""
    y = np.asarray(y, dtype=float)
    return np.asarray(pore_pressure, dtype=float) - (
        P_ATM + RHO_W * G * np.clip(STILL_LEVEL - y, 0.0, None))


def read_run(directory: str, times) -> dict:
    """One run: label, cell size h, every dump's time and front, and per requested time the
    nearest dump (or None when the run has not reached it) with its eta(x), particles, masses."""
    paths = list_dumps(directory, NAME)
    if not paths:
        raise SystemExit(f"no dumps {NAME}_<step>.h5 in {directory}")
    dump_times = np.array([float(read_attrs(p)["time"]) for p in paths])
    spacing = float(np.median(np.diff(dump_times))) if len(paths) > 1 else 0.0
    first = read_dump(paths[0])
    m0 = masses(first)
    fronts = [slide_front(first)] + [slide_front(read_dump(path)) for path in paths[1:]]
    run = {"dir": directory, "h": float(np.asarray(first["attrs"]["dx"]).reshape(3)[0]),
           "times": dump_times, "fronts": np.array(fronts), "at": {}}
    run["label"] = f"{os.path.basename(os.path.normpath(directory))} ({run['h'] * 1e3:g} mm)"
    for t in times:
        i = nearest_index(dump_times, t)
        if abs(dump_times[i] - t) > 0.5 * spacing + 1e-9:
            run["at"][t] = None
            continue
        d = read_dump(paths[i])
        x, eta = free_surface(d)
        m = masses(d)
        p = d["particles"][SAND]
        run["at"][t] = {
            "file": os.path.basename(paths[i]), "time": d["time"], "x": x, "eta": eta,
            "front": slide_front(d), "advance": slide_front(d) - fronts[0], "px": p["x"], "py": p["y"],
            "excess": excess_pore_pressure(p["y"], p["pore_pressure"]),
            "mass_change": max(abs(m[k] / m0[k] - 1.0) for k in CONSERVED if m0.get(k, 0.0) > 0.0),
            "air": entrained_air(d),
        }
    return run


def compare(runs: list[dict], times) -> dict:
    """Per time: the runs that reached it (coarse to fine) with, from the second on, the eta
    difference to the previous one ("diff": (rms, max, n)), and the observed orders of every
    three successive ones ("orders": list of (labels, p_rms, p_max, p_front))."""
    out = {}
    for t in times:
        present = sorted((r for r in runs if r["at"][t] is not None), key=lambda r: -r["h"])
        diffs = [None]
        for coarse, fine in zip(present, present[1:]):
            a, b = coarse["at"][t], fine["at"][t]
            diffs.append(eta_difference(b["x"], b["eta"], a["x"], a["eta"]))
        orders = []
        for k in range(2, len(present)):
            h = [present[k - j]["h"] for j in (2, 1, 0)]
            fr = [present[k - j]["at"][t]["advance"] for j in (2, 1, 0)]
            orders.append(([present[k - j]["label"] for j in (2, 1, 0)],
                           observed_order(h, (diffs[k - 1][0], diffs[k][0])),
                           observed_order(h, (diffs[k - 1][1], diffs[k][1])),
                           observed_order(h, (abs(fr[1] - fr[0]), abs(fr[2] - fr[1])))))
        out[t] = {"runs": present, "diffs": diffs, "orders": orders}
    return out


def print_table(runs: list[dict], times, study: dict) -> None:
    """The comparison table on stdout."""
    for r in runs:
        print(f"{r['label']}: {r['dir']}, {len(r['times'])} dumps to t = {r['times'][-1]:.3f} s")
    print("published eta(x) at 0.4 / 0.8 s: none stated in text or tables (module docstring)")
    head = (f"{'t req':>5} {'run':<22} {'dump t':>6} {'eta max [cm] @ x':>17} "
            f"{'eta min [cm] @ x':>17} {'front':>6} {'adv.':>6} {'dmass':>8} {'air m2':>7} "
            f"{'L2 d [cm]':>9} "
            f"{'max d':>6} {'n':>4} {'excess pore p min/p1/med/p99/max [kPa]':>54}")
    for t in times:
        print(head)
        entry = study[t]
        diff_of = {id(r): diff for r, diff in zip(entry["runs"], entry["diffs"])}
        for r in runs:
            a = r["at"][t]
            if a is None:
                print(f"{t:5.2f} {r['label']:<22} not reached (last dump t = "
                      f"{r['times'][-1]:.3f} s)")
                continue
            i, j = np.nanargmax(a["eta"]), np.nanargmin(a["eta"])
            diff = diff_of[id(r)]
            d = "" if diff is None else f"{diff[0] * 100:9.3f} {diff[1] * 100:6.2f} {diff[2]:4d}"
            ex = a["excess"] / 1e3
            print(f"{t:5.2f} {r['label']:<22} {a['time']:6.3f} "
                  f"{a['eta'][i] * 100:+7.2f} @ {a['x'][i]:5.3f}  "
                  f"{a['eta'][j] * 100:+7.2f} @ {a['x'][j]:5.3f}  {a['front']:6.3f} {a['advance']:6.3f} "
                  f"{a['mass_change']:8.1e} {a['air']:7.4f} {d:>21} "
                  f"{ex.min():10.1f} {np.percentile(ex, 1):10.1f} {np.median(ex):10.2f} "
                  f"{np.percentile(ex, 99):10.1f} {ex.max():10.1f}")
        for labels, p_rms, p_max, p_front in entry["orders"]:
            print(f"{t:5.2f} observed order ({' > '.join(labels)}): eta L2 {p_rms:.2f}, "
                  f"eta max {p_max:.2f}, front advance {p_front:.2f}")


def plot(runs: list[dict], times, out: str) -> list[str]:
    """The three PNGs; returns their paths."""
    plt = pyplot()
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    paths = []

    fig, axes = plt.subplots(2, len(times), figsize=(6 * len(times), 6), squeeze=False,
                             sharex=True)
    for c, t in enumerate(times):
        top, bottom = axes[0, c], axes[1, c]
        for k, r in enumerate(runs):
            a = r["at"][t]
            if a is None:
                continue
            colour = colours[k % len(colours)]
            top.plot(a["x"], a["eta"] * 100.0, color=colour,
                     label=f"{r['label']}, t = {a['time']:.3f} s")
            bottom.plot(a["px"], a["py"], ".", ms=1.5, color=colour)
        top.set_title(f"t = {t:g} s")
        top.set_ylabel("eta [cm]")
        if top.lines:
            top.legend(fontsize=7)
        bottom.plot(BED_X, BED_Y, "k-", lw=1)
        bottom.set_xlabel("x [m]")
        bottom.set_ylabel("y [m]")
        bottom.set_xlim(0.0, 4.0)
        bottom.set_ylim(0.0, 2.0)
        bottom.set_aspect("equal")
    fig.tight_layout()
    paths.append(os.path.join(out, "debris_ladder_eta.png"))
    save_figure(fig, paths[-1])

    fig, ax = plt.subplots(figsize=(6, 4))
    for k, r in enumerate(runs):
        ax.plot(r["times"], r["fronts"], "o-", ms=3, color=colours[k % len(colours)],
                label=r["label"])
    ax.set_xlabel("t [s]")
    ax.set_ylabel("slide front x [m]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    paths.append(os.path.join(out, "debris_ladder_front.png"))
    save_figure(fig, paths[-1])

    shown = [r["at"][t]["excess"] for t in times for r in runs if r["at"][t] is not None]
    limit = float(np.percentile(np.abs(np.concatenate(shown)), 98)) / 1e3 if shown else 1.0
    fig, axes = plt.subplots(len(times), len(runs), figsize=(4.5 * len(runs), 3 * len(times)),
                             squeeze=False)
    for row, t in enumerate(times):
        for col, r in enumerate(runs):
            ax = axes[row, col]
            ax.plot(BED_X, BED_Y, "k-", lw=1)
            a = r["at"][t]
            if a is None:
                ax.set_title(f"{r['label']}: t = {t:g} s not reached", fontsize=8)
            else:
                sc = ax.scatter(a["px"], a["py"], c=a["excess"] / 1e3, s=3, cmap="RdBu_r",
                                vmin=-max(limit, 1e-9), vmax=max(limit, 1e-9))
                ax.set_title(f"{r['label']}, t = {a['time']:.3f} s", fontsize=8)
                fig.colorbar(sc, ax=ax, label="excess pore p [kPa]")
            ax.set_xlim(0.8, 3.0)
            ax.set_ylim(0.0, 1.7)
            ax.set_aspect("equal")
    fig.suptitle("excess pore pressure (colour scale: 98th percentile of |value|)", fontsize=9)
    fig.tight_layout()
    paths.append(os.path.join(out, "debris_ladder_pore.png"))
    save_figure(fig, paths[-1])
    return paths


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True,
                        help="output directory of one run (repeat for each run)")
    parser.add_argument("--times", type=float, nargs="+", default=[0.4, 0.8])
    parser.add_argument("--out", default=None, help="where the PNGs go (default: first --dir)")
    args = parser.parse_args(argv)
    runs = [read_run(d, args.times) for d in args.dir]
    runs.sort(key=lambda r: -r["h"])
    study = compare(runs, args.times)
    print_table(runs, args.times, study)
    out = args.out or args.dir[0]
    os.makedirs(out, exist_ok=True)
    for path in plot(runs, args.times, out):
        print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
