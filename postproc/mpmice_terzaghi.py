"""One-dimensional isothermal consolidation (MPMICE, paper eq. 78) against Biot/Terzaghi's exact
solution with the fluid compressibility, at several resolutions.

Usage:  python -m postproc.mpmice_terzaghi [--out docs/validation] [--cells 25 50 100 200]
                                           [--nranks 1]
        python -m postproc.mpmice_terzaghi --quasi-static [--cells ...]  (densities / 100)
        python -m postproc.mpmice_terzaghi --dir output/mpmice_terzaghi   (one finished run)

Scene namelists/mpmice_terzaghi_1d.nml: a saturated elastic column, H = 1 m along y, impermeable
fixed base, drained top face at 1 atm, a 10 kPa load on the skeleton at that face from t = 0
(`&boundary solid = 'traction'`). With a
compressible pore fluid (K_f) and incompressible grains the excess pore pressure obeys
(1/E_v + n/K_f) dp/dt = (k/mu) d^2p/dz^2, so
    c_v = (k/mu) / (1/E_v + n/K_f),   k/mu = d^2 n^3 / (180 mu phi_s^2)  (Carman-Kozeny, eq. 77),
    p0  = F / (1 + n E_v / K_f)        (undrained response to the sudden load),
    p(z, t) = sum_m (2 p0 / M) sin(M z / H) exp(-M^2 T_v),  M = pi (2m + 1)/2,  T_v = c_v t / H^2,
z = H - y the depth below the drained top (K_f -> infinity gives the paper's c_v, 4.12 m^2/s).
For every dump the excess pressure /cell/pressure - 101325 along y is compared with p at the
dump's time attribute: relative L2 error ||p - p_exact|| / ||p_exact|| over the cells. Printed per
resolution: the wall time of the run, the error at the dumps nearest T_v = 0.05, 0.1, 0.2, 0.5, 1,
the largest error over the dumps with T_v >= 0.1 (TV_MIN), and the degree of consolidation
U = 1 - mean(p) / p0 against U(T_v); then the observed order between successive resolutions.
Writes mpmice_terzaghi.png (profiles p/p0 against depth at 100 cells, U against T_v, L2 error
against cells) and mpmice_terzaghi.csv.

The scene solves Biot's dynamic equations; eq. 78 is their quasi-static limit and contains no
density. --quasi-static divides the grain and water densities by 100 (QUASI_STATIC_SET), which
leaves eq. 78 unchanged and removes the undrained P-wave ringing of the step load and the
inertia of the drag relaxation (0.9 ms with the paper's densities, ~0.35 % of c_v at 100 cells):
the comparison then measures the discretisation alone (mpmice_terzaghi_quasi_static.csv/.png).
"""
from __future__ import annotations

import math
import os
import tempfile
import time as _time

import numpy as np

from postproc.analytic import (carman_kozeny_conductivity, oedometer_modulus,
                               terzaghi_degree_of_consolidation, terzaghi_excess_pressure)
from postproc.figures import pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump, read_run_dumps
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_terzaghi_1d.nml")
NAME = "terzaghi"
#: Scene parameters (namelists/mpmice_terzaghi_1d.nml).
PARAMS = {
    "youngs_modulus": 1.0e7, "poisson_ratio": 0.3, "porosity": 0.3, "grain_size": 1.0e-3,
    "viscosity": 1.0e-3, "bulk_modulus": 2.0e9, "load": 1.0e4, "height": 1.0,
    "reference_pressure": 101325.0,
}
TV_REPORT = (0.05, 0.1, 0.2, 0.5, 1.0)   # time factors reported (nearest dumps)
#: Dumps below this T_v are left out of the maximum error: the step load rings the column's
#: undrained P-wave (period 4 H / c_u = 2.3 ms, decaying by drag over ~6 ms), which the
#: quasi-static eq. 78 does not contain (docs/validation/mpmice_terzaghi.md shows it).
TV_MIN = 0.1
#: --set groups of the quasi-static comparison: densities / 100 (eq. 78 has none).
QUASI_STATIC_SET = ("&solid name = 'soil', density = 26.5 /",
                    "&fluid name = 'water', reference_density = 9.998 /")
TERMS = 400                         # series terms: exp(-M^2 T_v) < 1e-300 beyond at T_v >= 0.01


# --------------------------------------------------------------------------- exact solution

def biot_consolidation_coefficient(youngs_modulus, poisson_ratio, porosity, grain_size,
                                   viscosity, bulk_modulus=math.inf) -> float:
    """c_v = (k/mu) / (1/E_v + n/K_f) [m^2/s] with the Carman-Kozeny k/mu (phi_s = 1 - n);
    K_f = inf gives the paper's c_v = E_v n^3 d^2 / (180 (1 - n)^2 mu)."""
    conductivity = float(carman_kozeny_conductivity(1.0 - porosity, grain_size, viscosity))
    e_v = oedometer_modulus(youngs_modulus, poisson_ratio)
    return conductivity / (1.0 / e_v + porosity / bulk_modulus)


def undrained_pressure(load, youngs_modulus, poisson_ratio, porosity,
                       bulk_modulus=math.inf) -> float:
    """Initial excess pore pressure p0 = F / (1 + n E_v / K_f) [Pa] under a sudden load F: the
    skeleton strain eps = n p0 / K_f equals the pore-fluid compression, F = E_v eps + p0."""
    e_v = oedometer_modulus(youngs_modulus, poisson_ratio)
    return load / (1.0 + porosity * e_v / bulk_modulus)


def consolidation_constants(params: dict | None = None) -> tuple[float, float]:
    """(c_v [m^2/s], p0 [Pa]) of the scene."""
    p = PARAMS if params is None else params
    c_v = biot_consolidation_coefficient(p["youngs_modulus"], p["poisson_ratio"], p["porosity"],
                                         p["grain_size"], p["viscosity"], p["bulk_modulus"])
    p0 = undrained_pressure(p["load"], p["youngs_modulus"], p["poisson_ratio"], p["porosity"],
                            p["bulk_modulus"])
    return c_v, p0


def exact_excess_pressure(y, time: float, params: dict | None = None) -> np.ndarray:
    """Exact excess pore pressure [Pa] at heights y [m] (drained top at y = H) and time [s]."""
    p = PARAMS if params is None else params
    c_v, p0 = consolidation_constants(p)
    height = p["height"]
    depth = (height - np.asarray(y, dtype=float)) / height
    return terzaghi_excess_pressure(depth, c_v * time / height**2, p0, terms=TERMS)


# --------------------------------------------------------------------------- analysis of dumps

def pressure_profile(dump: dict, reference_pressure: float = PARAMS["reference_pressure"]):
    """(y [m], excess pressure [Pa]) along y of a 1D-in-y dump (from :func:`read_dump`)."""
    _, y, _ = cell_centres(dump)
    return y, dump["cell"]["pressure"][0, :, 0] - reference_pressure


def excess_profiles(out: str) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """(time, y, excess pressure) of every dump of the run in ``out`` after the first."""
    result = []
    for path in list_dumps(out, NAME)[1:]:
        dump = read_dump(path)
        y, excess = pressure_profile(dump)
        result.append((float(dump["time"]), y, excess))
    return result


def relative_l2(numeric: np.ndarray, exact: np.ndarray) -> float:
    """||numeric - exact|| / ||exact|| (discrete, over the cells)."""
    return float(np.linalg.norm(numeric - exact) / np.linalg.norm(exact))


def observed_order(cells, errors) -> list[float]:
    """log(e_i / e_{i+1}) / log(N_{i+1} / N_i) between successive resolutions."""
    return [float(math.log(errors[i] / errors[i + 1]) / math.log(cells[i + 1] / cells[i]))
            if errors[i] > 0.0 and errors[i + 1] > 0.0 else math.nan
            for i in range(len(cells) - 1)]


def analyse_dumps(dumps, params: dict | None = None) -> dict:
    """Errors of a sequence of dumps (dicts from :func:`read_dump`, in time order).

    Returns time, tv, l2_error (NaN at T_v = 0), u_numeric, u_exact (arrays per dump), y,
    pressure (excess pressure per dump, an [ndump, ncells] array), max_error (over T_v >= TV_MIN),
    at_tv ({target T_v: {index, tv, time, l2_error, u_numeric, u_exact, depth, p_over_p0,
    exact_over_p0}} at the dump nearest each target of TV_REPORT) and c_v, p0.
    """
    p = PARAMS if params is None else params
    c_v, p0 = consolidation_constants(p)
    height = p["height"]
    times, errors, u_num, pressures = [], [], [], []
    y = None
    for dump in dumps:
        y, excess = pressure_profile(dump, p["reference_pressure"])
        t = float(dump["time"])
        times.append(t)
        pressures.append(excess)
        errors.append(relative_l2(excess, exact_excess_pressure(y, t, p)) if t > 0.0
                      else math.nan)
        u_num.append(1.0 - float(np.mean(excess)) / p0)
    times = np.asarray(times)
    tv = c_v * times / height**2
    errors = np.asarray(errors)
    pressures = np.asarray(pressures)
    late = tv >= TV_MIN
    result = {
        "time": times, "tv": tv, "l2_error": errors, "u_numeric": np.asarray(u_num),
        "u_exact": terzaghi_degree_of_consolidation(tv, terms=TERMS), "y": y,
        "pressure": pressures, "c_v": c_v, "p0": p0,
        "max_error": float(np.max(errors[late])) if np.any(late) else math.nan,
        "at_tv": {},
    }
    for target in TV_REPORT:
        if target > tv[-1] * 1.05 + 1e-12:     # the run stopped before this time factor
            continue
        i = int(np.argmin(np.abs(tv - target)))
        result["at_tv"][target] = {
            "index": i, "tv": float(tv[i]), "time": float(times[i]),
            "l2_error": float(errors[i]), "u_numeric": float(result["u_numeric"][i]),
            "u_exact": float(result["u_exact"][i]), "depth": (height - y) / height,
            "p_over_p0": pressures[i] / p0,
            "exact_over_p0": exact_excess_pressure(y, times[i], p) / p0,
        }
    return result


# --------------------------------------------------------------------------- runs

def fixed_dt_args(cells: int, grain_size: float, dt: float, end_time: float,
                  output_interval: float, output_dir: str,
                  drag_scheme: str | None = None) -> list[str]:
    """mpmice arguments of the quasi-static column (QUASI_STATIC_SET) with `cells` cells along y
    and grain size `grain_size` [m], run at the fixed step `dt` [s] to `end_time` [s]: cfl 1 and
    dt_min = 0.75 dt, so a step the scene rejects, or the CFL limit, stops the run instead of
    shortening dt. `drag_scheme` sets &coupling drag_scheme (the namelist's when None)."""
    args = [NAMELIST,
            "--set", f"&grid ncells = 1, {cells}, 1 /",
            "--set", f"&solid name='soil', grain_size = {grain_size!r} /"]
    if drag_scheme is not None:
        args += ["--set", f"&coupling drag_scheme = '{drag_scheme}' /"]
    for text in QUASI_STATIC_SET:
        args += ["--set", text]
    return args + ["--set", f"&time cfl = 1.0, dt_init = {dt!r}, dt_max = {dt!r}, "
                            f"dt_min = {0.75 * dt!r} /",
                   "--set", f"&run end_time = {end_time!r}, output_interval = "
                            f"{output_interval!r}, output_dir = '{output_dir}' /"]


def run_resolution(workdir: str, cells: int, nranks: int = 1, extra_set=(),
                   params: dict | None = None) -> dict:
    """Run the scene with `cells` cells along y; return :func:`analyse_dumps` of its dumps plus
    cells, nranks, wall_time [s] and output_dir."""
    out = os.path.join(workdir, f"terzaghi_n{cells}_r{nranks}")
    args = [NAMELIST,
            "--set", f"&grid ncells = 1, {cells}, 1 /",
            "--set", f"&run output_dir = '{out}' /"]
    for text in extra_set:
        args += ["--set", text]
    start = _time.perf_counter()
    run_mpmice(args, nranks=nranks, cwd=workdir)
    wall = _time.perf_counter() - start
    result = analyse_dumps(read_run_dumps(out, NAME), params)
    result.update({"cells": cells, "nranks": nranks, "wall_time": wall, "output_dir": out})
    return result


def run_terzaghi(workdir: str, cells=(25, 50, 100, 200), nranks: int = 1, extra_set=()) -> dict:
    """Run every resolution in `cells` (an int or a sequence) in `workdir`.

    Returns {"cells": [...], "runs": {N: run_resolution(...)}, "max_error": [per N],
    "order_max": [observed order of max_error between successive N],
    "error_at_tv": {T_v: [per N]}, "order_at_tv": {T_v: [...]}, "wall_time": [per N]}.
    """
    cells = [int(cells)] if np.isscalar(cells) else [int(n) for n in cells]
    runs = {n: run_resolution(workdir, n, nranks, extra_set) for n in cells}
    max_error = [runs[n]["max_error"] for n in cells]
    error_at_tv = {tv: [runs[n]["at_tv"][tv]["l2_error"] if tv in runs[n]["at_tv"] else math.nan
                        for n in cells] for tv in TV_REPORT}
    return {
        "cells": cells, "runs": runs, "max_error": max_error,
        "order_max": observed_order(cells, max_error),
        "error_at_tv": error_at_tv,
        "order_at_tv": {tv: observed_order(cells, e) for tv, e in error_at_tv.items()},
        "wall_time": [runs[n]["wall_time"] for n in cells],
    }


# --------------------------------------------------------------------------- report

def print_report(study: dict) -> None:
    c_v, p0 = consolidation_constants()
    c_v_rigid = biot_consolidation_coefficient(
        PARAMS["youngs_modulus"], PARAMS["poisson_ratio"], PARAMS["porosity"],
        PARAMS["grain_size"], PARAMS["viscosity"])
    print(f"c_v = {c_v:.6g} m^2/s (incompressible fluid: {c_v_rigid:.6g}), p0 = {p0:.6g} Pa "
          f"(load {PARAMS['load']:.6g} Pa)")
    for n in study["cells"]:
        r = study["runs"][n]
        print(f"{n} cells ({r['nranks']} ranks): wall time {r['wall_time']:.2f} s, "
              f"max L2 error (T_v >= {TV_MIN}) = {r['max_error']:.3e}")
        for target, a in r["at_tv"].items():
            print(f"  T_v = {target:<5} (dump T_v = {a['tv']:.4f}, t = {a['time']:.5g} s): "
                  f"L2 error {a['l2_error']:.3e}, U = {a['u_numeric']:.5f} "
                  f"(exact {a['u_exact']:.5f})")
    cells = study["cells"]
    for i, order in enumerate(study["order_max"]):
        per_tv = ", ".join(f"T_v {tv}: {study['order_at_tv'][tv][i]:.2f}" for tv in TV_REPORT)
        print(f"order {cells[i]} -> {cells[i + 1]} cells: max error {order:.2f} ({per_tv})")


def write_csv(study: dict, path: str) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write("cells,nranks,wall_time,tv_target,tv,time,l2_error,u_numeric,u_exact,"
                "max_error,order_max\n")
        for i, n in enumerate(study["cells"]):
            r = study["runs"][n]
            order = study["order_max"][i - 1] if i > 0 else math.nan
            for target, a in r["at_tv"].items():
                f.write(f"{n},{r['nranks']},{r['wall_time']:.3f},{target},{a['tv']:.6f},"
                        f"{a['time']:.6g},{a['l2_error']:.6e},{a['u_numeric']:.6f},"
                        f"{a['u_exact']:.6f},{r['max_error']:.6e},{order:.4f}\n")


def plot(study: dict, path: str, profile_cells: int = 100) -> None:
    plt = pyplot()

    cells = study["cells"]
    shown = min(cells, key=lambda n: abs(n - profile_cells))
    r = study["runs"][shown]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    ax = axes[0]
    depth = np.linspace(0.0, 1.0, 400)
    c_v, p0 = consolidation_constants()
    for k, (target, a) in enumerate(r["at_tv"].items()):
        color = f"C{k}"
        ax.plot(terzaghi_excess_pressure(depth, a["tv"], 1.0, terms=TERMS), depth, "-",
                color=color, lw=1)
        ax.plot(a["p_over_p0"], a["depth"], "o", color=color, ms=3, mfc="none",
                label=f"T_v = {a['tv']:.3f}")
    ax.invert_yaxis()
    ax.set_xlabel("p / p0")
    ax.set_ylabel("depth z / H")
    ax.set_title(f"excess pore pressure, {shown} cells (lines: exact)")
    ax.legend(fontsize=8)
    ax = axes[1]
    tv = np.linspace(1e-4, max(float(r["tv"][-1]), 0.1), 300)
    ax.plot(tv, terzaghi_degree_of_consolidation(tv, terms=TERMS), "k-", lw=1, label="exact")
    for k, n in enumerate(cells):
        rn = study["runs"][n]
        late = rn["tv"] >= TV_MIN        # the t = 0 dump is before the load acts
        ax.plot(rn["tv"][late], rn["u_numeric"][late], "o", ms=3, mfc="none", color=f"C{k}",
                label=f"{n} cells")
    ax.set_xlabel("T_v = c_v t / H^2")
    ax.set_ylabel("U = 1 - mean(p) / p0")
    ax.set_title("degree of consolidation")
    ax.legend(fontsize=8)
    ax = axes[2]
    ax.loglog(cells, study["max_error"], "ko-", label=f"max over T_v >= {TV_MIN}")
    for k, target in enumerate(TV_REPORT):
        errors = study["error_at_tv"][target]
        if np.all(np.isnan(errors)):
            continue
        ax.loglog(cells, errors, "s--", ms=4, color=f"C{k}", label=f"T_v = {target}")
    for i, order in enumerate(study["order_max"]):
        x = math.sqrt(cells[i] * cells[i + 1])
        y = math.sqrt(study["max_error"][i] * study["max_error"][i + 1])
        ax.annotate(f"{order:.2f}", (x, y), textcoords="offset points", xytext=(4, 4),
                    fontsize=8)
    ax.set_xlabel("cells")
    ax.set_ylabel("relative L2 error of p")
    ax.set_title("convergence (labels: observed order)")
    ax.legend(fontsize=8)
    fig.suptitle(f"Isothermal consolidation (MPMICE), c_v = {c_v:.3f} m^2/s, p0 = {p0:.0f} Pa")
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def report_directory(output_dir: str) -> dict:
    """Compare the dumps of one finished run in `output_dir` with the exact solution: print the
    error at the report times and write terzaghi_vs_exact.png there (scripts/run.sh)."""
    r = analyse_dumps(read_run_dumps(output_dir, NAME))
    cells = len(r["y"])
    study = {"cells": [cells], "runs": {cells: r}, "max_error": [r["max_error"]],
             "order_max": [], "error_at_tv": {tv: [r["at_tv"][tv]["l2_error"]
                                                    if tv in r["at_tv"] else math.nan]
                                               for tv in TV_REPORT}, "wall_time": [math.nan]}
    for target, a in r["at_tv"].items():
        print(f"T_v = {target:<5} (dump T_v = {a['tv']:.4f}, t = {a['time']:.4g} s): relative L2 "
              f"error {a['l2_error']:.3e}, U = {a['u_numeric']:.5f} (exact {a['u_exact']:.5f})")
    print(f"largest relative L2 error over the dumps with T_v >= {TV_MIN}: {r['max_error']:.3e}")
    path = os.path.join(output_dir, "terzaghi_vs_exact.png")
    plot(study, path, profile_cells=cells)
    print(f"comparison plot: {path}")
    return r


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[25, 50, 100, 200])
    parser.add_argument("--nranks", type=int, default=1)
    parser.add_argument("--dir", help="only compare the dumps of a finished run in DIR")
    parser.add_argument("--quasi-static", action="store_true",
                        help="densities / 100: the quasi-static limit eq. 78 describes")
    args = parser.parse_args(argv)
    if args.dir:
        report_directory(args.dir)
        return 0
    os.makedirs(args.out, exist_ok=True)
    extra = QUASI_STATIC_SET if args.quasi_static else ()
    tag = "mpmice_terzaghi_quasi_static" if args.quasi_static else "mpmice_terzaghi"
    with tempfile.TemporaryDirectory() as work:
        study = run_terzaghi(work, sorted(args.cells), args.nranks, extra_set=extra)
    print_report(study)
    plot(study, os.path.join(args.out, f"{tag}.png"))
    write_csv(study, os.path.join(args.out, f"{tag}.csv"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
