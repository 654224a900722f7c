"""The excess pore pressure in the cell that a sediment's surface passes through (issue 32 item
5; docs/earthquake_liquefaction.md, "The surface cell of a settling sediment"), measured with
postproc/mpmice_surface_cell.py:

* 1D (namelists/mpmice_settling_column_1d.nml, 3 s, about 2 s): a stress-free soft layer
  consolidates under its weight and its surface sinks 7 cm through its 0.1 m surface cell at
  up to 40 mm/s. As Terzaghi/Gibson consolidation says, the surface cell's excess pore pressure
  stays >= 0 (measured +31 .. +206 Pa, the cell's buoyant weight 971 Pa) and below that of the
  cell under it, and the column down to the centre of the cell under the surface cell carries
  its buoyant weight to 2.6 %.
* 2D (namelists/mpmice_spreading_mound_2d.nml to 0.2 s, about 2 s): the crest of a spreading
  stress-free mound sinks inside its surface cell; the cell reads a suction of -4.3 kPa at
  0.15 s (4.5 cells' buoyant weight; -1.5 kPa with d = 0.5 mm, -0.1 kPa with 2 mm; -2.4 kPa
  at 0.05 m cells with 0.5 mm), which its top particles carry as sigma'_v while the cell below
  is at sigma'_v = 0 and -1.8 kPa: the particles' stress and the cells' pressures miss the
  column's vertical balance at that cell's centre by 1.2 kPa (1.3 times its overburden) with
  no inertia (48 Pa). Known artefact of the default face drag 'cell', xfail(strict=True).
* The option `&coupling face_drag = 'face_plane'` (each half cell with the solid fraction in
  that half) on both scenes: the 1D surface cell drained once the surface has passed its
  centre, the mound's crest suction within a quarter of a cell's buoyant weight."""
import os

import numpy as np
import pytest

from postproc.mpmice_surface_cell import column_rows
from postproc.run_case import ROOT

COLUMN = os.path.join(ROOT, "namelists", "mpmice_settling_column_1d.nml")
MOUND = os.path.join(ROOT, "namelists", "mpmice_spreading_mound_2d.nml")


def test_settling_column_surface_cell_has_no_suction(run_mpmice, tmp_path):
    """1D consolidation: the surface cell (solid fraction 0.55 -> 0.17 as the surface sinks
    through it) keeps p_ex >= -20 Pa (2 % of a cell's buoyant weight) and below the cell
    under it; the column's balance at the centre of the cell under the surface cell closes to
    4 % of its overburden (measured <= 2.6 %)."""
    out = os.path.join(str(tmp_path), "column")
    run_mpmice([COLUMN, "--set", f"&run output_dir = '{out}' /"], nranks=1, cwd=str(tmp_path),
               check=True)
    rows = column_rows(out, "settle")
    assert rows[0]["surface"] - rows[-1]["surface"] > 0.05  # it sinks through the cell
    assert rows[0]["phis_s"] > 0.5 and rows[-1]["phis_s"] < 0.25
    pex = np.array([r["pex_s"] for r in rows])
    below = np.array([r["pex_b"] for r in rows])
    assert pex.min() > -20.0, pex.min()
    assert np.all(pex < below), (pex, below)
    rel = [abs(r["deficit"]) / r["overburden"] for r in rows]
    assert max(rel) < 0.04, max(rel)


@pytest.mark.xfail(strict=True, reason="known artefact: suction of the crest's surface cell of a "
                   "spreading sediment, -4.3 kPa measured (docs/mpmice.md, Known problems)")
def test_spreading_mound_surface_cell_has_no_suction(run_mpmice, tmp_path):
    """The crest's surface cell of the spreading mound keeps its excess pore pressure relative
    to the free water above within a quarter of a cell's buoyant weight (240 Pa; measured
    -4470 Pa at 0.15 s) and the column balance under it within the same (measured -1184 Pa)."""
    out = os.path.join(str(tmp_path), "mound")
    run_mpmice([MOUND, "--set", f"&run output_dir = '{out}', end_time = 0.2 /"], nranks=1,
               cwd=str(tmp_path), check=True)
    rows = column_rows(out, "mound", x_right=0.3)
    weight = rows[0]["cell_weight"]
    assert min(r["rel_s"] for r in rows) > -0.25 * weight
    assert min(r["deficit"] for r in rows) > -0.25 * weight


FACE_PLANE = "&coupling face_drag = 'face_plane' /"


def test_face_plane_drag_settling_column_top_is_drained(run_mpmice, tmp_path):
    """`&coupling face_drag = 'face_plane'` on the 1D column: each half of the surface cell
    resists as the length of sediment it holds. While the sediment surface lies above the
    surface cell's centre, that centre is inside the consolidating layer, where Terzaghi/Gibson
    give 0 < p_ex below the cell under it (measured 196 Pa at 0.1 s, falling to 1 Pa as the
    surface reaches the centre); once the surface has sunk below the centre, the cell's upper
    half holds no sediment and the cell is drained as the free water above: its excess pore
    pressure relative to the water cell above ("rel", free of the whole water column's
    oscillation, which reaches 19 Pa in single dumps) within 20 Pa (measured <= 2.6 Pa; with the
    default 'cell' +31 .. +92 Pa). The surface passes the centre during the run, so both are
    checked on several dumps."""
    out = os.path.join(str(tmp_path), "column")
    run_mpmice([COLUMN, "--set", f"&run output_dir = '{out}' /", "--set", FACE_PLANE],
               nranks=1, cwd=str(tmp_path), check=True)
    rows = column_rows(out, "settle")
    assert rows[0]["surface"] - rows[-1]["surface"] > 0.05
    assert rows[0]["phis_s"] > 0.5 and rows[-1]["phis_s"] < 0.25
    dy = 0.1  # the scene's cells
    centre = np.array([(r["js"] + 0.5) * dy for r in rows])
    above = np.array([r["surface"] for r in rows]) > centre
    pex = np.array([r["pex_s"] for r in rows])
    below = np.array([r["pex_b"] for r in rows])
    assert np.count_nonzero(above) >= 3 and np.count_nonzero(~above) >= 3, above
    assert np.all(pex[above] > 0.0), pex[above]
    assert np.all(pex < below), (pex, below)
    rel = np.array([r["rel_s"] for r in rows])
    assert np.abs(rel[~above]).max() <= 20.0, rel[~above]


def test_face_plane_drag_spreading_mound_has_no_suction(run_mpmice, tmp_path):
    """`&coupling face_drag = 'face_plane'` on the spreading mound: the crest's surface cell
    keeps its excess pore pressure relative to the free water above within a quarter of a
    cell's buoyant weight (240 Pa; measured -153 Pa at most, against -4470 Pa with the default
    'cell'). The column balance under it is not checked here: it still misses by -627 Pa in the
    first dump (0.05 s), then -419, +184, +188 Pa (docs/soil_models.md)."""
    out = os.path.join(str(tmp_path), "mound")
    run_mpmice([MOUND, "--set", f"&run output_dir = '{out}', end_time = 0.2 /", "--set",
                FACE_PLANE], nranks=1, cwd=str(tmp_path), check=True)
    rows = column_rows(out, "mound", x_right=0.3)
    weight = rows[0]["cell_weight"]
    assert min(r["rel_s"] for r in rows) > -0.25 * weight
