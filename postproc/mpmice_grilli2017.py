"""Grilli et al. (2017) test 17 against the laboratory records: gauges WG1..4 and slide shapes.

Usage:  python -m postproc.mpmice_grilli2017 --dir RUN [--dir RUN2 ...] [--label L ...]
            [--reference DIR] [--shift S] [--shape-shift S] [--out DIR] [--stem STEM]

Runs of namelists/mpmice_grilli2017_2d.nml (any cell size; dumps every 0.02 s: the code writes
no per-step probe series, so the gauges are sampled from the dumps). The reference folder
(default ../shared/reference/experiments/grilli2017 beside the repository, or
$MPMICE_REFERENCE/experiments/grilli2017; the digitised records, never copied into the
project) holds eta(t) at the four gauges and the slide's surface at t = 0, 0.02, 0.17, 0.32,
0.47, 0.62 s. The digitised points carry a reading error of a few
percent of the plotted range (the digitiser is not named).

Free surface at a gauge: measures.free_surface, method "height" (the depth of water
sum_j phi_w / (phi_w + phi_air) dy of the column, exact for a level surface at any cell size;
the "crossing" of the share 0.5 reads a level surface that cuts a cell off by up to half a cell,
10 mm at 40 mm cells), linear in x between column centres at the gauge x = 1.4, 2.4, 3.4,
4.4 m (0.79, 1.79, 2.79, 3.79 m beyond the still-water shoreline x = 0.6086 m), minus its
value in the first dump: the
regions fill whole cells, so the grid holds the still level 0.33 m at the nearest cell face
(0.32 m at 40 mm, 0.34 m at 20 mm, 0.33 m at 10 mm cells); the script prints that level.

Time origin: the records' time is the experiment's clock; the model's t = 0 is the gate's
removal. ``--shift S`` maps model time to record time, t_rec = t_model + S (default 0.3 s, the
shift both codes whose files the reference holds apply to their gauges for the gate opening).
``--shape-shift`` does the same for the shapes (default 0: the t = 0 shape is the wedge at
rest, as the scene starts). For each shape the script also reports the model time that fits
it best (the smallest RMS over the dumps): a measured estimate of the shapes' clock offset.

Gauge measures, per gauge, on the first wave (record times up to FIRST_WAVE_END[g]):
leading crest (largest eta before the trough), trough (smallest eta), crest after the trough
(largest eta between the trough and the window's end), each as amplitude [mm] and arrival [s];
the model's window reaches 0.3 s further, so that a late model wave is measured as late;
for the record and the model (NaN where the model run does not reach the record's time of
that extremum + 0.15 s, the trough's time for the leading crest); relative amplitude error
and arrival error; RMS of model - record over the window (record interpolated at the dump
times) and the record's own RMS there.

Shape measures, per time: RMS [mm] of the model surface - digitised y at the digitised points of
the upper envelope (a point with another one within 5 mm in x and more than 10 mm higher lies on
a steep face, where y(x) is not single-valued, and is left out); model surface in a bin of one
cell width = the highest bead particle + half a particle spacing (the bed y = 0.756 - 0.7 x
where the bin holds no bead); front = the largest x of the beads (+ half a particle spacing)
against the digitised shape's largest x; centroid x = the beads' mass-weighted mean x against
the centroid of the digitised thickness y - bed over x (trapezoids; its area, 5.5e-3 to
7.8e-3 m^2 over the six times against the wedge's 6.0e-3, shows the digitising scatter).

Writes <stem>_gauges.png, <stem>_shapes.png and <stem>.csv (one row per measure and run; stem
default grilli2017) in --out (default: the first run's folder); prints the same numbers.
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc import measures
from postproc.figures import pyplot, save_figure, write_table
from postproc.mpmice_io import read_run_dumps
from postproc.reference import experiment_folder

NAME = "grilli"
WATER, AIR, BEADS = "water", "air", "beads"
STILL_LEVEL = 0.33                       # m
VERTICAL = (1, +1)                       # gravity along -y
SHORELINE = 0.6086                       # m: still level on the slope y = 0.756 - 0.7 x
GAUGES = {"WG1": 1.4, "WG2": 2.4, "WG3": 3.4, "WG4": 4.4}   # m, scene frame
#: end [s, record clock] of the first wave (trough and the crest after it) per gauge, read from
#: the records: WG1 trough 1.46 s, crest 1.85 s; WG2 2.14 / 2.70; WG3 2.83 / 3.48; WG4 3.47 / 4.20
FIRST_WAVE_END = {"WG1": 2.05, "WG2": 2.95, "WG3": 3.65, "WG4": 4.40}
SHAPE_TIMES = (0.0, 0.02, 0.17, 0.32, 0.47, 0.62)
#: the reference folder (postproc/reference.py: ../shared/reference or $MPMICE_REFERENCE)
DEFAULT_REFERENCE = experiment_folder("grilli2017")
MARGIN = 0.15                            # s: a model extremum counts when the run covers it + this
LATE = 0.3                               # s: the model's window reaches this far past the record's


def bed_height(x):
    """Slope of the scene frame, y = 0.756 - 0.7 x down to the floor y = 0 (m)."""
    return np.maximum(0.756 - 0.7 * np.asarray(x, dtype=float), 0.0)


def read_reference_csv(path: str) -> dict[str, np.ndarray]:
    """Columns of a reference CSV (``#`` lines skipped, the first other line the header)."""
    with open(path, encoding="utf-8") as f:
        rows = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    header = [h.strip() for h in rows[0].split(",")]
    values = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    return {h: values[:, i] for i, h in enumerate(header)}


def reference_gauges(folder: str) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """{gauge: (t [s], eta [m])} of the records, sorted by time."""
    out = {}
    for g in GAUGES:
        ref = read_reference_csv(os.path.join(folder, f"grilli2017_test17_{g}.csv"))
        order = np.argsort(ref["t_s"], kind="stable")
        out[g] = (ref["t_s"][order], ref["eta_mm"][order] * 1e-3)
    return out


def reference_shapes(folder: str) -> dict[float, tuple[np.ndarray, np.ndarray]]:
    """{t: (x [m] scene frame, y [m])} of the digitised slide surfaces, sorted by x."""
    ref = read_reference_csv(os.path.join(folder, "grilli2017_test17_slide_shapes.csv"))
    out = {}
    for t in SHAPE_TIMES:
        sel = np.isclose(ref["t_s"], t)
        order = np.argsort(ref["x_sif_m"][sel])
        out[t] = (ref["x_sif_m"][sel][order], ref["y_src_m"][sel][order])
    return out


def upper_envelope(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Mask of the digitised points on the upper envelope (module notes)."""
    keep = np.ones(x.size, dtype=bool)
    for n in range(x.size):
        near = np.abs(x - x[n]) < 5e-3
        keep[n] = not np.any(y[near] > y[n] + 10e-3)
    return keep


def gauge_series(dumps: list[dict]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(model times, {gauge: eta [m]}) from the dumps."""
    times = np.array([d["time"] for d in dumps])
    series = {g: np.empty(len(dumps)) for g in GAUGES}
    for n, d in enumerate(dumps):
        (x,), eta = measures.free_surface(d, WATER, [AIR], STILL_LEVEL, "height",
                                          vertical=VERTICAL)
        for g, xg in GAUGES.items():
            series[g][n] = np.interp(xg, x, eta)
    for g in GAUGES:
        series[g] -= series[g][0]
    return times, series


def initial_level(dump: dict) -> float:
    """Still level [m] the grid holds at WG1 in a dump (the first one: at rest)."""
    (x,), eta = measures.free_surface(dump, WATER, [AIR], 0.0, "height", vertical=VERTICAL)
    return float(np.interp(GAUGES["WG1"], x, eta))


def extrema(t, eta, t_end):
    """(leading crest, trough, crest after it) of eta(t) over t <= t_end, each (t, eta)."""
    sel = t <= t_end
    t, eta = t[sel], eta[sel]
    it = int(np.argmin(eta))
    lead = int(np.argmax(eta[:it + 1])) if it > 0 else it
    after = it + int(np.argmax(eta[it:]))
    return [(t[i], eta[i]) for i in (lead, it, after)]


def gauge_measures(ref, t_model, model, shift) -> list[dict]:
    """Rows of the gauge comparison (module notes)."""
    rows = []
    t_rec = t_model + shift
    covered = t_rec[-1]
    for g in GAUGES:
        tr, er = ref[g]
        t_end = FIRST_WAVE_END[g]
        rec = extrema(tr, er, t_end)
        mod = extrema(t_rec, model[g], min(t_end + LATE, covered))
        # the leading crest is the largest eta before the trough: both need the trough covered
        needs = (rec[1][0], rec[1][0], rec[2][0])
        for name, (t0, e0), (t1, e1), t_need in zip(
                ("leading crest", "trough", "crest after trough"), rec, mod, needs):
            ok = covered >= min(t_need + MARGIN, t_end + LATE)
            rows.append({"gauge": g, "measure": name, "record_t_s": t0,
                         "record_eta_mm": e0 * 1e3,
                         "model_t_s": t1 if ok else np.nan,
                         "model_eta_mm": e1 * 1e3 if ok else np.nan,
                         "amplitude_error": (e1 / e0 - 1.0) if ok else np.nan,
                         "arrival_error_s": (t1 - t0) if ok else np.nan})
        sel = t_rec <= min(t_end, covered)
        e_ref = np.interp(t_rec[sel], tr, er)
        rms = float(np.sqrt(np.mean((model[g][sel] - e_ref) ** 2))) if np.any(sel) else np.nan
        rms_ref = float(np.sqrt(np.mean(e_ref ** 2))) if np.any(sel) else np.nan
        rows.append({"gauge": g, "measure": "rms over first wave", "record_t_s": t_end,
                     "record_eta_mm": rms_ref * 1e3, "model_t_s": min(t_end, covered),
                     "model_eta_mm": rms * 1e3, "amplitude_error": rms / rms_ref
                     if rms_ref > 0 else np.nan, "arrival_error_s": np.nan})
    return rows


def slide_surface(dump: dict, x: np.ndarray) -> np.ndarray:
    """Model slide surface [m] at the points x (module notes)."""
    p = dump["particles"][BEADS]
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    ppc = 2.0                                       # particles per cell and axis of the scene
    surf = bed_height(x).copy()
    for n, xn in enumerate(x):
        sel = np.abs(p["x"] - xn) <= 0.5 * dx
        if np.any(sel):
            surf[n] = max(surf[n], float(np.max(p["y"][sel])) + 0.5 * dx / ppc)
    return surf


def record_centroid(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(area [m^2], centroid x [m]) of the digitised slide: thickness y - bed over x (trapezoids
    through the upper-envelope points)."""
    h = np.maximum(y - bed_height(x), 0.0)
    area = float(np.trapezoid(h, x))
    return area, float(np.trapezoid(h * x, x)) / area


def model_centroid(dump: dict) -> float:
    """Mass-weighted mean x [m] of the beads."""
    p = dump["particles"][BEADS]
    return float(np.average(p["x"], weights=p["mass"]))


def front(dump: dict) -> float:
    """Largest x [m] of the beads plus half a particle spacing."""
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    return float(np.max(dump["particles"][BEADS]["x"])) + 0.25 * dx


def shape_measures(shapes, dumps, shape_shift) -> list[dict]:
    """Rows of the shape comparison: RMS and front at the model time t - shape_shift, and the
    model time of the best fit."""
    rows = []
    times = np.array([d["time"] for d in dumps])
    for t, (x_all, y_all) in shapes.items():
        env = upper_envelope(x_all, y_all)
        xs, ys = x_all[env], y_all[env]
        rms_all = np.array([np.sqrt(np.mean((slide_surface(d, xs) - ys) ** 2)) for d in dumps])
        target = t - shape_shift
        n = int(np.argmin(np.abs(times - target)))
        ok = abs(times[n] - target) < 0.011
        best = int(np.argmin(rms_all))
        area, centroid = record_centroid(xs, ys)
        rows.append({"time_s": t, "model_time_s": times[n] if ok else np.nan,
                     "record_area_m2": area, "record_centroid_x_m": centroid,
                     "model_centroid_x_m": model_centroid(dumps[n]) if ok else np.nan,
                     "rms_mm": rms_all[n] * 1e3 if ok else np.nan,
                     "record_front_m": float(np.max(x_all)),
                     "model_front_m": front(dumps[n]) if ok else np.nan,
                     "best_model_time_s": times[best], "best_rms_mm": rms_all[best] * 1e3})
    return rows


def plot_gauges(ref, runs, shift, path):
    plt = pyplot()
    fig, axes = plt.subplots(len(GAUGES), 1, figsize=(8, 9), sharex=True)
    for ax, g in zip(axes, GAUGES):
        tr, er = ref[g]
        ax.plot(tr, er * 1e3, "ko", ms=3, mfc="none", label="Grilli et al. (2017), digitised")
        for label, (t_model, model) in runs.items():
            ax.plot(t_model + shift, model[g] * 1e3, "-", label=label)
        ax.axvline(FIRST_WAVE_END[g], color="0.7", lw=0.8)
        ax.set_ylabel(f"{g} eta [mm]")
        ax.set_xlim(0.0, 5.0)
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel(f"t [s] (record clock; model time + {shift:g} s)")
    fig.tight_layout()
    save_figure(fig, path)


def plot_shapes(shapes, dumps_by_run, shape_shift, path):
    plt = pyplot()
    fig, axes = plt.subplots(3, 2, figsize=(10, 8), sharex=True, sharey=True)
    xb = np.linspace(0.6, 1.6, 50)
    for ax, (t, (xs, ys)) in zip(axes.ravel(), shapes.items()):
        ax.plot(xb, bed_height(xb), "k-", lw=1)
        ax.axhline(STILL_LEVEL, color="b", lw=0.5)
        ax.plot(xs, ys, "ko", ms=3, mfc="none", label="digitised")
        for label, dumps in dumps_by_run.items():
            times = np.array([d["time"] for d in dumps])
            n = int(np.argmin(np.abs(times - (t - shape_shift))))
            if abs(times[n] - (t - shape_shift)) < 0.011:
                p = dumps[n]["particles"][BEADS]
                ax.plot(p["x"], p["y"], ".", ms=1.5, label=f"{label} t = {times[n]:.2f} s")
        ax.set_title(f"t = {t:.2f} s", fontsize=9)
        ax.set_xlim(0.6, 1.6)
        ax.set_ylim(0.0, 0.35)
        ax.legend(fontsize=6)
    fig.tight_layout()
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True, help="run folder (repeatable)")
    parser.add_argument("--label", action="append", default=None, help="label per --dir")
    parser.add_argument("--reference", default=DEFAULT_REFERENCE)
    parser.add_argument("--shift", type=float, default=0.3)
    parser.add_argument("--shape-shift", type=float, default=0.0)
    parser.add_argument("--out", default=None)
    parser.add_argument("--stem", default="grilli2017", help="file name stem of the outputs")
    args = parser.parse_args(argv)
    if not os.path.isdir(args.reference):
        raise SystemExit(f"reference folder {args.reference} not found (--reference DIR)")
    labels = args.label or [os.path.basename(os.path.normpath(d)) for d in args.dir]
    if len(labels) != len(args.dir):
        raise SystemExit("give one --label per --dir")
    out = args.out or args.dir[0]
    os.makedirs(out, exist_ok=True)
    ref, shapes = reference_gauges(args.reference), reference_shapes(args.reference)
    runs, dumps_by_run, table = {}, {}, []
    for label, folder in zip(labels, args.dir):
        try:
            dumps = read_run_dumps(folder, NAME)
        except RuntimeError as error:
            raise SystemExit(str(error)) from None
        dumps_by_run[label] = dumps
        t_model, model = gauge_series(dumps)
        runs[label] = (t_model, model)
        print(f"{label}: {len(dumps)} dumps to t = {t_model[-1]:.2f} s (record clock "
              f"{t_model[-1] + args.shift:.2f} s); still level on the grid "
              f"{initial_level(dumps[0]):.4f} m")
        print("  gauge measure               record t  eta[mm]   model t  eta[mm]  "
              "amp err  arr err[s]")
        for row in gauge_measures(ref, t_model, model, args.shift):
            print(f"  {row['gauge']} {row['measure']:22s} {row['record_t_s']:8.2f} "
                  f"{row['record_eta_mm']:8.2f} {row['model_t_s']:9.2f} "
                  f"{row['model_eta_mm']:8.2f} {row['amplitude_error']:8.2f} "
                  f"{row['arrival_error_s']:9.2f}")
            table.append({"run": label, "kind": "gauge", **row})
        print("  shape t  model t  rms[mm]  front rec  front model  centroid rec  centroid model"
              "  best t  best rms")
        for row in shape_measures(shapes, dumps, args.shape_shift):
            print(f"  {row['time_s']:7.2f} {row['model_time_s']:8.2f} {row['rms_mm']:8.2f} "
                  f"{row['record_front_m']:10.3f} {row['model_front_m']:12.3f} "
                  f"{row['record_centroid_x_m']:13.3f} {row['model_centroid_x_m']:15.3f} "
                  f"{row['best_model_time_s']:7.2f} {row['best_rms_mm']:9.2f}")
            table.append({"run": label, "kind": "shape", **row})
    plot_gauges(ref, runs, args.shift, os.path.join(out, f"{args.stem}_gauges.png"))
    plot_shapes(shapes, dumps_by_run, args.shape_shift,
                os.path.join(out, f"{args.stem}_shapes.png"))
    fields = sorted({k for row in table for k in row}, key=lambda k: (k not in ("run", "kind"), k))
    write_table(os.path.join(out, f"{args.stem}.csv"), table, fields)
    print(f"written: {out}/{args.stem}_gauges.png, {args.stem}_shapes.png, {args.stem}.csv")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
