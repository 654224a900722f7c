"""Closed-box conservation of the ICE scene: sloshing water under air (namelists/ice_slosh.nml).

Usage:  python -m postproc.ice_conservation [--out docs/validation] [--nranks 1]

Runs the scene (walls everywhere, dumps every 5 ms), sums per dump the mass of each fluid and the
total energy sum rho_bar V (cv T + |u|^2/2 - g.x), and prints the largest relative change between
successive dumps divided by the steps between them (the change per step), also for the mass.
Writes ice_conservation.csv into --out.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from postproc.figures import parse_study_args, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_slosh.nml")
CV = {"air": 717.5, "water": 4145.4}
GRAVITY = np.array([0.0, -9.81, 0.0])


def totals(dump: dict, fluids) -> tuple[dict, float]:
    """Mass per fluid [kg] and total energy [J] of a dump."""
    dx = np.asarray(dump["attrs"]["dx"], dtype=float).reshape(3)
    vol = float(np.prod(dx))
    x, y, z = np.meshgrid(*cell_centres(dump), indexing="ij")
    potential = -(GRAVITY[0] * x + GRAVITY[1] * y + GRAVITY[2] * z)
    masses, energy = {}, 0.0
    for f in fluids:
        rho = dump["cell"][f"{f}/density"]
        ke = 0.5 * sum(dump["cell"][f"{f}/velocity_{c}"] ** 2 for c in "xyz")
        masses[f] = float(np.sum(rho) * vol)
        energy += float(np.sum(rho * (CV[f] * dump["cell"][f"{f}/temperature"] + ke + potential))
                        * vol)
    return masses, energy


def study(workdir: str, nranks: int = 1) -> list[dict]:
    """Per-dump rows: step, masses, energy, and the relative changes per step since the last."""
    out = os.path.join(workdir, "slosh")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}', output_interval = 0.005 /"],
               nranks=nranks, cwd=workdir)
    rows = []
    for path in list_dumps(out, "slosh"):
        d = read_dump(path)
        masses, energy = totals(d, ["air", "water"])
        rows.append({"step": d["step"], "masses": masses, "energy": energy})
    for prev, row in zip(rows, rows[1:]):
        steps = max(row["step"] - prev["step"], 1)
        row["energy_change_per_step"] = abs(row["energy"] / prev["energy"] - 1.0) / steps
        row["mass_change_per_step"] = max(abs(row["masses"][f] / prev["masses"][f] - 1.0)
                                          for f in prev["masses"] if prev["masses"][f] > 0) / steps
    return rows


def main(argv=None) -> int:
    parser = study_parser(__doc__, nranks=True)
    args = parse_study_args(parser, argv)
    with tempfile.TemporaryDirectory() as work:
        rows = study(work, args.nranks)
    print("  step   mass change/step   energy change/step")
    for row in rows[1:]:
        print(f"{row['step']:6d}   {row['mass_change_per_step']:16.3e}   "
              f"{row['energy_change_per_step']:18.3e}")
    with open(os.path.join(args.out, "ice_conservation.csv"), "w") as f:
        f.write("step,mass_change_per_step,energy_change_per_step\n")
        for row in rows[1:]:
            f.write(f"{row['step']},{row['mass_change_per_step']:.4e},"
                    f"{row['energy_change_per_step']:.4e}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
