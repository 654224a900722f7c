"""Diagnostics of the Rondon et al. (2011) runs (docs/validation/rondon2011.md, "What the models
miss"): what carries the front, and which particles change volume.

Usage:  python -m postproc.mpmice_rondon_diagnose DIR [DIR ...] [--times 1 2 3]
            [--plot PNG --plot-times T1 T2 ...]

Per run and per dump (or at the dumps nearest to ``--times``) it prints:

* ``front``: the postproc's front (largest bead x plus half the particle spacing), and the
  fronts by mass: the x behind which 99 % and 95 % of the beads' mass lies (``x99``, ``x95``);
* ``beyond``: the particles ahead of L0 + 2 cm (the run-out material): their share of the mass,
  the share of them that is suspended (porosity at or past ``max_porosity``, no effective
  stress), their mean solid fraction and mean p' [Pa] (-trace(stress)/3), and their mean height
  above the floor [cm];
* ``contact front``: the largest x of the particles in contact (not suspended) plus half the
  particle spacing;
* ``volume budget`` since the previous printed dump: the change of the summed particle volume
  [cm^3 per cm of width] of the particles in contact at both dumps (``dV contact``), of those
  that were in contact and are suspended now (``dV to susp.``) and of those already suspended
  at the previous dump (``dV susp.``); a positive total draws liquid into the mass (suction), a
  negative one expels it; ``near probe``: the same total and its suspended part for the
  particles within ``NEAR`` of the wall at the previous dump (the mass over the probe);
* ``base p``: the base excess pore pressure at the probe (as postproc.mpmice_rondon);
* ``overlap``: the largest summed volume of the particles of one cell over the cell's volume
  (``overlap``; 1 for particles that tile the cells).

``--plot PNG`` draws the beads of each run (one row per run) at ``--plot-times`` (one column
each, the nearest dump), coloured by their solid fraction, the suspended ones (no effective
stress) as crosses.
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc import mpmice_rondon as rondon
from postproc.measures import by_id, mean_stress
from postproc.mpmice_io import read_run_dumps

BEYOND = rondon.L0 + 0.02     # m: particles ahead of it are counted as run-out material
NEAR = rondon.PROBE_X + 0.02  # m: particles behind it are the mass over the pressure probe


def mass_front(parts: dict, share: float) -> float:
    """The x [m] behind which `share` of the beads' mass lies."""
    order = np.argsort(parts["x"])
    cum = np.cumsum(parts["mass"][order]) / np.sum(parts["mass"])
    return float(parts["x"][order][np.searchsorted(cum, share)])


def state(dump: dict) -> dict:
    """Per particle (sorted by id): x, y, mass, volume, solid fraction, p' and the suspended
    flag of the beads of one dump."""
    group = rondon.solid_group(dump)
    parts = dump["particles"][rondon.SOLID]
    p = by_id(parts)
    phi = p["mass"] / (float(group["density"]) * p["volume"])
    n_max = float(group.get("max_porosity", 1.0))
    return {"id": p["id"], "x": p["x"], "y": p["y"], "mass": p["mass"], "volume": p["volume"],
            "phi": phi, "suspended": (1.0 - phi) >= n_max - 1e-6,
            "p": mean_stress(p), "parts": p}


def overlap(dump: dict) -> float:
    """The largest summed volume of the beads whose centres lie in one cell, over the cell's
    volume: 1 for particles that tile the cells; well above 1 where particles report volumes
    (J = det F) that overlap, i.e. packings looser than the space their grains occupy."""
    attrs = dump["attrs"]
    lower = np.asarray(attrs["lower"], dtype=float).reshape(3)
    dx = np.asarray(attrs["dx"], dtype=float).reshape(3)
    n = np.asarray(attrs["ncells"], dtype=int).reshape(3)
    parts = dump["particles"][rondon.SOLID]
    idx = [np.clip(((np.asarray(parts[a]) - lower[k]) / dx[k]).astype(int), 0, n[k] - 1)
           for k, a in enumerate(("x", "y"))]
    cover = np.zeros(n[:2])
    np.add.at(cover, tuple(idx), np.asarray(parts["volume"]) / float(np.prod(dx)))
    return float(cover.max())


def report(folder: str, times=None) -> list[dict]:
    """Print the diagnostics of one run; return one dict per printed dump."""
    dumps = read_run_dumps(folder, rondon.NAME)
    have = np.array([d["time"] for d in dumps])
    picks = range(len(dumps)) if not times else \
        sorted({0, *(int(np.argmin(np.abs(have - t))) for t in times)})
    width = float(np.asarray(dumps[0]["attrs"]["upper"]).reshape(3)[2]
                  - np.asarray(dumps[0]["attrs"]["lower"]).reshape(3)[2])
    rows, prev = [], None
    print(f"== {folder}")
    for k in picks:
        d = dumps[k]
        s = state(d)
        half = 0.5 * rondon.spacing(d)
        contact = ~s["suspended"]
        row = {"t": d["time"], "front": rondon.model_front(d),
               "contact_front": float(np.max(s["x"][contact])) + half if contact.any()
               else np.nan,
               "x99": mass_front(s["parts"], 0.99), "x95": mass_front(s["parts"], 0.95),
               "base_p": rondon.base_pressure(d, dumps[0]), "overlap": overlap(d)}
        ahead = s["x"] > BEYOND
        row["beyond_mass"] = float(np.sum(s["mass"][ahead]) / np.sum(s["mass"]))
        row["beyond_suspended"] = float(np.mean(s["suspended"][ahead])) if ahead.any() else 0.0
        row["beyond_phi"] = float(np.mean(s["phi"][ahead])) if ahead.any() else np.nan
        row["beyond_p"] = float(np.mean(s["p"][ahead])) if ahead.any() else np.nan
        row["beyond_height"] = float(np.mean(s["y"][ahead])) if ahead.any() else np.nan
        row["dv_contact"] = row["dv_to_suspended"] = row["dv_suspended"] = np.nan
        row["dv_near"] = row["dv_near_suspended"] = np.nan
        if prev is not None and np.array_equal(prev["id"], s["id"]):
            dv = (s["volume"] - prev["volume"]) / width * 1e4     # cm^3 per cm of width
            row["dv_contact"] = float(np.sum(dv[~prev["suspended"] & ~s["suspended"]]))
            row["dv_to_suspended"] = float(np.sum(dv[~prev["suspended"] & s["suspended"]]))
            row["dv_suspended"] = float(np.sum(dv[prev["suspended"]]))
            near = prev["x"] < NEAR
            row["dv_near"] = float(np.sum(dv[near]))
            row["dv_near_suspended"] = float(np.sum(dv[near & (prev["suspended"] |
                                                                s["suspended"])]))
        print(f"t = {row['t']:5.2f} s  front {row['front'] * 100:6.2f}  contact front "
              f"{row['contact_front'] * 100:6.2f}  x99 {row['x99'] * 100:6.2f}"
              f"  x95 {row['x95'] * 100:6.2f} cm | beyond {BEYOND * 100:g} cm: mass "
              f"{row['beyond_mass']:.3f}, suspended {row['beyond_suspended']:.2f}, phi "
              f"{row['beyond_phi']:.3f}, p' {row['beyond_p']:6.1f} Pa, height "
              f"{row['beyond_height'] * 100:5.2f} cm | dV contact {row['dv_contact']:+7.3f}, to susp. "
              f"{row['dv_to_suspended']:+7.3f}, susp. {row['dv_suspended']:+7.3f} cm^3/cm; near probe "
              f"{row['dv_near']:+7.3f} (susp. {row['dv_near_suspended']:+7.3f}) | "
              f"base p {row['base_p']:7.1f} Pa | overlap {row['overlap']:5.2f}")
        rows.append(row)
        prev = s
    return rows


def plot(folders: list[str], times: list[float], path: str) -> str:
    """The beads of each run at the dumps nearest to `times`, by solid fraction; suspended
    particles as crosses."""
    from postproc.figures import pyplot, save_figure
    plt = pyplot()
    fig, axes = plt.subplots(len(folders), len(times), figsize=(4.2 * len(times),
                                                                 1.5 * len(folders) + 0.8),
                             squeeze=False)
    image = None
    for i, folder in enumerate(folders):
        dumps = read_run_dumps(folder, rondon.NAME)
        have = np.array([d["time"] for d in dumps])
        for j, t in enumerate(times):
            ax = axes[i, j]
            d = dumps[int(np.argmin(np.abs(have - t)))]
            s = state(d)
            contact = ~s["suspended"]
            image = ax.scatter(s["x"][contact] * 100, s["y"][contact] * 100, c=s["phi"][contact],
                               s=4, cmap="viridis", vmin=0.3, vmax=0.62)
            ax.scatter(s["x"][~contact] * 100, s["y"][~contact] * 100, c=s["phi"][~contact],
                       s=10, marker="x", cmap="viridis", vmin=0.3, vmax=0.62, linewidths=0.7)
            ax.set_xlim(0, 22)
            ax.set_ylim(0, 5.2)
            ax.set_aspect("equal")
            ax.set_title(f"{os.path.basename(folder.rstrip('/'))}, t = {d['time']:.2f} s",
                         fontsize=8)
            ax.tick_params(labelsize=7)
    fig.colorbar(image, ax=axes, shrink=0.8, label="solid fraction (x: suspended)")
    return save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dirs", nargs="+", help="output directories of Rondon runs")
    parser.add_argument("--times", nargs="*", type=float, default=None,
                        help="print only the dumps nearest to these times [s]")
    parser.add_argument("--plot", default=None, help="write the particle figure here (PNG)")
    parser.add_argument("--plot-times", nargs="+", type=float, default=[1.0, 2.0, 3.0])
    args = parser.parse_args(argv)
    for folder in args.dirs:
        report(folder, args.times)
    if args.plot:
        print(plot(args.dirs, args.plot_times, args.plot))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
