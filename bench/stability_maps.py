"""Stability maps: where a method fails (docs/accuracy.md).

Run through bench/accuracy_charts.py (`--only drag_map ...`), which writes
docs/stability_<study>.csv + .png for each.

Stability maps:
  drag_map            consolidation column (50 cells, densities / 100) at a fixed dt (2^-22 ..
                      2^-14 s) x grain size (1 mm .. 10 um: drag relaxation rate beta = 9.8e4 ..
                      9.8e8 1/s), implicit vs explicit drag (&coupling drag_scheme); extends
                      postproc/mpmice_stiff_drag.py (Darcy column map, solver's dt) to fixed dt
                      and the solid's CFL number. Failed = exit status 3 (non-finite state, or
                      dt below &time dt_min = 0.75 dt: a rejected step or the CFL limit);
                      inaccurate = max |p - p_exact| / p0 below the top 5 cells > 5 %.
  mpm_cfl_map         elastic bar, &time cfl x E / E_ref (1 .. 1e-5 at fixed v0: the tip
                      amplitude grows from 0.003 to 0.8 cells), linear vs GIMP. The run loop's
                      stops decide (docs/accuracy.md "Failure detection"): unstable = stopped
                      by &run max_energy_growth = 1.05 (kinetic + strain energy > 1.05 E(0));
                      failed = any other exit status 3 (non-finite state, a particle lost:
                      max_particle_loss_fraction = 0, the CFL step collapsed: min_dt_ratio =
                      0.25) or the step cap (10x the planned steps); inaccurate = tip-history
                      error > 10 %.
  crossing_map        elastic column under self-weight (postproc.mpm_column), E = 1e7 .. 3e4 Pa
                      (top displacement 0.03 .. 11 cells), 25 and 50 cells, linear vs GIMP:
                      stress oscillation = max over particles of |s_i - (s_{i-1} + s_{i+1}) / 2|
                      / (rho g H) (sigma_yy sorted by height), and max |sigma_yy - exact| /
                      (rho g H) (exact: the weight above the particle, valid at any strain).
                      Noisy = oscillation > 5 %; failed = exit status 3 (non-finite, a particle
                      lost, the step collapsed, as for mpm_cfl_map) or the step cap.
  soil_cfl_map        soil column under self-weight (1 m, 25 cells, GIMP, geostatic start, 20
                      periods), &time cfl 0.25 .. 1 x stiffness: the critical-state sand (E = 1e7
                      .. 1e5 Pa, loose: yields from the start) and Modified Cam-Clay (kappa =
                      0.002 .. 0.05, OCR 1: on its yield surface). unstable = stopped by &run
                      max_energy_growth = 1.2; failed = other exit status 3 or the step cap;
                      noisy = stress oscillation > 5 % (as crossing_map); inaccurate = max
                      |sigma_yy - exact| > 5 % of the base's sigma'_v.
"""
from __future__ import annotations

import math
import os
import sys

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from bench.accuracy_runs import (                                   # noqa: E402
    ENERGY_LIMIT, MAP_STOPS, STEP_CAP, lost_particles, run_bar, run_failed, stop_kind, timed_run)
from postproc import mpmice_terzaghi                                # noqa: E402
from postproc import mpmice_stiff_drag as stiff                     # noqa: E402
from postproc.analytic import oedometer_modulus                     # noqa: E402
from postproc.figures import pyplot, save_figure                    # noqa: E402
from postproc.mpm_common import particles                           # noqa: E402
from postproc.mpmice_io import list_dumps, read_dump                # noqa: E402
from postproc.run_case import ROOT                                  # noqa: E402


DRAG_GRAINS = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5)
DRAG_DT_EXPONENTS = (22, 20, 18, 16, 14)
DRAG_END = 2.0**-7        # s (7.8 ms: T_v = 0.032 at d = 1 mm), exact for every 2^-k dt
DRAG_CELLS = 50
DRAG_ERROR_LIMIT = 0.05   # max |p - p_exact| / p0 below the top 5 cells
#: The map uses the quasi-static densities (mpmice_terzaghi.QUASI_STATIC_SET, / 100): with the
#: paper's densities the undrained P-wave ringing of the step load (resolved, hence undamped, at
#: small dt) is still 10-27 % of p0 at t = 2^-6 s, a dynamic effect eq. 78 does not contain.
DRAG_SOLID_DENSITY, DRAG_FLUID_DENSITY = 26.5, 9.998
SOLID_WAVE_SPEED = math.sqrt(oedometer_modulus(1.0e7, 0.3) / DRAG_SOLID_DENSITY)   # m/s


def drag_rate(grain_size: float, solid_fraction: float = 0.7) -> float:
    """beta = K_d / (n rho_f) [1/s] of the map's column (quasi-static fluid density)."""
    return stiff.drag_coefficient(solid_fraction, grain_size) \
        / ((1.0 - solid_fraction) * DRAG_FLUID_DENSITY)


def map_drag(work: str, quick: bool) -> list[dict]:
    grains = (1e-3, 1e-4, 1e-5) if quick else DRAG_GRAINS
    exps = (20, 16, 14) if quick else DRAG_DT_EXPONENTS
    rows = []
    for d in grains:
        params = stiff.terzaghi_params(d)
        for k in exps:
            dt = 2.0**-k
            for scheme in stiff.SCHEMES:
                out = os.path.join(work, f"drag_{d:.0e}_{k}_{scheme}")
                args = mpmice_terzaghi.fixed_dt_args(DRAG_CELLS, d, dt, DRAG_END, DRAG_END / 4,
                                                     out, drag_scheme=scheme)
                run = timed_run(args, out, mpmice_terzaghi.NAME, 1, work)
                below = math.nan
                verdict = "failed"
                if run["exit_code"] == 0:
                    dump = read_dump(list_dumps(out, mpmice_terzaghi.NAME)[-1])
                    below = stiff.analyse_terzaghi_dump(dump, params)["max_error_below_top"]
                    verdict = "ok" if below <= DRAG_ERROR_LIMIT else "inaccurate"
                rows.append({
                    "scheme": scheme, "grain_size": d, "dt": dt,
                    "beta_dt": drag_rate(d) * dt,
                    "solid_cfl": dt * SOLID_WAVE_SPEED * DRAG_CELLS, "verdict": verdict,
                    "max_error_below_top": below, "steps": run["steps"],
                    "time_reached": run["time_reached"], "run_s": run["run_s"],
                    "reason": run["reason"][:90]})
    return rows


MPM_CFLS = (0.25, 0.5, 0.75, 0.9, 1.0)
MPM_E_RATIOS = (1.0, 1e-2, 1e-4, 1e-5)
MPM_CELLS = 40
BAR_ERROR_LIMIT = 0.10


def map_mpm_cfl(work: str, quick: bool) -> list[dict]:
    cfls = (0.5, 1.0) if quick else MPM_CFLS
    ratios = (1.0, 1e-4) if quick else MPM_E_RATIOS
    rows = []
    for shape in ("linear", "gimp"):
        for ratio in ratios:
            for cfl in cfls:
                r = run_bar(work, MPM_CELLS, shape, e_ratio=ratio, cfl=cfl, stops=True)
                growth = r.get("energy_growth", math.nan)
                if stop_kind(r["run"]) == "energy growth":
                    verdict = "unstable"
                elif run_failed(r["run"], r.get("particles_lost", 0)) or \
                        not math.isfinite(r["history_error"]):
                    verdict = "failed"
                elif growth > ENERGY_LIMIT:    # not reached: the stop fires first
                    verdict = "unstable"
                elif r["history_error"] > BAR_ERROR_LIMIT:
                    verdict = "inaccurate"
                else:
                    verdict = "ok"
                rows.append({
                    "shape": shape, "e_ratio": ratio, "cfl": cfl,
                    "amplitude_cells": r["amplitude"] * MPM_CELLS, "verdict": verdict,
                    "energy_growth": growth, "energy_drift": r["energy_drift"],
                    "history_error": r["history_error"], "period_error": r["period_error"],
                    "particles_lost": r.get("particles_lost", 0),
                    "stop": stop_kind(r["run"]),
                    "steps": r["run"]["steps"], "run_s": r["run"]["run_s"],
                    "reason": r["run"]["reason"][:90]})
    return rows


COLUMN_E = (1.0e7, 1.0e6, 3.0e5, 1.0e5, 3.0e4)
NOISE_LIMIT = 0.05


def column_stress(out: str, run: dict, unit_weight: float, height: float) -> tuple:
    """The 1D column runs' measures (particles 'soil' in <out>/column1d_*.h5): particles lost,
    the stress error max |sigma_yy - exact| / (unit_weight H) (exact: -unit_weight (H - Y0), the
    weight above the particle, valid at any strain in 1D) and the stress oscillation max |s_i -
    (s_{i-1} + s_{i+1}) / 2| / (unit_weight H) (sigma_yy sorted by height), NaN for a failed
    run; with the first and the last dump's particles."""
    paths = list_dumps(out, "column1d")
    _, p0 = particles(paths[0], "soil")
    _, p1 = particles(paths[-1], "soil")
    res = {"particles_lost": lost_particles(run, p0, p1), "stress_error": math.nan,
           "oscillation": math.nan}
    if not run_failed(run, res["particles_lost"]):
        order = np.argsort(p0["y"])
        s = p1["stress_yy"][order]
        scale = unit_weight * height
        res["stress_error"] = float(np.max(np.abs(s + unit_weight * (height - p0["y"][order])))
                                    / scale)
        res["oscillation"] = float(np.max(np.abs(s[1:-1] - 0.5 * (s[:-2] + s[2:]))) / scale)
    return res, p0, p1


def run_column(work: str, cells: int, shape: str, youngs: float) -> dict:
    """The 1D column of postproc.mpm_column with Young's modulus `youngs`: ramp 10 periods of
    the first mode, end after 20 (the validation's 0.5 s / 1 s at E = 1e7 Pa)."""
    rho, g, nu, height = 2000.0, 9.81, 0.3, 1.0
    m = oedometer_modulus(youngs, nu)
    period = 4.0 * height / math.sqrt(m / rho)
    out = os.path.join(work, f"column_{shape}_{cells}_{youngs:g}")
    run = timed_run([os.path.join(ROOT, "namelists", "mpm_column_1d.nml"),
                     "--set", f"&grid ncells = 1, {int(round(1.25 * cells))}, 1 /",
                     "--set", f"&numerics shape_function = '{shape}' /",
                     "--set", f"&solid name = 'soil', youngs_modulus = {youngs!r} /",
                     "--set", f"&mpm gravity_ramp_time = {10 * period!r} /",
                     "--set", f"&time dt_max = {period!r} /",
                     "--set", f"&run output_dir = '{out}', end_time = {20 * period!r}, "
                              f"output_interval = 0.0, "
                              f"max_steps = {int(STEP_CAP * 20 * 4 * cells / 0.4) + 100} /",
                     "--set", MAP_STOPS],
                    out, "column1d", 1, work)
    res, p0, p1 = column_stress(out, run, rho * g, height)
    res.update({"run": run, "u_top_cells": rho * g * height**2 / (2.0 * m) * cells / height})
    if not run_failed(run, res["particles_lost"]):
        res["top_displacement_cells"] = float((np.max(p1["y"]) - np.max(p0["y"])) * cells
                                              / height)
    return res


def map_crossing(work: str, quick: bool) -> list[dict]:
    rows = []
    for shape in ("linear", "gimp"):
        for cells in ((25,) if quick else (25, 50)):
            for youngs in ((1.0e7, 1.0e5) if quick else COLUMN_E):
                r = run_column(work, cells, shape, youngs)
                osc = r["oscillation"]
                verdict = "failed" if run_failed(r["run"], r["particles_lost"]) or \
                    not math.isfinite(osc) \
                    else ("noisy" if osc > NOISE_LIMIT else "ok")
                rows.append({"shape": shape, "cells": cells, "youngs_modulus": youngs,
                             "u_top_cells": r["u_top_cells"], "verdict": verdict,
                             "oscillation": osc, "stress_error": r["stress_error"],
                             "particles_lost": r["particles_lost"],
                             "stop": stop_kind(r["run"]),
                             "steps": r["run"]["steps"], "run_s": r["run"]["run_s"],
                             "reason": r["run"]["reason"][:90]})
    return rows


#: Soil column of the soil_cfl_map: H = 1 m, 25 cells, grains 2650 kg/m^3 at porosity n,
#: geostatic start (K0 = nu / (1 - nu)), full gravity, local damping 0.1, 20 periods of the
#: first mode at the base's wave speed. Stiffness ladders: the sand's E [Pa], the clay's kappa.
SOIL_CELLS = 25
SOIL_RHO_S, SOIL_NU, SOIL_H = 2650.0, 0.3, 1.0
SOIL_CFLS = (0.25, 0.5, 0.75, 0.9, 1.0)
SOIL_STIFFNESS = {"critical_state_sand": (1.0e7, 1.0e6, 1.0e5),
                  "cam_clay": (0.002, 0.01, 0.05)}
SOIL_POROSITY = {"critical_state_sand": 0.45, "cam_clay": 0.5}
#: energy stop of the soil map: kinetic + strain energy > SOIL_ENERGY_FACTOR x (E(0) + W)
SOIL_ENERGY_FACTOR = 1.2
SOIL_ERROR_LIMIT = 0.05


def soil_base_modulus(model: str, stiffness: float) -> float:
    """Constrained modulus [Pa] at the column's base at t = 0: the sand's from E and nu; the
    clay's K + 4G/3 with K = v p' / kappa, p' = (1 + 2 K0) / 3 sigma'_v (docs/soil_models.md)."""
    if model == "critical_state_sand":
        return oedometer_modulus(stiffness, SOIL_NU)
    n = SOIL_POROSITY[model]
    k0 = SOIL_NU / (1.0 - SOIL_NU)
    p = (1.0 + 2.0 * k0) / 3.0 * (1.0 - n) * SOIL_RHO_S * 9.81 * SOIL_H
    bulk = p / (1.0 - n) / stiffness
    return bulk * (1.0 + 4.0 / 3.0 * 1.5 * (1.0 - 2.0 * SOIL_NU) / (1.0 + SOIL_NU))


def soil_solid(model: str, stiffness: float) -> str:
    """The &solid group of the map's column."""
    common = (f"name = 'soil', model = '{model}', density = {SOIL_RHO_S!r}, "
              f"porosity = {SOIL_POROSITY[model]!r}, poisson_ratio = {SOIL_NU!r}, "
              f"geostatic = .true.")
    if model == "critical_state_sand":   # loose (phi 0.55 < phi_m): yields at K0 and contracts
        return (f"&solid {common}, youngs_modulus = {stiffness!r}, friction_mu1 = 0.577, "
                f"critical_solid_fraction = 0.585, dilatancy_constant = 4.09 /")
    return (f"&solid {common}, critical_state_ratio = 1.0, compression_index = 0.2, "
            f"swelling_index = {stiffness!r}, ocr = 1.0 /")


def run_soil_column(work: str, model: str, stiffness: float, cfl: float) -> dict:
    """The geostatic soil column at `cfl`; returns the run, the stress error max |sigma_yy -
    exact| / sigma'_v,base (exact: -(1 - n) rho_s g (H - Y0), the weight above the particle at
    any strain in 1D), the stress oscillation (as map_crossing) and the energy peak."""
    n = SOIL_POROSITY[model]
    rho = (1.0 - n) * SOIL_RHO_S
    c = math.sqrt(soil_base_modulus(model, stiffness) / rho)
    period = 4.0 * SOIL_H / c
    dx = SOIL_H / SOIL_CELLS
    planned = 20.0 * period / (cfl * dx / c)
    out = os.path.join(work, f"soil_{model}_{stiffness:g}_{cfl:g}")
    run = timed_run([os.path.join(ROOT, "namelists", "mpm_column_1d.nml"),
                     "--set", f"&grid ncells = 1, {int(round(1.25 * SOIL_CELLS))}, 1 /",
                     "--set", soil_solid(model, stiffness),
                     "--set", "&mpm gravity_ramp_time = 0.0 /",
                     "--set", f"&time cfl = {cfl!r}, dt_max = {period!r} /",
                     "--set", f"&run output_dir = '{out}', end_time = {20 * period!r}, "
                              f"output_interval = 0.0, "
                              f"max_steps = {int(STEP_CAP * planned) + 100} /",
                     "--set", MAP_STOPS,
                     "--set", f"&run max_energy_growth = {SOIL_ENERGY_FACTOR!r} /"],
                    out, "column1d", 1, work)
    res, p0, p1 = column_stress(out, run, rho * 9.81, SOIL_H)
    res.update({"run": run, "base_modulus": soil_base_modulus(model, stiffness),
                "period": period})
    if not run_failed(run, res["particles_lost"]):
        res["settlement_cells"] = float((np.max(p0["y"]) - np.max(p1["y"])) / dx)
    return res


def map_soil_cfl(work: str, quick: bool) -> list[dict]:
    cfls = (0.5, 1.0) if quick else SOIL_CFLS
    rows = []
    for model, ladder in SOIL_STIFFNESS.items():
        for stiffness in (ladder[::2] if quick else ladder):
            for cfl in cfls:
                r = run_soil_column(work, model, stiffness, cfl)
                if stop_kind(r["run"]) == "energy growth":
                    verdict = "unstable"
                elif run_failed(r["run"], r["particles_lost"]) or \
                        not math.isfinite(r["stress_error"]):
                    verdict = "failed"
                elif r["oscillation"] > NOISE_LIMIT:
                    verdict = "noisy"
                elif r["stress_error"] > SOIL_ERROR_LIMIT:
                    verdict = "inaccurate"
                else:
                    verdict = "ok"
                rows.append({"model": model, "stiffness": stiffness,
                             "base_modulus": r["base_modulus"], "cfl": cfl, "verdict": verdict,
                             "stress_error": r["stress_error"], "oscillation": r["oscillation"],
                             "settlement_cells": r.get("settlement_cells", math.nan),
                             "particles_lost": r["particles_lost"], "stop": stop_kind(r["run"]),
                             "steps": r["run"]["steps"], "run_s": r["run"]["run_s"],
                             "reason": r["run"]["reason"][:90]})
    return rows


STABILITY = {"drag_map": map_drag, "mpm_cfl_map": map_mpm_cfl, "crossing_map": map_crossing,
             "soil_cfl_map": map_soil_cfl}

# --------------------------------------------------------------------------- plots

VERDICT_STYLE = {"ok": ("o", "tab:green"), "inaccurate": ("s", "tab:orange"),
                 "unstable": ("^", "tab:purple"), "noisy": ("D", "tab:orange"),
                 "failed": ("x", "tab:red")}


def _legend_verdicts(ax, rows: list[dict]) -> None:
    """Legend of the verdicts of `rows`, in VERDICT_STYLE's order."""
    for v in sorted({r["verdict"] for r in rows}, key=list(VERDICT_STYLE).index):
        m, c = VERDICT_STYLE[v]
        ax.plot([], [], m, color=c, label=v, mfc="none" if m not in "x" else c)
    ax.legend(fontsize=8, loc="best")


def _verdict_points(ax, rows: list[dict], x: str, y: str, plot, note, xytext) -> None:
    """r[x] against r[y] of every row with `plot` (ax.loglog, ax.semilogy, ...), a marker in the
    style of the row's verdict, labelled with note(r) where that is not None."""
    for r in rows:
        m, c = VERDICT_STYLE[r["verdict"]]
        plot(r[x], r[y], m, color=c, ms=9, mfc="none" if m != "x" else c)
        text = note(r)
        if text is not None:
            ax.annotate(text, (r[x], r[y]), textcoords="offset points", xytext=xytext,
                        fontsize=6)


def _cfl_axis(ax, rows: list[dict], title: str) -> None:
    """The x axis, title and verdict legend of a map over &time cfl."""
    ax.set_xlabel("&time cfl (dt = cfl dx / (c + |v|); validation caps it at 1)")
    ax.set_title(title, fontsize=9)
    ax.set_xlim(0.15, 1.15)
    _legend_verdicts(ax, rows)


def plot_drag(rows: list[dict], path: str) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    for ax, scheme in zip(axes, stiff.SCHEMES):
        _verdict_points(ax, [r for r in rows if r["scheme"] == scheme], "beta_dt", "solid_cfl",
                        ax.loglog, lambda r: f"{r['max_error_below_top']:.1e}"
                        if math.isfinite(r["max_error_below_top"]) else None, (5, -10))
        ax.axvline(2.0, color="grey", ls=":", lw=1)
        ax.axhline(1.0, color="grey", ls=":", lw=1)
        ax.set_xlabel("drag relaxation beta dt = K_d dt / (n rho_f)")
        ax.set_title(f"drag_scheme = '{scheme}'")
        _legend_verdicts(ax, rows)
    axes[0].set_ylabel("solid CFL number dt c_p / dx")
    fig.suptitle("Consolidation column, 50 cells, densities / 100, fixed dt 2^-22 .. 2^-14 s "
                 "x grain size 1 mm .. 10 um (to t = 2^-7 s)\nfailed: exit status 3 (non-finite, or dt < "
                 "dt_min = 0.75 dt); inaccurate: max |p - p_exact| / p0 below the top 5 cells > "
                 f"{DRAG_ERROR_LIMIT:.0%} (labels)", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)


def plot_mpm_cfl(rows: list[dict], path: str) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    for ax, shape in zip(axes, ("linear", "gimp")):
        _verdict_points(ax, [r for r in rows if r["shape"] == shape], "cfl", "amplitude_cells",
                        ax.semilogy,
                        lambda r: f"{r['energy_growth']:+.1e}\n{r['history_error']:.1e}"
                        if math.isfinite(r["energy_growth"]) else None, (5, -12))
        _cfl_axis(ax, rows, f"shape_function = '{shape}'")
    axes[0].set_ylabel("tip amplitude [cells] (E / E_ref = 1 .. 1e-5 at v0 = 0.01 m/s)")
    fig.suptitle(f"Elastic bar, {MPM_CELLS} cells, 10 periods. unstable: stopped by &run "
                 f"max_energy_growth = {1 + ENERGY_LIMIT:g} (energy > {1 + ENERGY_LIMIT:g} E(0)); "
                 f"failed: other exit status 3; inaccurate: tip-history error > "
                 f"{BAR_ERROR_LIMIT:.0%}\n(labels: energy growth reached, tip-history error)",
                 fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)


def plot_crossing(rows: list[dict], path: str) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for k, shape in enumerate(("linear", "gimp")):
        for j, cells in enumerate(sorted({r["cells"] for r in rows})):
            pts = [r for r in rows if r["shape"] == shape and r["cells"] == cells
                   and math.isfinite(r["oscillation"])]
            ls = "-" if shape == "linear" else "--"
            label = f"{shape}, {cells} cells"
            axes[0].loglog([r["u_top_cells"] for r in pts], [r["oscillation"] for r in pts],
                           "o" if shape == "linear" else "s", ls=ls, color=f"C{2 * j + k}",
                           label=label, mfc="none")
            axes[1].loglog([r["u_top_cells"] for r in pts], [r["stress_error"] for r in pts],
                           "o" if shape == "linear" else "s", ls=ls, color=f"C{2 * j + k}",
                           label=label, mfc="none")
    for r in rows:
        if r["verdict"] == "failed":
            axes[0].plot(r["u_top_cells"], NOISE_LIMIT, "rx", ms=9)
    axes[0].axhline(NOISE_LIMIT, color="grey", ls=":", lw=1)
    axes[0].set_ylabel("stress oscillation max |s_i - (s_i-1 + s_i+1)/2| / (rho g H)")
    axes[1].set_ylabel("max |sigma_yy - exact| / (rho g H)")
    for ax in axes:
        ax.set_xlabel("exact top displacement [cells] (E = 1e7 .. 3e4 Pa)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Elastic column under self-weight (1D MPM), gravity ramped over 10 periods, "
                 f"end 20 periods; noisy: oscillation > {NOISE_LIMIT:.0%} (dotted line); "
                 "red x: failed (exit status 3: particle lost or step collapsed)", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)


def plot_soil_cfl(rows: list[dict], path: str) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    labels = {"critical_state_sand": "critical-state sand (E = 1e7 .. 1e5 Pa)",
              "cam_clay": "Modified Cam-Clay (kappa = 0.002 .. 0.05)"}
    for ax, model in zip(axes, SOIL_STIFFNESS):
        _verdict_points(ax, [r for r in rows if r["model"] == model], "cfl", "base_modulus",
                        ax.semilogy, lambda r: f"{r['stress_error']:.1e}"
                        if math.isfinite(r["stress_error"]) else None, (5, -10))
        _cfl_axis(ax, rows, f"model = '{model}': {labels[model]}")
    axes[0].set_ylabel("constrained modulus at the base, t = 0 [Pa]")
    fig.suptitle(f"Soil column under self-weight (1D MPM, GIMP, {SOIL_CELLS} cells, geostatic "
                 f"start, 20 periods). unstable: stopped by &run max_energy_growth = "
                 f"{SOIL_ENERGY_FACTOR:g}; failed: other exit status 3\nnoisy: stress oscillation "
                 f"> {NOISE_LIMIT:.0%}; inaccurate: max |sigma_yy - exact| > "
                 f"{SOIL_ERROR_LIMIT:.0%} of sigma'_v,base (labels)", fontsize=9)
    fig.tight_layout()
    save_figure(fig, path)


STABILITY_PLOTS = {"drag_map": plot_drag, "mpm_cfl_map": plot_mpm_cfl,
                   "crossing_map": plot_crossing, "soil_cfl_map": plot_soil_cfl}
