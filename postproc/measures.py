"""Measures of any scene from its dumps (dicts of :func:`postproc.mpmice_io.read_dump`): the free
surface of a liquid, the front, run-out and height of a solid moving in any direction, masses.
Used by :mod:`postproc.slide` and the scene scripts (docs/postprocessing.md).

Free surface (:func:`free_surface`): in every column of cells along the vertical axis (the axis
of gravity, :func:`postproc.run_files.vertical_axis`), the liquid's share of the fluid volume
s = phi_liquid / (sum of the fluids' phi) gives the surface either as

* ``"crossing"``: from the top down, the first place where s reaches ``threshold`` (default 0.5),
  linear between cell centres (NaN in a column without such a crossing); a cell without fluid
  counts as s = 0; or
* ``"height"``: the depth of liquid sum_j s_j dz above the column's lower edge (a cell with
  less than 1e-3 fluid counts as s = 1), exact for a level surface at any cell size.

Slide (:func:`slide_direction`, :func:`front`, :func:`runout`): the direction a solid moves is
the horizontal axis (an active axis other than the vertical one) along which its mass-weighted
centre moved most between two dumps, with the sign of that move; the front is the particle
farthest along that direction (largest x for +x, smallest x for -x); the run-out at a time is how
far the front has advanced along the direction since the first dump.
"""
from __future__ import annotations

import numpy as np

from postproc.mpmice_io import cell_centres
from postproc.run_files import AXES, active_axes, materials, vertical_axis


def by_id(parts: dict) -> dict:
    """The particle arrays of a solid sorted by particle id (as stored when there is no id)."""
    if "id" not in parts:
        return dict(parts)
    order = np.argsort(parts["id"])
    return {k: np.asarray(v)[order] for k, v in parts.items()}


def mean_stress(parts: dict) -> np.ndarray:
    """p' = -tr(sigma') / 3 of every particle of a solid's arrays [Pa] (tension positive)."""
    return -(parts["stress_xx"] + parts["stress_yy"] + parts["stress_zz"]) / 3.0


def masses(dump: dict) -> dict[str, float]:
    """Mass [kg] of every fluid (sum of its bulk density times the cell volume) and every solid
    (sum of its particle masses) of a dump."""
    vol = float(np.prod(np.asarray(dump["attrs"]["dx"]).reshape(3)))
    out = {}
    for key, field in dump["cell"].items():
        if key.endswith("/density"):
            out[key.split("/")[0]] = float(np.sum(field)) * vol
    for name, parts in dump.get("particles", {}).items():
        out[name] = float(np.sum(parts["mass"]))
    return out


def fluid_share(dump: dict, liquid: str, others=None, floor: float = 0.0,
                empty: float = 0.0) -> np.ndarray:
    """phi_liquid / (phi_liquid + sum of the other fluids' phi) per cell ``[i, j, k]``; ``empty``
    where that sum is not above ``floor``. ``others``: the other fluids (default: every other
    fluid of the dump, :func:`postproc.run_files.materials`)."""
    if others is None:
        others = [f for f in materials(dump)["fluids"] if f != liquid]
    key = f"{liquid}/volume_fraction"
    if key not in dump["cell"]:
        raise KeyError(f"the dump has no cell field {key}")
    w = dump["cell"][key]
    total = w.copy()
    for other in others:
        total = total + dump["cell"][f"{other}/volume_fraction"]
    return np.where(total > floor, w / np.maximum(total, 1e-300), empty)


def free_surface(dump: dict, liquid: str = "water", others=None, level: float = 0.0,
                 method: str = "crossing", threshold: float = 0.5,
                 vertical: tuple[int, int] | None = None):
    """(coordinates, eta) of the liquid's free surface: ``coordinates`` the cell-centre vectors
    of the horizontal axes (the other axes, in order x, y, z, that are active), ``eta`` [m] the
    surface's position along the vertical axis minus ``level``, indexed like those axes (one
    value per column; a 0-d array when no horizontal axis is active). ``method``: "crossing" or
    "height" (module notes); ``vertical``: (axis, up), default :func:`vertical_axis`."""
    axis, up = vertical if vertical is not None else vertical_axis(dump)
    centres = cell_centres(dump)
    z = centres[axis]
    if method == "crossing":
        share = fluid_share(dump, liquid, others, 0.0, 0.0)
    elif method == "height":
        share = fluid_share(dump, liquid, others, 1e-3, 1.0)
    else:
        raise ValueError(f"free_surface: method {method!r} (allowed: crossing, height)")
    share = np.ascontiguousarray(np.moveaxis(share, axis, -1))
    horizontal = [d for d in range(3) if d != axis]
    if up < 0:                       # index upward along the last axis
        share, z = share[..., ::-1], z[::-1]
    n = z.size
    if method == "height":
        dz = z[1] - z[0] if n > 1 else up * float(np.asarray(dump["attrs"]["dx"])[axis])
        eta = np.sum(share, axis=-1) * dz + (z[0] - 0.5 * dz) - level
    else:
        eta = np.full(share.shape[:-1], np.nan)
        if n > 1:
            below, above = share[..., :-1], share[..., 1:]
            cross = (above < threshold) & (threshold <= below)     # between j - 1 and j
            has = np.any(cross, axis=-1)
            j = n - 1 - np.argmax(cross[..., ::-1], axis=-1)        # the highest crossing
            sj = np.take_along_axis(share, j[..., None], -1)[..., 0]
            sb = np.take_along_axis(share, (j - 1)[..., None], -1)[..., 0]
            f = (threshold - sj) / np.where(has, sb - sj, 1.0)
            value = z[j] + f * (z[j - 1] - z[j]) - level
            eta = np.where(has, value, np.nan)
    keep = [d for d in horizontal if d in active_axes(dump)]
    drop = tuple(i for i, d in enumerate(horizontal) if d not in keep)
    eta = eta[tuple(0 if i in drop else slice(None) for i in range(len(horizontal)))]
    return [centres[d] for d in keep], np.asarray(eta)


def centre_of_mass(parts: dict) -> np.ndarray:
    """Mass-weighted mean position (x, y, z) [m] of a solid's particles (plain mean without a
    ``mass`` array; missing coordinates count as 0)."""
    weights = parts.get("mass")
    out = np.zeros(3)
    for d, key in enumerate(AXES):
        if key in parts and len(parts[key]):
            out[d] = np.average(parts[key], weights=weights)
    return out


def slide_direction(first: dict, last: dict, solid: str,
                    vertical: tuple[int, int] | None = None) -> tuple[int, int]:
    """(axis, sign) of the solid's motion from dump ``first`` to dump ``last``: the horizontal
    axis (active, not the vertical one; the vertical one only in 1D) along which its centre of
    mass moved most, and the sign of that move (+1 toward larger coordinates). ValueError when
    it did not move along any of them."""
    axis_v, _ = vertical if vertical is not None else vertical_axis(first)
    active = active_axes(first)
    candidates = [d for d in active if d != axis_v] or active
    move = (centre_of_mass(last["particles"][solid])
            - centre_of_mass(first["particles"][solid]))
    axis = max(candidates, key=lambda d: abs(move[d]))
    if move[axis] == 0.0:
        along = ", ".join(AXES[d] for d in candidates)
        raise ValueError(f"solid {solid} did not move along {along} between t = "
                         f"{first['time']} and {last['time']} s")
    return axis, (1 if move[axis] > 0.0 else -1)


def front(parts: dict, axis: int = 0, sign: int = 1) -> float:
    """Position [m] along ``axis`` of the particle farthest in direction ``sign``: the largest
    coordinate for +1, the smallest for -1."""
    coord = np.asarray(parts[AXES[axis]], dtype=float)
    return float(np.max(coord)) if sign > 0 else float(np.min(coord))


def runout(front_now: float, front_start: float, sign: int) -> float:
    """Distance [m] the front has advanced in direction ``sign`` since ``front_start``."""
    return sign * (front_now - front_start) + 0.0   # + 0.0: no "-0.0" at the start


def top(parts: dict, vertical: tuple[int, int]) -> float:
    """Position [m] along the vertical axis of the highest particle (``vertical`` = (axis, up))."""
    return front(parts, vertical[0], vertical[1])


def bottom(parts: dict, vertical: tuple[int, int]) -> float:
    """Position [m] along the vertical axis of the lowest particle."""
    return front(parts, vertical[0], -vertical[1])
