"""Stiff-drag stability of the coupled MPMICE scene (paper eq. 22, errata E8): the implicit and the
explicit fluid-solid momentum exchange (`&coupling drag_scheme`) for grain sizes d = 1 mm .. 1 um,
in the steady Darcy column (a grain size x time step map) and in 1D consolidation.

Usage:  python -m postproc.mpmice_stiff_drag [--out docs/validation] [--nranks 1]
                                             [--max-steps 200000] [--from-csv CSV]

The Kozeny-Carman drag coefficient per mixture volume, K_d = 180 phi_s^2 mu / (d^2 n), grows as
1/d^2: for the rigid column (phi_s = 0.7) the fluid's drag relaxation rate beta = K_d / (n rho_f)
is 9.8e2 1/s at d = 1 mm and 9.8e8 1/s at d = 1 um. A forward-Euler (explicit) exchange is stable
only for beta dt < 2 (drawn on the map); the implicit exchange has no such limit.

Failure criterion: the run's exit status. 3 = the run failed: non-finite values in the state, or
the time step fell below &time dt_min (after rejected steps, each retried at dt/2, or because the
scene's own stability limit - the advective CFL, which only binds once the velocities blow up -
dropped below it). 0 = stable. Any other status is an error of the study (raised).

(a) Darcy, namelists/mpmice_darcy_1d.nml with phi_s = 0.7 (porosity 0.3), dp = 0.5 atm, for d in
GRAIN_SIZES x drag_scheme x a fixed time step DT in DARCY_DTS: &time dt_init = dt_max = DT, cfl = 1
and dt_min = 0.75 DT, so that the step is fixed and any rejected step (dt/2) or any CFL reduction
counts as a failure *at this DT*. The DTs are powers of two, 2^-17 .. 2^-7 s (7.6e-6 .. 7.8e-3 s, a
factor 4 apart, spanning the nominal 1e-5, 1e-4, 1e-3 and 1e-2 s): with a decimal DT the summed time
misses an output or end time by more than the driver's landing slack (1e-9 dt) after some thousand
steps, and the ~1e-14 s remainder step then fails dt_min (a driver issue: `&time dt_init = dt_max =
1e-5`, output_interval 0.05, end 0.1 s fails at t = 0.1 s even with the default dt_min = 1e-12 s);
multiples of a power of two are exact. End time: the pore pressure diffuses with D = K K_f / n (K =
carman_kozeny_conductivity, K_f = 2 GPa), over t_D = L^2 n / (K K_f) (L = 1 m; 4.9e-4 s at d = 1 mm,
490 s at d = 1 um); the slowest mode decays as exp(-pi^2 t / t_D), so T_steady = max(STEADY_FACTOR
t_D, T_MIN) with STEADY_FACTOR = 1 (the slowest mode down by e^-pi^2 = 5e-5; measured: cell
velocities steady to 2e-3 at 0.6 t_D, 1e-4 at t_D) and T_MIN = 0.1 s for the acoustic/inertial
start-up at large d. The number of steps is capped at --max-steps (default 2e5, ~12 s of wall time):
a run that reaches the cap stops at cap * DT < T_steady and is reported 'not steady (step cap)' (its
stability over that many steps is still recorded); a run whose interior velocity still changes by
more than STEADY_CHANGE = 1e-4 between its last two dumps is 'not steady (drifting)'. Recorded:
status, steps, wall time, and when stable: the relative error of the interior pore velocity - the
mean /cell/water/velocity_x of the 0-based cells 7..12 of 20 (centres 0.75 .. 1.25 m, symmetric
about the column centre, so the slowest, antisymmetric diffusion mode cancels in it) - against eq.
77 (postproc.analytic.darcy_pore_velocity), the largest cell-wise deviation |u_i / U_f - 1| over the
10 column cells (which that mode does not cancel in), and the relative change of the interior
velocity between the last two of the ~10 dumps.

(b) Terzaghi, namelists/mpmice_terzaghi_1d.nml with 50 cells, d in GRAIN_SIZES x drag_scheme at the
solver's own dt (the namelist's cfl = 0.5, dt_init 1e-6, dt_max 1e-4 s, default dt_min) to t = 0.02
s (dumps every 5 ms): status; for stable runs the relative L2 error of the excess pore pressure at
the last dump against the exact solution with c_v (prop. d^2) and p0 of
mpmice_terzaghi.consolidation_constants(params with the grain size), the largest error below the top
5 cells over p0, and the mean excess pressure there over p0 (numeric and exact). T_v = c_v t / H^2
is 0.08 at d = 1 mm and 8e-8 at d = 1 um: the exact solution is then the undrained p0 everywhere but
a drained layer sqrt(c_v t) = 0.3 mm thick at the top. The Fourier series of
mpmice_terzaghi.exact_excess_pressure (400 terms) is only converged for T_v >= 0.01, so below that
the image (erfc) series is used (exact_excess_pressure here).

Prints a table; writes mpmice_stiff_drag.csv (one row per run) and mpmice_stiff_drag.png (left:
the Darcy map, grain size x DT, one marker per scheme; right: Terzaghi, grain size x scheme;
marker: filled = stable, colour = log10 error; hollow = stable but not steady; red x = failed).
"""
from __future__ import annotations

import math
import os
import tempfile
import time as _time

import numpy as np

from postproc import mpmice_darcy, mpmice_terzaghi
from postproc.analytic import carman_kozeny_conductivity, darcy_pore_velocity
from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice

GRAIN_SIZES = (1.0e-3, 1.0e-4, 1.0e-5, 1.0e-6)      # m
SCHEMES = ("implicit", "explicit")
#: Fixed time steps of the Darcy map: powers of two (exact sums, see the module docstring).
DARCY_DTS = tuple(2.0**-k for k in (17, 15, 13, 11, 9, 7))
MAX_STEPS = 200_000                 # cap of the number of steps of one Darcy run
DUMPS = 10                          # dumps per Darcy run (the last two measure steadiness)
STEADY_FACTOR = 1.0                 # T_steady = STEADY_FACTOR * t_D ...
T_MIN = 0.1                         # s, ... but at least this
DT_MIN_FRACTION = 0.75              # &time dt_min = this * DT: a rejected step (dt/2) fails
STEADY_CHANGE = 1e-4                # largest relative change between the last two dumps

# Darcy scene (namelists/mpmice_darcy_1d.nml)
DARCY_PHI_S = 0.7
DARCY_DP_ATM = 0.5
ATM = mpmice_darcy.ATM
VISCOSITY = mpmice_darcy.MU         # Pa s
FLUID_DENSITY = 999.8               # kg/m^3
FLUID_BULK_MODULUS = 2.0e9          # Pa
LENGTH = mpmice_darcy.LENGTH        # m, the column
INTERIOR_CELLS = slice(7, 13)       # 0-based cells 7..12 of 20: centres 0.75 .. 1.25 m
COLUMN_CELLS = slice(5, 15)         # the 10 cells inside 0.5 .. 1.5 m

# Terzaghi scene (namelists/mpmice_terzaghi_1d.nml)
TERZAGHI_CELLS = 50
TERZAGHI_END = 0.02                 # s
TERZAGHI_OUTPUT = 0.005             # s
TOP_CELLS = 5                       # cells at the drained top left out of the 'below' measures
SERIES_TV_MIN = 0.01                # below this T_v the erfc image series gives the exact p


# --------------------------------------------------------------------------- analytic pieces

def drag_coefficient(solid_fraction: float, grain_size: float,
                     viscosity: float = VISCOSITY) -> float:
    """Kozeny-Carman K_d = 180 phi_s^2 mu / (d^2 (1 - phi_s)) [kg/(m^3 s)] (per mixture volume,
    errata E7)."""
    return 180.0 * solid_fraction**2 * viscosity / (grain_size**2 * (1.0 - solid_fraction))


def drag_relaxation_rate(solid_fraction: float, grain_size: float) -> float:
    """beta = K_d / (n rho_f) [1/s]: the fluid's velocity relaxation rate against a rigid solid;
    a forward-Euler exchange is stable for beta dt < 2."""
    return drag_coefficient(solid_fraction, grain_size) \
        / ((1.0 - solid_fraction) * FLUID_DENSITY)


def pressure_diffusion_time(solid_fraction: float, grain_size: float,
                            length: float = LENGTH) -> float:
    """t_D = L^2 n / (K K_f) [s]: the pore pressure of the rigid column diffuses with
    D = K K_f / n; its slowest mode decays as exp(-pi^2 t / t_D)."""
    conductivity = float(carman_kozeny_conductivity(solid_fraction, grain_size, VISCOSITY))
    return length**2 * (1.0 - solid_fraction) / (conductivity * FLUID_BULK_MODULUS)


def darcy_schedule(grain_size: float, dt: float, max_steps: int = MAX_STEPS,
                   solid_fraction: float = DARCY_PHI_S) -> dict:
    """Steps of one fixed-dt Darcy run: t_steady, steps (capped), end_time = steps dt,
    output_interval (a multiple of dt, ~DUMPS dumps) and steady (end_time >= t_steady)."""
    t_d = pressure_diffusion_time(solid_fraction, grain_size)
    t_steady = max(STEADY_FACTOR * t_d, T_MIN)
    needed = int(math.ceil(t_steady / dt - 1e-9))
    steps = min(needed, max_steps)
    every = max(1, steps // DUMPS)
    return {"t_diffusion": t_d, "t_steady": t_steady, "steps_needed": needed, "steps": steps,
            "end_time": steps * dt, "output_interval": every * dt, "steady": steps >= needed}


def darcy_exact_velocity(grain_size: float, solid_fraction: float = DARCY_PHI_S,
                         dp_atm: float = DARCY_DP_ATM) -> float:
    """Eq. 77: the steady pore velocity U_f [m/s] of the column."""
    return float(darcy_pore_velocity(solid_fraction, grain_size, VISCOSITY, dp_atm * ATM, LENGTH))


def terzaghi_params(grain_size: float) -> dict:
    """mpmice_terzaghi.PARAMS with the grain size `grain_size`."""
    return dict(mpmice_terzaghi.PARAMS, grain_size=grain_size)


def _erfc(x: np.ndarray) -> np.ndarray:
    return np.vectorize(math.erfc, otypes=[float])(x)


def excess_pressure_images(depth, time_factor: float, p0: float, images: int = 8) -> np.ndarray:
    """Short-time exact excess pressure [Pa] of 1D consolidation (drained at depth 0, impermeable
    at depth 1, p = p0 at t = 0): p / p0 = 1 - sum_k (-1)^k [erfc((2k + z) / (2 sqrt(T_v))) +
    erfc((2k + 2 - z) / (2 sqrt(T_v)))], z = depth / H; `images` terms are ample for T_v < 1."""
    z = np.asarray(depth, dtype=float)
    root = 2.0 * math.sqrt(time_factor)
    total = np.zeros_like(z)
    for k in range(images):
        total += (-1.0) ** k * (_erfc((2 * k + z) / root) + _erfc((2 * k + 2 - z) / root))
    return p0 * (1.0 - total)


def exact_excess_pressure(y, time: float, params: dict) -> np.ndarray:
    """Exact excess pore pressure [Pa] at heights y [m] and time [s] for every T_v: the Fourier
    series of mpmice_terzaghi for T_v >= SERIES_TV_MIN, the erfc image series below."""
    c_v, p0 = mpmice_terzaghi.consolidation_constants(params)
    height = params["height"]
    tv = c_v * time / height**2
    if tv >= SERIES_TV_MIN:
        return mpmice_terzaghi.exact_excess_pressure(y, time, params)
    depth = (height - np.asarray(y, dtype=float)) / height
    return excess_pressure_images(depth, tv, p0)


# --------------------------------------------------------------------------- runs

def read_status(output_dir: str, name: str) -> dict:
    """`key = value` lines of <output_dir>/<name>.status (state, step, time, reason)."""
    path = os.path.join(output_dir, f"{name}.status")
    status = {}
    if os.path.isfile(path):
        with open(path, encoding="utf-8") as f:
            for line in f:
                key, sep, value = line.partition("=")
                if sep:
                    status[key.strip()] = value.strip()
    return status


def run_scene(args, output_dir: str, name: str, nranks: int, cwd: str) -> dict:
    """Run mpmice (unchecked); return exit_code, status ('stable' or 'failed'), steps,
    time_reached, reason, wall_time, and the dump paths. Exit codes other than 0 and 3 raise."""
    start = _time.perf_counter()
    result = run_mpmice(args, nranks=nranks, cwd=cwd, check=False, timeout=900)
    wall = _time.perf_counter() - start
    if result.returncode not in (0, 3):
        raise RuntimeError(f"mpmice exited with {result.returncode}:\n{result.stdout}\n"
                           f"{result.stderr}")
    status = read_status(output_dir, name)
    reason = status.get("reason", "")
    if not reason:
        lines = [l for l in (result.stdout + result.stderr).splitlines() if "mpmice: " in l]
        reason = lines[-1].split("mpmice: ", 1)[1] if lines else ""
    return {
        "exit_code": result.returncode,
        "status": "stable" if result.returncode == 0 else "failed",
        "steps": int(status.get("step", -1)),
        "time_reached": float(status.get("time", "nan")),
        "reason": reason, "wall_time": wall,
        "dumps": list_dumps(output_dir, name) if os.path.isdir(output_dir) else [],
    }


def interior_velocity(dump: dict) -> float:
    """Mean water x velocity [m/s] over INTERIOR_CELLS."""
    return float(np.mean(dump["cell"]["water/velocity_x"][INTERIOR_CELLS, 0, 0]))


def run_darcy_case(workdir: str, grain_size: float, scheme: str, dt: float, nranks: int = 1,
                   max_steps: int = MAX_STEPS) -> dict:
    """One fixed-dt Darcy run (module docstring (a)); one result row."""
    plan = darcy_schedule(grain_size, dt, max_steps)
    out = os.path.join(workdir, f"darcy_d{grain_size:.0e}_{scheme}_dt{dt:.3e}")
    args = [mpmice_darcy.NAMELIST,
            "--set", f"&solid name='{mpmice_darcy.SOLID}', porosity = {1.0 - DARCY_PHI_S:.12g}, "
                     f"grain_size = {grain_size:.12g} /",
            "--set", f"&boundary face='x-', pressure = "
                     f"{mpmice_darcy.P_REF + DARCY_DP_ATM * ATM:.12g} /",
            "--set", f"&coupling drag_scheme = '{scheme}' /",
            "--set", f"&time dt_init = {dt!r}, dt_max = {dt!r}, "
                     f"dt_min = {DT_MIN_FRACTION * dt!r}, cfl = 1.0 /",
            "--set", f"&run end_time = {plan['end_time']!r}, "
                     f"output_interval = {plan['output_interval']!r}, output_dir = '{out}' /"]
    run = run_scene(args, out, mpmice_darcy.NAME, nranks, workdir)
    u_exact = darcy_exact_velocity(grain_size)
    row = {
        "scene": "darcy", "scheme": scheme, "grain_size": grain_size, "dt": dt,
        "beta_dt": drag_relaxation_rate(DARCY_PHI_S, grain_size) * dt,
        "t_diffusion": plan["t_diffusion"], "end_time": plan["end_time"],
        "steps_planned": plan["steps"], "u_exact": u_exact,
        "u_numeric": math.nan, "rel_error": math.nan, "max_cell_deviation": math.nan,
        "steady_change": math.nan, "steady": "",
        "l2_error": math.nan, "level_below_top": math.nan, "max_error_below_top": math.nan,
        "exact_level_below_top": math.nan, "time_factor": math.nan,
    }
    row.update({k: v for k, v in run.items() if k != "dumps"})
    if run["status"] == "stable":
        dumps = [read_dump(p) for p in run["dumps"][-2:]]
        last = dumps[-1]
        u_num = interior_velocity(last)
        cells = last["cell"]["water/velocity_x"][COLUMN_CELLS, 0, 0]
        row.update({
            "u_numeric": u_num, "rel_error": u_num / u_exact - 1.0,
            "max_cell_deviation": float(np.max(np.abs(cells / u_exact - 1.0))),
            "steady_change": abs(u_num - interior_velocity(dumps[0])) / abs(u_num)
            if len(dumps) > 1 and u_num != 0.0 else math.nan,
        })
        row["steady"] = ("not steady (step cap)" if not plan["steady"] else
                         "not steady (drifting)" if not row["steady_change"] < STEADY_CHANGE
                         else "steady")
    return row


def run_terzaghi_case(workdir: str, grain_size: float, scheme: str, nranks: int = 1,
                      end_time: float = TERZAGHI_END, output_interval: float = TERZAGHI_OUTPUT,
                      cells: int = TERZAGHI_CELLS) -> dict:
    """One Terzaghi run at the solver's own dt (module docstring (b)); one result row."""
    out = os.path.join(workdir, f"terzaghi_d{grain_size:.0e}_{scheme}")
    args = [mpmice_terzaghi.NAMELIST,
            "--set", f"&grid ncells = 1, {cells}, 1 /",
            "--set", f"&solid name='soil', grain_size = {grain_size:.12g} /",
            "--set", f"&coupling drag_scheme = '{scheme}' /",
            "--set", f"&run end_time = {end_time!r}, output_interval = {output_interval!r}, "
                     f"output_dir = '{out}' /"]
    run = run_scene(args, out, mpmice_terzaghi.NAME, nranks, workdir)
    params = terzaghi_params(grain_size)
    c_v, p0 = mpmice_terzaghi.consolidation_constants(params)
    row = {
        "scene": "terzaghi", "scheme": scheme, "grain_size": grain_size, "dt": math.nan,
        "beta_dt": math.nan, "t_diffusion": params["height"]**2 / c_v, "end_time": end_time,
        "steps_planned": -1, "u_exact": math.nan, "u_numeric": math.nan, "rel_error": math.nan,
        "max_cell_deviation": math.nan, "steady_change": math.nan, "steady": "",
        "l2_error": math.nan, "level_below_top": math.nan, "max_error_below_top": math.nan,
        "exact_level_below_top": math.nan, "time_factor": c_v * end_time / params["height"]**2,
    }
    row.update({k: v for k, v in run.items() if k != "dumps"})
    if run["status"] == "stable":
        analysis = analyse_terzaghi_dump(read_dump(run["dumps"][-1]), params)
        row.update(analysis)
        row["dt"] = row["time_reached"] / row["steps"] if row["steps"] > 0 else math.nan
    return row


def analyse_terzaghi_dump(dump: dict, params: dict, top_cells: int = TOP_CELLS) -> dict:
    """l2_error (all cells), max_error_below_top (max |p - p_exact| / p0 below the top
    `top_cells` cells), level_below_top and exact_level_below_top (mean p / p0 there, numeric
    and exact) and time_factor of one dump."""
    c_v, p0 = mpmice_terzaghi.consolidation_constants(params)
    y, excess = mpmice_terzaghi.pressure_profile(dump, params["reference_pressure"])
    t = float(dump["time"])
    exact = exact_excess_pressure(y, t, params)
    below = y < params["height"] - top_cells * (y[1] - y[0]) + 1e-12
    return {
        "l2_error": mpmice_terzaghi.relative_l2(excess, exact),
        "max_error_below_top": float(np.max(np.abs(excess[below] - exact[below]))) / p0,
        "level_below_top": float(np.mean(excess[below])) / p0,
        "exact_level_below_top": float(np.mean(exact[below])) / p0,
        "time_factor": c_v * t / params["height"]**2,
    }


def run_study(workdir: str, nranks: int = 1, max_steps: int = MAX_STEPS,
              grain_sizes=GRAIN_SIZES, dts=DARCY_DTS, schemes=SCHEMES) -> list[dict]:
    """Every Darcy (grain size x scheme x DT) and Terzaghi (grain size x scheme) run."""
    rows = []
    for d in grain_sizes:
        for dt in dts:
            for scheme in schemes:
                rows.append(run_darcy_case(workdir, d, scheme, dt, nranks, max_steps))
    for d in grain_sizes:
        for scheme in schemes:
            rows.append(run_terzaghi_case(workdir, d, scheme, nranks))
    return rows


# --------------------------------------------------------------------------- report

CSV_COLUMNS = ("scene", "scheme", "grain_size", "dt", "beta_dt", "status", "exit_code", "steps",
               "steps_planned", "time_reached", "end_time", "t_diffusion", "wall_time", "steady",
               "u_exact", "u_numeric", "rel_error", "max_cell_deviation", "steady_change",
               "time_factor", "l2_error", "max_error_below_top", "level_below_top",
               "exact_level_below_top", "reason")


def _fmt(value, spec=".4e"):
    if isinstance(value, float):
        return "" if math.isnan(value) else format(value, spec)
    return str(value)


def write_csv(rows: list[dict], path: str) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(CSV_COLUMNS) + "\n")
        for r in rows:
            values = []
            for key in CSV_COLUMNS:
                text = _fmt(r[key], ".6e") if key not in ("wall_time",) else f"{r[key]:.3f}"
                values.append('"' + text.replace('"', "'") + '"' if "," in text else text)
            f.write(",".join(values) + "\n")


def read_csv(path: str) -> list[dict]:
    """The rows of a CSV written by :func:`write_csv` (numbers as float, NaN for empty)."""
    import csv
    text_columns = ("scene", "scheme", "status", "steady", "reason")
    rows = []
    with open(path, encoding="utf-8", newline="") as f:
        for record in csv.DictReader(f):
            row = {}
            for key, value in record.items():
                if key in text_columns:
                    row[key] = value
                elif key in ("exit_code", "steps", "steps_planned"):
                    row[key] = int(float(value))
                else:
                    row[key] = float(value) if value else math.nan
            rows.append(row)
    return rows


def _short_reason(r: dict) -> str:
    reason = r["reason"]
    if r["status"] != "failed":
        return ""
    if "non-finite" in reason:
        return "non-finite"
    if "dt_min" in reason:
        return "dt < dt_min"
    return reason[:40]


def print_table(rows: list[dict]) -> None:
    darcy = [r for r in rows if r["scene"] == "darcy"]
    if darcy:
        print("Darcy column, phi_s = 0.7, dp = 0.5 atm, fixed dt (dt_min = 0.75 dt): U_f error "
              "= interior mean (cells 7..12) / eq. 77 - 1; cell dev = max over the column cells")
        print(f"{'d [m]':>7} {'dt [s]':>9} {'beta dt':>9} {'scheme':>8} {'status':>7} "
              f"{'steps':>7} {'t [s]':>9} {'wall [s]':>8} {'U_f error':>10} {'cell dev':>9} "
              f"{'change':>9}  note")
        for r in darcy:
            note = r["steady"] if r["status"] == "stable" else _short_reason(r)
            print(f"{r['grain_size']:7.0e} {r['dt']:9.3e} {r['beta_dt']:9.2e} {r['scheme']:>8} "
                  f"{r['status']:>7} {r['steps']:7d} {r['time_reached']:9.4g} "
                  f"{r['wall_time']:8.2f} {_fmt(r['rel_error'], '10.2e'):>10} "
                  f"{_fmt(r['max_cell_deviation'], '9.2e'):>9} "
                  f"{_fmt(r['steady_change'], '9.1e'):>9}  {note}")
    terz = [r for r in rows if r["scene"] == "terzaghi"]
    if terz:
        print(f"Terzaghi, {TERZAGHI_CELLS} cells, solver dt (cfl 0.5), to t = {TERZAGHI_END} s: "
              f"L2 = relative L2 error of p at the last dump; below top = cells below the top "
              f"{TOP_CELLS}")
        print(f"{'d [m]':>7} {'scheme':>8} {'status':>7} {'steps':>6} {'t [s]':>9} "
              f"{'mean dt':>9} {'wall [s]':>8} {'T_v':>9} {'L2 error':>9} {'max err/p0':>10} "
              f"{'p/p0 below':>10} {'exact':>7}  note")
        for r in terz:
            print(f"{r['grain_size']:7.0e} {r['scheme']:>8} {r['status']:>7} {r['steps']:6d} "
                  f"{r['time_reached']:9.3e} {_fmt(r['dt'], '9.2e'):>9} {r['wall_time']:8.2f} "
                  f"{r['time_factor']:9.2e} {_fmt(r['l2_error'], '9.2e'):>9} "
                  f"{_fmt(r['max_error_below_top'], '10.2e'):>10} "
                  f"{_fmt(r['level_below_top'], '10.4f'):>10} "
                  f"{_fmt(r['exact_level_below_top'], '7.4f'):>7}  {_short_reason(r)}")
    print("failure criterion: exit status 3 (non-finite state, or dt below &time dt_min after "
          "rejected steps / a collapsing stability limit)")
    print(f"total wall time of the runs: {sum(r['wall_time'] for r in rows):.1f} s")


def plot(rows: list[dict], path: str) -> None:
    plt = pyplot()
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D

    norm = Normalize(vmin=-8.0, vmax=2.5)
    cmap = plt.get_cmap("viridis")
    shift = {"implicit": 1.0 / 1.25, "explicit": 1.25}
    shape = {"implicit": "o", "explicit": "s"}

    def draw(ax, x, y, r, error):
        if r["status"] == "failed":
            ax.plot(x, y, "x", color="red", ms=9, mew=2)
        elif r["steady"].startswith("not steady"):
            ax.plot(x, y, shape[r["scheme"]], mfc="none", mec="0.4", ms=9, mew=1.5)
        else:
            value = math.log10(max(abs(error), 1e-12))
            ax.plot(x, y, shape[r["scheme"]], color=cmap(norm(value)), mec="k", ms=9)

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.6, 1]})
    fig.subplots_adjust(left=0.07, right=0.88, bottom=0.2, top=0.88, wspace=0.15)
    ax = axes[0]
    darcy = [r for r in rows if r["scene"] == "darcy"]
    for r in darcy:
        draw(ax, r["grain_size"] * shift[r["scheme"]], r["dt"], r, r["rel_error"])
    if darcy:
        d = np.logspace(math.log10(min(r["grain_size"] for r in darcy)) - 0.3,
                        math.log10(max(r["grain_size"] for r in darcy)) + 0.3, 50)
        ax.plot(d, [2.0 / drag_relaxation_rate(DARCY_PHI_S, g) for g in d], "k--", lw=1,
                label="explicit limit beta dt = 2")
        ax.set_ylim(min(r["dt"] for r in darcy) / 3, max(r["dt"] for r in darcy) * 3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("grain size d [m] (circle: implicit, left; square: explicit, right)")
    ax.set_ylabel("fixed time step dt [s]")
    ax.set_title("Darcy column, phi_s = 0.7: |U_f / eq. 77 - 1| (interior mean)", fontsize=10)
    handles = [Line2D([], [], ls="--", color="k", lw=1, label="explicit limit beta dt = 2"),
               Line2D([], [], marker="x", ls="", color="red", mew=2, label="failed (status 3)"),
               Line2D([], [], marker="o", ls="", mfc="none", mec="0.4",
                      label="stable, not steady (step cap or drifting)")]
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13),
              ncol=3, frameon=False)

    ax = axes[1]
    terz = [r for r in rows if r["scene"] == "terzaghi"]
    level = {"implicit": 1.0, "explicit": 0.0}
    for r in terz:
        draw(ax, r["grain_size"], level[r["scheme"]], r, r["l2_error"])
    ax.set_xscale("log")
    ax.set_yticks([0.0, 1.0], ["explicit", "implicit"])
    ax.set_ylim(-0.6, 1.6)
    ax.set_xlabel("grain size d [m]")
    ax.set_title(f"Terzaghi, {TERZAGHI_CELLS} cells, t = {TERZAGHI_END} s: relative L2 error "
                 "of p", fontsize=10)
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, cax=fig.add_axes([0.9, 0.2, 0.015, 0.68]), label="log10 |error|")
    fig.suptitle("Stiff drag: implicit vs explicit momentum exchange (paper eq. 22, errata E8)")
    save_figure(fig, path, dpi=120)


def main(argv=None) -> int:
    parser = study_parser(__doc__, nranks=True)
    parser.add_argument("--max-steps", type=int, default=MAX_STEPS,
                        help="cap of the steps of one Darcy run (default %(default)s)")
    parser.add_argument("--from-csv", metavar="CSV",
                        help="no runs: print and plot the rows of a CSV of an earlier study")
    args = parse_study_args(parser, argv)
    if args.from_csv:
        rows = read_csv(args.from_csv)
        print_table(rows)
        plot(rows, os.path.join(args.out, "mpmice_stiff_drag.png"))
        return 0
    start = _time.perf_counter()
    with tempfile.TemporaryDirectory() as work:
        rows = run_study(work, args.nranks, args.max_steps)
    print_table(rows)
    print(f"study wall time {_time.perf_counter() - start:.1f} s")
    plot(rows, os.path.join(args.out, "mpmice_stiff_drag.png"))
    write_csv(rows, os.path.join(args.out, "mpmice_stiff_drag.csv"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
