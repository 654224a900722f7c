"""1D channels with 'inflow' / 'outflow' / 'pressure' faces (ICE scene):
namelists/ice_channel_water.nml (water at rest, inflow u = 1 m/s at x-, 'pressure' face at x+)
and namelists/ice_channel_air.nml (uniform air flow at 1 m/s, inflow at x-, outflow at x+).

Usage:  python -m postproc.ice_channel [--nranks 1]

Both scenes run 200 fixed steps of 5 ms with a dump after every step. Per step n the domain mass
M = sum rho_bar V changes by dt A (rho_1 u_in - rho_N u_out): the inflow face carries the inner
cell's density (even ghosts, zero limited slope) at the prescribed u_in, the x+ face the last
cell's density at its face velocity, which is the last cell's velocity u_N at time n for an
outflow face (not corrected by the pressure) and, once the flow is steady, for a pressure face.
`measures` returns that balance residual relative to the inflow flux dt A rho_1 u_in, the largest
|u - 1| and the pressure range. Also runs the air channel starting from rest (pure-Neumann
pressure problem with a non-zero right-hand side) and prints everything.
"""
from __future__ import annotations

import argparse
import os
import tempfile

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

WATER = os.path.join(ROOT, "namelists", "ice_channel_water.nml")
AIR = os.path.join(ROOT, "namelists", "ice_channel_air.nml")
U_IN = 1.0     # m/s, &boundary velocity of the x- face
DT = 5.0e-3    # s, fixed step of both namelists


def run(workdir: str, namelist: str, tag: str, nranks: int = 1, sets=()) -> list[dict]:
    """All dumps (one per step) of a run of `namelist` with extra `--set` texts."""
    out = os.path.join(workdir, f"{tag}_{nranks}")
    args = [namelist, "--set", f"&run output_dir = '{out}' /"]
    for s in sets:
        args += ["--set", s]
    run_mpmice(args, nranks=nranks, cwd=workdir)
    return [read_dump(p) for p in list_dumps(out, "channel")]


def measures(dumps: list[dict], fluid: str, settled: int = 50) -> dict:
    """Mass balance per step (all steps and from step `settled` on), |u - 1| and pressure."""
    dx = np.asarray(dumps[0]["attrs"]["dx"], dtype=float).reshape(3)
    area = float(dx[1] * dx[2])
    rho = np.array([d["cell"][f"{fluid}/density"][:, 0, 0] for d in dumps])
    u = np.array([d["cell"][f"{fluid}/velocity_x"][:, 0, 0] for d in dumps])
    p = np.array([d["cell"]["pressure"][:, 0, 0] for d in dumps])
    mass = rho.sum(axis=1) * float(np.prod(dx))
    f_in = DT * area * rho[:-1, 0] * U_IN
    f_out = DT * area * rho[:-1, -1] * u[:-1, -1]
    balance = (np.diff(mass) - (f_in - f_out)) / f_in
    return {
        "steps": dumps[-1]["step"],
        "balance_all": float(np.max(np.abs(balance))),
        "balance_settled": float(np.max(np.abs(balance[settled:]))),
        "mass_change_settled": float(np.max(np.abs(np.diff(mass)[settled:] / mass[settled:-1]))),
        "flux_out_over_in_settled": float(np.max(np.abs(f_out[settled:] / f_in[settled:] - 1.0))),
        "flux_out_over_in_final": float(abs(f_out[-1] / f_in[-1] - 1.0)),
        "density_spread_final": float(np.ptp(rho[-1]) / np.mean(rho[-1])),
        "max_u_error_settled": float(np.max(np.abs(u[settled + 1:] - U_IN))),
        "max_u_error_final": float(np.max(np.abs(u[-1] - U_IN))),
        "p_min_final": float(p[-1].min()),
        "p_max_final": float(p[-1].max()),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nranks", type=int, default=1)
    args = parser.parse_args(argv)
    cases = [("water channel, inflow + pressure", WATER, "water", "water", ()),
             ("air channel, inflow + outflow, uniform", AIR, "air", "air", ()),
             ("air channel, inflow + outflow, from rest", AIR, "air_rest", "air",
              ("&fluid name = 'air', velocity = 0, 0, 0 /",))]
    with tempfile.TemporaryDirectory() as work:
        for title, namelist, tag, fluid, sets in cases:
            m = measures(run(work, namelist, tag, args.nranks, sets), fluid)
            print(title)
            for key, value in m.items():
                print(f"  {key:26s} {value:.6e}" if isinstance(value, float) else
                      f"  {key:26s} {value}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
