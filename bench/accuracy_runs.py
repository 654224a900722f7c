"""Running the scenes of the speed-against-accuracy study and the stability maps
(bench/accuracy_charts.py, bench/stability_maps.py): timed runs, how a run ended, the Pareto
front, the elastic bar shared by a chart and a map, the CSV tables."""
from __future__ import annotations

import csv
import math
import os
import re
import sys
import time as _time

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from postproc import mpm_bar                                        # noqa: E402
from postproc import mpmice_stiff_drag as stiff                     # noqa: E402
from postproc.figures import write_table                            # noqa: E402
from postproc.mpm_common import particles, series                   # noqa: E402
from postproc.mpmice_io import list_dumps                           # noqa: E402
from postproc.run_case import run_mpmice                            # noqa: E402


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


def total_run_seconds(text: str) -> float:
    """The program's last 'total run' timer [s] in a run's output or log (nan when absent)."""
    m = _TOTAL_RUN.findall(text)
    return float(m[-1]) if m else math.nan


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
    return {
        "exit_code": result.returncode, "state": status.get("state", "?"),
        "reason": status.get("reason", ""), "steps": int(status.get("step", -1)),
        "time_reached": float(status.get("time", "nan")),
        "run_s": total_run_seconds(result.stdout), "wall_s": wall,
    }


def row_of(scene: str, method: str, cells: int, nranks: int, run: dict, error: float,
           **extra) -> dict:
    row = {"scene": scene, "method": method, "cells": cells, "nranks": nranks,
           "run_s": run["run_s"], "wall_s": run["wall_s"], "steps": run["steps"],
           "error": error if run["exit_code"] == 0 else math.nan, "state": run["state"]}
    row.update(extra)
    return row


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


#: Energy stop of the MPM maps: kinetic + strain energy > (1 + ENERGY_LIMIT) E(0).
ENERGY_LIMIT = 0.05


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


# --------------------------------------------------------------------------- tables

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
