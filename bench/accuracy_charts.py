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
Stability maps: bench/stability_maps.py (the same --only names here).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time as _time

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from bench.accuracy_runs import (                                   # noqa: E402
    pareto_front, read_csv, row_of, run_bar, side_walls, timed_run, total_run_seconds, write_csv)
from bench.stability_maps import STABILITY, STABILITY_PLOTS         # noqa: E402
from postproc import ice_sod, mpmice_darcy, mpmice_terzaghi         # noqa: E402
from postproc import mpmice_rondon as rondon                        # noqa: E402
from postproc import mpmice_stiff_drag as stiff                     # noqa: E402
from postproc import mpmice_thermal_cavity as cavity                # noqa: E402
from postproc.figures import pyplot, save_figure                    # noqa: E402
from postproc.mpmice_io import list_dumps, read_dump                # noqa: E402
from postproc.run_case import ROOT                                  # noqa: E402


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
        return total_run_seconds(f.read())


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


# --------------------------------------------------------------------------- output

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
