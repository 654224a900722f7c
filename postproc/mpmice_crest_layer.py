"""Why the basal layer under the earthquake slope's crest stops building up pore pressure: per
shaking cycle, for the layer monitors of :mod:`postproc.mpmice_earthquake_slope` (the particles
that start within 0.25 m of (x, 0.35 m) under the crest and under the flanks), the shaking that
arrives there, the cyclic densification it drives, the pore water that leaves, and how close
the skeleton is to its yield surface (docs/earthquake_liquefaction.md, "Why the layer under
the crest holds").

    python -m postproc.mpmice_crest_layer --dir RUN_DIR [--monitors "layer, crest" ...]

All stresses are taken relative to the dump at the shaking's start t_s (`acceleration_start`
of the base, read from the run's echo quake.used.nml, as are the sediment's constants). Per
monitor and cycle n (dumps with t in (t_s + (n-1)/f, t_s + n/f], and the one before):

* shaking: CSR = half the range of the monitor's mean tau_xy / its mean sigma'_v at t_s; the
  elastic shear strain amplitude gamma_el = that half range / G (the strain that the
  densification counts with `densification_elastic`); the share of the particles whose own
  half range of tau_xy / G exceeds `densification_threshold`; the kinematic amplitude gamma_kin
  = half the range of du_x/dy + du_y/dx of an affine fit to the monitor particles'
  displacements since t_s;
* densification: with checkpoints (`checkpoint_interval` a divisor of 1/f) the median change
  of the particles' counted reversals and of eps_vd over the cycle and the share that
  densified (`checkpoint/particles/sediment/cyclic`); always the eps_vd that Byrne's law
  (css_densify) gives for two half cycles of each particle's measured gamma_el, replayed from
  eps_vd = 0 at t_s (:func:`replay_densification`); K eps_vd / sigma'_v(t_s) of both;
* drainage: the pore water that leaves the layer's cells around the monitor (the box of cells
  with centres within 0.3 m of the monitor in x and 0.2 < y < 0.5 m) over the cycle, per
  unit volume of the box: from the cells' relative flux n (v_w - v_s) through the box's faces
  (:func:`box_outflow`), and from Darcy's law with the Kozeny-Carman k and the cells' excess
  pore pressure (:func:`darcy_box_outflow`); the mean vertical hydraulic gradient across the
  box's top face; K eps_out / sigma'_v(t_s) of both;
* state at the cycle's end: r_u (excess pore pressure / sigma'_v at t = 0, as the slope
  postproc), sigma'_v / sigma'_v(t_s), the change of the total vertical stress since t_s
  (change of sigma'_v plus change of the excess pore pressure) / sigma'_v(t_s), p' / p'(t_s),
  the mean mobilised strength
  tau / (mu p') (mu = mu_1 + K_d (phi - phi_m), phi = phi0 V0 / V) and the share of the
  particles at tau >= 0.95 mu p' or with p' <= 0.1 p'(t_s); and the share of the sediment's
  buoyant weight above the monitor's height (from the cells' sediment solid fraction,
  :func:`buoyant_overburden`) that sigma'_v + p_ex of its particles carries ("carried", also
  at t_s), and the share that the particles' tau_xy on the box's vertical sides carries off the
  column (:func:`side_shear`; "shed"): carried + shed = 1 in a column in equilibrium whose
  particle stress and cell pressure make up its total stress;
* the column's vertical balance (:func:`column_balance`): the deficit of the total vertical
  stress sigma'_v + p_ex of the particles in a 0.1 m band across the box at the monitor's
  height against the buoyant weight above minus the side shear, the same deficit at
  TOP_DEPTH below the column's highest particle ("top"; deficit - top is the column body's own
  imbalance), the vertical inertia of the particles in the column (sum m a_y over the column's
  area, a_y from the velocities of the dumps before and after), and the lowest box-mean cell
  excess pore pressure in the top 0.4 m of the column (the crest surface's suction); r_u less
  the top's deficit / sigma'_v at t = 0 (what r_u would read had the column's top carried its
  buoyant weight).
"""
from __future__ import annotations

import argparse
import os

import numpy as np

from postproc.analytic import carman_kozeny_conductivity
from postproc.measures import by_id
from postproc.mpmice_earthquake_slope import (NAME, RU_MONITORS, RU_RADIUS, SEDIMENT, base_shaking,
                                              cell_excess_pressure, excess_pore_pressure,
                                              hydrostatic_pressure)
from postproc.mpmice_io import cell_centres, list_dumps, read_dump

RHO_W = 999.8          # kg/m^3
G_ACC = 9.81           # m/s^2
MU_W = 1.0e-3          # Pa s: the water's viscosity (the scene's)
LAYER = (0.2, 0.5)     # m: the basal layer's bottom and top
BOX_HALF_WIDTH = 0.3   # m: cells with centres within this of the monitor's x
NEAR_YIELD = 0.95      # tau / (mu p') counted as at the yield surface
LOW_P = 0.1            # p' / p'(t_s) counted as lost
TOP_DEPTH = 0.25       # m: depth below the column's highest particle of the "top" deficit
BAND = 0.1             # m: height of the band that averages the total stress


def kozeny_carman(grain_size: float, porosity: np.ndarray | float, mu_w: float = MU_W,
                  rho_w: float = RHO_W, g: float = G_ACC) -> np.ndarray | float:
    """Hydraulic conductivity k = d^2 n^3 rho_w g / (180 (1 - n)^2 mu_w) [m/s]: the Carman-Kozeny
    k/mu of `postproc.analytic` times the water's unit weight."""
    n = np.asarray(porosity, dtype=float)
    return carman_kozeny_conductivity(1.0 - n, grain_size, mu_w) * rho_w * g


def replay_densification(amplitudes: np.ndarray, c1: float, c2: float = 0.0, threshold: float = 0.0,
                         evd_max: float = 0.0, evd0: np.ndarray | float = 0.0) -> np.ndarray:
    """eps_vd after half cycles of amplitudes[..., h] (h the half cycle; each column a particle
    or anything else), by the increment of css_densify: d eps_vd = a C_1 exp(-C_2 eps_vd / a) for
    a > threshold (C_2 = 0.4 / C_1 when c2 <= 0), bounded by evd_max (> 0). Returns eps_vd after
    each half cycle, shape of `amplitudes`."""
    amps = np.atleast_2d(np.asarray(amplitudes, dtype=float))
    if c1 <= 0.0:                                     # densification off
        return np.broadcast_to(np.asarray(evd0, dtype=float)[..., None] + 0.0 * amps,
                               amps.shape).reshape(np.shape(amplitudes)).copy()
    c2 = c2 if c2 > 0.0 else 0.4 / c1
    evd = np.broadcast_to(np.asarray(evd0, dtype=float), amps.shape[:-1]).copy()
    out = np.empty_like(amps)
    for h in range(amps.shape[-1]):
        a = amps[..., h]
        counts = a > threshold
        safe = np.where(counts, a, 1.0)
        inc = np.where(counts, safe * c1 * np.exp(-c2 * evd / safe), 0.0)
        if evd_max > 0.0:
            inc = np.clip(np.minimum(inc, evd_max - evd), 0.0, None)
        evd = evd + inc
        out[..., h] = evd
    return out.reshape(np.shape(amplitudes)) if np.ndim(amplitudes) >= 2 else out[0]


def box_outflow(flux_x: np.ndarray, flux_y: np.ndarray, box: tuple[slice, slice],
                dx: float, dy: float) -> float:
    """Net outflow rate per unit volume [1/s] of the box of cells box = (slice in i, slice in j)
    given cell-centred fluxes q [m/s] (indexed [i, j]): the face flux is the mean of the two cells
    beside the face; the bottom face of a box whose j slice starts at 0 is closed."""
    i, j = box
    i0, i1 = i.start, i.stop
    j0, j1 = j.start, j.stop
    qx_right = 0.5 * (flux_x[i1 - 1, j0:j1] + flux_x[i1 % flux_x.shape[0], j0:j1])
    qx_left = 0.5 * (flux_x[i0, j0:j1] + flux_x[i0 - 1, j0:j1])
    qy_top = 0.5 * (flux_y[i0:i1, j1 - 1] + flux_y[i0:i1, j1])
    qy_bottom = 0.5 * (flux_y[i0:i1, j0] + flux_y[i0:i1, j0 - 1]) if j0 > 0 else 0.0 * qy_top
    out = (np.sum(qx_right) - np.sum(qx_left)) * dy + (np.sum(qy_top) - np.sum(qy_bottom)) * dx
    return float(out / ((i1 - i0) * dx * (j1 - j0) * dy))


def darcy_box_outflow(excess: np.ndarray, k: np.ndarray, box: tuple[slice, slice], dx: float,
                      dy: float, rho_w: float = RHO_W, g: float = G_ACC) -> tuple[float, float]:
    """(net outflow rate per unit volume [1/s], mean vertical hydraulic gradient across the top
    face [-], positive upward flow) of the box of cells from Darcy's law q = -(k / gamma_w)
    grad p_ex with the cells' excess pore pressure p_ex [Pa] and conductivity k [m/s] ([i, j];
    face values: differences of the two cells, harmonic k); the bottom face at j = 0 is
    closed."""
    gw = rho_w * g

    def face(ka, kb, pa, pb, h):
        kf = 2.0 * ka * kb / np.maximum(ka + kb, 1e-300)
        return -kf / gw * (pb - pa) / h        # flux from a to b

    i, j = box
    i0, i1, j0, j1 = i.start, i.stop, j.start, j.stop
    nx = excess.shape[0]
    right = face(k[i1 - 1, j0:j1], k[i1 % nx, j0:j1], excess[i1 - 1, j0:j1], excess[i1 % nx, j0:j1], dx)
    left = face(k[i0, j0:j1], k[i0 - 1, j0:j1], excess[i0, j0:j1], excess[i0 - 1, j0:j1], dx)
    top = face(k[i0:i1, j1 - 1], k[i0:i1, j1], excess[i0:i1, j1 - 1], excess[i0:i1, j1], dy)
    bottom = (face(k[i0:i1, j0], k[i0:i1, j0 - 1], excess[i0:i1, j0], excess[i0:i1, j0 - 1], dy)
              if j0 > 0 else 0.0 * top)
    out = (np.sum(right) + np.sum(left)) * dy + (np.sum(top) + np.sum(bottom)) * dx
    gradient = float(np.mean((excess[i0:i1, j1 - 1] - excess[i0:i1, j1]) / dy) / gw)
    return float(out / ((i1 - i0) * dx * (j1 - j0) * dy)), gradient


def affine_shear(x0: np.ndarray, y0: np.ndarray, ux: np.ndarray, uy: np.ndarray) -> float:
    """Engineering shear strain du_x/dy + du_y/dx of the least-squares affine fit u = a + B X to
    displacements (ux, uy) of points starting at (x0, y0)."""
    a = np.column_stack([np.ones_like(x0), x0 - x0.mean(), y0 - y0.mean()])
    cx = np.linalg.lstsq(a, ux, rcond=None)[0]
    cy = np.linalg.lstsq(a, uy, rcond=None)[0]
    return float(cx[2] + cy[1])


def half_range(values) -> np.ndarray:
    """Half of max - min along the first axis."""
    v = np.asarray(values, dtype=float)
    return 0.5 * (v.max(axis=0) - v.min(axis=0))


def sediment_constants(run_dir: str) -> dict:
    """The sediment's constants from the run's echo quake.used.nml."""
    from postproc.namelist import parse_namelist_groups
    with open(os.path.join(run_dir, f"{NAME}.used.nml"), encoding="utf-8") as handle:
        groups = parse_namelist_groups(handle.read())
    for group, v in groups:
        if group == "solid" and str(v.get("name", "")).strip("'\"") == SEDIMENT:
            e, nu = float(v["youngs_modulus"]), float(v["poisson_ratio"])
            return {"G": e / (2.0 * (1.0 + nu)), "K": e / (3.0 * (1.0 - 2.0 * nu)),
                    "phi0": 1.0 - float(v["porosity"]), "rho_s": float(v["density"]),
                    "grain_size": float(v["grain_size"]),
                    "mu1": float(v["friction_mu1"]), "k_dil": float(v["dilatancy_constant"]),
                    "phi_m": float(v["critical_solid_fraction"]),
                    "c1": float(v["densification_c1"]), "c2": float(v["densification_c2"]),
                    "threshold": float(v["densification_threshold"]),
                    "evd_max": float(v["densification_max"])}
    raise RuntimeError(f"no &solid '{SEDIMENT}' in {run_dir}/{NAME}.used.nml")


def particle_state(s: dict, v0: np.ndarray, c: dict, idx: np.ndarray) -> dict:
    """p', tau / (mu p') and sigma'_v of the particles idx of a dump (sorted by id)."""
    sxx, syy, szz, sxy = (s[f"stress_{k}"][idx] for k in ("xx", "yy", "zz", "xy"))
    p = -(sxx + syy + szz) / 3.0
    tau = np.sqrt(0.5 * ((sxx + p) ** 2 + (syy + p) ** 2 + (szz + p) ** 2) + sxy**2)
    mu = c["mu1"] + c["k_dil"] * (c["phi0"] * v0[idx] / s["volume"][idx] - c["phi_m"])
    mob = np.where(p > 10.0, tau / (mu * np.where(p > 10.0, p, 1.0)), np.nan)
    return {"p": p, "mob": mob, "sv": -syy, "tau_xy": sxy}


def box_of(dump: dict, x_m: float) -> tuple[slice, slice]:
    """The cells (i slice, j slice) with centres within BOX_HALF_WIDTH of x_m and inside LAYER."""
    x, y, _ = cell_centres(dump)
    ii = np.flatnonzero(np.abs(x - x_m) <= BOX_HALF_WIDTH + 1e-9)
    jj = np.flatnonzero((y > LAYER[0]) & (y < LAYER[1]))
    return slice(int(ii[0]), int(ii[-1]) + 1), slice(int(jj[0]), int(jj[-1]) + 1)


def cell_drainage(dump: dict, box: tuple[slice, slice],
                  grain_size: float) -> tuple[float, float, float]:
    """(outflow rate from n (v_w - v_s), outflow rate from Darcy, vertical gradient) of a box."""
    cell = dump["cell"]
    n = cell["porosity"][:, :, 0]
    qx = n * (cell["water/velocity_x"][:, :, 0] - cell[f"{SEDIMENT}/velocity_x"][:, :, 0])
    qy = n * (cell["water/velocity_y"][:, :, 0] - cell[f"{SEDIMENT}/velocity_y"][:, :, 0])
    x, y, _ = cell_centres(dump)
    dx, dy = x[1] - x[0], y[1] - y[0]
    rel = box_outflow(qx, qy, box, dx, dy)
    excess = cell["pressure"][:, :, 0] - hydrostatic_pressure(y)[None, :]
    k = kozeny_carman(grain_size, np.clip(n, 0.05, 0.95))
    darcy, grad = darcy_box_outflow(excess, k, box, dx, dy)
    return rel, darcy, grad


def buoyant_overburden(dump: dict, box: tuple[slice, slice], y_m: float, rho_s: float,
                       rho_w: float = RHO_W, g: float = G_ACC) -> float:
    """The sediment's buoyant weight per unit area above height y_m [Pa], mean over the box's
    columns: sum over the cells of (rho_s - rho_w) phi_s g dy, phi_s the cells' solid volume
    fraction times the sediment's share of it, the cell holding y_m counted from y_m up. Equal
    to sigma'_v + p_ex at y_m where the
    column carries its own weight (no shear on vertical planes, no vertical acceleration)."""
    _, y, _ = cell_centres(dump)
    dy = y[1] - y[0]
    share = np.clip((y + 0.5 * dy - y_m) / dy, 0.0, 1.0)
    phi = (dump["cell"]["solid_volume_fraction"][box[0], :, 0]
           * dump["cell"][f"{SEDIMENT}/volume_fraction"][box[0], :, 0])
    return float(np.mean(np.sum(phi * share[None, :], axis=1)) * (rho_s - rho_w) * g * dy)


def side_shear(x: np.ndarray, y: np.ndarray, tau_xy: np.ndarray, x_left: float, x_right: float,
               y_m: float, top: float, h: float = 0.1) -> float:
    """The load [Pa] that shear stresses on the vertical sides x_left and x_right of a column carry
    off its base at y_m: (1/w) sum over bins of height h from y_m to `top` of (tau_xy(x_right) -
    tau_xy(x_left)) h, w = x_right - x_left, tau_xy the mean of the particles within h/2 of the
    side and of the bin's centre (tension positive, as the dumps; 0 for an empty bin). From the
    vertical equilibrium of the column, its base carries its weight minus this."""
    total = 0.0
    for yc in np.arange(y_m + 0.5 * h, top, h):
        for xs, sign in ((x_right, 1.0), (x_left, -1.0)):
            m = (np.abs(x - xs) < 0.5 * h) & (np.abs(y - yc) < 0.5 * h)
            if np.any(m):
                total += sign * float(np.mean(tau_xy[m])) * h
    return total / (x_right - x_left)


def band_mean(x: np.ndarray, y: np.ndarray, values: np.ndarray, x_left: float, x_right: float,
              y_c: float, h: float = BAND) -> float:
    """Mean of `values` over the particles with x_left < x < x_right and |y - y_c| < h / 2 (nan
    for an empty band)."""
    m = (x > x_left) & (x < x_right) & (np.abs(y - y_c) < 0.5 * h)
    return float(np.mean(values[m])) if np.any(m) else float("nan")


def column_balance(x: np.ndarray, y: np.ndarray, total: np.ndarray, tau_xy: np.ndarray,
                   x_left: float, x_right: float, y_m: float, overburden, depth: float = TOP_DEPTH
                   ) -> tuple[float, float]:
    """(deficit at y_m, deficit at `depth` below the highest particle between the sides) [Pa]
    of a column's vertical balance: the band mean of the particles' total vertical stress
    `total` = sigma'_v + p_ex (compression positive) minus (overburden(y) - side_shear(y)), the
    buoyant weight above y (a callable) less the load that the shear on the sides carries
    off. 0 where the column carries its own weight; deficit(y_m) - deficit(top) is the imbalance
    that arises in the column's body between the two heights."""
    inside = (x > x_left) & (x < x_right)
    stop = float(np.max(y[inside])) + BAND

    def deficit(yy):
        return (band_mean(x, y, total, x_left, x_right, yy)
                - overburden(yy) + side_shear(x, y, tau_xy, x_left, x_right, yy, stop))
    return deficit(y_m), deficit(stop - BAND - depth)


def column_inertia(x: np.ndarray, y: np.ndarray, mass: np.ndarray, a_y: np.ndarray,
                   x_left: float, x_right: float, y_m: float, thickness: float) -> float:
    """sum m a_y [Pa] of the particles between the sides and above y_m per unit of the column's
    area (x_right - x_left) * thickness: the load that the column's vertical acceleration adds
    at its base (a_y > 0 upward)."""
    m = (x > x_left) & (x < x_right) & (y > y_m)
    return float(np.sum(mass[m] * a_y[m]) / ((x_right - x_left) * thickness))


def checkpoint_cyclic(run_dir: str) -> dict[float, dict]:
    """{time: {'evd', 'reversals'} sorted by particle id} of the run's checkpoints that hold the
    sediment's cyclic state."""
    import h5py
    found = {}
    for entry in sorted(os.listdir(run_dir)):
        if not (entry.startswith(f"{NAME}_checkpoint_") and entry.endswith(".h5")):
            continue
        with h5py.File(os.path.join(run_dir, entry), "r") as f:
            g = f"checkpoint/particles/{SEDIMENT}/"
            if g + "cyclic" not in f:
                continue
            order = np.argsort(f[g + "id"][...])
            cyc = np.asarray(f[g + "cyclic"][...])[order]
            found[float(f.attrs["time"])] = {"evd": cyc[:, 0], "reversals": cyc[:, 4]}
    return found


def analyse(run_dir: str, monitors: list[str]) -> list[dict]:
    """One row per (monitor, cycle) of the measures in the module header."""
    c = sediment_constants(run_dir)
    _, f, duration, t_s = base_shaking(run_dir)
    period = 1.0 / f
    paths = list_dumps(run_dir, NAME)
    dumps = [read_dump(p) for p in paths]
    times = np.array([d["time"] for d in dumps])
    s0 = by_id(dumps[0]["particles"][SEDIMENT])
    i_s = int(np.argmin(np.abs(times - t_s)))
    ss = by_id(dumps[i_s]["particles"][SEDIMENT])
    sv00 = -s0["stress_yy"]
    ckpt = checkpoint_cyclic(run_dir)
    rows = []
    for name in monitors:
        xm, ym = RU_MONITORS[name]
        idx = np.flatnonzero((s0["x"] - xm) ** 2 + (s0["y"] - ym) ** 2 < RU_RADIUS**2)
        box = box_of(dumps[0], xm)
        st_s = particle_state(ss, s0["volume"], c, idx)
        svs, ps = float(np.mean(st_s["sv"])), st_s["p"]
        pex_s = float(np.mean(excess_pore_pressure(dumps[i_s], ss)[idx]))
        over_s = buoyant_overburden(dumps[i_s], box, ym, c["rho_s"])
        x_cells, _, _ = cell_centres(dumps[0])
        dxc = x_cells[1] - x_cells[0]
        sides = (x_cells[box[0].start] - 0.5 * dxc, x_cells[box[0].stop - 1] + 0.5 * dxc)
        top = float(np.max(s0["y"])) + 0.1

        def shed(s):
            return side_shear(s["x"], s["y"], s["stress_xy"], sides[0], sides[1], ym, top)
        shed_s = shed(ss)
        evd_replay = np.zeros(len(idx))
        for n in range(1, int(round(duration * f)) + 1):
            t0, t1 = t_s + (n - 1) * period, t_s + n * period
            if times[-1] < t1 - 1e-9:
                break
            sel = [k for k in range(len(dumps)) if t0 - 1e-9 <= times[k] <= t1 + 1e-9]
            parts = [by_id(dumps[k]["particles"][SEDIMENT]) for k in sel]
            states = [particle_state(s, s0["volume"], c, idx) for s in parts]
            tau = np.array([st["tau_xy"] for st in states])           # [dump, particle]
            tau_mean = tau.mean(axis=1)
            gam = [affine_shear(ss["x"][idx], ss["y"][idx], s["x"][idx] - ss["x"][idx],
                                s["y"][idx] - ss["y"][idx]) for s in parts]
            amp_p = half_range(tau) / c["G"]
            before = evd_replay.copy()
            evd_replay = replay_densification(np.column_stack([amp_p, amp_p]), c["c1"], c["c2"],
                                              c["threshold"], c["evd_max"], before)[:, -1]
            drain = np.array([cell_drainage(dumps[k], box, c["grain_size"]) for k in sel[1:]])
            end, pend = parts[-1], states[-1]
            pex = excess_pore_pressure(dumps[sel[-1]], end)[idx]
            row = {"monitor": name, "cycle": n, "t_end": float(times[sel[-1]]),
                   "n_particles": len(idx), "sv_s": svs,
                   "csr": float(half_range(tau_mean) / svs),
                   "gamma_el": float(half_range(tau_mean) / c["G"]),
                   "above_threshold": float(np.mean(amp_p > c["threshold"])),
                   "gamma_kin": float(half_range(gam)),
                   "evd_replay": float(np.median(evd_replay - before)),
                   "out_rel": float(np.mean(drain[:, 0]) * period),
                   "out_darcy": float(np.mean(drain[:, 1]) * period),
                   "gradient": float(np.mean(drain[:, 2])),
                   "ru": float(np.mean(pex) / np.mean(sv00[idx])),
                   "sv_ratio": float(np.mean(pend["sv"]) / svs),
                   "total_change": float((np.mean(pend["sv"]) - svs + np.mean(pex) - pex_s) / svs),
                   "carried_s": float((svs + pex_s) / over_s),
                   "shed_s": float(shed_s / over_s),
                   "shed": float(shed(end) / buoyant_overburden(dumps[sel[-1]], box, ym, c["rho_s"])),
                   "carried": float((np.mean(pend["sv"]) + np.mean(pex))
                                    / buoyant_overburden(dumps[sel[-1]], box, ym, c["rho_s"])),
                   "p_ratio": float(np.mean(pend["p"]) / np.mean(ps)),
                   "mob": float(np.nanmean(pend["mob"])),
                   "near_yield": float(np.mean(pend["mob"] >= NEAR_YIELD)),
                   "p_lost": float(np.mean(pend["p"] <= LOW_P * ps))}
            ck0 = next((ckpt[t] for t in ckpt if abs(t - t0) < 1e-6), None)
            ck1 = next((ckpt[t] for t in ckpt if abs(t - t1) < 1e-6), None)
            if ck0 is not None and ck1 is not None:
                devd = ck1["evd"][idx] - ck0["evd"][idx]
                row["evd_ckpt"] = float(np.median(devd))
                row["reversals_ckpt"] = float(np.median(ck1["reversals"][idx] - ck0["reversals"][idx]))
                row["densified_ckpt"] = float(np.mean(devd > 0.0))
            dump_end = dumps[sel[-1]]
            total = -end["stress_yy"] + excess_pore_pressure(dump_end, end)
            bal = column_balance(end["x"], end["y"], total, end["stress_xy"], sides[0], sides[1],
                                 ym, lambda yy: buoyant_overburden(dump_end, box, yy, c["rho_s"]))
            over_end = buoyant_overburden(dump_end, box, ym, c["rho_s"])
            row["deficit"], row["top_deficit"] = bal[0] / over_end, bal[1] / over_end
            row["ru_top"] = row["ru"] - bal[1] / float(np.mean(sv00[idx]))
            k_end = sel[-1]
            if 0 < k_end < len(dumps) - 1:
                before_, after_ = (by_id(dumps[k]["particles"][SEDIMENT]) for k in (k_end - 1, k_end + 1))
                a_y = (after_["velocity_y"] - before_["velocity_y"]) / (times[k_end + 1] - times[k_end - 1])
                row["inertia"] = column_inertia(end["x"], end["y"], end["mass"], a_y, sides[0], sides[1],
                                                ym, float(dump_end["attrs"]["dx"][2])) / over_end
            else:
                row["inertia"] = float("nan")
            inside = (end["x"] > sides[0]) & (end["x"] < sides[1])
            y_top = float(np.max(end["y"][inside]))
            _, yc, _ = cell_centres(dump_end)
            near_top = (yc > y_top - 0.4) & (yc < y_top)
            row["suction"] = float(np.min(np.mean(cell_excess_pressure(dump_end)[box[0]][:, near_top],
                                                  axis=0)))
            row["K"] = c["K"]
            rows.append(row)
    return rows


def print_rows(rows: list[dict]) -> None:
    """The per-cycle table, one line per monitor and cycle."""
    print("monitor              cyc  CSR   g_el    >thr  g_kin   | evd_rep  (Kevd/sv) rev_ck evd_ck"
          "  (K/sv) dens | out_rel  out_darcy (K/sv) i_top | r_u   sv/sv_s dtot  p/p_s  mob  "
          ">=0.95 p_lost carried shed")
    for r in rows:
        k_sv = r["K"] / r["sv_s"]
        ck = (f"{r['reversals_ckpt']:5.1f} {r['evd_ckpt']:7.1e} ({r['evd_ckpt'] * k_sv:4.2f}) "
              f"{r['densified_ckpt']:4.2f}" if "evd_ckpt" in r else "    -       -        -     - ")
        print(f"{r['monitor']:20s} {r['cycle']:3d}  {r['csr']:4.2f} {r['gamma_el']:7.1e} "
              f"{r['above_threshold']:4.2f} {r['gamma_kin']:7.1e} | {r['evd_replay']:7.1e} "
              f"({r['evd_replay'] * k_sv:5.2f}) {ck} | {r['out_rel']:+8.1e} {r['out_darcy']:+8.1e} "
              f"({r['out_darcy'] * k_sv:+5.2f}) {r['gradient']:+5.2f} | {r['ru']:5.2f} "
              f"{r['sv_ratio']:5.2f} {r['total_change']:+5.2f} {r['p_ratio']:5.2f} {r['mob']:5.2f} "
              f"{r['near_yield']:5.2f} "
              f"{r['p_lost']:5.2f} {r['carried']:5.2f} {r['shed']:+5.2f}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", required=True, help="run output folder")
    parser.add_argument("--monitors", nargs="+", default=["layer, crest", "layer, left flank"],
                        choices=list(RU_MONITORS), help="monitors of mpmice_earthquake_slope")
    args = parser.parse_args(argv)
    rows = analyse(args.dir, args.monitors)
    print("sigma'_v(t_s) [kPa]: " + ", ".join(
        f"{r['monitor']} {r['sv_s'] / 1000.0:.1f}" for r in rows if r["cycle"] == 1))
    print("(sigma'_v + p_ex) / buoyant overburden at t_s: " + ", ".join(
        f"{r['monitor']} {r['carried_s']:.2f} (shed by shear on the sides {r['shed_s']:+.2f})"
        for r in rows if r["cycle"] == 1))
    print_rows(rows)
    print("column balance at the cycles' ends, / buoyant overburden: deficit of the band's "
          "sigma'_v + p_ex at the monitor's height (W' - shed); the same at "
          f"{TOP_DEPTH} m below the column's top; body = deficit - top; inertia sum m a_y; "
          "suction: lowest cell p_ex in the top 0.4 m [kPa]; r_u less the top's deficit")
    for r in rows:
        print(f"{r['monitor']:20s} {r['cycle']:3d}  deficit {r['deficit']:+5.2f}  top "
              f"{r['top_deficit']:+5.2f}  body {r['deficit'] - r['top_deficit']:+5.2f}  inertia "
              f"{r['inertia']:+6.3f}  suction {r['suction'] / 1000.0:+6.2f}  r_u {r['ru']:4.2f} "
              f"-> {r['ru_top']:4.2f}  1-p'/p'_s {1.0 - r['p_ratio']:4.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
