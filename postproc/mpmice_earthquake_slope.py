"""Earthquake-induced submarine landslide with the coupled scene: base motion, slope displacement,
excess pore pressure, plastic strain and the surface wave (namelists/mpmice_earthquake_slope_2d.nml,
docs/applications.md).

Usage:  python -m postproc.mpmice_earthquake_slope --dir output/mpmice_earthquake_slope_2d [--out DIR]
            [--average]
        python -m postproc.mpmice_earthquake_slope --compare loose=DIR1 dense=DIR2 [--out DIR]

Per dump it prints: the base's displacement (mean over its particles, unwrapped across the
periodic x faces) and the prescribed one x(t) = A/w (t - sin(w t)/w); the sediment's largest
displacement relative to the base; the largest accumulated plastic strain; the excess pore
pressure of the sediment (the particle's pore pressure, i.e. the pressure of the cell holding it,
minus the hydrostatic pressure p_atm + rho_w g (h - y) at that cell's centre: min / max and the
mean over the particles within 0.3 m of three monitoring points, crest, left and right
mid-flank); the pore pressure's cell-to-cell noise (99th percentile / largest |excess of a
sediment cell minus the mean of its two x neighbours|); the free-surface elevation
eta (water share 0.5 contour, m above the still level) max / min; the largest relative mass
change of each material. Writes earthquake_slope.png (snapshots: relative displacement, plastic
strain and excess pore pressure of the particles, with the free surface) and
earthquake_slope_history.png (base motion, monitored excess pore pressure, eta extremes).
A second table gives the crest's mean displacement relative to the base (particles starting
above y = 2.3 m) and the pore-pressure ratio r_u = excess pore pressure / initial vertical
effective stress (means over the particles within 0.25 m of four points: the bank's core and
the basal layer under the crest and both flanks), with 1 - sigma'_v / sigma'_v0 of the same
particles beside it; then the noise's p99 averaged over the dumps 0.2-0.85 s and its largest
value there (and that of the running mean `cell/pressure_average` when the run kept one,
`&ice pressure_average_time`). With --average the excess pore pressures and r_u are those of
the running mean at the particles' cells instead of the instantaneous cell pressure. A third
table gives r_u per shaking cycle (at the cycle's end and its largest value
within it); a fourth the monitors' initial tau/p' and tau_xy/sigma'_v0, and per cycle their
cyclic stress ratio (half the range of the mean tau_xy over the cycle's dumps / sigma'_v0) and
the spread (standard deviation) of their particles' volumetric strain V/V0 - 1. The base's shaking (amplitude, frequency, duration, start) is read from the run's echo
quake.used.nml. --compare draws r_u and the crest displacement of several runs into
earthquake_slope_ru.png, and the base acceleration over r_u at each monitor into
earthquake_slope_ru_cycles.png.
The dumps open in ParaView through <name>.xmf.
"""
from __future__ import annotations

import math
import os

import numpy as np

from postproc import measures
from postproc.figures import pyplot, save_figure
from postproc.measures import by_id, masses  # noqa: F401  (also used by the test)
from postproc.mpmice_io import cell_centres, parse_compare_runs, parse_run_dir

NAME = "quake"
STILL_LEVEL = 3.5            # m
P_ATM = 101325.0             # Pa
RHO_W = 999.8                # kg/m^3
G = 9.81                     # m/s^2
AMPLITUDE = 9.81             # m/s^2 (1 g)
FREQUENCY = 2.0              # Hz
DURATION = 1.0               # s: the shaking stops after 2 cycles (v = 0 there)
WATER, AIR, SEDIMENT, BASE = "water", "air", "sediment", "base"
# monitoring points (initial positions): crest centre at mid-height, left and right mid-flank;
# the excess pore pressure there is the mean over the particles that start within MONITOR_RADIUS
MONITOR_RADIUS = 0.3         # m
MONITORS = {"crest": (5.789, 1.5), "left flank": (3.1, 1.0), "right flank": (8.5, 1.0)}
# pore-pressure ratio r_u = (mean excess pore pressure) / (mean initial vertical effective
# stress -sigma'_yy) of the particles that start within RU_RADIUS of these points: the bank's
# core and the basal layer under the crest and under each flank (docs/earthquake_liquefaction.md)
RU_RADIUS = 0.25             # m
RU_MONITORS = {"bank core": (5.789, 1.2), "layer, crest": (5.789, 0.35),
               "layer, left flank": (3.1, 0.35), "layer, right flank": (8.5, 0.35)}
CREST_Y0 = 2.3               # m: particles starting above it are the crest's


def prescribed_displacement(t: float, a: float = AMPLITUDE, f: float = FREQUENCY,
                            duration: float = DURATION, start: float = 0.0) -> float:
    """x(t) - x(0) [m] of a base with a(t) = a sin(2 pi f (t - start)) starting from rest at
    `start` (`&solid acceleration_start`; at rest before), a = 0 after `start + duration` (the
    velocity kept)."""
    w = 2.0 * math.pi * f
    t = max(t - start, 0.0)
    ts = min(t, duration) if duration > 0.0 else t
    return a / w * (ts - math.sin(w * ts) / w) + a * (1.0 - math.cos(w * ts)) / w * (t - ts)


def shaking_parts(shaking: tuple) -> tuple[float, float, float, float]:
    """(a, f, duration, start) of a shaking tuple of :func:`base_shaking` (start 0 when a
    3-tuple (a, f, duration) is given)."""
    a, f, duration = shaking[:3]
    return a, f, duration, (shaking[3] if len(shaking) > 3 else 0.0)


def base_shaking(run_dir: str, name: str = NAME) -> tuple[float, float, float, float]:
    """The base's shaking (amplitude a [m/s^2] along x, frequency [Hz], duration [s], start
    [s]) as the run's echo ``<run_dir>/<name>.used.nml`` gives it (the rigid solid named
    'base'); the shipped slope's 1 g, 2 Hz, 1 s from 0 s when the echo is missing."""
    from postproc.namelist import parse_namelist_groups
    path = os.path.join(run_dir, f"{name}.used.nml")
    if not os.path.exists(path):
        return AMPLITUDE, FREQUENCY, DURATION, 0.0
    with open(path, encoding="utf-8") as handle:
        groups = parse_namelist_groups(handle.read())
    for group, values in groups:
        if group == "solid" and str(values.get("name", "")).strip("'\"") == BASE:
            amp = values.get("acceleration_amplitude", [AMPLITUDE])
            amp = amp[0] if isinstance(amp, list) else amp
            return (float(amp), float(values.get("acceleration_frequency", FREQUENCY)),
                    float(values.get("acceleration_duration", DURATION)),
                    float(values.get("acceleration_start", 0.0)))
    return AMPLITUDE, FREQUENCY, DURATION, 0.0


def base_acceleration(t: np.ndarray, shaking: tuple[float, float, float]) -> np.ndarray:
    """a(t) [m/s^2] of the base: a sin(2 pi f (t - start)) while start <= t <= start +
    duration, else 0."""
    a, f, duration, start = shaking_parts(shaking)
    t = np.asarray(t, dtype=float) - start
    return np.where((t >= 0.0) & (t <= duration), a * np.sin(2.0 * math.pi * f * t), 0.0)


def shaking_cycles(rows: list[dict], shaking: tuple[float, float, float]):
    """Yield (n, the rows inside cycle n, the row nearest the cycle's end) for each shaking cycle n
    (t in (start + (n-1)/f, start + n/f]) that the rows cover to its end."""
    _, f, duration, start = shaking_parts(shaking)
    t = np.array([r["time"] for r in rows])
    for n in range(1, int(round(duration * f)) + 1):
        t0, t1 = start + (n - 1) / f, start + n / f
        if t[-1] < t1 - 1e-9:
            return
        inside = [r for r in rows if t0 < r["time"] <= t1 + 1e-9]
        yield n, inside, rows[int(np.argmin(np.abs(t - t1)))]


def mark_cycle_ends(axes, shaking: tuple, until: float | None = None) -> None:
    """Grey vertical lines on every axis at the ends of the shaking's cycles, start + n / f, up
    to `until` [s] (default: the shaking's end)."""
    _, f, duration, start = shaking_parts(shaking)
    end = start + duration if until is None else until
    for ax in axes:
        for c in np.arange(start + 1.0 / f, end + 1e-9, 1.0 / f):
            ax.axvline(c, color="0.85", lw=0.6, zorder=0)


def draw_base_acceleration(ax, runs: dict[str, list[dict]], samples: int = 2000) -> None:
    """Each run's base acceleration a(t)/g on `ax` (colour C<n> in the runs' order, from 0 to
    its last dump, `samples` points), with its axis label and legend."""
    for n, (label, rows) in enumerate(runs.items()):
        tt = np.linspace(0.0, rows[-1]["time"], samples)
        ax.plot(tt, base_acceleration(tt, rows[0]["shaking"]) / G, "-", color=f"C{n}", lw=1,
                label=label)
    ax.set_ylabel("base a / g")
    ax.legend(fontsize=8, loc="upper right")


def ru_axis(ax, label: str) -> None:
    """An r_u panel: its label, and lines at r_u = 1 (liquefied) and 0."""
    ax.set_ylabel(label, fontsize=8)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.axhline(0.0, color="0.6", lw=0.6)


def cycle_table(rows: list[dict], shaking: tuple[float, float, float]) -> list[dict]:
    """Per shaking cycle n (t in (start + (n-1)/f, start + n/f]): r_u at each monitor at the
    cycle's end (the dump nearest start + n/f) and its largest value within the cycle."""
    table = []
    for n, inside, end in shaking_cycles(rows, shaking):
        table.append({"cycle": n, "time": end["time"], "end": dict(end["ru"]),
                      "max": {k: max(r["ru"][k] for r in inside) for k in RU_MONITORS}})
    return table


def print_cycle_table(table: list[dict]) -> None:
    """r_u per cycle (:func:`cycle_table`)."""
    print("cycle  t [s]  r_u at the cycle's end (largest in the cycle): " + " / ".join(RU_MONITORS))
    for c in table:
        cells = " / ".join(f"{c['end'][k]:5.2f} ({c['max'][k]:5.2f})" for k in RU_MONITORS)
        print(f"{c['cycle']:5d} {c['time']:6.2f}  {cells}")


def domain_length(dump: dict) -> float:
    """Length [m] of the domain in x."""
    x, _, _ = cell_centres(dump)
    dx = x[1] - x[0]
    return float(x[-1] - x[0] + dx)


def unwrapped(dx: np.ndarray, length: float) -> np.ndarray:
    """Displacements across the periodic x faces, taken in (-L/2, L/2]."""
    return dx - length * np.round(dx / length)


def free_surface(dump: dict, level: float = STILL_LEVEL) -> tuple[np.ndarray, np.ndarray]:
    """(x of the column centres, eta [m]): the height of the water in each column of cells,
    sum_j s_j dy with s = phi_w / (phi_w + phi_air) the water's share of the fluid volume (1 in
    cells with no fluid), minus `level` [m]; exact for a level surface at any cell size
    (:func:`postproc.measures.free_surface`, method "height")."""
    (x,), eta = measures.free_surface(dump, WATER, [AIR], level, "height", vertical=(1, +1))
    return x, eta


def hydrostatic_pressure(y: np.ndarray, level: float = STILL_LEVEL) -> np.ndarray:
    """p_atm + rho_w g (level - y) below `level`, p_atm above it [Pa]."""
    return P_ATM + RHO_W * G * np.maximum(level - y, 0.0)


def particle_cells(dump: dict, x: np.ndarray, y: np.ndarray,
                   length: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(i, j) of the cells holding the points (x, y) [m] of the dump's first z layer, clipped
    to the grid; with `length` [m] x is taken periodic over it."""
    xc, yc, _ = cell_centres(dump)
    dx, dy = xc[1] - xc[0], yc[1] - yc[0]
    sx = x - (xc[0] - 0.5 * dx)
    if length is not None:
        sx = sx % length
    i = np.clip(np.floor(sx / dx).astype(int), 0, len(xc) - 1)
    j = np.clip(np.floor((y - (yc[0] - 0.5 * dy)) / dy).astype(int), 0, len(yc) - 1)
    return i, j


def excess_pore_pressure(dump: dict, parts: dict, field: str | None = None) -> np.ndarray:
    """Pore pressure minus the hydrostatic value at the centre of the particle's cell [Pa]: the
    particle's `pore_pressure` (its cell's pressure), or with `field` (e.g. `pressure_average`,
    the running mean of `&ice pressure_average_time`) that cell field at the particle's cell."""
    i, j = particle_cells(dump, parts["x"], parts["y"])
    hydro = hydrostatic_pressure(cell_centres(dump)[1][j])
    if not np.any(parts["pore_pressure"]):        # the initial dump: not computed yet
        return np.zeros_like(hydro)
    if field is not None:
        return dump["cell"][field][i, j, 0] - hydro
    return parts["pore_pressure"] - hydro


def cell_excess_pressure(dump: dict, level: float = STILL_LEVEL,
                         field: str = "pressure") -> np.ndarray:
    """The cells' pressure (the dump's `cell/<field>`: `pressure`, or `pressure_average`, the
    running mean of `&ice pressure_average_time`) minus the hydrostatic p_atm + rho_w g
    (level - y) at their centres [Pa], indexed [i, j] (the first z layer)."""
    _, y, _ = cell_centres(dump)
    return dump["cell"][field][:, :, 0] - hydrostatic_pressure(y, level)[None, :]


def pore_pressure_roughness(dump: dict, min_fraction: float = 0.3, field: str = "pressure",
                            level: float = STILL_LEVEL, solid: str = SEDIMENT,
                            base: str = BASE) -> tuple[float, float]:
    """(99th percentile, largest) of |a sediment cell's excess pore pressure minus the mean of
    its two x neighbours| [Pa] (periodic in x): the cell-to-cell noise of the pore pressure in a
    layer that is uniform along x (docs/mpmice.md, known problems). Sediment cells: sediment
    volume fraction above `min_fraction`, no base, both x neighbours sediment cells too; (0, 0)
    when there are none. `field`, `level`: as :func:`cell_excess_pressure`; `solid`, `base`: the
    sediment's and the base's names."""
    ex = cell_excess_pressure(dump, level, field)
    sed = dump["cell"][f"{solid}/volume_fraction"][:, :, 0]
    rigid = dump["cell"][f"{base}/volume_fraction"][:, :, 0]
    cells = (sed > min_fraction) & (rigid < 1e-3)
    inner = cells & np.roll(cells, 1, axis=0) & np.roll(cells, -1, axis=0)
    if not np.any(inner):
        return 0.0, 0.0
    dev = np.abs(ex - 0.5 * (np.roll(ex, 1, axis=0) + np.roll(ex, -1, axis=0)))[inner]
    return float(np.percentile(dev, 99)), float(np.max(dev))


def pore_pressure_ratio(pex: np.ndarray, sigma_v0: np.ndarray) -> float:
    """r_u = mean excess pore pressure / mean initial vertical effective stress of a group of
    particles [-] (1: the pore water carries the whole initial effective stress)."""
    return float(np.mean(pex) / np.mean(sigma_v0))


def effective_stress_ratio(sigma_v: np.ndarray, sigma_v0: np.ndarray) -> float:
    """1 - mean sigma'_v / mean sigma'_v0 of a group of particles [-]: the loss of vertical
    effective stress, r_u's counterpart from the skeleton (equal to r_u where the total vertical
    stress stays at its initial value)."""
    return float(1.0 - np.mean(sigma_v) / np.mean(sigma_v0))


def shear_ratio(parts: dict, index: np.ndarray) -> np.ndarray:
    """tau / p' of particles `index`: tau = sqrt(s:s / 2) of the effective stress's deviator
    (plane strain, sigma'_zz included), p' = -tr(sigma') / 3 [-] (0 where p' <= 0)."""
    sxx, syy, szz, sxy = (parts[f"stress_{c}"][index] for c in ("xx", "yy", "zz", "xy"))
    p = -(sxx + syy + szz) / 3.0
    tau = np.sqrt(0.5 * ((sxx + p) ** 2 + (syy + p) ** 2 + (szz + p) ** 2) + sxy**2)
    return np.where(p > 0.0, tau / np.where(p > 0.0, p, 1.0), 0.0)


def cycle_diagnostics(rows: list[dict], shaking: tuple[float, float, float]) -> list[dict]:
    """Per shaking cycle (as :func:`cycle_table`) and r_u monitor: the cyclic stress ratio CSR
    = half the range of the monitor's mean tau_xy over the cycle's dumps / its mean initial
    sigma'_v0, and the spread (standard deviation) of its particles' volumetric strain
    V / V0 - 1 at the cycle's end."""
    table = []
    for n, inside, end in shaking_cycles(rows, shaking):
        csr = {}
        for k in RU_MONITORS:
            tau = [r["tau_xy"][k] for r in inside]
            csr[k] = 0.5 * (max(tau) - min(tau)) / end["sigma_v0"][k]
        table.append({"cycle": n, "csr": csr, "ev_spread": dict(end["ev_spread"])})
    return table


def print_cycle_diagnostics(rows: list[dict], table: list[dict]) -> None:
    """The initial tau / p' and tau_xy / sigma'_v0 of each r_u monitor, then per cycle the CSR
    and the particles' volumetric strain spread (:func:`cycle_diagnostics`)."""
    first = rows[0]
    print("initial tau/p' (tau_xy/sigma'_v0): " + " / ".join(
        f"{first['tau_over_p'][k]:.3f} ({first['tau_xy'][k] / first['sigma_v0'][k]:+.3f})"
        for k in RU_MONITORS))
    print("cycle  CSR / spread of eps_v at the cycle's end: " + " / ".join(RU_MONITORS))
    for c in table:
        cells = " / ".join(f"{c['csr'][k]:4.2f} {c['ev_spread'][k]:.1e}" for k in RU_MONITORS)
        print(f"{c['cycle']:5d}  {cells}")


def analyse(dumps: list[dict], shaking: tuple[float, float, float] | None = None,
            field: str | None = None) -> list[dict]:
    """One row of measured quantities per dump (see the module header); `shaking` (a, f,
    duration: :func:`base_shaking`) sets the prescribed base motion (default: the shipped 1 g);
    `field`: the cell field the excess pore pressures and r_u are taken from
    (:func:`excess_pore_pressure`; default the particles' pore pressure)."""
    a_base, f_base, d_base, s_base = shaking_parts(shaking or (AMPLITUDE, FREQUENCY, DURATION))
    length = domain_length(dumps[0])
    s0, b0 = by_id(dumps[0]["particles"][SEDIMENT]), by_id(dumps[0]["particles"][BASE])
    monitors = {k: np.flatnonzero((s0["x"] - px) ** 2 + (s0["y"] - py) ** 2 < MONITOR_RADIUS**2)
                for k, (px, py) in MONITORS.items()}
    ru_monitors = {k: np.flatnonzero((s0["x"] - px) ** 2 + (s0["y"] - py) ** 2 < RU_RADIUS**2)
                   for k, (px, py) in RU_MONITORS.items()}
    sv0 = -s0["stress_yy"]                       # initial vertical effective stress [Pa]
    crest = s0["y"] > CREST_Y0
    m0 = masses(dumps[0])
    # the still level as the initial fluid regions hold it (cells whose centre is below it)
    level = STILL_LEVEL + float(np.mean(free_surface(dumps[0])[1]))
    rows = []
    for d in dumps:
        s, b = by_id(d["particles"][SEDIMENT]), by_id(d["particles"][BASE])
        base_dx = float(np.mean(unwrapped(b["x"] - b0["x"], length)))
        ux = unwrapped(s["x"] - s0["x"], length) - base_dx
        uy = s["y"] - s0["y"]
        rel = np.hypot(ux, uy)
        pex = excess_pore_pressure(d, s, field)
        _, eta = free_surface(d, level)
        m = masses(d)
        rough = pore_pressure_roughness(d)
        rough_avg = pore_pressure_roughness(d, field="pressure_average") \
            if "pressure_average" in d["cell"] else None
        rows.append({
            "time": float(d["time"]), "base_dx": base_dx, "shaking": (a_base, f_base, d_base, s_base),
            "base_dx_prescribed": prescribed_displacement(float(d["time"]), a_base, f_base, d_base,
                                                          s_base),
            "rel_disp_max": float(np.max(rel)), "ux": ux, "uy": uy, "rel": rel,
            "plastic_max": float(np.max(s["plastic_strain"])), "plastic": s["plastic_strain"],
            "pex": pex, "pex_min": float(np.min(pex)), "pex_max": float(np.max(pex)),
            "pex_monitor": {k: float(np.mean(pex[i])) for k, i in monitors.items()},
            "ru": {k: pore_pressure_ratio(pex[i], sv0[i]) for k, i in ru_monitors.items()},
            "ru_effective": {k: effective_stress_ratio(-s["stress_yy"][i], sv0[i])
                             for k, i in ru_monitors.items()},
            "tau_xy": {k: float(np.mean(s["stress_xy"][i])) for k, i in ru_monitors.items()},
            "sigma_v0": {k: float(np.mean(sv0[i])) for k, i in ru_monitors.items()},
            "ev_spread": {k: float(np.std(s["volume"][i] / s0["volume"][i] - 1.0))
                          for k, i in ru_monitors.items()},
            "tau_over_p": {k: float(np.mean(shear_ratio(s, i))) for k, i in ru_monitors.items()},
            "crest_ux": float(np.mean(ux[crest])), "crest_uy": float(np.mean(uy[crest])),
            "roughness_p99": rough[0], "roughness_max": rough[1], "roughness_average": rough_avg,
            "eta": eta, "level": level, "eta_max": float(np.nanmax(eta)), "eta_min": float(np.nanmin(eta)),
            "mass_change": {k: abs(m[k] / m0[k] - 1.0) for k in m0 if m0[k] > 0.0},
            "x": s["x"], "y": s["y"], "y0": s0["y"],
        })
    return rows


def plot(dumps: list[dict], rows: list[dict], out: str) -> list[str]:
    """Snapshot and history figures; returns their paths."""
    plt = pyplot()
    pick = sorted({0, len(rows) // 3, (2 * len(rows)) // 3, len(rows) - 1})
    fig, axes = plt.subplots(len(pick), 3, figsize=(15, 2.2 * len(pick)), squeeze=False)
    for r, i in enumerate(pick):
        row, d = rows[i], dumps[i]
        xs, eta = free_surface(d, row["level"])
        for c, (key, label, cmap, lim) in enumerate([
                ("rel", "|u - u_base| [m]", "viridis", None),
                ("plastic", "plastic strain [-]", "magma", None),
                ("pex", "excess pore pressure [kPa]", "coolwarm", "sym")]):
            ax = axes[r][c]
            v = row[key] / (1000.0 if key == "pex" else 1.0)
            kw = {}
            if lim == "sym":
                # scale from the bank (start above the layer): the cells the lowest sediment row
                # shares with the base's top carry a stuck pressure that would swamp the colours
                bank = row["y0"] > 0.5
                vmax = max(float(np.percentile(np.abs(v[bank]), 99)), 1e-9)
                kw = {"vmin": -vmax, "vmax": vmax}
            sc = ax.scatter(row["x"], row["y"], c=v, s=2, cmap=cmap, **kw)
            ax.plot(xs, eta + row["level"], "b-", lw=1)
            ax.set_title(f"t = {row['time']:.2f} s: {label}", fontsize=8)
            ax.set_aspect("equal")
            ax.set_xlim(xs[0], xs[-1])
            ax.set_ylim(0.0, STILL_LEVEL + 0.6)
            fig.colorbar(sc, ax=ax, fraction=0.02)
    fig.tight_layout()
    snap = os.path.join(out, "earthquake_slope.png")
    save_figure(fig, snap, dpi=100)
    t = np.array([r["time"] for r in rows])
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    a1.plot(t, [r["base_dx"] for r in rows], "o", label="base (particles)")
    tt = np.linspace(0.0, t[-1], 200)
    a1.plot(tt, [prescribed_displacement(v, *rows[0]["shaking"]) for v in tt], "k-", lw=1,
            label="prescribed")
    a1.plot(t, [r["rel_disp_max"] for r in rows], "s-", label="sediment: max |u - u_base|")
    a1.set_ylabel("displacement [m]")
    a1.legend(fontsize=8)
    for k in MONITORS:
        a2.plot(t, [r["pex_monitor"][k] / 1000.0 for r in rows], "o-", label=k)
    a2.set_ylabel("excess pore pressure [kPa]")
    a2.legend(fontsize=8)
    a3.plot(t, [r["eta_max"] * 100.0 for r in rows], "o-", label="eta max")
    a3.plot(t, [r["eta_min"] * 100.0 for r in rows], "o-", label="eta min")
    a3.set_ylabel("free surface [cm]")
    a3.set_xlabel("t [s]")
    a3.legend(fontsize=8)
    fig.tight_layout()
    hist = os.path.join(out, "earthquake_slope_history.png")
    save_figure(fig, hist, dpi=100)
    return [snap, hist]


def print_table(rows: list[dict]) -> None:
    """The per-dump table of :func:`main`."""
    print("  t [s]  base dx [m]  prescribed  max|u-ub| [m]  max eps_p  pex min/max [kPa]"
          "  pex crest/left/right [kPa]  noise p99/max [kPa]  eta max/min [cm]  mass change")
    for r in rows:
        mon = "/".join(f"{v / 1000.0:.1f}" for v in r["pex_monitor"].values())
        print(f"{r['time']:7.3f} {r['base_dx']:11.5f} {r['base_dx_prescribed']:11.5f} "
              f"{r['rel_disp_max']:13.4f} {r['plastic_max']:10.4f} "
              f"{r['pex_min'] / 1000.0:8.1f}/{r['pex_max'] / 1000.0:.1f} {mon:>22s} "
              f"{r['roughness_p99'] / 1000.0:12.1f}/{r['roughness_max'] / 1000.0:.1f} "
              f"{r['eta_max'] * 100.0:8.2f}/{r['eta_min'] * 100.0:.2f} "
              f"{max(r['mass_change'].values()):10.2e}")
    print("  t [s]  crest u_x/u_y rel. base [m]  r_u " + " / ".join(RU_MONITORS)
          + "  (1 - sigma'_v/sigma'_v0 at the same points)")
    for r in rows:
        ru = " / ".join(f"{v:5.2f}" for v in r["ru"].values())
        re = " / ".join(f"{v:5.2f}" for v in r["ru_effective"].values())
        print(f"{r['time']:7.3f} {r['crest_ux']:9.3f}/{r['crest_uy']:.3f}  {ru}  ({re})")
    start = shaking_parts(rows[0]["shaking"])[3]
    shaking = [r for r in rows if start + 0.2 <= r["time"] <= start + 0.85 + 1e-9]
    if shaking:
        print(f"noise {start + 0.2:.2f}-{start + 0.85:.2f} s: p99 mean {np.mean([r['roughness_p99'] for r in shaking]) / 1e3:.1f} kPa,"
              f" largest {max(r['roughness_max'] for r in shaking) / 1e3:.1f} kPa")
        if shaking[0]["roughness_average"] is not None:
            avg = [r["roughness_average"] for r in shaking]
            print(f"noise of the running mean (cell/pressure_average) {start + 0.2:.2f}-"
                  f"{start + 0.85:.2f} s: p99 mean {np.mean([a[0] for a in avg]) / 1e3:.1f} kPa,"
                  f" largest {max(a[1] for a in avg) / 1e3:.1f} kPa")


def compare(runs: dict[str, list[dict]], out: str) -> str:
    """Figure of several runs (label -> rows of :func:`analyse`): r_u at each monitor against
    time, the crest's displacement relative to the base and the sediment's largest displacement
    relative to the base; returns its path."""
    plt = pyplot()
    fig, grid = plt.subplots(2, 3, figsize=(13.0, 7.0))
    axes = list(grid.flat)
    spread = axes.pop()          # the sixth panel: largest displacement relative to the base
    styles = ["-", "--", ":", "-."]
    for n, (label, rows) in enumerate(runs.items()):
        t = np.array([r["time"] for r in rows])
        for ax, key in zip(axes, RU_MONITORS):
            ax.plot(t, [r["ru"][key] for r in rows], styles[n % 4], color=f"C{n}", marker="o",
                    ms=3, label=label)
        axes[-1].plot(t, [r["crest_ux"] for r in rows], "-", color=f"C{n}", marker="o", ms=3,
                      label=f"{label}: u_x")
        axes[-1].plot(t, [r["crest_uy"] for r in rows], ":", color=f"C{n}", marker="s", ms=3,
                      label=f"{label}: u_y")
        spread.plot(t, [r["rel_disp_max"] for r in rows], "-", color=f"C{n}", marker="o", ms=3,
                    label=label)
    for ax, key in zip(axes, RU_MONITORS):
        ax.axhline(1.0, color="k", lw=0.8)
        _, _, duration, start = shaking_parts(rows[0]["shaking"])
        ax.axvspan(start, start + duration, color="0.9", zorder=0)
        ax.set_title(f"r_u, {key}", fontsize=9)
        ax.set_xlabel("t [s]")
    axes[0].set_ylabel("excess pore pressure / initial sigma'_v")
    axes[0].legend(fontsize=8)
    axes[-1].set_title("crest displacement relative to the base", fontsize=9)
    axes[-1].set_ylabel("[m]")
    axes[-1].set_xlabel("t [s]")
    axes[-1].legend(fontsize=7)
    spread.set_title("sediment: largest |u - u_base|", fontsize=9)
    spread.set_ylabel("[m]")
    spread.set_xlabel("t [s]")
    spread.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "earthquake_slope_ru.png")
    save_figure(fig, path, dpi=100)
    return path


def cycles_figure(runs: dict[str, list[dict]], out: str) -> str:
    """Figure of several runs (label -> rows of :func:`analyse`): the base acceleration a(t)/g
    over r_u against time at the three basal-layer monitors and the bank's core, to see the
    build-up cycle by cycle; returns its path."""
    plt = pyplot()
    keys = list(RU_MONITORS)[1:] + list(RU_MONITORS)[:1]
    fig, axes = plt.subplots(len(keys) + 1, 1, figsize=(8.0, 10.0), sharex=True)
    t_end = max(r["time"] for rows in runs.values() for r in rows)
    draw_base_acceleration(axes[0], runs, 1000)
    for n, (label, rows) in enumerate(runs.items()):
        t = np.array([r["time"] for r in rows])
        for ax, key in zip(axes[1:], keys):
            ax.plot(t, [r["ru"][key] for r in rows], "-", color=f"C{n}", marker="o", ms=2.5,
                    label=label)
    for ax, key in zip(axes[1:], keys):
        ru_axis(ax, f"r_u, {key}")
    mark_cycle_ends(axes, next(iter(runs.values()))[0]["shaking"], t_end)
    axes[-1].set_xlabel("t [s] (grey lines: the end of each shaking cycle)")
    fig.tight_layout()
    path = os.path.join(out, "earthquake_slope_ru_cycles.png")
    save_figure(fig, path, dpi=100)
    return path


def compare_main(argv) -> int:
    """``--compare LABEL=DIR [LABEL=DIR ...] --out DIR``: the r_u / displacement figure."""
    args, runs = parse_compare_runs("r_u and displacement of several runs", NAME,
                                    lambda dumps, path: analyse(dumps, base_shaking(path)), argv)
    for label, rows in runs.items():
        print(f"== {label}: {args.paths[label]}")
        print_table(rows)
        print_cycle_table(cycle_table(rows, rows[0]["shaking"]))
        print_cycle_diagnostics(rows, cycle_diagnostics(rows, rows[0]["shaking"]))
    print(f"plot: {compare(runs, args.out)}")
    print(f"plot: {cycles_figure(runs, args.out)}")
    return 0


def main(argv=None) -> int:
    import sys
    argv = sys.argv[1:] if argv is None else argv
    if "--compare" in argv:
        return compare_main(argv)
    args, dumps = parse_run_dir(__doc__.splitlines()[0], NAME, argv, flags={
        "--average": "r_u and the excess pore pressures from the running mean "
                     "cell/pressure_average (&ice pressure_average_time)"})
    rows = analyse(dumps, base_shaking(args.dir), "pressure_average" if args.average else None)
    print_table(rows)
    print_cycle_table(cycle_table(rows, rows[0]["shaking"]))
    print_cycle_diagnostics(rows, cycle_diagnostics(rows, rows[0]["shaking"]))
    for path in plot(dumps, rows, args.out or args.dir):
        print(f"plot: {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
