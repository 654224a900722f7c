"""Underwater granular column collapse of Rondon, Pouliquen & Aussillous (2011), dense against
loose packing: front, base excess pore pressure and surface profiles, experiment against model
(namelists/mpmice_rondon_dense_2d.nml and mpmice_rondon_loose_2d.nml;
docs/validation/rondon2011.md).

Usage:  python -m postproc.mpmice_rondon --dense output/mpmice_rondon_dense_2d
            --loose output/mpmice_rondon_loose_2d [--reference DIR] [--out DIR]

Either run may be left out (its panels then show the experiment only). ``--reference`` is the
folder of the digitised data (default ../shared/reference/experiments/rondon2011 relative to the
repository root, or beside the main checkout when the repository is a git worktree; the data
are read there, never copied); without it the model alone is reported.

Definitions (the same for the model and the experiment):

* surface profile h(x): in every column of width ``dx`` (the grid's cells), the top of the
  material; model: the highest bead particle whose x lies in the column plus half the particle
  spacing; experiment: the digitised profile.
* front: the toe of that profile, the largest x where the bed is covered; model: the largest
  particle x plus half the particle spacing. The experiment's front files start at 7.09 cm
  (dense) and 6.92 cm (loose) at t = 0 while the column is L0 = 6 cm long: their origin is offset.
  This script subtracts that offset (the file's first value minus L0) so that the front starts
  at L0, and prints the profiles' toes next to the shifted front (:func:`front_check`).
* base excess pore pressure: the cell pressure in the bottom row of cells, linearly interpolated
  in x to the probe ``PROBE_X`` = 2 cm from the wall (SedFoam's comparison probes are at x = 2 and
  3 cm, y ~ 0; the data files' header), minus the same quantity in the first dump (the run
  starts hydrostatic, ``&physics hydrostatic_init``).
* run-out: front minus L0; final run-out: at the last time (model: the run's end time, which is
  shorter than the experiment's for the coarse runs: reported with it); t90: the first time the
  run-out reaches 90 % of its final value.

Writes ``rondon2011.png`` (3 rows: front, base pressure, profiles; dense left, loose right) and
``rondon2011.csv`` (one row per case and source: peak base pressure with its sign and time, final
run-out, its time, t90) in ``--out`` (default: docs/validation); ``--stem`` renames both (the
Mohr-Coulomb runs of the ``*_mc_2d.nml`` scenes: ``--stem rondon2011_mc``).
"""
from __future__ import annotations

import argparse
import csv
import os

import numpy as np

from postproc import measures
from postproc.figures import VALIDATION_DIR, pyplot, save_figure
from postproc.mpmice_io import cell_centres, read_run_dumps
from postproc.namelist import parse_namelist_groups
from postproc.reference import experiment_folder
from postproc.run_case import ROOT

NAME = "rondon"
SOLID = "beads"
L0 = 0.06                    # m: column length (both packings)
H0 = {"dense": 0.042, "loose": 0.048}   # m
PROBE_X = 0.02               # m: base pressure probe, from the closed wall
PPC = 2                      # particles per cell per direction in the shipped scenes
CASES = ("dense", "loose")
def default_reference(root: str = ROOT) -> str:
    """The Rondon data folder (postproc/reference.py)."""
    return experiment_folder("rondon2011", root)


DEFAULT_REFERENCE = default_reference()


def _read_csv(path: str) -> tuple[list[str], np.ndarray]:
    """(column names, rows as floats) of a data file whose comment lines start with '#'; only
    the numeric leading columns are kept."""
    with open(path, encoding="utf-8") as handle:
        lines = [line.strip() for line in handle if line.strip() and not line.startswith("#")]
    header = lines[0].split(",")
    rows = []
    for line in lines[1:]:
        values = []
        for item in line.split(","):
            try:
                values.append(float(item))
            except ValueError:
                break
        rows.append(values)
    width = min(len(r) for r in rows)
    return header[:width], np.array([r[:width] for r in rows], dtype=float)


def read_reference(folder: str, case: str) -> dict:
    """The experiment of one packing: ``front`` (t [s], x [m] as stored, from the wall),
    ``front_offset`` [m] (first stored value minus L0), ``pressure`` (t [s], p [Pa], sorted by
    time), ``profiles`` {t [s]: (x [m], h [m])}."""
    stem = os.path.join(folder, f"rondon2011_{case}")
    _, front = _read_csv(stem + "_front.csv")
    _, pressure = _read_csv(stem + "_base_pore_pressure.csv")
    _, prof = _read_csv(stem + "_profiles.csv")
    order = np.argsort(pressure[:, 0], kind="stable")
    profiles = {}
    for t in sorted(set(prof[:, 0])):
        rows = prof[prof[:, 0] == t]
        rows = rows[np.argsort(rows[:, 1])]
        profiles[float(t)] = (rows[:, 1], rows[:, 2])
    x_front = front[:, 1] / 100.0
    return {"front": (front[:, 0], x_front), "front_offset": float(x_front[0] - L0),
            "pressure": (pressure[order, 0], pressure[order, 1]), "profiles": profiles}


def front_check(ref: dict) -> list[tuple[float, float, float]]:
    """(t, toe of the profile at t, stored front interpolated at t) [s, m, m] for every profile
    time inside the front file's range: how far the stored front lies ahead of the profiles."""
    t_f, x_f = ref["front"]
    out = []
    for t, (x, _) in ref["profiles"].items():
        if t_f[0] <= t <= t_f[-1]:
            out.append((t, float(x[-1]), float(np.interp(t, t_f, x_f))))
    return out


def spacing(dump: dict) -> float:
    """Initial particle spacing [m] along x (cell size / the beads' particles per cell along x,
    from the input the dump carries; PPC when it is not given there)."""
    try:
        ppc = solid_group(dump).get("particles_per_cell", PPC)
    except KeyError:
        ppc = PPC
    n = int(ppc[0] if isinstance(ppc, (list, tuple)) else ppc)
    return float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0]) / n


def model_front(dump: dict) -> float:
    """Front [m]: the largest bead particle x plus half the particle spacing."""
    return measures.front(dump["particles"][SOLID], 0, +1) + 0.5 * spacing(dump)


def model_profile(dump: dict) -> tuple[np.ndarray, np.ndarray]:
    """(column centres x [m], h [m]) of the beads' top surface; h = 0 where a column is empty."""
    x_c, _, _ = cell_centres(dump)
    dx = float(np.asarray(dump["attrs"]["dx"]).reshape(3)[0])
    x0 = float(np.asarray(dump["attrs"]["lower"]).reshape(3)[0])
    parts = dump["particles"][SOLID]
    column = np.clip(((parts["x"] - x0) // dx).astype(int), 0, len(x_c) - 1)
    h = np.zeros(len(x_c))
    np.maximum.at(h, column, parts["y"] + 0.5 * spacing(dump))
    return x_c, h


def base_pressure(dump: dict, first: dict, probe_x: float = PROBE_X) -> float:
    """Excess pore pressure [Pa] at the base, x = probe_x: bottom-row cell pressure interpolated
    in x, minus the same in ``first`` (the hydrostatic start)."""
    x_c, _, _ = cell_centres(dump)
    now = dump["cell"]["pressure"][:, 0, 0]
    start = first["cell"]["pressure"][:, 0, 0]
    return float(np.interp(probe_x, x_c, now - start))


def solid_group(dump: dict) -> dict:
    """The resolved ``&solid`` group of the beads (from the input the dump carries)."""
    for name, group in parse_namelist_groups(dump["attrs"]["namelist"]):
        if name == "solid" and group.get("name") == SOLID:
            return group
    raise KeyError(f"no &solid name = '{SOLID}' in {dump['path']}")


def packing(dump: dict) -> dict:
    """The beads' packing: ``mean`` solid fraction (mass-weighted) of the particles, 1 - n with
    n = 1 - m / (rho_s V); ``suspended``: share of the particles at or past ``max_porosity``
    (no grain contacts); ``critical``: share at or below ``min_porosity`` (Mohr-Coulomb, when set)
    or, for the critical-state sand, at or above its ``critical_solid_fraction`` phi_m (denser
    than the quasi-static critical packing)."""
    group = solid_group(dump)
    parts = dump["particles"][SOLID]
    phi = parts["mass"] / (float(group["density"]) * parts["volume"])
    n = 1.0 - phi
    n_max = float(group.get("max_porosity", 1.0))
    n_min = float(group.get("min_porosity", 0.0))
    if group.get("model") == "critical_state_sand":
        n_min = 1.0 - float(group.get("critical_solid_fraction", 0.585))
    return {"mean": float(np.average(phi, weights=parts["mass"])),
            "suspended": float(np.mean(n >= n_max - 1e-6)),
            "critical": float(np.mean(n <= n_min + 1e-6)) if n_min > 0.0 else 0.0}


def model_series(dumps: list[dict]) -> dict:
    """Time series of a run: ``t``, ``front`` [m], ``pressure`` [Pa] (at PROBE_X), one per dump."""
    return {"t": np.array([d["time"] for d in dumps]),
            "front": np.array([model_front(d) for d in dumps]),
            "pressure": np.array([base_pressure(d, dumps[0]) for d in dumps]),
            "packing": [packing(d) for d in dumps]}


def summary(t: np.ndarray, front: np.ndarray, p_t: np.ndarray, p: np.ndarray) -> dict:
    """Peak base pressure (largest |p|, signed) and its time, final run-out (front - L0 at the
    last time) and that time, t90 (first time the run-out reaches 90 % of the final one)."""
    k = int(np.argmax(np.abs(p))) if len(p) else None
    runout = np.asarray(front) - L0
    final = float(runout[-1])
    reached = np.nonzero(runout >= 0.9 * final)[0] if final > 0 else []
    return {"peak_pressure_Pa": float(p[k]) if k is not None else float("nan"),
            "peak_time_s": float(p_t[k]) if k is not None else float("nan"),
            "final_runout_m": final, "final_time_s": float(t[-1]),
            "t90_s": float(t[reached[0]]) if len(reached) else float("nan")}


#: The issue's targets (docs/validation/rondon2011.md, "Targets"): the base pressure's peak
#: within PEAK_TOLERANCE of the experiment's, the final run-out within RUNOUT_TOLERANCE, and
#: the dense collapse at least SLOWER times slower than the loose one by t90.
PEAK_TOLERANCE = 0.40
RUNOUT_TOLERANCE = 0.15
SLOWER = 3.0
#: A front that moves more than this over the last ADVANCE_WINDOW of a run is still advancing:
#: its last run-out is not a final one [m, s] (the experiment's fronts move 0.4 mm, dense, and
#: -0.3 mm, loose, over their last 2 s).
ADVANCE_LIMIT = 0.002
ADVANCE_WINDOW = 2.0


def targets(series: dict, refs: dict) -> list[tuple[str, str, bool]]:
    """The targets of a run against the experiment: ``series`` {case: :func:`model_series`},
    ``refs`` {case: :func:`read_reference`}. Per case: the base pressure's sign at the
    experiment's pressure times within the run (share of the points with the experiment's
    sign), the peak (largest |p| of the run, signed) of the experiment's sign and within
    PEAK_TOLERANCE of its size,
    the final run-out within RUNOUT_TOLERANCE of the experiment's (and whether the front still
    moves); with both cases, the ratio of the t90s. Returns (target, measured, hit) rows."""
    rows = []
    t90 = {}
    for case, ser in series.items():
        ref = refs[case]
        t_p, p_ref = ref["pressure"]
        inside = t_p <= ser["t"][-1]
        model_p = np.interp(t_p[inside], ser["t"], ser["pressure"])
        same = np.sign(model_p) == np.sign(p_ref[inside])
        share = float(np.mean(same)) if same.size else float("nan")
        rows.append((f"{case}: base pressure has the experiment's sign at its "
                     f"{int(np.sum(inside))} points to {ser['t'][-1]:g} s",
                     f"{share:.0%} of them", bool(same.size) and bool(np.all(same))))
        t_f, x_f = ref["front"]
        exp = summary(t_f, x_f - ref["front_offset"], t_p, p_ref)
        mod = summary(ser["t"], ser["front"], ser["t"], ser["pressure"])
        err = abs(mod["peak_pressure_Pa"]) / abs(exp["peak_pressure_Pa"]) - 1.0
        rows.append((f"{case}: peak base pressure within {PEAK_TOLERANCE:.0%}",
                     f"{mod['peak_pressure_Pa']:+.0f} Pa at {mod['peak_time_s']:g} s against "
                     f"{exp['peak_pressure_Pa']:+.0f} Pa ({err:+.0%})",
                     np.sign(mod["peak_pressure_Pa"]) == np.sign(exp["peak_pressure_Pa"])
                     and abs(err) <= PEAK_TOLERANCE))
        late = ser["t"] >= ser["t"][-1] - ADVANCE_WINDOW
        moved = float(ser["front"][-1] - np.min(ser["front"][late]))
        err = (mod["final_runout_m"] - exp["final_runout_m"]) / exp["final_runout_m"]
        still = moved > ADVANCE_LIMIT
        rows.append((f"{case}: final run-out within {RUNOUT_TOLERANCE:.0%}",
                     f"{mod['final_runout_m'] * 100:.2f} cm at {mod['final_time_s']:g} s against "
                     f"{exp['final_runout_m'] * 100:.2f} cm ({err:+.0%}); the front moved "
                     f"{moved * 100:.2f} cm over the last {ADVANCE_WINDOW:g} s"
                     + (", still advancing" if still else ""),
                     abs(err) <= RUNOUT_TOLERANCE and not still))
        t90[case] = (mod["t90_s"], exp["t90_s"])
    if "dense" in t90 and "loose" in t90:
        ratio = t90["dense"][0] / t90["loose"][0]
        exp_ratio = t90["dense"][1] / t90["loose"][1]
        rows.append((f"dense at least {SLOWER:g} times slower than loose by t90",
                     f"{t90['dense'][0]:g} / {t90['loose'][0]:g} s = {ratio:.1f} times "
                     f"(experiment {exp_ratio:.1f})", ratio >= SLOWER))
    return rows


#: Window of the speed-against-accuracy chart (bench/accuracy_charts.py ``rondon``) [s]: it
#: holds the first front point of each packing (0.55 s dense, 0.64 s loose) and the first base
#: pressure point of each (1.13 s); the experiment has no pressure data before 1.1 s.
CHART_END = 1.15


def data_errors(series: dict, ref: dict, t_end: float) -> dict:
    """Relative errors of one run against the experiment at the data's times up to ``t_end``:
    ``runout`` (model run-out front - L0 against the shifted front file's, each point |m - e| /
    e; the file's first point, which fixes the shift, is left out) and ``pressure`` (base
    excess pore pressure, |m - e| / |e|); the model's series is
    interpolated linearly in time between its dumps. Returns {"runout": [(t, model, exp,
    error)], "pressure": [...]} (run-out in m, pressure in Pa)."""
    out = {"runout": [], "pressure": []}
    t_f, x_f = ref["front"]
    t_p, p = ref["pressure"]
    for t, x in zip(t_f[1:], x_f[1:]):      # the first point is the shift's origin (L0)
        if t <= t_end and t <= series["t"][-1]:
            e = x - ref["front_offset"] - L0
            m = float(np.interp(t, series["t"], series["front"])) - L0
            out["runout"].append((float(t), m, float(e), abs(m - e) / abs(e)))
    for t, v in zip(t_p, p):
        if t <= t_end and t <= series["t"][-1]:
            m = float(np.interp(t, series["t"], series["pressure"]))
            out["pressure"].append((float(t), m, float(v), abs(m - v) / abs(v)))
    return out


def chart_error(runs: dict, reference: str = DEFAULT_REFERENCE,
                t_end: float = CHART_END) -> dict:
    """The speed-against-accuracy chart's error of a dense/loose pair ``runs`` {case: output
    dir}: the mean of the relative errors of every data point up to ``t_end`` of both packings
    (:func:`data_errors`: run-out and base pressure); also each point's error as
    ``<case>_<quantity>_<t>``, the model's value there as ``..._model`` (m, Pa), the mean per
    quantity, and per case the peak base pressure and the run-out at the window's end."""
    points, model = {}, {}
    for case, folder in runs.items():
        series = model_series(read_run_dumps(folder, NAME))
        errs = data_errors(series, read_reference(reference, case), t_end)
        for quantity, rows in errs.items():
            for t, m, _, e in rows:
                points[f"{case}_{quantity}_{t:.3g}s"] = e
                model[f"{case}_{quantity}_{t:.3g}s_model"] = m
        model[f"{case}_peak_pressure_Pa"] = float(series["pressure"][np.argmax(np.abs(
            series["pressure"]))])
        model[f"{case}_runout_end_m"] = float(series["front"][-1] - L0)
    values = list(points.values())
    out = {"error": float(np.mean(values)) if values else float("nan")}
    for quantity in ("runout", "pressure"):
        mine = [v for k, v in points.items() if f"_{quantity}_" in k]
        out[f"{quantity}_error"] = float(np.mean(mine)) if mine else float("nan")
    out.update(points)
    out.update(model)
    return out


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dense", default=None, help="output directory of the dense run")
    parser.add_argument("--loose", default=None, help="output directory of the loose run")
    parser.add_argument("--reference", default=DEFAULT_REFERENCE,
                        help="folder of the digitised experiment (default: %(default)s)")
    parser.add_argument("--out", default=VALIDATION_DIR)
    parser.add_argument("--stem", default="rondon2011",
                        help="file name of the figure and the CSV, without suffix "
                             "(default: %(default)s)")
    return parser


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    runs = {c: getattr(args, c) for c in CASES if getattr(args, c)}
    if not runs:
        raise SystemExit("give --dense DIR and/or --loose DIR")
    have_ref = os.path.isdir(args.reference)
    if not have_ref:
        print(f"reference folder {args.reference} not found: model only")
    os.makedirs(args.out, exist_ok=True)
    plt = pyplot()
    fig, axes = plt.subplots(3, 2, figsize=(11, 10))
    rows = []
    refs, runs_series = {}, {}    # per case, for the targets
    for col, case in enumerate(CASES):
        ax_f, ax_p, ax_h = axes[0, col], axes[1, col], axes[2, col]
        ref = read_reference(args.reference, case) if have_ref else None
        if ref is not None:
            refs[case] = ref
            t_f, x_f = ref["front"]
            off = ref["front_offset"]
            ax_f.plot(t_f, (x_f - off) * 100, "ko", ms=4,
                      label=f"experiment (front file - {off * 100:.2f} cm)")
            toes = [(t, x[-1]) for t, (x, _) in ref["profiles"].items()]
            ax_f.plot([a for a, _ in toes], [b * 100 for _, b in toes], "ks", mfc="none",
                      label="experiment (profiles' toe)")
            for t, toe, stored in front_check(ref):
                print(f"{case}: t = {t:5.2f} s  profile toe {toe * 100:6.2f} cm  front file "
                      f"{stored * 100:6.2f} cm (ahead by {(stored - toe) * 100:5.2f} cm; "
                      f"shifted: {(stored - off - toe) * 100:5.2f} cm)")
            t_p, p = ref["pressure"]
            ax_p.plot(t_p, p, "ko", ms=4, label="experiment")
            for i, (t, (x, h)) in enumerate(ref["profiles"].items()):
                ax_h.plot(x * 100, h * 100, "o", ms=3, color=f"C{i}", label=f"exp. {t:g} s")
            s = summary(t_f, x_f - off, t_p, p)
            rows.append({"case": case, "source": "experiment", **s})
        if case in runs:
            dumps = read_run_dumps(runs[case], NAME)
            series = model_series(dumps)
            runs_series[case] = series
            ax_f.plot(series["t"], series["front"] * 100, "b-", label="model")
            ax_p.plot(series["t"], series["pressure"], "b-",
                      label=f"model (x = {PROBE_X * 100:g} cm)")
            times = sorted(ref["profiles"]) if ref is not None else [d["time"] for d in dumps[::5]]
            have = np.array([d["time"] for d in dumps])
            for i, t in enumerate(times):
                k = int(np.argmin(np.abs(have - t)))
                if abs(have[k] - t) > 0.05 * max(t, 1.0):
                    continue
                x, h = model_profile(dumps[k])
                h = np.where(h > 0.0, h, np.nan)         # empty columns: no line
                ax_h.plot(x * 100, h * 100, "-", color=f"C{i}", label=f"model {have[k]:g} s")
            s = summary(series["t"], series["front"], series["t"], series["pressure"])
            rows.append({"case": case, "source": "model", **s})
            for t, f, p, k in zip(series["t"], series["front"], series["pressure"],
                                  series["packing"]):
                print(f"{case} model: t = {t:6.2f} s  front {f * 100:6.2f} cm  "
                      f"base excess pressure {p:8.1f} Pa  solid fraction {k['mean']:.4f}  "
                      f"suspended {k['suspended']:.3f}  at critical packing {k['critical']:.3f}")
        ax_f.set_title(f"{case}: L0 = {L0 * 100:g} cm, H0 = {H0[case] * 100:g} cm")
        ax_f.set_xlabel("t [s]")
        ax_f.set_ylabel("front [cm from the wall]")
        ax_p.set_xlabel("t [s]")
        ax_p.set_ylabel("base excess pore pressure [Pa]")
        ax_p.axhline(0.0, color="0.6", lw=0.5)
        ax_h.set_xlabel("x [cm]")
        ax_h.set_ylabel("h [cm]")
        for ax in (ax_f, ax_p, ax_h):
            ax.legend(fontsize=7)
    fig.tight_layout()
    print(save_figure(fig, os.path.join(args.out, args.stem + ".png")))
    path = os.path.join(args.out, args.stem + ".csv")
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v)
                             for k, v in row.items()})
    for row in rows:
        print(row)
    print(path)
    if have_ref:
        print("targets (docs/validation/rondon2011.md):")
        for target, measured, hit in targets(runs_series, refs):
            print(f"  {'hit   ' if hit else 'missed'}  {target}: {measured}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
