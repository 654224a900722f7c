"""Front, run-out and height of a solid moving in any direction, and the free surface of a liquid,
over the dumps of any run.

Usage:  python -m postproc.slide RUN_DIR --solid NAME [--name RUN] [--direction +x|-x|+y|-y|+z|-z]
            [--liquid FLUID | --liquid none] [--level L] [--surface crossing|height] [--out DIR]

The direction of motion is found from the solid's displacement (postproc/measures.py): the
horizontal axis (an active axis that is not the vertical one, which is the axis of gravity in the
run's input, else y in 2D and z in 3D) along which the solid's centre of mass moved most between
the first and the last dump, with the sign of that move; --direction imposes it. Per dump:

* front [m]: the coordinate, along that axis, of the particle farthest in the direction (largest
  x for +x, smallest x for -x);
* run-out [m]: how far the front has advanced in the direction since the first dump;
* top [m]: the highest particle's vertical coordinate; height [m]: top minus the lowest
  particle's vertical coordinate in the first dump (the deposit's height above the solid's
  initial base);
* with a liquid (default water when the run has it): the free surface eta [m] relative to
  --level (default: the mean surface of the first dump) in every column, method --surface
  (default crossing: where the liquid's share of the fluid volume reaches 0.5), its max and min.

Prints the table and a summary (direction, final front, run-out, final top and height), writes
<name>_slide_<solid>.csv (one row per dump) and <name>_slide_<solid>.png (front and run-out
against time; the solid's particles in the first and the last dump, in the plane of the
direction and the vertical; the free surface of each dump) into --out (default RUN_DIR/postproc).
Exit status 1 with one line on stderr for a missing directory, no dumps, an unknown solid or
liquid, or a solid that did not move (give --direction).
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc import measures
from postproc.figures import pyplot, save_figure
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_files import AXES, materials, run_name, vertical_axis

COLUMNS = ("time", "front", "runout", "top", "height", "eta_max", "eta_min")


def parse_direction(text: str) -> tuple[int, int]:
    """'+x', '-y', 'z' (= '+z') -> (axis, sign); ValueError otherwise."""
    text = text.strip().lower()
    sign = -1 if text.startswith("-") else 1
    axis = text.lstrip("+-")
    if axis not in AXES or len(text) - len(axis) > 1:
        raise ValueError(f"--direction {text}: allowed +x, -x, +y, -y, +z, -z")
    return AXES.index(axis), sign


def direction_label(axis: int, sign: int) -> str:
    """(0, -1) -> '-x'."""
    return ("+" if sign > 0 else "-") + AXES[axis]


def analyse(dumps: list[dict], solid: str, direction: tuple[int, int] | None = None,
            liquid: str | None = None, level: float | None = None,
            surface: str = "crossing") -> dict:
    """Front, run-out, top, height and free-surface extremes of every dump (module notes).
    Returns {"direction": (axis, sign), "vertical": (axis, up), "level": level or None,
    "rows": [{column: value}], "surfaces": [(coordinates, eta)] (empty without a liquid)}."""
    first, last = dumps[0], dumps[-1]
    for d in dumps:
        if solid not in d.get("particles", {}):
            raise KeyError(f"solid {solid!r} has no particles in {d['path']} (solids: "
                           f"{', '.join(d.get('particles', {})) or 'none'})")
    vertical = vertical_axis(first)
    if direction is None:
        direction = measures.slide_direction(first, last, solid, vertical)
    axis, sign = direction
    if liquid is not None and level is None:
        _, eta0 = measures.free_surface(first, liquid, level=0.0, method=surface,
                                        vertical=vertical)
        level = float(np.nanmean(eta0)) if np.any(np.isfinite(eta0)) else 0.0
    front0 = measures.front(first["particles"][solid], axis, sign)
    base0 = measures.bottom(first["particles"][solid], vertical)
    rows, surfaces = [], []
    for d in dumps:
        parts = d["particles"][solid]
        f = measures.front(parts, axis, sign)
        top = measures.top(parts, vertical)
        row = {"time": float(d["time"]), "front": f, "runout": measures.runout(f, front0, sign),
               "top": top, "height": vertical[1] * (top - base0),
               "eta_max": np.nan, "eta_min": np.nan}
        if liquid is not None:
            coords, eta = measures.free_surface(d, liquid, level=level, method=surface,
                                                vertical=vertical)
            surfaces.append((coords, eta))
            if np.any(np.isfinite(eta)):
                row["eta_max"], row["eta_min"] = float(np.nanmax(eta)), float(np.nanmin(eta))
        rows.append(row)
    return {"direction": direction, "vertical": vertical, "level": level, "rows": rows,
            "surfaces": surfaces}


def write_csv(rows: list[dict], path: str) -> str:
    """The table, one row per dump (columns COLUMNS; NaN where there is no liquid)."""
    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(f"{r[c]:.9g}" for c in COLUMNS) + "\n")
    return path


def plot(dumps: list[dict], result: dict, solid: str, path: str) -> str:
    """Front and run-out against time, the solid at the start and the end, the free surfaces."""
    plt = pyplot()
    axis, sign = result["direction"]
    vert = result["vertical"][0]
    rows = result["rows"]
    t = [r["time"] for r in rows]
    npanel = 3 if result["surfaces"] else 2
    fig, axes = plt.subplots(npanel, 1, figsize=(7, 3.2 * npanel))
    ax = axes[0]
    ax.plot(t, [r["front"] for r in rows], "o-", ms=3, label="front")
    ax.set_ylabel(f"front {AXES[axis]} [m]")
    ax.set_xlabel("t [s]")
    twin = ax.twinx()
    twin.plot(t, [r["runout"] for r in rows], "s--", ms=3, color="C1", label="run-out")
    twin.set_ylabel("run-out [m]")
    ax.set_title(f"{solid}: moving {direction_label(axis, sign)}", fontsize=9)
    ax = axes[1]
    for d, style, label in ((dumps[0], "C0", "first"), (dumps[-1], "C3", "last")):
        p = d["particles"][solid]
        ax.plot(p[AXES[axis]], p[AXES[vert]], ".", ms=1.5, color=style,
                label=f"{label} dump, t = {d['time']:.3g} s")
    ax.set_xlabel(f"{AXES[axis]} [m]")
    ax.set_ylabel(f"{AXES[vert]} [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, markerscale=5)
    if result["surfaces"]:
        ax = axes[2]
        for d, (coords, eta) in zip(dumps, result["surfaces"]):
            if eta.ndim == 1:
                ax.plot(coords[0], eta, label=f"t = {d['time']:.3g} s")
            elif eta.ndim == 2:             # 3D: the row through the middle, along the motion
                keep = [i for i in range(3) if i != vert]
                a = keep.index(axis) if axis in keep else 0
                line = np.take(eta, eta.shape[1 - a] // 2, axis=1 - a)
                ax.plot(coords[a], line, label=f"t = {d['time']:.3g} s")
        ax.set_ylabel(f"eta [m] (relative to {result['level']:.4g} m)")
        ax.set_xlabel(f"{AXES[axis]} [m]")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", help="output directory of a run")
    parser.add_argument("--solid", required=True, help="the solid whose front is followed")
    parser.add_argument("--name", default=None, help="run name (when RUN_DIR holds several)")
    parser.add_argument("--direction", default=None, help="+x, -x, +y, -y, +z or -z")
    parser.add_argument("--liquid", default=None, help="fluid of the free surface, or none")
    parser.add_argument("--level", type=float, default=None, help="still level [m]")
    parser.add_argument("--surface", default="crossing", choices=("crossing", "height"))
    parser.add_argument("--out", default=None, help="where the CSV and PNG go")
    args = parser.parse_args(argv)
    name = run_name(args.run_dir, args.name)
    try:
        direction = parse_direction(args.direction) if args.direction else None
    except ValueError as error:
        raise SystemExit(str(error)) from None
    dumps = [read_dump(p) for p in list_dumps(args.run_dir, name)]
    fluids = materials(dumps[0])["fluids"]
    liquid = args.liquid
    if liquid is None:
        liquid = "water" if "water" in fluids else None
    elif liquid.lower() == "none":
        liquid = None
    elif liquid not in fluids:
        raise SystemExit(f"--liquid {liquid}: not a fluid of {name} (fluids: "
                         f"{', '.join(fluids) or 'none'})")
    try:
        result = analyse(dumps, args.solid, direction, liquid, args.level, args.surface)
    except (KeyError, ValueError) as error:
        message = error.args[0]
        if isinstance(error, ValueError) and "did not move" in message:
            message += "; give --direction"
        raise SystemExit(message) from None
    axis, sign = result["direction"]
    print(f"{name}: solid {args.solid}, moving {direction_label(axis, sign)}"
          f"{' (given)' if direction else ' (from its displacement)'}, vertical "
          f"{'+' if result['vertical'][1] > 0 else '-'}{AXES[result['vertical'][0]]}"
          + (f", free surface of {liquid} relative to {result['level']:.6g} m" if liquid else ""))
    print(f"{'t [s]':>10} {'front [m]':>11} {'run-out [m]':>12} {'top [m]':>9} {'height [m]':>11}"
          + (f" {'eta max [m]':>12} {'eta min [m]':>12}" if liquid else ""))
    for r in result["rows"]:
        print(f"{r['time']:10.4f} {r['front']:11.5f} {r['runout']:12.5f} {r['top']:9.5f} "
              f"{r['height']:11.5f}"
              + (f" {r['eta_max']:12.5f} {r['eta_min']:12.5f}" if liquid else ""))
    end = result["rows"][-1]
    print(f"final (t = {end['time']:.4g} s): front {AXES[axis]} = {end['front']:.5f} m, run-out "
          f"{end['runout']:.5f} m, top {end['top']:.5f} m, height {end['height']:.5f} m")
    out = args.out or os.path.join(args.run_dir, "postproc")
    os.makedirs(out, exist_ok=True)
    stem = os.path.join(out, f"{name}_slide_{args.solid}")
    print(f"table: {write_csv(result['rows'], stem + '.csv')}")
    print(f"plot: {plot(dumps, result, args.solid, stem + '.png')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
