"""Read MPMICE HDF5 dumps and checkpoints (file layout: ``docs/io.md``).

The Fortran writer stores grid fields with the Fortran extent ``(ni, nj, nk)``; HDF5 keeps it
in C order, so h5py sees shape ``(nk, nj, ni)``.  This module transposes every grid field on
read, so that ``dump["cell"]["pressure"][i, j, k]`` is cell ``(i+1, j+1, k+1)`` of the Fortran
code (0-based here).  Particle arrays are returned as stored: 1-D arrays of length N (all ranks
concatenated), or ``(N, ncomp)`` for arrays written as ``values(ncomp, n)``.

Only numpy and h5py are needed::

    from postproc.mpmice_io import list_dumps, read_dump, cell_centres
    dump = read_dump(list_dumps("output", "shock_tube")[-1])
    x, y, z = cell_centres(dump)
    p = dump["cell"]["pressure"][:, 0, 0]
"""
from __future__ import annotations

import argparse
import os
import re
import warnings

import h5py
import numpy as np

#: Reserved dataset of every particle group: particles written by each rank.
RANK_COUNTS = "rank_counts"


def attribute_value(value):
    """An HDF5 attribute as a plain Python/numpy value (strings decoded, NULs stripped)."""
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0").decode("ascii", errors="replace")
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "S":
            return [bytes(v).rstrip(b"\0").decode("ascii", errors="replace") for v in value.flat]
        return value.copy()
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_attrs(path: str, group: str = "/") -> dict:
    """Attributes of ``group`` (default: the root, i.e. the dump header) of file ``path``."""
    with h5py.File(path, "r") as f:
        return {key: attribute_value(val) for key, val in f[group].attrs.items()}


def grid_array(dataset) -> np.ndarray:
    """A grid field dataset as a numpy array indexed ``[i, j, k]`` (transposed from the file)."""
    return np.ascontiguousarray(np.asarray(dataset[...]).T)


def read_dump(path: str, include_other: bool = False) -> dict:
    """Everything of one dump or checkpoint file.

    Returns a dict with keys

    * ``path``: the file; ``attrs``: root attributes (``time``, ``step``, ``dt``, ``ndim``,
      ``ncells``, ``lower``, ``upper``, ``dx``, ...), with ``time`` and ``step`` also at top level;
    * ``cell``: ``{name: array[i, j, k]}`` for every dataset under ``/cell``, named by its path
      below ``/cell`` (``"pressure"``, ``"water/density"``);
    * ``node``: the same for ``/node`` (node fields, extent ``ncells + 1`` where active);
    * ``particles``: ``{set: {field: array}}`` for every group ``/particles/<set>``
      (``rank_counts`` left out);
    * ``other``: ``{path: array as stored}`` for all remaining datasets (e.g. ``/checkpoint``),
      only when ``include_other`` is true (checkpoints can be large).
    """
    dump = {"path": path, "cell": {}, "node": {}, "particles": {}, "other": {}}
    with h5py.File(path, "r") as f:
        dump["attrs"] = {key: attribute_value(val) for key, val in f.attrs.items()}

        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            parts = name.split("/")
            if parts[0] in ("cell", "node") and obj.ndim == 3:
                dump[parts[0]]["/".join(parts[1:])] = grid_array(obj)
            elif parts[0] == "particles" and len(parts) >= 3:
                if parts[-1] == RANK_COUNTS:
                    return
                group = "/".join(parts[1:-1])
                dump["particles"].setdefault(group, {})[parts[-1]] = np.asarray(obj[...])
            elif include_other:
                dump["other"][name] = np.asarray(obj[...])

        f.visititems(visit)
    attrs = dump["attrs"]
    dump["time"] = float(attrs["time"]) if "time" in attrs else None
    dump["step"] = int(attrs["step"]) if "step" in attrs else None
    return dump


def list_dumps(output_dir: str, name: str) -> list[str]:
    """Dump files ``<output_dir>/<name>_<step>.h5`` (6 or more digits) sorted by step.

    Checkpoints and other files whose name has more after ``<name>_`` than the step number
    (``<name>_checkpoint_000100.h5``) are not listed, nor temporary files (``.h5.tmp``). A file
    that is not a readable dump (a truncated file left by an older version or another program)
    is skipped with a warning (``UserWarning``) naming it.
    """
    pattern = re.compile(r"^" + re.escape(name) + r"_(\d{6,})\.h5$")
    found = []
    for entry in os.listdir(output_dir):
        match = pattern.match(entry)
        if match:
            path = os.path.join(output_dir, entry)
            problem = dump_problem(path)
            if problem:
                warnings.warn(f"skipping {path}: {problem}", stacklevel=2)
                continue
            found.append((int(match.group(1)), path))
    return [path for _, path in sorted(found)]


def dump_problem(path: str) -> str:
    """Why ``path`` is not a readable dump ('' when it is one): it must open as HDF5 and carry
    the root attributes ``time`` and ``step``."""
    try:
        with h5py.File(path, "r") as f:
            missing = [key for key in ("time", "step") if key not in f.attrs]
    except (OSError, ValueError) as err:
        return f"not a readable HDF5 file ({err})"
    if missing:
        return "no root attribute " + ", ".join(missing)
    return ""


def read_run_dumps(output_dir: str, name: str, last: int | None = None) -> list[dict]:
    """The dumps ``<output_dir>/<name>_<step>.h5`` read (:func:`read_dump`), in step order: every
    one, or the `last` ones; RuntimeError when there is none."""
    paths = list_dumps(output_dir, name)
    if not paths:
        raise RuntimeError(f"no dumps {name}_<step>.h5 in {output_dir}")
    return [read_dump(path) for path in (paths if last is None else paths[-last:])]


def parse_run_dir(description: str, name: str, argv=None,
                  flags: dict[str, str] | None = None) -> tuple[argparse.Namespace, list[dict]]:
    """Command line of a script that reports on one finished run: ``--dir DIR`` (the run's output
    directory, required), ``--out DIR`` (where the plots go, created when missing; None: DIR)
    and the script's own on/off options ``flags`` {"--name": help}. Returns the parsed arguments
    and every dump ``<name>_<step>.h5`` of DIR; exits with status 1 and "no dumps
    <name>_<step>.h5 in DIR" when there is none (the reader's message when DIR is missing)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--dir", required=True, help="output directory of a run")
    parser.add_argument("--out", default=None)
    for flag, text in (flags or {}).items():
        parser.add_argument(flag, action="store_true", help=text)
    args = parser.parse_args(argv)
    try:
        dumps = read_run_dumps(args.dir, name)
    except (RuntimeError, OSError) as error:
        raise SystemExit(str(error)) from None
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    return args, dumps


def parse_compare_runs(description: str, name: str, analyse, argv=None):
    """Command line of a script that compares runs: ``--compare LABEL=DIR [LABEL=DIR ...]``
    and ``--out DIR`` (default '.', created). Returns the parsed arguments (with ``paths``:
    {label: DIR}) and {label: ``analyse(dumps, DIR)``} with the dumps ``<name>_<step>.h5`` of
    each DIR, in the order given; exits with the reader's message when a DIR has none."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--compare", nargs="+", required=True, metavar="LABEL=DIR")
    parser.add_argument("--out", default=".")
    args = parser.parse_args(argv)
    runs = {}
    args.paths = {}
    for item in args.compare:
        label, _, path = item.partition("=")
        args.paths[label] = path
        try:
            runs[label] = analyse(read_run_dumps(path, name), path)
        except (RuntimeError, OSError) as error:
            raise SystemExit(str(error)) from None
    os.makedirs(args.out, exist_ok=True)
    return args, runs


def run_or_compare(argv, description: str, name: str, analyse, report, figure, write_csv) -> int:
    """The command line of a scene's report: ``--dir DIR`` prints ``report(analyse(dumps,
    DIR))`` for one run; ``--compare LABEL=DIR [LABEL=DIR ...] [--out DIR]``
    (:func:`parse_compare_runs`) prints it for each run under its folder, then draws
    ``figure(runs, out)`` and writes ``write_csv(runs, out)``, each returning its path."""
    if "--compare" in argv:
        args, runs = parse_compare_runs(description, name, analyse, argv)
        for label, rows in runs.items():
            print(f"== {label}: {args.paths[label]}")
            report(rows)
        print(f"plot: {figure(runs, args.out)}")
        print(f"csv: {write_csv(runs, args.out)}")
        return 0
    args, dumps = parse_run_dir(description, name, argv)
    report(analyse(dumps, args.dir))
    return 0


def _grid_geometry(dump: dict):
    attrs = dump["attrs"] if "attrs" in dump else dump
    ncells = np.asarray(attrs["ncells"], dtype=int).reshape(3)
    lower = np.asarray(attrs["lower"], dtype=float).reshape(3)
    dx = np.asarray(attrs["dx"], dtype=float).reshape(3)
    return ncells, lower, dx


def cell_centres(dump: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cell-centre coordinates [m] along x, y and z (1-D arrays of length ``ncells``).

    ``dump`` is a dict from :func:`read_dump` (or its ``attrs``).  Use
    ``np.meshgrid(x, y, z, indexing="ij")`` for 3-D coordinate arrays matching ``[i, j, k]``.
    """
    ncells, lower, dx = _grid_geometry(dump)
    return tuple(lower[d] + (np.arange(ncells[d]) + 0.5) * dx[d] for d in range(3))


def node_positions(dump: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Node coordinates [m] along x, y and z as stored in node datasets.

    ``ncells + 1`` nodes in active non-periodic dimensions, ``ncells`` in periodic ones (from the
    root attribute ``periodic``) and one node in inactive dimensions.
    """
    ncells, lower, dx = _grid_geometry(dump)
    attrs = dump["attrs"] if "attrs" in dump else dump
    periodic = np.asarray(attrs.get("periodic", [0, 0, 0]), dtype=int).reshape(3)
    axes = []
    for d in range(3):
        if ncells[d] == 1:
            n = 1
        elif periodic[d]:
            n = ncells[d]
        else:
            n = ncells[d] + 1
        axes.append(lower[d] + np.arange(n) * dx[d])
    return tuple(axes)
