"""The pore pressure in the cell that a settling sediment's surface passes through (issue 32
item 5; docs/earthquake_liquefaction.md, "The surface cell of a settling sediment"). Per dump,
for a column of cells x_left < x < x_right (the whole width in 1D):

* the sediment surface (the column's highest particle plus half its deformed height in 1D,
  the highest particle in 2D) and the surface cell js (the cell holding the highest particle);
* the surface cell's and the cell below's box-mean solid fraction, excess pore pressure over
  the hydrostatic p_top + rho_w g (top - y) (rho_w of the dump's topmost water cell) and the
  same relative to the water cell above the surface cell ("rel": removes the whole water
  column's pressure oscillation), the relative velocity v_w - v_s of the surface cell;
* the particles' mean sigma'_v (compression positive) in the surface cell and the cell below;
* the column's vertical balance at the centre of the cell below the surface cell: the
  particles' sigma'_v there (a line fitted to those within one cell of that height) + p_ex minus the sediment's buoyant weight above that height
  (sum over the cells of phi_s (rho_s - rho_w) g dy) plus the load the side shear carries off
  (:func:`postproc.mpmice_crest_layer.side_shear`), and the column's vertical inertia
  sum m a_y above that height (a_y from the dumps before and after): "deficit" and "inertia",
  both in Pa; in a column in equilibrium deficit + inertia = 0 (`depth_cells` moves the plane
  further down).

    python -m postproc.mpmice_surface_cell --dir RUN_DIR --name NAME [--solid sand]
        [--x-left 0 --x-right 0.3]

Analytic expectation for a 1D settling (consolidating) layer under free water: p_ex = 0 at the
sediment surface, rising below it (Terzaghi/Gibson), never below 0 (the stress-free layer
loads its pore water, it does not suck it in).
"""
from __future__ import annotations

import argparse

import numpy as np

from postproc.mpmice_crest_layer import side_shear
from postproc.mpmice_io import cell_centres, list_dumps, read_dump

G_ACC = 9.81
RHO_S = 2650.0


def column_rows(out_dir: str, name: str, solid: str = "sand", x_left: float | None = None,
                x_right: float | None = None, depth_cells: int = 1) -> list[dict]:
    """One dict per dump (the first, t = 0, left out) with the measures of the module doc, the
    balance ("deficit", "inertia", "overburden") at the centre of the cell `depth_cells` below
    the surface cell."""
    dumps = [read_dump(p) for p in list_dumps(out_dir, name)]
    rows = []
    for n, d in enumerate(dumps):
        if n == 0:
            continue
        xc, yc, _ = cell_centres(d)
        dx, dy = d["attrs"]["dx"][0], d["attrs"]["dx"][1]
        top_face = d["attrs"]["upper"][1]
        xl = d["attrs"]["lower"][0] if x_left is None else x_left
        xr = d["attrs"]["upper"][0] if x_right is None else x_right
        ii = np.flatnonzero((xc > xl) & (xc < xr))
        cell = d["cell"]
        wf = cell["water/volume_fraction"][ii, :, 0]
        rho_w = float(np.mean(cell["water/density"][ii, -1, 0] / wf[:, -1]))
        p_top = 101325.0
        pex = np.mean(cell["pressure"][ii, :, 0], axis=0) - (p_top + rho_w * G_ACC * (top_face - yc))
        phis = np.mean(cell["solid_volume_fraction"][ii, :, 0], axis=0)
        rel_v = np.mean(cell["water/velocity_y"][ii, :, 0] - cell[f"{solid}/velocity_y"][ii, :, 0], axis=0)
        p = d["particles"][solid]
        x, y = p["x"], p["y"]
        inside = (x > xl) & (x < xr)
        sv = -p["stress_yy"]
        itop = np.flatnonzero(inside)[np.argmax(y[inside])]
        surf = float(y[itop])
        if len(xc) == 1:  # 1D: the top particle's upper edge
            surf += 0.5 * float(p["volume"][itop]) / (dx * d["attrs"]["dx"][2])
        js = min(int((y[itop] - d["attrs"]["lower"][1]) // dy), len(yc) - 1)

        def band(j):
            m = inside & (y > yc[j] - 0.5 * dy) & (y <= yc[j] + 0.5 * dy)
            return float(np.mean(sv[m])) if np.any(m) else 0.0
        def at(yy):  # sigma'_v at height yy: a line fitted to the particles within one cell of it
            m = inside & (np.abs(y - yy) <= dy)
            if np.count_nonzero(m) < 2 or np.ptp(y[m]) < 1e-9:
                return float(np.mean(sv[m])) if np.any(m) else 0.0
            slope, icpt = np.polyfit(y[m] - yy, sv[m], 1)
            return float(icpt)
        y_b = yc[js - depth_cells]
        share = np.clip((yc + 0.5 * dy - y_b) / dy, 0.0, 1.0)
        overburden = float(np.sum(phis * share) * (RHO_S - rho_w) * G_ACC * dy)
        shear = 0.0 if len(xc) == 1 else side_shear(x, y, p["stress_xy"], xl, xr, y_b, surf + dy, h=dy)
        deficit = at(y_b) + pex[js - depth_cells] - (overburden - shear)
        inertia = float("nan")
        if 0 < n < len(dumps) - 1:
            prev, nxt = dumps[n - 1]["particles"][solid], dumps[n + 1]["particles"][solid]
            if len(prev["id"]) == len(p["id"]) == len(nxt["id"]):
                a_y = ((nxt["velocity_y"][np.argsort(nxt["id"])] - prev["velocity_y"][np.argsort(prev["id"])])
                       / (dumps[n + 1]["time"] - dumps[n - 1]["time"]))[np.argsort(np.argsort(p["id"]))]
                m = inside & (y > y_b)
                inertia = float(np.sum(p["mass"][m] * a_y[m]) / ((xr - xl) * d["attrs"]["dx"][2]))
        rows.append({"t": d["time"], "surface": surf, "js": js, "phis_s": phis[js], "phis_b": phis[js - 1],
                     "pex_s": pex[js], "pex_b": pex[js - 1], "rel_s": pex[js] - pex[js + 1],
                     "sv_s": band(js), "sv_b": band(js - 1), "vw_vs": rel_v[js],
                     "deficit": deficit, "inertia": inertia, "overburden": overburden,
                     "cell_weight": (RHO_S - rho_w) * G_ACC * dy * 0.6})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", required=True)
    ap.add_argument("--name", required=True)
    ap.add_argument("--solid", default="sand")
    ap.add_argument("--x-left", type=float, default=None)
    ap.add_argument("--x-right", type=float, default=None)
    a = ap.parse_args(argv)
    print("t [s] | surface [m] | phi_s surf/below | p_ex surf/below [Pa] | surf - water above [Pa] | "
          "sigma'_v surf/below [Pa] | v_w - v_s [mm/s] | deficit / inertia / overburden [Pa]")
    for r in column_rows(a.dir, a.name, a.solid, a.x_left, a.x_right):
        print(f"{r['t']:.2f} | {r['surface']:.3f} | {r['phis_s']:.2f}/{r['phis_b']:.2f} | "
              f"{r['pex_s']:+.0f}/{r['pex_b']:+.0f} | {r['rel_s']:+.0f} | {r['sv_s']:.0f}/{r['sv_b']:.0f} | "
              f"{r['vw_vs'] * 1e3:+.0f} | {r['deficit']:+.0f} / {r['inertia']:+.0f} / {r['overburden']:.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
