"""Shared helpers of the MPM validation scripts: particle dumps sorted by id, the per-step series
file written by the 'mpm' scene, elastic constants."""
from __future__ import annotations

import os

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_files import read_step_csv


#: Dumps <name>_<step>.h5 of a run in step order: :func:`postproc.mpmice_io.list_dumps` (the one
#: implementation; this name is kept for older callers).
dump_paths = list_dumps


def particles(path: str, solid: str) -> tuple[float, dict[str, np.ndarray]]:
    """(time, {field: array}) of one solid in one dump, particles sorted by id."""
    dump = read_dump(path)
    fields = dump["particles"][solid]
    order = np.argsort(fields["id"])
    return dump["time"], {key: np.asarray(val)[order] for key, val in fields.items()}


def series(output_dir: str, name: str) -> dict[str, np.ndarray]:
    """Columns of <output_dir>/<name>_mpm_series.csv (time, kinetic_energy, strain_energy,
    xmax, ymax, zmax, xmin, ymin, zmin)."""
    return read_step_csv(os.path.join(output_dir, f"{name}_mpm_series.csv"))
