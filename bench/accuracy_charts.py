"""Speed against accuracy and stability maps.

Usage:  python bench/accuracy_charts.py [--quick] [--out docs] [--only NAME ...] [--list]

One command regenerates every chart. Each accuracy chart runs a resolution ladder of an existing
validation scene for several method choices, measures the run time and the error against the
scene's exact or benchmark solution, and writes docs/accuracy_<scene>.csv + .png: error against
run time, one curve per method choice, the Pareto front (no other run is both faster and more
accurate) marked. Each stability study writes docs/stability_<study>.csv + .png: a map of where a
method fails, with the failure criterion in the title.

Run time: the program's own "total run" timer (the largest over the ranks; everything from the
scene's set-up to the end, launch of mpirun excluded, ~0.3 s); the CSV also holds the wall time
of the whole mpirun call. The machine is shared: treat times as +-20 %.

Accuracy charts (--only names):
  sod                 ICE Sod tube (postproc.ice_sod), rel. L1 density error at t = 0.2;
                      advection order 1 vs 2 (&numerics advection_order), 1 vs 2 ranks.
  terzaghi            consolidation (postproc.mpmice_terzaghi), the paper's densities: largest
                      rel. L2 pore-pressure error over the dumps with T_v >= 0.1 (t <= 0.25 s);
                      1D, 1D on 2 ranks, 2D (4 x N, free-slip/roller side walls), 3D (4 x N x 4).
  terzaghi_qs         the same with --quasi-static densities (/ 100); 10x the steps (the solid's
                      CFL step), so shorter ladders and no 3D.
  darcy               steady Darcy column (postproc.mpmice_darcy, phi_s = 0.7, dp = 0.5 atm):
                      |U_f / U_f,exact - 1| of the mean pore velocity in the column; 1D, 1D on 2
                      ranks, 2D (N x 4, side walls).
  bar                 elastic bar, first mode (postproc.mpm_bar): largest |u_tip - exact| over
                      10 periods / amplitude; linear vs GIMP, GIMP on 2 ranks.
  cavity              porous thermal cavity (postproc.mpmice_thermal_cavity), Ra = 100, to 0.3
                      thermal times (steady from 0.2): |Nu_hot / 3.1 - 1| (benchmark 3.10-3.16);
                      advection order 1 vs 2.
  grilli              Grilli et al. (2017) test 17 (postproc.mpmice_grilli2017): RMS of model -
                      record at WG1 over its first wave / the record's RMS; 40, 20 mm cells (and
                      10 mm for the Forchheimer curve) x drag law (Forchheimer, Kozeny-Carman) x
                      air layer (0.07, 0.11, 0.19 m); runs in $MPMICE_GRILLI_RUNS are reused.
  rondon              Rondon et al. (2011) underwater column collapse, dense + loose pair
                      (postproc.mpmice_rondon, critical-state sand), 10 / 5 / 2.5 / 1.25 mm
                      cells, to 1.15 s: mean relative error of the run-out at the experiment's
                      first front points (0.55 s dense, 0.64 s loose) and of the base excess pore
                      pressure at its first points (1.13 s); run time of the pair; GIMP vs
                      linear at cfl 0.4, GIMP at cfl 0.2.
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

import argparse
import csv
import math
import os
import re
import sys
import tempfile
import time as _time

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from postproc import ice_sod, mpm_bar, mpmice_darcy, mpmice_terzaghi  # noqa: E402
from postproc import mpmice_rondon as rondon                           # noqa: E402
from postproc import mpmice_stiff_drag as stiff                        # noqa: E402
from postproc import mpmice_thermal_cavity as cavity                   # noqa: E402
from postproc.figures import pyplot, save_figure, write_table  # noqa: E402
from postproc.mpm_common import constrained_modulus, particles, series  # noqa: E402
from postproc.mpmice_io import list_dumps, read_dump                   # noqa: E402
from postproc.run_case import ROOT, run_mpmice                         # noqa: E402

#: Free-slip / roller side walls (tests/validation/test_mpmice_parallel.py SIDE_WALLS).
def side_walls(faces) -> str:
    """&boundary groups: free-slip fluid and roller solid on each face of `faces`."""
    return "".join(f"\n&boundary\n  face = '{f}'\n  fluid = 'free_slip'\n  solid = 'roller'\n/\n"
                   for f in faces)


# --------------------------------------------------------------------------- Pareto front

def pareto_front(times, errors, rtol: float = 0.0) -> np.ndarray:
    """Boolean mask of the non-dominated points (both coordinates minimised): point i is on the
    front unless some j has time_j <= time_i and error_j <= error_i with at least one strictly
    smaller. Errors that agree to the relative tolerance `rtol` count as equal (the same
    discretisation on 1 and 2 ranks differs by the solver tolerance only: the slower run is then
    dominated). Points with a non-finite time or error are never on the front; of exact
    duplicates all are kept."""
    t = np.asarray(times, dtype=float)
    e = np.asarray(errors, dtype=float)
    ok = np.isfinite(t) & np.isfinite(e)
    front = ok.copy()
    for i in np.nonzero(ok)[0]:
        no_worse = e <= e[i] * (1.0 + rtol)
        better = e < e[i] * (1.0 - rtol)
        dominated = ok & (t <= t[i]) & no_worse & ((t < t[i]) | better)
        if np.any(dominated):
            front[i] = False
    return front


# --------------------------------------------------------------------------- running

_TOTAL_RUN = re.compile(r"^\s*total run\s+([0-9.eE+-]+)\s*$", re.M)


def timed_run(args, out: str, name: str, nranks: int = 1, cwd: str | None = None,
              timeout: float = 1800) -> dict:
    """Run mpmice (exit status 0 or 3 accepted); return exit_code, state, reason, steps,
    time_reached (from <out>/<name>.status), run_s (the program's 'total run' timer) and wall_s
    (the mpirun call)."""
    start = _time.perf_counter()
    result = run_mpmice(args, nranks=nranks, cwd=cwd, check=False, timeout=timeout)
    wall = _time.perf_counter() - start
    if result.returncode not in (0, 3):
        raise RuntimeError(f"mpmice exited with {result.returncode}:\n{result.stdout[-3000:]}\n"
                           f"{result.stderr[-3000:]}")
    status = stiff.read_status(out, name)
    m = _TOTAL_RUN.findall(result.stdout)
    return {
        "exit_code": result.returncode, "state": status.get("state", "?"),
        "reason": status.get("reason", ""), "steps": int(status.get("step", -1)),
        "time_reached": float(status.get("time", "nan")),
        "run_s": float(m[-1]) if m else math.nan, "wall_s": wall,
    }


def row_of(scene: str, method: str, cells: int, nranks: int, run: dict, error: float,
           **extra) -> dict:
    row = {"scene": scene, "method": method, "cells": cells, "nranks": nranks,
           "run_s": run["run_s"], "wall_s": run["wall_s"], "steps": run["steps"],
           "error": error if run["exit_code"] == 0 else math.nan, "state": run["state"]}
    row.update(extra)
    return row


# --------------------------------------------------------------------------- accuracy scenes

def chart_sod(work: str, quick: bool) -> list[dict]:
    ladder = (100, 200, 400) if quick else (100, 200, 400, 800, 1600, 3200)
    rows = []
    for order, nranks in ((1, 1), (2, 1), (2, 2)):
        if quick and nranks == 2:
            continue
        for n in ladder:
            out = os.path.join(work, f"sod_o{order}_r{nranks}_{n}")
            run = timed_run([ice_sod.NAMELIST, "--set", f"&grid ncells = {n}, 1, 1 /",
                             "--set", f"&run output_dir = '{out}' /",
                             "--set", f"&numerics advection_order = {order} /"],
                            out, "sod", nranks, work)
            err = ice_sod.density_error(read_dump(list_dumps(out, "sod")[-1])) \
                if run["exit_code"] == 0 else math.nan
            rows.append(row_of("sod", f"order {order}, {nranks} rank{'s' * (nranks > 1)}", n,
                               nranks, run, err))
    return rows


def _terzaghi_namelist(work: str, dim: int) -> str:
    if dim == 1:
        return mpmice_terzaghi.NAMELIST
    path = os.path.join(work, f"terzaghi_{dim}d.nml")
    with open(mpmice_terzaghi.NAMELIST, encoding="utf-8") as src, \
            open(path, "w", encoding="utf-8") as dst:
        dst.write(src.read() + side_walls(("x-", "x+") if dim == 2 else
                                          ("x-", "x+", "z-", "z+")))
    return path


def _terzaghi_grid_sets(dim: int, n: int) -> list[str]:
    if dim == 1:
        return ["--set", f"&grid ncells = 1, {n}, 1 /"]
    if dim == 2:
        return ["--set", f"&grid ncells = 4, {n}, 1, upper = 0.1, 1.0, 0.01 /",
                "--set", "&solid name='soil', upper = 0.1, 1.0, 0.01, "
                         "particles_per_cell = 2, 1, 1 /"]
    return ["--set", f"&grid ncells = 4, {n}, 4, upper = 0.1, 1.0, 0.1 /",
            "--set", "&solid name='soil', upper = 0.1, 1.0, 0.1, particles_per_cell = 2, 1, 2 /"]


def chart_terzaghi(work: str, quick: bool, quasi_static: bool = False) -> list[dict]:
    extra = mpmice_terzaghi.QUASI_STATIC_SET if quasi_static else ()
    scene = "terzaghi_qs" if quasi_static else "terzaghi"
    ladders = {  # (dim, nranks): cells
        (1, 1): (25, 50, 100) if quick else (25, 50, 100, 200, 400),
        (1, 2): () if quick else (25, 50, 100, 200, 400),
        (2, 1): (25,) if quick else (25, 50, 100),
        (3, 1): () if quick else (25, 50),
    }
    if quasi_static:   # the solid's CFL step is 10x smaller (densities / 100): 10x the steps
        ladders = {(1, 1): (25, 50) if quick else (25, 50, 100, 200, 400),
                   (1, 2): () if quick else (25, 50, 100),
                   (2, 1): () if quick else (25, 50)}
    rows = []
    for (dim, nranks), ladder in ladders.items():
        nml = _terzaghi_namelist(work, dim)
        for n in ladder:
            out = os.path.join(work, f"{scene}_{dim}d_r{nranks}_{n}")
            args = [nml, "--set", f"&run output_dir = '{out}' /"] + _terzaghi_grid_sets(dim, n)
            for text in extra:
                args += ["--set", text]
            run = timed_run(args, out, mpmice_terzaghi.NAME, nranks, work)
            err = math.nan
            if run["exit_code"] == 0:
                dumps = [read_dump(p) for p in list_dumps(out, mpmice_terzaghi.NAME)]
                err = mpmice_terzaghi.analyse_dumps(dumps)["max_error"]
            label = f"{dim}D, {nranks} rank{'s' * (nranks > 1)}"
            rows.append(row_of(scene, label, n, nranks, run, err, cells_total=n * 4**(dim - 1)))
    return rows


def chart_darcy(work: str, quick: bool) -> list[dict]:
    phi, dp = 0.7, 0.5
    exact = mpmice_darcy.exact_pore_velocity(phi, dp)
    ladders = {(1, 1): (20, 40, 80) if quick else (20, 40, 80, 160, 320),
               (1, 2): () if quick else (20, 40, 80, 160, 320),
               (2, 1): () if quick else (20, 40, 80)}
    nml2 = os.path.join(work, "darcy_2d.nml")
    with open(mpmice_darcy.NAMELIST, encoding="utf-8") as src, \
            open(nml2, "w", encoding="utf-8") as dst:
        dst.write(src.read() + side_walls(("y-", "y+")))
    rows = []
    for (dim, nranks), ladder in ladders.items():
        for n in ladder:
            out = os.path.join(work, f"darcy_{dim}d_r{nranks}_{n}")
            grid = f"&grid ncells = {n}, 1, 1 /" if dim == 1 else \
                f"&grid ncells = {n}, 4, 1, upper = 2.0, 0.4, 0.1 /"
            args = [mpmice_darcy.NAMELIST if dim == 1 else nml2, "--set", grid,
                    "--set", f"&solid name='porous', porosity = {1.0 - phi:.12g}"
                             + (", upper = 1.5, 0.4, 0.1" if dim == 2 else "") + " /",
                    "--set", f"&boundary face='x-', pressure = "
                             f"{mpmice_darcy.P_REF + dp * mpmice_darcy.ATM:.12g} /",
                    "--set", f"&run output_dir = '{out}' /"]
            run = timed_run(args, out, mpmice_darcy.NAME, nranks, work)
            err = math.nan
            if run["exit_code"] == 0:
                dump = read_dump(list_dumps(out, mpmice_darcy.NAME)[-1])
                inside = mpmice_darcy.column_cells(dump)
                u = float(np.mean(dump["cell"]["water/velocity_x"][inside, :, 0]))
                err = abs(u / exact - 1.0)
            rows.append(row_of("darcy", f"{dim}D, {nranks} rank{'s' * (nranks > 1)}", n, nranks,
                               run, err))
    return rows


#: Step cap of the MPM maps: STEP_CAP x the planned steps (&run max_steps), a backstop only:
#: the run loop's stops (MAP_STOPS) end a blown-up run long before.
STEP_CAP = 10.0

#: The run loop's stops the MPM maps use (driver_stops): a particle lost, the CFL step below a
#: quarter of the first step's (|v| > 3 c: velocities blown up).
MAP_STOPS = "&run max_particle_loss_fraction = 0.0, min_dt_ratio = 0.25 /"


def stop_kind(run: dict) -> str:
    """Which stop ended a failed run: 'energy growth', 'particle loss', 'time step collapsed',
    'non-finite values', 'time step' (below dt_min); '' for a run that was not stopped."""
    if run["exit_code"] == 0:
        return ""
    for kind in ("energy growth", "particle loss", "time step collapsed", "non-finite values",
                 "time step"):
        if run["reason"].startswith(kind):
            return kind
    return "?"


def lost_particles(run: dict, p0: dict, p1: dict) -> int:
    """Particles lost: from the particle-loss stop's reason ('particle loss: N of M ...'), else
    the difference of the first and last dump."""
    if stop_kind(run) == "particle loss":
        return int(run["reason"].split(":")[1].split()[0])
    return len(p0["id"]) - len(p1["id"])


def run_failed(run: dict, particles_lost: int = 0) -> bool:
    """Exit status 3 (any stop of the run loop), stopped before the end (step cap), or
    particles lost."""
    return run["exit_code"] != 0 or run["state"] != "finished" or particles_lost > 0


def run_bar(work: str, cells: int, shape: str, nranks: int = 1, e_ratio: float = 1.0,
            cfl: float | None = None, v0: float = mpm_bar.V0, stops: bool = False) -> dict:
    """The elastic bar (postproc.mpm_bar) with E scaled by e_ratio (end time 10 periods);
    returns the run and the error measures of mpm_bar.run_bar (NaN when it failed). `stops`:
    the map's run-loop stops (MAP_STOPS and &run max_energy_growth = 1 + ENERGY_LIMIT)."""
    c = mpm_bar.C * math.sqrt(e_ratio)
    period = 4.0 * mpm_bar.L / c
    omega = math.pi * c / (2.0 * mpm_bar.L)
    out = os.path.join(work, f"bar_{shape}_{cells}_r{nranks}_e{e_ratio:g}_c{cfl}")
    args = [mpm_bar.NAMELIST, "--set", f"&grid ncells = {int(round(1.25 * cells))}, 1, 1 /",
            "--set", f"&numerics shape_function = '{shape}' /",
            "--set", f"&solid name = 'bar', velocity = {v0!r}, 0.0, 0.0, "
                     f"youngs_modulus = {mpm_bar.E * e_ratio!r} /",
            "--set", f"&run output_dir = '{out}', end_time = {10 * period!r}, "
                     f"output_interval = 0.0 /",
            "--set", f"&time dt_max = {period!r} /"]
    cfl_used = 0.2 if cfl is None else cfl          # the namelist's cfl = 0.2
    planned = 10.0 * period / (cfl_used * mpm_bar.L / cells / c)
    args += ["--set", f"&time cfl = {cfl_used!r} /",
             "--set", f"&run max_steps = {int(STEP_CAP * planned) + 100} /"]
    if stops:
        args += ["--set", MAP_STOPS,
                 "--set", f"&run max_energy_growth = {1.0 + ENERGY_LIMIT!r} /"]
    run = timed_run(args, out, "bar1d", nranks, work)
    res = {"run": run, "history_error": math.nan, "period_error": math.nan,
           "energy_drift": math.nan, "amplitude": math.nan}
    if not os.path.isfile(os.path.join(out, "bar1d_mpm_series.csv")):
        return res
    paths = list_dumps(out, "bar1d")
    _, p0 = particles(paths[0], "bar")
    _, p1 = particles(paths[-1], "bar")
    res["particles_lost"] = lost_particles(run, p0, p1)
    x_tip = float(np.max(p0["x"]))
    s = series(out, "bar1d")
    t = np.concatenate([[0.0], s["time"]])
    u = np.concatenate([[0.0], s["xmax"] - x_tip])
    energy = s["kinetic_energy"] + s["strain_energy"]
    amplitude = v0 / omega * math.sin(math.pi * x_tip / (2.0 * mpm_bar.L))
    with np.errstate(all="ignore"):
        finite = np.all(np.isfinite(u)) and np.all(np.isfinite(energy))
        res["amplitude"] = amplitude
        if finite and len(energy) > 1:
            res["energy_growth"] = float((np.max(energy) - energy[0]) / energy[0])
        if finite and len(energy) > 1 and run["exit_code"] == 0:
            res["energy_drift"] = float((energy[-1] - energy[0]) / energy[0])
            res["history_error"] = float(np.max(np.abs(u - amplitude * np.sin(omega * t)))
                                         / amplitude)
            crossings = mpm_bar.upward_crossings(t[1:], u[1:])
            if len(crossings) > 1:
                res["period_error"] = abs(float(np.mean(np.diff(crossings))) - period) / period
    return res


def chart_bar(work: str, quick: bool) -> list[dict]:
    ladder = (10, 20, 40) if quick else (10, 20, 40, 80, 160)
    rows = []
    for shape, nranks in (("linear", 1), ("gimp", 1), ("gimp", 2)):
        if quick and nranks == 2:
            continue
        for n in ladder:
            r = run_bar(work, n, shape, nranks)
            rows.append(row_of("bar", f"{shape}, {nranks} rank{'s' * (nranks > 1)}", n, nranks,
                               r["run"], r["history_error"], period_error=r["period_error"],
                               energy_drift=r["energy_drift"]))
    return rows


CAVITY_RA = 100.0
CAVITY_NU = cavity.BENCHMARK[CAVITY_RA]
CAVITY_END = 0.3          # thermal times


def chart_cavity(work: str, quick: bool) -> list[dict]:
    grain = cavity.grain_for(CAVITY_RA)
    end = CAVITY_END * cavity.THERMAL_TIME
    rows = []
    for order in (1, 2):
        for n in ((10, 20) if quick else (10, 20, 40)):
            if quick and order == 1:
                continue
            out = os.path.join(work, f"cavity_o{order}_{n}")
            args = [cavity.NAMELIST,
                    "--set", f"&grid ncells = {n}, {n}, 1, upper = 1.0, 1.0, {1.0 / n} /",
                    "--set", f"&run output_dir = '{out}', end_time = {end}, "
                             f"output_interval = {end / 3} /",
                    "--set", f"&solid name = '{cavity.SOLID}', grain_size = {grain}, "
                             f"upper = 1.0, 1.0, {1.0 / n}, particles_per_cell = 2, 2, 1 /",
                    "--set", f"&numerics advection_order = {order} /"]
            run = timed_run(args, out, cavity.NAME, 1, work, timeout=3600)
            err, change, nu = math.nan, math.nan, math.nan
            if run["exit_code"] == 0:
                dumps = [read_dump(p) for p in list_dumps(out, cavity.NAME)]
                nu = cavity.wall_nusselt(dumps[-1])[0]
                prev = cavity.wall_nusselt(dumps[-2])[0]
                change = abs(nu - prev) / abs(nu)
                err = abs(nu / CAVITY_NU - 1.0)
            rows.append(row_of("cavity", f"advection order {order}", n, 1, run, err, nu=nu,
                               last_change=change))
    return rows


#: Grilli et al. (2017) test 17: model end [s] = record 2.05 s (the end of WG1's first wave) - 0.3
GRILLI_END = 1.75
#: curve label -> case of postproc.mpmice_grilli2017_cases (drag law, air layer's height)
GRILLI_CURVES = {"Forchheimer (Ergun) drag, air 0.11 m": "base",
                 "Kozeny-Carman drag, air 0.11 m": "kozeny",
                 "Forchheimer, air 0.07 m": "air007",
                 "Forchheimer, air 0.19 m": "air019"}


def _grilli_log_run_time(out: str) -> float:
    """The program's 'total run' timer from <out>/grilli.log (nan when absent)."""
    path = os.path.join(out, "grilli.log")
    if not os.path.isfile(path):
        return math.nan
    with open(path, encoding="utf-8") as f:
        m = _TOTAL_RUN.findall(f.read())
    return float(m[-1]) if m else math.nan


def chart_grilli(work: str, quick: bool) -> list[dict]:
    """Grilli test 17 (postproc.mpmice_grilli2017): RMS of model - record at WG1 over its first
    wave / the record's RMS there; 40, 20 (and, base curve only, 10) mm cells x drag law x air
    layer. Runs go to $MPMICE_GRILLI_RUNS when set (a finished run there is reused: its run
    time is read from its log, its wall time left NaN), else to the temporary folder."""
    from postproc import mpmice_grilli2017 as grilli                  # noqa: PLC0415
    from postproc import mpmice_grilli2017_cases as grilli_cases      # noqa: PLC0415
    root = os.environ.get("MPMICE_GRILLI_RUNS", work)
    ref = grilli.reference_gauges(grilli.DEFAULT_REFERENCE)
    rows = []
    for label, case in GRILLI_CURVES.items():
        ladder = (40,) if quick else ((40, 20, 10) if case == "base" else (40, 20))
        for mm in ladder:
            out, code, wall = grilli_cases.run_case(case, mm, GRILLI_END, root)
            status = stiff.read_status(out, grilli.NAME)
            finished = status.get("state") == "finished"
            run = {"exit_code": 0 if finished else (code if code is not None else 3),
                   "state": status.get("state", "?"), "steps": int(status.get("step", -1)),
                   "run_s": _grilli_log_run_time(out), "wall_s": wall}
            err, trough, arrival = math.nan, math.nan, math.nan
            if finished:
                t_model, model = grilli.gauge_series(list_dumps_read(out, grilli.NAME))
                meas = {(r["gauge"], r["measure"]): r
                        for r in grilli.gauge_measures(ref, t_model, model, 0.3)}
                err = meas[("WG1", "rms over first wave")]["amplitude_error"]
                trough = meas[("WG1", "trough")]["amplitude_error"]
                arrival = meas[("WG1", "trough")]["arrival_error_s"]
            rows.append(row_of("grilli", label, round(5600 / mm), 1, run, err,
                               cell_mm=mm, wg1_trough_amp_error=trough,
                               wg1_trough_arrival_error_s=arrival))
    return rows


def list_dumps_read(out: str, name: str) -> list[dict]:
    """Every dump of a run, read."""
    return [read_dump(p) for p in list_dumps(out, name)]


#: The Rondon et al. (2011) pair (docs/validation/rondon2011.md): method -> (shape function,
#: &time cfl, cells along x of the full ladder, of --quick, &mpm velocity_transfer). 30 / 60 /
#: 120 / 240 cells: 10 / 5 / 2.5 / 1.25 mm.
RONDON_METHODS = {
    "GIMP, cfl 0.4": ("gimp", 0.4, (30, 60, 120, 240), (30,), "flip"),
    "linear, cfl 0.4": ("linear", 0.4, (30, 60, 120), (30,), "flip"),
    "GIMP, cfl 0.2": ("gimp", 0.2, (30, 60), (), "flip"),
    "GIMP, cfl 0.4, APIC": ("gimp", 0.4, (30, 60, 120), (), "apic"),
}


def run_rondon_pair(work: str, cells: int, shape: str, cfl: float,
                    t_end: float = rondon.CHART_END,
                    transfer: str = "flip") -> tuple[dict, dict]:
    """The dense and the loose Rondon scene at `cells` x cells/3 (dumps every 0.05 s, to
    `t_end`) with the velocity transfer `transfer`; returns the pair as one run (run_s, wall_s,
    steps summed; failed if either failed) and rondon.chart_error of the pair (empty when a run
    failed)."""
    runs, dirs = [], {}
    for case in rondon.CASES:
        out = os.path.join(work, f"rondon_{case}_{shape}_{cfl:g}_{transfer}_{cells}")
        runs.append(timed_run([os.path.join(ROOT, "namelists", f"mpmice_rondon_{case}_2d.nml"),
                               "--set", f"&grid ncells = {cells}, {cells // 3}, 1 /",
                               "--set", f"&numerics shape_function = '{shape}' /",
                               "--set", f"&time cfl = {cfl!r} /",
                               "--set", f"&mpm velocity_transfer = '{transfer}' /",
                               "--set", f"&run output_dir = '{out}', end_time = {t_end!r}, "
                                        f"output_interval = 0.05 /"],
                              out, rondon.NAME, 1, work, timeout=4 * 3600))
        dirs[case] = out
    failed = next((r for r in runs if r["exit_code"] != 0), None)
    pair = dict(failed or runs[0])
    for key in ("run_s", "wall_s", "steps"):
        pair[key] = sum(r[key] for r in runs)
    return pair, ({} if failed else rondon.chart_error(dirs, t_end=t_end))


def chart_rondon(work: str, quick: bool, methods=None) -> list[dict]:
    """The Rondon chart's rows: every method of RONDON_METHODS, or those named in `methods`."""
    rows = []
    for method, (shape, cfl, ladder, quick_ladder, transfer) in RONDON_METHODS.items():
        if methods is not None and method not in methods:
            continue
        for n in (quick_ladder if quick else ladder):
            run, err = run_rondon_pair(work, n, shape, cfl, transfer=transfer)
            rows.append(row_of("rondon", method, n, 1, run, err.get("error", math.nan),
                               dx_mm=300.0 / n,
                               **{k: v for k, v in err.items() if k != "error"}))
    return rows


ACCURACY = {
    "sod": (chart_sod, "Sod shock tube (ICE), t = 0.2", "relative L1 density error"),
    "terzaghi": (chart_terzaghi, "Consolidation column (MPMICE), paper's densities",
                 "max rel. L2 pore-pressure error, T_v >= 0.1"),
    "terzaghi_qs": (lambda w, q: chart_terzaghi(w, q, quasi_static=True),
                    "Consolidation column (MPMICE), densities / 100 (quasi-static)",
                    "max rel. L2 pore-pressure error, T_v >= 0.1"),
    "darcy": (chart_darcy, "Steady Darcy column (MPMICE), phi_s = 0.7, dp = 0.5 atm",
              "|U_f / U_f,exact - 1| (mean pore velocity in the column)"),
    "bar": (chart_bar, "Elastic bar (MPM), first mode, 10 periods",
            "max |u_tip - exact| / amplitude"),
    "cavity": (chart_cavity, f"Porous thermal cavity (MPMICE), Ra = {CAVITY_RA:g}, "
                             f"{CAVITY_END} thermal times",
               f"|Nu_hot / {CAVITY_NU} - 1| (benchmarks 3.10-3.16)"),
    "grilli": (chart_grilli, f"Grilli et al. (2017) test 17 (MPMICE), WG1, model t <= "
                             f"{GRILLI_END} s",
               "RMS(model - record) / RMS(record) at WG1"),
    "rondon": (chart_rondon, f"Rondon et al. (2011) dense + loose pair (MPMICE, critical-state "
                             f"sand), to {rondon.CHART_END} s",
               "mean rel. error: run-out at 0.55 / 0.64 s, base pressure at 1.13 s"),
}


# --------------------------------------------------------------------------- stability maps

DRAG_GRAINS = (1e-3, 3e-4, 1e-4, 3e-5, 1e-5)
DRAG_DT_EXPONENTS = (22, 20, 18, 16, 14)
DRAG_END = 2.0**-7        # s (7.8 ms: T_v = 0.032 at d = 1 mm), exact for every 2^-k dt
DRAG_CELLS = 50
DRAG_ERROR_LIMIT = 0.05   # max |p - p_exact| / p0 below the top 5 cells
#: The map uses the quasi-static densities (mpmice_terzaghi.QUASI_STATIC_SET, / 100): with the
#: paper's densities the undrained P-wave ringing of the step load (resolved, hence undamped, at
#: small dt) is still 10-27 % of p0 at t = 2^-6 s, a dynamic effect eq. 78 does not contain.
DRAG_SOLID_DENSITY, DRAG_FLUID_DENSITY = 26.5, 9.998
SOLID_WAVE_SPEED = math.sqrt(constrained_modulus(1.0e7, 0.3) / DRAG_SOLID_DENSITY)   # m/s


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
ENERGY_LIMIT = 0.05
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


def run_column(work: str, cells: int, shape: str, youngs: float) -> dict:
    """The 1D column of postproc.mpm_column with Young's modulus `youngs`: ramp 10 periods of
    the first mode, end after 20 (the validation's 0.5 s / 1 s at E = 1e7 Pa)."""
    rho, g, nu, height = 2000.0, 9.81, 0.3, 1.0
    m = constrained_modulus(youngs, nu)
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
    res = {"run": run, "u_top_cells": rho * g * height**2 / (2.0 * m) * cells / height,
           "oscillation": math.nan, "stress_error": math.nan}
    paths = list_dumps(out, "column1d")
    _, p0 = particles(paths[0], "soil")
    _, p1 = particles(paths[-1], "soil")
    res["particles_lost"] = lost_particles(run, p0, p1)
    if not run_failed(run, res["particles_lost"]):
        order = np.argsort(p0["y"])
        y0 = p0["y"][order]
        s = p1["stress_yy"][order]
        scale = rho * g * height
        res["stress_error"] = float(np.max(np.abs(s + rho * g * (height - y0))) / scale)
        res["oscillation"] = float(np.max(np.abs(s[1:-1] - 0.5 * (s[:-2] + s[2:]))) / scale)
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
        return constrained_modulus(stiffness, SOIL_NU)
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
    res = {"run": run, "stress_error": math.nan, "oscillation": math.nan,
           "base_modulus": soil_base_modulus(model, stiffness), "period": period}
    paths = list_dumps(out, "column1d")
    _, p0 = particles(paths[0], "soil")
    _, p1 = particles(paths[-1], "soil")
    res["particles_lost"] = lost_particles(run, p0, p1)
    if not run_failed(run, res["particles_lost"]):
        order = np.argsort(p0["y"])
        s = p1["stress_yy"][order]
        scale = rho * 9.81 * SOIL_H
        res["stress_error"] = float(np.max(np.abs(s + rho * 9.81 * (SOIL_H - p0["y"][order])))
                                    / scale)
        res["oscillation"] = float(np.max(np.abs(s[1:-1] - 0.5 * (s[:-2] + s[2:]))) / scale)
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


# --------------------------------------------------------------------------- output

def write_csv(rows: list[dict], path: str) -> None:
    write_table(path, rows)


def read_csv(path: str) -> list[dict]:
    rows = []
    with open(path, newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            out = {}
            for k, v in r.items():
                try:
                    out[k] = int(v)
                except ValueError:
                    try:
                        out[k] = float(v)
                    except ValueError:
                        out[k] = v
            rows.append(out)
    return rows


def plot_accuracy(rows: list[dict], path: str, title: str, ylabel: str) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    markers = "osD^v<>"
    for k, m in enumerate(methods):
        pts = [r for r in rows if r["method"] == m and math.isfinite(r["error"])
               and r["error"] > 0]
        if not pts:
            continue
        ax.loglog([r["run_s"] for r in pts], [r["error"] for r in pts], marker=markers[k % 7],
                  ls="-", color=f"C{k}", label=m, mfc="none")
        for r in pts:
            ax.annotate(str(r["cells"]), (r["run_s"], r["error"]), textcoords="offset points",
                        xytext=(3, 3), fontsize=7, color=f"C{k}")
    front = sorted((r for r in rows if r.get("pareto") == 1 and r["error"] > 0),
                   key=lambda r: r["run_s"])
    if front:
        ax.step([r["run_s"] for r in front], [r["error"] for r in front], where="post",
                color="k", lw=1, ls="--", alpha=0.6)
        ax.plot([r["run_s"] for r in front], [r["error"] for r in front], "k*", ms=9,
                label="Pareto front")
    ax.set_xlabel("run time [s] (program's total, 1 core per rank)")
    ax.set_ylabel(ylabel)
    ax.set_title(title + "\n(labels: cells along the physics direction)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path)


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
        ax.set_xlabel("&time cfl (dt = cfl dx / (c + |v|); validation caps it at 1)")
        ax.set_title(f"shape_function = '{shape}'")
        ax.set_xlim(0.15, 1.15)
        _legend_verdicts(ax, rows)
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
        ax.set_xlabel("&time cfl (dt = cfl dx / (c + |v|); validation caps it at 1)")
        ax.set_title(f"model = '{model}': {labels[model]}", fontsize=9)
        ax.set_xlim(0.15, 1.15)
        _legend_verdicts(ax, rows)
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


#: Errors equal to this relative tolerance count as equal on the Pareto front.
PARETO_RTOL = 1e-4


def mark_pareto(rows: list[dict]) -> None:
    front = pareto_front([r["run_s"] for r in rows], [r["error"] for r in rows],
                         rtol=PARETO_RTOL)
    for r, f in zip(rows, front):
        r["pareto"] = int(f)


def print_rows(name: str, rows: list[dict]) -> None:
    print(f"== {name}")
    keys = [k for k in rows[0] if k not in ("scene", "reason")]
    print("  " + " ".join(f"{k:>12s}" for k in keys))
    for r in rows:
        print("  " + " ".join(f"{r[k]:12.4g}" if isinstance(r[k], float) else f"{r[k]!s:>12}"
                              for k in keys))
    sys.stdout.flush()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short ladders (< 3 min)")
    parser.add_argument("--out", default=os.path.join(ROOT, "docs"))
    parser.add_argument("--only", nargs="+", choices=list(ACCURACY) + list(STABILITY),
                        help="only these charts/maps")
    parser.add_argument("--replot", action="store_true", help="re-plot from the CSVs in --out")
    args = parser.parse_args(argv)
    names = args.only or list(ACCURACY) + list(STABILITY)
    os.makedirs(args.out, exist_ok=True)
    start = _time.perf_counter()
    with tempfile.TemporaryDirectory() as work:
        for name in names:
            t0 = _time.perf_counter()
            prefix = "accuracy" if name in ACCURACY else "stability"
            csv_path = os.path.join(args.out, f"{prefix}_{name}.csv")
            png_path = os.path.join(args.out, f"{prefix}_{name}.png")
            if name in ACCURACY:
                func, title, ylabel = ACCURACY[name]
                rows = read_csv(csv_path) if args.replot else func(work, args.quick)
                mark_pareto(rows)
                write_csv(rows, csv_path)
                plot_accuracy(rows, png_path, title, ylabel)
            else:
                rows = read_csv(csv_path) if args.replot else STABILITY[name](work, args.quick)
                write_csv(rows, csv_path)
                STABILITY_PLOTS[name](rows, png_path)
            print_rows(name, rows)
            print(f"   {name}: {_time.perf_counter() - t0:.1f} s -> {png_path}", flush=True)
    print(f"all done in {_time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
