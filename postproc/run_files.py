"""What the output directory of any run holds, for the scene-independent tools
(:mod:`postproc.snapshots`, :mod:`postproc.slide`, :mod:`postproc.series`; docs/postprocessing.md).

* the run's name (:func:`run_name`: from ``<name>.used.nml``, else from the dump files);
* its dumps and their times (:func:`dump_times`), the dumps nearest to requested times
  (:func:`pick_dumps`);
* its materials (:func:`materials`: fluids, solids, rigid solids, gravity), from the resolved
  input every dump carries (root attribute ``namelist``), else from the datasets;
* the vertical axis (:func:`vertical_axis`: along gravity) and the active axes;
* the per-step CSV files (:func:`read_step_csv`, :func:`step_files`): ``<name>_mpm_series.csv``
  (MPM scene: energies and particle extents), ``<name>_contact_force.csv`` (coupled scene with
  rigid bodies: the force on each one).

Dumps are read with :mod:`postproc.mpmice_io` (the one reader)::

    from postproc.run_files import run_name, pick_dumps, materials
    name = run_name("output/run")
    paths = list_dumps("output/run", name)
    chosen = pick_dumps(paths, [0.5, 1.0])
"""
from __future__ import annotations

import os
import re

import numpy as np

from postproc.mpmice_io import list_dumps, read_attrs
from postproc.namelist import parse_namelist_groups

AXES = "xyz"
_DUMP = re.compile(r"^(.+)_(\d{6,})\.h5$")
_NOT_DUMPS = ("_checkpoint", "_failed")


def run_name(run_dir: str, name: str | None = None) -> str:
    """The run name of the dumps ``<name>_<step>.h5`` in ``run_dir``: ``name`` when given (it
    must have dumps there), else the stem of the one ``<name>.used.nml`` that has dumps, else the
    one name the dump files carry (checkpoints and failure dumps left out). SystemExit with one
    line (exit status 1) when the directory is missing, holds no dumps or several runs."""
    if not os.path.isdir(run_dir):
        raise SystemExit(f"{run_dir}: no such directory")
    if name is not None:
        if not list_dumps(run_dir, name):
            raise SystemExit(f"no dumps {name}_<step>.h5 in {run_dir}")
        return name
    entries = sorted(os.listdir(run_dir))
    used = [e[:-len(".used.nml")] for e in entries if e.endswith(".used.nml")]
    used = [n for n in used if list_dumps(run_dir, n)]
    if len(used) == 1:
        return used[0]
    names = sorted({m.group(1) for m in map(_DUMP.match, entries)
                    if m and not m.group(1).endswith(_NOT_DUMPS)})
    if not names:
        raise SystemExit(f"no dumps <name>_<step>.h5 in {run_dir}")
    if len(names) > 1:
        raise SystemExit(f"{run_dir} holds the dumps of several runs ({', '.join(names)}): "
                         "choose one with --name")
    return names[0]


def dump_times(paths) -> np.ndarray:
    """Time [s] of each dump (root attribute ``time``, read without the datasets)."""
    return np.array([float(read_attrs(p)["time"]) for p in paths])


def pick_dumps(paths, times=None, count: int = 4) -> list[int]:
    """Indices (ascending, no repeats) of the dumps nearest to each of ``times`` [s]; with
    ``times`` None, ``count`` dumps evenly spaced from the first to the last (every dump when
    there are no more than ``count``); with ``times == "all"``, every dump."""
    n = len(paths)
    if n == 0:
        return []
    if isinstance(times, str) and times == "all":
        return list(range(n))
    if times is None:
        if n <= count:
            return list(range(n))
        return sorted({int(round(k * (n - 1) / (count - 1))) for k in range(count)})
    have = dump_times(paths)
    return sorted({int(np.argmin(np.abs(have - float(t)))) for t in times})


def active_axes(dump: dict) -> list[int]:
    """Axes (0, 1, 2 for x, y, z) with more than one cell."""
    ncells = np.asarray(dump["attrs"]["ncells"], dtype=int).reshape(3)
    return [d for d in range(3) if ncells[d] > 1]


def _namelist(dump: dict) -> list[tuple[str, dict]]:
    text = dump["attrs"].get("namelist")
    return parse_namelist_groups(text) if isinstance(text, str) and text else []


def materials(dump: dict) -> dict:
    """The run's materials: ``{"fluids": [names], "solids": [names], "rigid": [names],
    "gravity": array(3) or None}``.

    From the resolved input in the dump (``&fluid``/``&solid name``, ``&solid model = 'rigid'``,
    ``&physics gravity``) when it is there; else fluids are the ``/cell/<name>`` groups with a
    ``volume_fraction`` that are no particle set, solids the particle sets, no solid is known to be
    rigid and gravity is None. Only materials present in the dump are listed."""
    cell_groups = {key.split("/")[0] for key in dump["cell"] if "/" in key}
    sets = list(dump.get("particles", {}))
    groups = _namelist(dump)
    if groups:
        fluids = [g["name"] for n, g in groups if n == "fluid" and "name" in g]
        solids = [g["name"] for n, g in groups if n == "solid" and "name" in g]
        rigid = [g["name"] for n, g in groups
                 if n == "solid" and str(g.get("model", "")).lower() == "rigid"]
        physics = dict(groups).get("physics", {})
        gravity = physics.get("gravity")
        gravity = np.asarray(gravity, dtype=float).reshape(3) if gravity is not None else None
        return {"fluids": [f for f in fluids if f in cell_groups],
                "solids": [s for s in solids if s in sets or s in cell_groups],
                "rigid": [s for s in rigid if s in sets or s in cell_groups],
                "gravity": gravity}
    fluids = sorted(g for g in cell_groups
                    if f"{g}/volume_fraction" in dump["cell"] and g not in sets)
    return {"fluids": fluids, "solids": sets, "rigid": [], "gravity": None}


def vertical_axis(dump: dict) -> tuple[int, int]:
    """(axis, up) of a dump: the axis of the largest gravity component and up = -sign of it
    (+1: up is toward larger coordinates). Without gravity (none in the input, or zero): the
    last active axis (y in 2D, z in 3D, x in 1D), up = +1."""
    gravity = materials(dump)["gravity"]
    if gravity is not None and np.any(gravity != 0.0):
        axis = int(np.argmax(np.abs(gravity)))
        return axis, (-1 if gravity[axis] > 0.0 else 1)
    active = active_axes(dump)
    return (active[-1] if active else 0), 1


def read_step_csv(path: str) -> dict[str, np.ndarray]:
    """Columns of a per-step CSV file (a header line of names, then one row of numbers per step)
    as ``{name: 1-D array}``; empty arrays when the file has no row yet."""
    with open(path, encoding="utf-8") as handle:
        header = handle.readline().strip().split(",")
        rows = [line.split(",") for line in handle if line.strip()]
    data = np.array([[float(v) for v in row] for row in rows], dtype=float).reshape(
        len(rows), len(header))
    return {key: data[:, i].copy() for i, key in enumerate(header)}


def step_files(run_dir: str, name: str) -> dict[str, str]:
    """The per-step CSV files ``<run_dir>/<name>_<what>.csv``: ``{what: path}`` (e.g.
    ``{"mpm_series": ..., "contact_force": ...}``), sorted by ``what``."""
    prefix = f"{name}_"
    found = {}
    for entry in sorted(os.listdir(run_dir)):
        if entry.startswith(prefix) and entry.endswith(".csv"):
            found[entry[len(prefix):-len(".csv")]] = os.path.join(run_dir, entry)
    return found
