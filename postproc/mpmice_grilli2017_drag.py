"""Grilli et al. (2017) test 17: the fluid-solid drag in the cells the slide only partly fills.

Usage:  python -m postproc.mpmice_grilli2017_drag [--dir RUN ...] [--t0 T] [--t1 T] [--slip W]

Prints
1. the drag coefficient per unit cell volume K = phi_f phi c [kg/m^3/s] (the drag force per
   cell volume over the slip, f = K |u_s - u_f|) of the scene's beads (d = 4 mm, packing
   phi_p = 0.61, water) against the cell's fill f = phi / phi_p, split into the Ergun law's
   linear and quadratic parts at the slip --slip, for the three ways a partly filled cell can
   be read (exchange_drag, mpmice_solid_coupling):
   * cell:     the law at the cell's mean fraction phi (n = 1 - phi), as in a cell that no face
               plane marks as a surface cell (a dilute suspension over the whole cell);
   * series:   the law at the body's own fraction phi_p, scaled by (1 - phi) / (1 - phi_p), as
               in a surface cell (`surface_body_fraction`, `&solid surface_drag_parallel =
               .false.`): the cell's water forced through the packing (flow across the surface);
   * parallel: the law at phi_p scaled by (1 - phi_p) / (1 - phi) (`surface_drag_parallel =
               .true.`): the packing's share f of the cell at its own porosity and the cell's
               slip, the free water beside it undragged (flow along the surface);
2. for each run folder: where the drag on the beads acts over model t0 <= t <= t1 (dumps), the
   share of the drag force (|f| summed over the cells) in cells with phi < phi_p / 2 and the
   beads' volume there, with the drag rebuilt from the dumped cell fields (the tracked solid
   fraction less the bed's particle volume, the cell velocities, the water's fraction and
   specific volume) for each of the three readings; a cell counts as a surface cell (the series or
   parallel reading) when a face neighbour holds no beads and another holds more than the cell,
   the dumps' stand-in for the face-plane test of `surface_body_fraction` (the body's fraction
   taken as the fullest neighbour's, at most phi_p); cells with bed use the partner rule of
   `mpmice_rigid_contact.partner_fields` (phi / (1 - phi_bed); none at phi_bed >= 0.5); and the
   beads' mean slip in the partly filled cells and in the others.
"""
from __future__ import annotations

import argparse

import numpy as np

from postproc import mpmice_grilli2017 as grilli
from postproc.mpmice_io import read_run_dumps

GRAIN = 4.0e-3          # m
PACKING = 0.61          # the beads' packing fraction (porosity 0.39)
MU_W = 1.0e-3           # Pa s
RHO_W = 999.8           # kg/m^3
ERGUN_A, ERGUN_B = 150.0, 1.75
WALL_FRACTION = 0.5     # mpmice_rigid_contact: a cell at least half bed is a wall cell


def reduced(phi_k, slip):
    """Linear and quadratic parts of the reduced coefficient c(phi_k) of exchange_drag
    ('forchheimer'): a mu phi / (n^2 d^2) and b rho w / (n d)."""
    n = 1.0 - phi_k
    return ERGUN_A * MU_W * phi_k / (n**2 * GRAIN**2), ERGUN_B * RHO_W * slip / (n * GRAIN)


def scale(phi, phi_body, reading):
    """Factor on c(phi_body) of a surface cell (`surface_drag_scale`)."""
    if reading == "series":
        return (1.0 - phi) / (1.0 - phi_body)
    return (1.0 - phi_body) / (1.0 - phi)


def coefficient(phi, slip, reading):
    """K = phi_f phi c per cell volume [kg/m^3/s] (linear, quadratic), water filling the rest."""
    if reading == "cell":
        lin, quad = reduced(phi, slip)
        s = 1.0
    else:
        lin, quad = reduced(PACKING, slip)
        s = scale(phi, PACKING, reading)
    k = (1.0 - phi) * phi * s
    return k * lin, k * quad


def table(slip: float) -> None:
    print(f"K = phi_f phi c per cell volume [kg/m^3/s] of the beads at slip {slip} m/s "
          "(linear / quadratic part)")
    print(f"{'fill f':>7} {'phi':>6} | {'cell':>17} | {'series':>17} | {'parallel':>17} | "
          "series/cell parallel/cell (total)")
    for f in (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0):
        phi = f * PACKING
        row = {r: coefficient(phi, slip, r) for r in ("cell", "series", "parallel")}
        tot = {r: sum(v) for r, v in row.items()}
        print(f"{f:7.2f} {phi:6.3f} | " + " | ".join(
            f"{row[r][0]:7.0f} {row[r][1]:9.0f}" for r in ("cell", "series", "parallel"))
            + f" | {tot['series'] / tot['cell']:6.2f} {tot['parallel'] / tot['cell']:6.2f}")


def surface_cells(phi):
    """A face neighbour without beads and another with more than the cell; the body's fraction
    (the fullest neighbour's, at most the packing)."""
    pad = np.pad(phi, 1)
    neigh = np.stack([pad[:-2, 1:-1], pad[2:, 1:-1], pad[1:-1, :-2], pad[1:-1, 2:]])
    empty = np.any(neigh <= 1.0e-9, axis=0)
    fmax = np.max(neigh, axis=0)
    surf = (phi > 0.0) & empty & (fmax > phi + 1.0e-9)
    return surf, np.minimum(np.maximum(fmax, phi), PACKING)


def drag_field(c, reading):
    """|f| per cell [N/m^3] and its component along the slope on the beads."""
    bed = np.minimum(c["bed/volume_fraction"][:, :, 0], 0.999)
    phi = np.clip(c["solid_volume_fraction"][:, :, 0] - bed, 0.0, 0.999)
    phw = c[f"{grilli.WATER}/volume_fraction"][:, :, 0]
    rho = 1.0 / c[f"{grilli.WATER}/specific_volume"][:, :, 0]
    du = np.stack([c[f"{grilli.WATER}/velocity_{a}"][:, :, 0] - c[f"{grilli.BEADS}/velocity_{a}"]
                   [:, :, 0] for a in "xy"])
    w = np.sqrt(np.sum(du**2, axis=0))
    phi_k = phi.copy()
    s = np.ones_like(phi)
    surf, body = surface_cells(phi)
    if reading != "cell":
        phi_k = np.where(surf, body, phi)
        s = np.where(surf, scale(phi, phi_k, reading), 1.0)
    with_bed = bed > 0.0
    phi_k = np.where(with_bed, np.minimum(phi / np.maximum(1.0 - bed, 1e-9), 0.999), phi_k)
    s = np.where(with_bed, 1.0 / np.maximum(1.0 - bed, 1e-9), s)
    n = 1.0 - phi_k
    cc = ERGUN_A * MU_W * phi_k / (n**2 * GRAIN**2) + ERGUN_B * rho * w / (n * GRAIN)
    k = np.where((phi > 0.0) & (bed < WALL_FRACTION), phw * phi * s * cc, 0.0)
    along = np.array([np.cos(np.radians(35.0)), -np.sin(np.radians(35.0))])
    return k * w, k * (along[0] * du[0] + along[1] * du[1]), phi, surf, w


def shares(folder: str, t0: float, t1: float) -> None:
    dumps = [d for d in read_run_dumps(folder, grilli.NAME) if t0 - 1e-9 <= d["time"] <= t1 + 1e-9]
    if not dumps:
        raise SystemExit(f"no dumps with {t0} <= t <= {t1} in {folder}")
    print(f"\n{folder}: {len(dumps)} dumps, model t = {t0} to {t1} s; partly filled: "
          f"phi < {PACKING / 2:.3f}")
    for reading in ("cell", "series", "parallel"):
        acc = np.zeros(8)
        for d in dumps:
            mag, along, phi, surf, w = drag_field(d["cell"], reading)
            full = phi >= 0.5 * PACKING
            area = float(np.prod(np.asarray(d["attrs"]["dx"]).reshape(3)[:2]))  # per metre depth
            part = (phi > 0.0) & (phi < 0.5 * PACKING)
            acc += [np.sum(mag[part]) / max(np.sum(mag), 1e-30),
                    np.sum(phi[part]) / np.sum(phi),
                    np.sum(mag[surf]) / max(np.sum(mag), 1e-30),
                    np.sum(phi[surf]) / np.sum(phi),
                    np.sum(along) * area,
                    np.sum(along[part]) * area,
                    np.average(w[part], weights=phi[part]), np.average(w[full], weights=phi[full])]
        acc /= len(dumps)
        print(f"  {reading:8s}: drag share in partly filled cells {acc[0]:.3f} (beads' volume "
              f"{acc[1]:.3f}); in surface cells {acc[2]:.3f} (volume {acc[3]:.3f}); drag along "
              f"the slope on the beads {acc[4]:.2f} N/m, of it in partly filled cells "
              f"{acc[5]:.2f} N/m")
    print(f"  slip |u_w - u_s| (mean over the beads' volume): partly filled cells {acc[6]:.3f} "
          f"m/s, the others {acc[7]:.3f} m/s")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", default=[], help="a run's output folder")
    parser.add_argument("--t0", type=float, default=0.1)
    parser.add_argument("--t1", type=float, default=0.4)
    parser.add_argument("--slip", type=float, default=0.1, help="slip of the table [m/s]")
    args = parser.parse_args(argv)
    table(args.slip)
    for folder in args.dir:
        shares(folder, args.t0, args.t1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
