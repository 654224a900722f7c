"""What sets a run's explicit step: the solids' particle wave speeds, per dump.

The code's stable step for a deforming solid is dt = cfl h / max_p (c_p + |v_p|) over all
particles (docs/mpmice.md "Which limit sets the step"), with the particle's drained P-wave speed
c_p^2 = (lambda + 2 mu) max(J, 1) / rho_0 for the rate models (linear elastic, Mohr-Coulomb, the
critical-state sand with a constant modulus), rho_0 = (1 - n) rho_grains and J = V / V_0 =
V rho_0 / m; a particle past the loosest packing (J > j_loose, `&solid max_porosity`) has none.

Usage:  python -m postproc.wave_speed RUN_DIR [--solid NAME] [--times T ...]

Per dump and solid it prints the speeds c + |v| [m/s]: the largest (the one that sets the step),
the 99.9th percentile and the median over the particles; the share of particles dilated past
J = 1.5; and the largest over the cells of a cell-averaged speed, sqrt(sum m c^2 / sum m) plus the
cell's largest |v|. That last number is what a step from the mass-weighted stiffness of a cell
(instead of its stiffest particle) would take: where it equals the particle maximum, the
dilated particles fill whole cells and such a rule would not lengthen the step.
"""
from __future__ import annotations

import argparse

import numpy as np

from postproc.analytic import oedometer_modulus
from postproc.mpmice_io import list_dumps, read_dump
from postproc.namelist import parse_namelist_groups
from postproc.run_files import pick_dumps, run_name

#: models whose wave speed is the rate form (lambda + 2 mu) max(J, 1) / rho_0
RATE_MODELS = ("linear_elastic", "mohr_coulomb", "critical_state_sand")
#: J above which a particle counts as dilated in the table
DILATED_J = 1.5


def solid_params(dump: dict, name: str) -> dict | None:
    """rho_0 [kg/m^3], the P-wave modulus lambda + 2 mu [Pa] and j_loose of solid `name` from
    the dump's resolved input; None for a model this tool does not cover (rigid, Neo-Hookean,
    Cam-Clay, a pressure-dependent modulus)."""
    text = dump["attrs"].get("namelist")
    groups = parse_namelist_groups(text) if isinstance(text, str) else []
    for group, g in groups:
        if group != "solid" or g.get("name") != name:
            continue
        if str(g.get("model", "")).lower() not in RATE_MODELS:
            return None
        if float(g.get("modulus_exponent", 0.0)) != 0.0:
            return None
        e, nu, n = float(g["youngs_modulus"]), float(g["poisson_ratio"]), float(g["porosity"])
        n_max = float(g.get("max_porosity", 1.0))
        return {"rho0": (1.0 - n) * float(g["density"]),
                "modulus": oedometer_modulus(e, nu),
                "j_loose": (1.0 - n) / (1.0 - n_max) if n_max < 1.0 else np.inf}
    return None


def particle_speeds(parts: dict, par: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(c, |v|, J) per particle."""
    jac = parts["volume"] * par["rho0"] / parts["mass"]
    c = np.where(jac > par["j_loose"], 0.0,
                 np.sqrt(par["modulus"] * np.maximum(jac, 1.0) / par["rho0"]))
    speed = np.sqrt(sum(parts[f"velocity_{a}"] ** 2 for a in "xyz" if f"velocity_{a}" in parts))
    return c, speed, jac


def cell_speed(parts: dict, c: np.ndarray, v: np.ndarray, dump: dict) -> float:
    """Largest over the cells of sqrt(sum m c^2 / sum m) + the cell's largest |v|."""
    attrs = dump["attrs"]
    lower, dx = np.asarray(attrs["lower"], float), np.asarray(attrs["dx"], float)
    ncells = np.asarray(attrs["ncells"], int)
    idx = [np.clip(((parts[a] - lower[d]) / dx[d]).astype(int), 0, ncells[d] - 1)
           for d, a in enumerate("xyz")]
    cell = np.ravel_multi_index(idx, ncells)
    _, inv = np.unique(cell, return_inverse=True)
    mass = np.bincount(inv, parts["mass"])
    mean_c2 = np.bincount(inv, parts["mass"] * c ** 2) / mass
    vmax = np.zeros(mass.size)
    np.maximum.at(vmax, inv, v)
    return float(np.max(np.sqrt(mean_c2) + vmax))


def dump_rows(dump: dict, solids=None) -> list[dict]:
    """One row per covered solid of `dump` (see the module docstring)."""
    rows = []
    for name, parts in dump["particles"].items():
        if solids and name not in solids or parts["mass"].size == 0:
            continue
        par = solid_params(dump, name)
        if par is None:
            continue
        c, v, jac = particle_speeds(parts, par)
        total = c + v
        rows.append({"time": dump["time"], "solid": name, "max": float(total.max()),
                     "p999": float(np.percentile(total, 99.9)),
                     "median": float(np.median(total)),
                     "dilated": float(np.mean(jac > DILATED_J)),
                     "cell_max": cell_speed(parts, c, v, dump)})
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--solid", action="append", default=[])
    parser.add_argument("--times", type=float, nargs="+", default=None)
    args = parser.parse_args(argv)
    paths = list_dumps(args.run_dir, run_name(args.run_dir))
    picked = list(range(len(paths))) if args.times is None else pick_dumps(paths, args.times)
    for n, i in enumerate(picked):
        dump = read_dump(paths[i])
        if n == 0:
            for name in args.solid:
                if name not in dump["particles"] or solid_params(dump, name) is None:
                    raise SystemExit(f"{args.run_dir}: no solid '{name}' with a rate model "
                                     f"({', '.join(RATE_MODELS)}, constant modulus) in the dumps")
            print(f"{'t [s]':>8} {'solid':>10} {'max c+|v|':>10} {'p99.9':>8} {'median':>8} "
                  f"{'J > 1.5':>8} {'cell max':>9}  [m/s]")
        for r in dump_rows(dump, args.solid):
            print(f"{r['time']:8.3f} {r['solid']:>10} {r['max']:10.1f} {r['p999']:8.1f} "
                  f"{r['median']:8.1f} {r['dilated']:8.2%} {r['cell_max']:9.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
