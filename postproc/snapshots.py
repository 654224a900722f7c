"""Snapshots of any run: cell fields and particles at chosen times, one PNG per dump.

Usage:  python -m postproc.snapshots RUN_DIR [--name NAME] [--times T [T ...] | --times all]
            [--fields F [F ...]] [--particles-colour FIELD] [--rigid SOLID [SOLID ...]]
            [--slice AXIS[=VALUE]] [--out DIR]

RUN_DIR is a run's output directory (dumps <name>_<step>.h5; the name is found from
<name>.used.nml or the dump files, --name when it holds several runs). For each requested time
the nearest dump is drawn (default: four dumps evenly spaced from the first to the last; "all":
every dump) into <out>/<name>_snapshot_<step>.png (default out: RUN_DIR/postproc).

Panels, one per field and one of the particles:

* --fields: cell fields by dataset name below /cell (``pressure``, ``water/density``,
  ``sand/volume_fraction``), ``<material>/speed`` (|u| from its velocity components), or the
  groups ``fractions`` (every fluid's volume fraction), ``velocity`` (every fluid's speed, with
  arrows in maps) and ``pressure``; default ``fractions pressure velocity`` (the groups a run
  without fluids lacks are left out; a run without fluids gets every solid's volume fraction
  and speed instead, a run with neither, e.g. heat conduction, every cell field); speeds are
  blank where the material's volume fraction is below 0.01;
* the particles of every solid coloured by --particles-colour (a particle dataset such as
  ``pore_pressure``, ``plastic_strain``, ``stress_yy``; ``speed``; or ``displacement``, the
  distance from the particle's position in the first dump, matched by id; default ``speed``);
  rigid solids (``&solid model = 'rigid'`` in the run's input, or named with --rigid) are drawn
  grey as they are in the dump, on the particle panel and on every map.

1D runs give line plots against the active coordinate (particles: the colour field against
position, rigid bodies as grey ticks); 2D runs give maps of the two active axes; 3D runs give
maps of a plane through the domain's middle: by default the plane holding the vertical (gravity)
axis and the first other axis, its normal the remaining axis; --slice y (or y=0.3 for the cell
layer holding y = 0.3 m) chooses the normal and the position. A 3D map shows the particles of the
cell layer cut by the plane.
Exit status 1 with one line on stderr for a missing directory, no dumps, an unknown field.
"""
from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

from postproc.figures import pyplot, save_figure
from postproc.measures import by_id
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_files import AXES, active_axes, materials, pick_dumps, run_name, vertical_axis

DEFAULT_FIELDS = ("fractions", "pressure", "velocity")
GROUPS = ("fractions", "velocity")


def _speed(store: dict, prefix: str) -> np.ndarray | None:
    comps = [store[f"{prefix}velocity_{a}"] for a in AXES if f"{prefix}velocity_{a}" in store]
    if not comps:
        return None
    return np.sqrt(sum(np.asarray(c, dtype=float) ** 2 for c in comps))


def resolve_fields(dump: dict, requested) -> list[str]:
    """The cell panels of ``requested`` (module notes) for a dump, groups expanded. A name that
    is neither a group, a dataset nor ``<material>/speed`` of a material with a velocity raises
    KeyError naming it and what the dump has."""
    fluids = materials(dump)["fluids"]
    explicit = requested is not None
    out = []
    for name in (requested if explicit else DEFAULT_FIELDS):
        if name == "fractions":
            out += [f"{f}/volume_fraction" for f in fluids
                    if f"{f}/volume_fraction" in dump["cell"]]
        elif name == "velocity":
            out += [f"{f}/speed" for f in fluids if f"{f}/velocity_x" in dump["cell"]]
        elif name in dump["cell"]:
            out.append(name)
        elif name.endswith("/speed") and _speed(dump["cell"], name[:-len("speed")]) is not None:
            out.append(name)
        elif explicit:
            raise KeyError(f"field {name!r} is not in {dump['path']} (cell fields: "
                           f"{', '.join(sorted(dump['cell']))}; groups: {', '.join(GROUPS)})")
    if not explicit and not out:       # no fluid, no pressure: the solids' fractions and speeds,
        for solid in materials(dump)["solids"]:            # else every field (heat conduction)
            if f"{solid}/volume_fraction" in dump["cell"]:
                out.append(f"{solid}/volume_fraction")
            if f"{solid}/velocity_x" in dump["cell"]:
                out.append(f"{solid}/speed")
        out = out or sorted(dump["cell"])
    return list(dict.fromkeys(out))


#: A material's speed is drawn where its volume fraction exceeds this (elsewhere it is blank).
SPEED_MIN_FRACTION = 0.01


def cell_field(dump: dict, name: str) -> np.ndarray:
    """A cell panel's values [i, j, k]: a dataset, or ``<material>/speed`` (NaN in cells where
    the material's volume fraction is not above SPEED_MIN_FRACTION)."""
    if name.endswith("/speed") and name not in dump["cell"]:
        prefix = name[:-len("speed")]
        speed = _speed(dump["cell"], prefix)
        fraction = dump["cell"].get(f"{prefix}volume_fraction")
        if fraction is not None:
            speed = np.where(fraction > SPEED_MIN_FRACTION, speed, np.nan)
        return speed
    return dump["cell"][name]


def particle_values(dump: dict, first: dict, solid: str, field: str) -> np.ndarray:
    """The colour values of a solid's particles (in the dump's order): a dataset, ``speed``, or
    ``displacement`` from the first dump (matched by id)."""
    parts = dump["particles"][solid]
    if field == "speed":
        speed = _speed(parts, "")
        if speed is None:
            raise KeyError(f"solid {solid!r} of {dump['path']} has no particle velocity: "
                           "choose --particles-colour")
        return speed
    if field == "displacement":
        now, start = by_id(parts), by_id(first["particles"][solid])
        if len(now["x"]) != len(start["x"]):
            raise KeyError(f"solid {solid!r}: the particle count changed since the first dump, "
                           "no displacement")
        dist = np.sqrt(sum((now[a] - start[a]) ** 2 for a in AXES if a in now))
        out = np.empty_like(dist)
        order = np.argsort(parts["id"]) if "id" in parts else np.arange(len(dist))
        out[order] = dist
        return out
    if field not in parts:
        raise KeyError(f"particle field {field!r} is not in solid {solid!r} of {dump['path']} "
                       f"(fields: {', '.join(sorted(parts))}, speed, displacement)")
    return np.asarray(parts[field], dtype=float)


def plane(dump: dict, slice_arg: str | None) -> tuple[list[int], int | None, int | None]:
    """([axis on the plot's x, axis on its y], normal axis, cell index of the slice) for a dump:
    1D: ([a], None, None); 2D: the active axes, the vertical one on the plot's y, the inactive
    axis as normal with index 0; 3D: the slice (module notes)."""
    active = active_axes(dump) or [0]
    vert, _ = vertical_axis(dump)
    if len(active) == 1:
        return active, None, None
    if len(active) == 2:
        a, b = active
        normal = [d for d in range(3) if d not in active][0]
        return ([b, a] if a == vert else [a, b]), normal, 0
    if slice_arg:
        key, _, value = slice_arg.partition("=")
        if key not in AXES:
            raise KeyError(f"--slice {slice_arg}: the axis must be x, y or z")
        normal = AXES.index(key)
    else:
        normal = [d for d in range(3) if d != vert][1]
        value = ""
    shown = [d for d in range(3) if d != normal]
    if vert in shown and shown[0] == vert:
        shown = shown[::-1]
    centres = cell_centres(dump)[normal]
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[normal])
    if value:
        try:
            position = float(value)
        except ValueError:
            raise KeyError(f"--slice {slice_arg}: the position must be a number [m]") from None
        index = int(np.clip(np.floor((position - (centres[0] - 0.5 * dx)) / dx), 0,
                            len(centres) - 1))
    else:
        index = len(centres) // 2
    return shown, normal, index


def plane_values(values: np.ndarray, shown: list[int], normal: int | None,
                 index: int | None) -> np.ndarray:
    """A cell field [i, j, k] on the drawn plane: 1-D along the axis for 1D runs, else 2-D
    [along shown[0], along shown[1]]."""
    if normal is None:
        return np.asarray(values).reshape(-1)
    cut = np.take(values, index, axis=normal)       # remaining axes in ascending order
    return cut if shown[0] < shown[1] else cut.T


def _in_layer(dump: dict, parts: dict, normal: int | None, index: int | None) -> np.ndarray:
    """Particles in the cell layer the plane cuts (all of them in 1D and 2D runs)."""
    n = len(parts["x"])
    if normal is None or len(active_axes(dump)) < 3:
        return np.ones(n, dtype=bool)
    centres = cell_centres(dump)[normal]
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[normal])
    lo = centres[index] - 0.5 * dx
    c = np.asarray(parts[AXES[normal]])
    return (c >= lo) & (c < lo + dx)


def draw(dump: dict, first: dict, fields: list[str], colour: str, rigid: list[str],
         slice_arg: str | None, path: str, title: str) -> str:
    """One snapshot PNG of a dump; returns its path."""
    plt = pyplot()
    shown, normal, index = plane(dump, slice_arg)
    centres = cell_centres(dump)
    solids = list(dump.get("particles", {}))
    moving = [s for s in solids if s not in rigid]
    values = {s: particle_values(dump, first, s, colour) for s in moving}
    npanel = len(fields) + (1 if solids else 0)
    if npanel == 0:
        raise KeyError(f"{dump['path']}: nothing to draw (no cell field asked for and no "
                       "particles)")
    ncols = min(3, npanel)
    nrows = math.ceil(npanel / ncols)
    if len(shown) == 1:
        size = (5.0 * ncols, 3.2 * nrows)
    else:                              # panels of about 5 x 5 inches at most, plus a colour bar
        extent = [float(centres[d][-1] - centres[d][0]) + 1e-12 for d in shown]
        ratio = extent[1] / extent[0]
        width, height = (5.0, max(1.5, 5.0 * ratio)) if ratio <= 1.0 else (max(2.0, 5.0 / ratio),
                                                                            5.0)
        size = ((width + 1.5) * ncols, (height + 1.0) * nrows + 0.4)
    fig, axes = plt.subplots(nrows, ncols, figsize=size, squeeze=False)
    for ax in axes.flat[npanel:]:
        ax.set_visible(False)
    if len(shown) == 1:                # 1D: every panel over the whole domain
        lower = float(np.asarray(dump["attrs"]["lower"]).reshape(3)[shown[0]])
        width = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[shown[0]]) * len(centres[shown[0]])
        for ax in axes.flat[:npanel]:
            ax.set_xlim(lower, lower + width)
    cut = {s: _in_layer(dump, dump["particles"][s], normal, index) for s in solids}

    def rigid_overlay(ax):
        for s in rigid:
            if s in dump.get("particles", {}):
                p, m = dump["particles"][s], cut[s]
                if len(shown) == 1:
                    ax.plot(p[AXES[shown[0]]][m], np.zeros(int(m.sum())), "|", color="0.4",
                            transform=ax.get_xaxis_transform(), ms=8)
                else:
                    ax.plot(p[AXES[shown[0]]][m], p[AXES[shown[1]]][m], ".", color="0.55", ms=1)

    for ax, name in zip(axes.flat, fields):
        value = plane_values(cell_field(dump, name), shown, normal, index)
        if len(shown) == 1:
            ax.plot(centres[shown[0]], value, "-")
            ax.set_ylabel(name)
        else:
            a, b = shown
            kw = {"vmin": 0.0, "vmax": 1.0} if name.endswith("volume_fraction") else {}
            mesh = ax.pcolormesh(centres[a], centres[b], value.T, shading="nearest",
                                 cmap="Blues" if "vmin" in kw else "viridis", **kw)
            fig.colorbar(mesh, ax=ax, label=name, fraction=0.046)
            if name.endswith("/speed"):
                prefix = name[:-len("speed")]
                comps = [f"{prefix}velocity_{AXES[d]}" for d in (a, b)]
                if all(c in dump["cell"] for c in comps) and np.nanmax(value, initial=0.0) > 0.0:
                    u, v = (np.where(np.isfinite(value), plane_values(dump["cell"][c], shown,
                                                                      normal, index), np.nan)
                            for c in comps)
                    si = max(1, len(centres[a]) // 20)
                    sj = max(1, len(centres[b]) // 20)
                    ax.quiver(centres[a][::si], centres[b][::sj], u[::si, ::sj].T,
                              v[::si, ::sj].T, color="w", width=0.003)
            ax.set_aspect("equal")
            ax.set_ylabel(f"{AXES[b]} [m]")
        rigid_overlay(ax)
        ax.set_xlabel(f"{AXES[shown[0]]} [m]")
        ax.set_title(name, fontsize=9)
    if solids:
        ax = axes.flat[len(fields)]
        if len(shown) == 1:
            for s in moving:
                ax.plot(dump["particles"][s][AXES[shown[0]]], values[s], ".", ms=2, label=s)
            ax.set_ylabel(colour)
            if moving:
                ax.legend(fontsize=7)
        else:
            a, b = shown
            lo = min((float(np.min(values[s][cut[s]])) for s in moving if cut[s].any()),
                     default=0.0)
            hi = max((float(np.max(values[s][cut[s]])) for s in moving if cut[s].any()),
                     default=1.0)
            sc = None
            for s in moving:
                p, m = dump["particles"][s], cut[s]
                sc = ax.scatter(p[AXES[a]][m], p[AXES[b]][m], c=values[s][m], s=2,
                                vmin=lo, vmax=max(hi, lo + 1e-300), cmap="viridis")
            if sc is not None:
                fig.colorbar(sc, ax=ax, label=colour, fraction=0.046)
            ax.set_xlim(centres[a][0] - 0.5 * (centres[a][1] - centres[a][0]),
                        centres[a][-1] + 0.5 * (centres[a][1] - centres[a][0]))
            ax.set_ylim(centres[b][0] - 0.5 * (centres[b][1] - centres[b][0]),
                        centres[b][-1] + 0.5 * (centres[b][1] - centres[b][0]))
            ax.set_aspect("equal")
            ax.set_ylabel(f"{AXES[b]} [m]")
        rigid_overlay(ax)
        ax.set_xlabel(f"{AXES[shown[0]]} [m]")
        ax.set_title(f"particles: {colour}" + (f" (rigid, grey: {', '.join(rigid)})"
                                               if any(r in solids for r in rigid) else ""),
                     fontsize=9)
    if len(active_axes(dump)) == 3:
        c = cell_centres(dump)[normal][index]
        title += f", plane {AXES[normal]} = {c:.4g} m"
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - 0.4 / size[1]))
    return save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", help="output directory of a run")
    parser.add_argument("--name", default=None, help="run name (when RUN_DIR holds several)")
    parser.add_argument("--times", nargs="+", default=None,
                        help="times [s] (the nearest dump each) or 'all'")
    parser.add_argument("--fields", nargs="+", default=None)
    parser.add_argument("--particles-colour", "--particles-color", dest="colour", default="speed")
    parser.add_argument("--rigid", nargs="+", default=[], help="solids to draw as rigid bodies")
    parser.add_argument("--slice", default=None, help="3D: normal axis of the plane [=position]")
    parser.add_argument("--out", default=None, help="where the PNGs go (default RUN_DIR/postproc)")
    args = parser.parse_args(argv)
    name = run_name(args.run_dir, args.name)
    paths = list_dumps(args.run_dir, name)
    times = args.times
    if times is not None and times != ["all"]:
        try:
            times = [float(t) for t in times]
        except ValueError:
            raise SystemExit(f"--times {' '.join(args.times)}: give numbers [s] or 'all'") from None
    elif times == ["all"]:
        times = "all"
    chosen = pick_dumps(paths, times)
    first = read_dump(paths[0])
    rigid = list(dict.fromkeys(materials(first)["rigid"] + args.rigid))
    try:
        fields = resolve_fields(first, args.fields)
        for s in (s for s in first.get("particles", {}) if s not in rigid):
            particle_values(first, first, s, args.colour)
        plane(first, args.slice)
        if not fields and not first.get("particles"):
            raise KeyError(f"{paths[0]}: nothing to draw (no cell field and no particles)")
    except KeyError as error:
        raise SystemExit(error.args[0]) from None
    out = args.out or os.path.join(args.run_dir, "postproc")
    os.makedirs(out, exist_ok=True)
    for i in chosen:
        dump = first if i == 0 else read_dump(paths[i])
        path = os.path.join(out, f"{name}_snapshot_{dump['step']:06d}.png")
        title = f"{name}: t = {dump['time']:.4g} s (step {dump['step']})"
        try:
            draw(dump, first, resolve_fields(dump, args.fields), args.colour, rigid,
                 args.slice, path, title)
        except KeyError as error:
            raise SystemExit(error.args[0]) from None
        print(f"t = {dump['time']:.4g} s: {path}")
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
