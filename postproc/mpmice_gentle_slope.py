"""Earthquake-induced liquefaction of a gentle submarine bank: the build-up of excess pore pressure
cycle by cycle and the lateral spreading it lets loose (namelists/mpmice_gentle_slope_loose_2d.nml
and _dense_2d.nml, docs/earthquake_liquefaction.md "A gentle bank: build-up and spreading").

Usage:  python -m postproc.mpmice_gentle_slope --dir output/mpmice_gentle_slope_loose_2d
        python -m postproc.mpmice_gentle_slope --compare loose=DIR1 dense=DIR2 [--out DIR]

The bank is found from the first dump's particles (any bank of one crest on a level layer, periodic
in x, wherever it lies, across x = 0 too): the base's top, the level layer's top (the lowest
column of sediment), the crest's top and
centre (the columns at the highest level) and the flanks' mid-points (the columns, left and right
of the crest, whose top is nearest the middle of the two levels). Monitors are the particles that
start within MONITOR_RADIUS of points at mid-height of the layer under the crest, under each flank
and under the toe (the column farthest from the crest), and at mid-height of the bank under the
crest. Per monitor and dump: r_u = (mean excess pore pressure of the particles' cells, the cell
pressure minus that of the first dump) / (mean sigma'_v0 of the particles), and the loss of
vertical effective stress 1 - sigma'_v / sigma'_v0 beside it. Per dump also: the mean horizontal
displacement relative to the base of each flank's surface (the particles that start in the top
SURFACE_DEPTH of the columns within FLANK_HALF_WIDTH of the flank's mid-point; negative: to -x),
the crest's mean settlement (its top SURFACE_DEPTH), the largest accumulated plastic strain and
the spread (standard deviation) of each monitor's volumetric strain V/V0 - 1 and
the pore pressure's cell-to-cell noise (99th percentile and largest |a sediment cell's excess
pressure minus the mean of its two x neighbours|, postproc.mpmice_earthquake_slope). The table
gives them per shaking cycle (the base's shaking read from the run's echo gentle.used.nml) and at
the last dump (after the shaking the spreading either stops or goes on: flow; the flanks'
displacement every 0.5 s after the shaking shows which); a second table
per monitor and cycle the cyclic stress ratio (half the range of the monitor's mean tau_xy over
the cycle / its sigma'_v0), and at the cycle's end the mobilised friction tau/p' (of its
particles' mean stress), the mean p' over the mean initial p'_0, the share of its particles at
p' = 0 (below 0.01 p'_0) and the volumetric strain's spread; the last line the noise's p99
averaged over the dumps of the shaking after its first 0.2 s and its largest value there.
--compare prints each run's table, draws the base acceleration, r_u at each monitor and the
flanks' displacement against time (gentle_slope.png) and writes the per-dump values
(gentle_slope.csv).
"""
from __future__ import annotations

import csv
import os

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.measures import by_id, mean_stress
from postproc.mpmice_earthquake_slope import (base_shaking, domain_length,
                                              draw_base_acceleration, mark_cycle_ends,
                                              particle_cells, pore_pressure_roughness, ru_axis,
                                              shaking_cycles, shaking_parts, shear_ratio,
                                              unwrapped)
from postproc.mpmice_io import cell_centres, run_or_compare

NAME = "gentle"
SOLID, BASE = "sand", "base"
MONITOR_RADIUS = 0.25        # m
SURFACE_DEPTH = 0.3          # m: the surface particles of a column
FLANK_HALF_WIDTH = 0.5       # m
MONITORS = ("layer, crest", "layer, left flank", "layer, right flank", "layer, toe",
            "bank, crest")


def bank_geometry(parts: dict, base_particles: dict, spacing: float, length: float) -> dict:
    """The bank's levels and points from its particles at the start (``spacing``: the particles'
    x spacing; ``length``: the periodic domain's length, the bank may lie across x = 0):
    ``base_top``, ``layer_top``, ``crest_top`` [m], ``crest`` (x of the crest's centre),
    ``left``, ``right`` (x of the flanks' mid-points) and ``columns`` (each particle column's x
    and top [m]); x in [0, length)."""
    base_top = 0.5 * float(np.max(base_particles["y"]) + np.min(parts["y"]))
    half = 0.5 * (float(np.min(parts["y"])) - float(np.max(base_particles["y"])))
    columns = np.round(parts["x"] / spacing).astype(int)
    keys = np.unique(columns)
    xs = np.array([np.mean(parts["x"][columns == k]) for k in keys])
    tops = np.array([np.max(parts["y"][columns == k]) for k in keys]) + half
    layer_top, crest_top = float(np.min(tops)), float(np.max(tops))
    # x from a column of the level layer on: the bank is one piece there, whatever its place
    toe = float(xs[int(np.argmin(tops))])
    xr = (xs - toe) % length
    at_crest = tops > crest_top - 1e-6
    crest = float(np.mean(xr[at_crest]))
    middle = 0.5 * (layer_top + crest_top)
    left = xr < crest
    x_left = float(xr[left][np.argmin(np.abs(tops[left] - middle))])
    x_right = float(xr[~left][np.argmin(np.abs(tops[~left] - middle))])
    return {"base_top": base_top, "layer_top": layer_top, "crest_top": crest_top,
            "crest": (toe + crest) % length, "left": (toe + x_left) % length,
            "right": (toe + x_right) % length, "columns": (xs, tops)}


def monitor_points(geometry: dict, length: float) -> dict[str, tuple[float, float]]:
    """The monitors' points (x, y) [m] (:data:`MONITORS`)."""
    g = geometry
    y_layer = 0.5 * (g["base_top"] + g["layer_top"])
    toe = (g["crest"] + 0.5 * length) % length
    return {"layer, crest": (g["crest"], y_layer), "layer, left flank": (g["left"], y_layer),
            "layer, right flank": (g["right"], y_layer), "layer, toe": (toe, y_layer),
            "bank, crest": (g["crest"], 0.5 * (g["layer_top"] + g["crest_top"]))}


def surface_members(parts: dict, geometry: dict, x0: float, length: float) -> np.ndarray:
    """Indices of the particles that start in the top SURFACE_DEPTH of the columns within
    FLANK_HALF_WIDTH of ``x0`` (periodic in x over ``length``)."""
    xs, tops = geometry["columns"]
    top = float(np.min(tops[np.abs(unwrapped(xs - x0, length)) <= FLANK_HALF_WIDTH]))
    return np.flatnonzero((np.abs(unwrapped(parts["x"] - x0, length)) <= FLANK_HALF_WIDTH)
                          & (parts["y"] > top - SURFACE_DEPTH))


def mobilised_friction(parts: dict, index: np.ndarray) -> float:
    """tau/p' of the mean effective stress of particles `index` (the particles' own ratios
    diverge where p' -> 0)."""
    mean = {f"stress_{c}": np.array([np.mean(parts[f"stress_{c}"][index])])
            for c in ("xx", "yy", "zz", "xy")}
    return float(shear_ratio(mean, np.array([0]))[0])


def analyse(dumps: list[dict], shaking: tuple) -> list[dict]:
    """One row per dump (the module header): ``time``, ``ru`` and ``lost`` ({monitor: value}),
    ``left``, ``right`` (the flanks' surface displacement along x relative to the base [m]),
    ``settlement`` (the crest's, positive down [m]), ``tau_xy`` and ``sigma_v0`` ({monitor: the
    mean shear stress and the mean initial vertical effective stress [Pa]}), ``mobilised``
    ({monitor: :func:`mobilised_friction`}), ``p_ratio`` ({monitor: mean p' / mean p'_0}),
    ``at_apex`` ({monitor: the share of its particles at p' < 0.01 mean p'_0}), ``spread``
    ({monitor: the standard deviation of its particles' volumetric strain V/V0 - 1}),
    ``plastic_max``, ``noise_p99``, ``noise_max`` [Pa]; ``shaking`` and ``geometry`` with every
    row."""
    first, base0 = by_id(dumps[0]["particles"][SOLID]), by_id(dumps[0]["particles"][BASE])
    length = domain_length(dumps[0])
    spacing = float(np.min(np.diff(np.unique(np.round(first["x"], 9)))))
    geometry = bank_geometry(first, base0, spacing, length)
    points = monitor_points(geometry, length)
    members = {k: np.flatnonzero((unwrapped(first["x"] - px, length)) ** 2 + (first["y"] - py) ** 2
                                 < MONITOR_RADIUS**2) for k, (px, py) in points.items()}
    sv0 = -first["stress_yy"]
    p_0 = mean_stress(first)
    flanks = {side: surface_members(first, geometry, geometry[side], length)
              for side in ("left", "right")}
    crest = surface_members(first, geometry, geometry["crest"], length)
    p0 = dumps[0]["cell"]["pressure"][:, :, 0]
    level = float(cell_centres(dumps[0])[1][-1] + 0.5 * dumps[0]["attrs"]["dx"][1])
    rows = []
    for dump in dumps:
        parts, base = by_id(dump["particles"][SOLID]), by_id(dump["particles"][BASE])
        base_dx = float(np.mean(unwrapped(base["x"] - base0["x"], length)))
        ux = unwrapped(parts["x"] - first["x"], length) - base_dx
        i, j = particle_cells(dump, parts["x"], parts["y"], length)
        pex = dump["cell"]["pressure"][i, j, 0] - p0[i, j]
        noise = pore_pressure_roughness(dump, level=level, solid=SOLID, base=BASE)
        p_now = mean_stress(parts)
        rows.append({
            "time": float(dump["time"]), "shaking": shaking, "geometry": geometry,
            "ru": {k: float(np.mean(pex[m]) / np.mean(sv0[m])) for k, m in members.items()},
            "lost": {k: 1.0 - float(np.mean(-parts["stress_yy"][m]) / np.mean(sv0[m]))
                     for k, m in members.items()},
            "left": float(np.mean(ux[flanks["left"]])),
            "right": float(np.mean(ux[flanks["right"]])),
            "settlement": -float(np.mean(parts["y"][crest] - first["y"][crest])),
            "tau_xy": {k: float(np.mean(parts["stress_xy"][m])) for k, m in members.items()},
            "sigma_v0": {k: float(np.mean(sv0[m])) for k, m in members.items()},
            "mobilised": {k: mobilised_friction(parts, m) for k, m in members.items()},
            "p_ratio": {k: float(np.mean(p_now[m]) / np.mean(p_0[m])) for k, m in members.items()},
            "at_apex": {k: float(np.mean(p_now[m] < 0.01 * np.mean(p_0[m])))
                        for k, m in members.items()},
            "spread": {k: float(np.std(parts["volume"][m] / first["volume"][m] - 1.0))
                       for k, m in members.items()},
            "plastic_max": float(np.max(parts["plastic_strain"])),
            "noise_p99": noise[0], "noise_max": noise[1]})
    return rows


def cycle_table(rows: list[dict]) -> list[dict]:
    """Per shaking cycle n the row at its end with the noise's p99 averaged over the cycle's
    dumps (``noise_mean``) and its largest value there, and each monitor's cyclic stress ratio
    ``csr`` (half the range of its mean tau_xy over the cycle's dumps / its sigma'_v0), then the
    last dump (cycle 0, ``csr`` 0) when it is after the shaking's end."""
    table = []
    for n, inside, end in shaking_cycles(rows, rows[0]["shaking"]):
        csr = {}
        for k in MONITORS:
            tau = [r["tau_xy"][k] for r in inside]
            csr[k] = 0.5 * (max(tau) - min(tau)) / end["sigma_v0"][k]
        table.append(dict(end, cycle=n, csr=csr,
                          noise_mean=float(np.mean([r["noise_p99"] for r in inside])),
                          noise_max=float(np.max([r["noise_max"] for r in inside]))))
    _, _, duration, start = shaking_parts(rows[0]["shaking"])
    after = [r for r in rows if r["time"] > start + duration + 1e-9]
    if after:
        table.append(dict(after[-1], cycle=0, csr={k: 0.0 for k in MONITORS},
                          noise_mean=float(np.mean([r["noise_p99"] for r in after])),
                          noise_max=float(np.max([r["noise_max"] for r in after]))))
    return table


def print_cycle_table(table: list[dict]) -> None:
    """The table of :func:`cycle_table`, one line per cycle (cycle 0: the last dump, after the
    shaking)."""
    print("r_u (loss of sigma'_v) at the cycle's end: " + " / ".join(MONITORS))
    print("cycle  t [s]  r_u (loss) per monitor | flank displacement left / right [cm] | crest"
          " settlement [cm] | largest plastic strain | noise p99 mean / largest [kPa]")
    for c in table:
        ru = " ".join(f"{c['ru'][k]:5.2f} ({c['lost'][k]:4.2f})" for k in MONITORS)
        label = f"{c['cycle']:5d}" if c["cycle"] else "  end"
        print(f"{label} {c['time']:6.2f}  {ru} | {100 * c['left']:6.2f} {100 * c['right']:6.2f} | "
              f"{100 * c['settlement']:5.2f} | {c['plastic_max']:5.3f} | "
              f"{c['noise_mean'] / 1e3:5.2f} {c['noise_max'] / 1e3:6.2f}")
    print("cycle  per monitor: CSR in the cycle; at its end tau/p', p'/p'_0, the share of the"
          " particles at p' = 0 and the spread (standard deviation) of the volumetric strain"
          " V/V0 - 1")
    for c in table:
        label = f"{c['cycle']:5d}" if c["cycle"] else "  end"
        print(f"{label}  " + " | ".join(f"{c['csr'][k]:5.3f} {c['mobilised'][k]:5.3f} "
                                        f"{c['p_ratio'][k]:4.2f} {c['at_apex'][k]:4.2f} "
                                        f"{c['spread'][k]:7.1e}" for k in MONITORS))


def noise_summary(rows: list[dict]) -> tuple[float, float]:
    """(mean of the noise's p99 over the dumps of the shaking after its first 0.2 s, the largest
    noise there) [Pa]."""
    _, _, duration, start = shaking_parts(rows[0]["shaking"])
    inside = [r for r in rows if start + 0.2 < r["time"] <= start + duration + 1e-9]
    if not inside:
        return 0.0, 0.0
    return (float(np.mean([r["noise_p99"] for r in inside])),
            float(np.max([r["noise_max"] for r in inside])))


def after_shaking(rows: list[dict], step: float = 0.5) -> list[tuple[float, float, float]]:
    """(time, left, right flank displacement [m]) at the shaking's end and every ``step`` [s]
    after it (the dump nearest each time), to the last dump: a bank that flows moves on at a
    steady rate, one that only spread stops."""
    _, _, duration, start = shaking_parts(rows[0]["shaking"])
    end, last = start + duration, rows[-1]["time"]
    marks = np.arange(end, last + 1e-9, step)
    times = np.array([r["time"] for r in rows])
    picked = [rows[int(np.argmin(np.abs(times - m)))] for m in marks]
    return [(r["time"], r["left"], r["right"]) for r in picked]


def print_after_shaking(rows: list[dict]) -> None:
    """The flanks' displacement after the shaking (:func:`after_shaking`), with the movement of
    each interval."""
    marks = after_shaking(rows)
    if len(marks) < 2:
        return
    print("after the shaking: t [s], left / right flank displacement [cm] (moved since the line"
          " before)")
    for n, (t, left, right) in enumerate(marks):
        moved = "" if n == 0 else (f" ({100 * (left - marks[n - 1][1]):+6.2f} / "
                                   f"{100 * (right - marks[n - 1][2]):+6.2f})")
        print(f"  {t:5.2f}  {100 * left:7.2f} / {100 * right:7.2f}{moved}")


def print_summary(rows: list[dict]) -> None:
    """The bank's geometry, the cycle table, the flanks after the shaking and the noise over
    the shaking."""
    print_geometry(rows)
    print_cycle_table(cycle_table(rows))
    print_after_shaking(rows)
    p99, largest = noise_summary(rows)
    print(f"pore-pressure noise over the shaking (after its first 0.2 s): p99 {p99 / 1e3:.2f} kPa "
          f"(mean over the dumps), largest {largest / 1e3:.2f} kPa")


def write_csv(runs: dict[str, list[dict]], path: str) -> str:
    """Per run and dump: time, r_u and the loss of sigma'_v per monitor, the flanks'
    displacement, the crest's settlement and the noise's p99."""
    with open(path, "w", newline="", encoding="utf-8") as handle:
        out = csv.writer(handle)
        out.writerow(["run", "time_s"] + [f"ru_{k}" for k in MONITORS]
                     + [f"lost_{k}" for k in MONITORS]
                     + ["left_flank_ux_m", "right_flank_ux_m", "crest_settlement_m",
                        "noise_p99_Pa"])
        for label, rows in runs.items():
            for r in rows:
                out.writerow([label, f"{r['time']:.4f}"] + [f"{r['ru'][k]:.4f}" for k in MONITORS]
                             + [f"{r['lost'][k]:.4f}" for k in MONITORS]
                             + [f"{r['left']:.5f}", f"{r['right']:.5f}",
                                f"{r['settlement']:.5f}", f"{r['noise_p99']:.1f}"])
    return path


def figure(runs: dict[str, list[dict]], out: str) -> str:
    """The base acceleration a(t)/g, r_u at each monitor and the flanks' displacement against
    time, every run; returns the path of gentle_slope.png."""
    plt = pyplot()
    fig, axes = plt.subplots(len(MONITORS) + 2, 1, figsize=(8.0, 13.0), sharex=True)
    draw_base_acceleration(axes[0], runs)
    for n, (label, rows) in enumerate(runs.items()):
        t = np.array([r["time"] for r in rows])
        for ax, k in zip(axes[1:-1], MONITORS):
            ax.plot(t, [r["ru"][k] for r in rows], "-", color=f"C{n}", marker="o", ms=2,
                    label=label)
        axes[-1].plot(t, [100 * r["left"] for r in rows], "-", color=f"C{n}",
                      label=f"{label}, left flank")
        axes[-1].plot(t, [100 * r["right"] for r in rows], "--", color=f"C{n}",
                      label=f"{label}, right flank")
    for ax, k in zip(axes[1:-1], MONITORS):
        ru_axis(ax, f"r_u, {k}")
    axes[-1].set_ylabel("flank surface\nu_x - u_base [cm]", fontsize=8)
    axes[-1].legend(fontsize=7, loc="lower left")
    mark_cycle_ends(axes, next(iter(runs.values()))[0]["shaking"])
    axes[-1].set_xlabel("t [s] (grey: the end of each shaking cycle)")
    fig.tight_layout()
    path = os.path.join(out, "gentle_slope.png")
    save_figure(fig, path, dpi=100)
    return path


def print_geometry(rows: list[dict]) -> None:
    """The bank's levels and monitor points as found from the particles."""
    g = rows[0]["geometry"]
    print(f"base top {g['base_top']:.3f} m, layer top {g['layer_top']:.3f} m, crest top "
          f"{g['crest_top']:.3f} m; crest x {g['crest']:.2f} m, flanks' mid-points x "
          f"{g['left']:.2f} / {g['right']:.2f} m")


def main(argv=None) -> int:
    import sys
    return run_or_compare(sys.argv[1:] if argv is None else argv, __doc__.splitlines()[0], NAME,
                          lambda dumps, path: analyse(dumps, base_shaking(path, NAME)),
                          print_summary, figure,
                          lambda runs, out: write_csv(runs, os.path.join(out, "gentle_slope.csv")))


if __name__ == "__main__":
    raise SystemExit(main())
