"""Grilli et al. (2017) test 17: the diagnostic and ladder runs of docs/validation/grilli2017.md.

Usage:  python -m postproc.mpmice_grilli2017_cases --list
        python -m postproc.mpmice_grilli2017_cases CASE [CASE ...] [--cells MM] [--end T]
            [--root DIR] [--nranks N] [--nice N] [--dry-run]

Each case is namelists/mpmice_grilli2017_2d.nml with a few changes (below), written to
<root>/<case>_<cells>mm/grilli.nml and run there with `mpirun -n N build/bin/mpmice` (the
beads' E = 1 MPa in every case, as in the comparison runs: the step is the solid's P wave;
end time --end, default 0.7 s: the slide over the six shapes' times). A case whose folder
already holds a finished run is skipped. Changes that `--set` cannot make (the `&region`
groups, the domain's height and the bed polygon that follows it) are made on the namelist's
text; the rest are `--set` options, printed with the command.

Cases (each isolates one candidate cause of the slow slide; the scene's values in brackets):
  base        the scene as shipped (bed mu 0.41, Forchheimer a = 150, b = 1.75, Mohr-Coulomb
              phi = 22.3 deg, psi = 0, porosity 0.39, air layer 0.11 m, instant release)
  dry         no water (the regions' air and water fractions swapped): granular model + bed only
  dry_mu0     dry and a frictionless bed (contact_friction = 0)
  mu0         bed friction 0 [0.41]
  mu025       bed friction 0.25 [0.41]
  mu030       bed friction 0.30 [0.41]
  mu033       bed friction 0.33 [0.41]: the contact's measured excess at 20 mm (+0.08) taken
              off, so that the bed's effective friction is ~0.41
  noslip      rigid_contact = 'no_slip' [friction]: the beads stick to the bed's nodes
  nodrag      drag_law = 'constant', drag_coefficient = 0 [forchheimer]: no fluid-solid drag
  darcy       forchheimer_b = 0 [1.75]: the linear (Darcy) part of the Ergun law only
  kozeny      drag_law = 'kozeny_carman' [forchheimer] (a = 180, b = 0)
  ergun_b05   forchheimer_b = 0.5 [1.75]
  surfpar     surface_drag_parallel = .true. [.false.]: the drag of the cells crossed by the
              slide's surface in parallel (flow along the surface), not in series
  phi30       friction_angle = 30 deg [22.3]
  phi15       friction_angle = 15 deg [22.3]
  phi5        friction_angle = 5 deg [22.3]: a nearly cohesionless-fluid packing that spreads
  dilate      dilation_angle = 5 deg [0]: a dense packing that dilates in shear
  css         model = 'critical_state_sand' with the glass-bead rheology of the Rondon scenes
              (mu1 0.38, mu2 0.7, J0 0.005, phi_m 0.585, K 4.09, eta_f 1e-3 Pa s, loosest
              packing 0.53): the packing 0.61 is denser than phi_m and dilates in shear
  css_mu025   css and bed friction 0.25
  loose       porosity 0.42 (packing 0.58) [0.39]
  air007      air layer 0.07 m (domain top 0.40 m) [0.11 m, top 0.44 m]
  air019      air layer 0.19 m (domain top 0.52 m)
Several cases may be combined with '+': 'mu025+darcy'.
"""
from __future__ import annotations

import argparse
import os
import shlex
import subprocess
import sys
import time

from postproc.run_case import ROOT

NAMELIST = os.path.join(ROOT, "namelists", "mpmice_grilli2017_2d.nml")
BEADS_E = "&solid name = 'beads', youngs_modulus = 1.0e6 /"
CSS = ("&solid name = 'beads', model = 'critical_state_sand', friction_mu1 = 0.38, "
       "friction_mu2 = 0.7, viscous_j0 = 0.005, critical_solid_fraction = 0.585, "
       "dilatancy_constant = 4.09, fluid_viscosity = 1.0e-3, max_porosity = 0.47, "
       "poisson_ratio = 0.3 /")

#: case -> (list of --set texts, function text -> text)
CASES: dict[str, tuple[list[str], object]] = {}


def _swap_regions(text: str) -> str:
    """Water fraction 0 and air 1 below the still level (the `&region` groups)."""
    water = "  material = 'water'\n  lower = 0.0, 0.0, 0.0\n  upper = 6.0, 0.33, 1.0\n"
    air = "  material = 'air'\n  lower = 0.0, 0.0, 0.0\n  upper = 6.0, 0.33, 1.0\n"
    if text.count(water + "  volume_fraction = 1.0") != 1 or \
            text.count(air + "  volume_fraction = 0.0") != 1:
        raise RuntimeError("the scene's &region groups are not the expected ones")
    text = text.replace(water + "  volume_fraction = 1.0", water + "  volume_fraction = 9.9")
    text = text.replace(air + "  volume_fraction = 0.0", air + "  volume_fraction = 1.0")
    return text.replace(water + "  volume_fraction = 9.9", water + "  volume_fraction = 0.0")


def _domain_top(top: float):
    """The domain's height `top` [m]: the grid, the solids' boxes and the bed polygon (the slope
    y = 0.756 - 0.7 x cut at the domain's top, or at x = 0.4 when the top is above y(0.4))."""
    def edit(text: str) -> str:
        for old in ("upper = 6.0, 0.44, 0.02", "polygon_x = 0.4, 0.4, 0.45143, 1.08",
                    "polygon_y = 0.0, 0.44, 0.44, 0.0"):
            if old not in text:
                raise RuntimeError(f"'{old}' not found in the scene")
        text = text.replace("upper = 6.0, 0.44, 0.02", f"upper = 6.0, {top:.4f}, 0.02")
        y04 = 0.756 - 0.7 * 0.4
        if top < y04:
            x_top = (0.756 - top) / 0.7
            text = text.replace("polygon_x = 0.4, 0.4, 0.45143, 1.08",
                                f"polygon_x = 0.4, 0.4, {x_top:.5f}, 1.08")
            text = text.replace("polygon_y = 0.0, 0.44, 0.44, 0.0",
                                f"polygon_y = 0.0, {top:.4f}, {top:.4f}, 0.0")
        else:
            text = text.replace("npoints = 4\n  polygon_x = 0.4, 0.4, 0.45143, 1.08",
                                "npoints = 3\n  polygon_x = 0.4, 0.4, 1.08")
            text = text.replace("polygon_y = 0.0, 0.44, 0.44, 0.0",
                                f"polygon_y = 0.0, {y04:.4f}, 0.0")
        return text
    return edit


def _same(text: str) -> str:
    return text


def _register():
    beads = "&solid name = 'beads', "
    table = {
        "base": ([], _same),
        "dry": ([], _swap_regions),
        "dry_mu0": (["&mpm contact_friction = 0.0 /"], _swap_regions),
        "mu0": (["&mpm contact_friction = 0.0 /"], _same),
        "mu025": (["&mpm contact_friction = 0.25 /"], _same),
        "mu030": (["&mpm contact_friction = 0.30 /"], _same),
        "mu033": (["&mpm contact_friction = 0.33 /"], _same),
        "noslip": (["&mpm rigid_contact = 'no_slip' /"], _same),
        "nodrag": ([beads + "drag_law = 'constant', drag_coefficient = 0.0 /"], _same),
        "darcy": ([beads + "forchheimer_b = 0.0 /"], _same),
        "kozeny": ([beads + "drag_law = 'kozeny_carman' /"], _same),
        "ergun_b05": ([beads + "forchheimer_b = 0.5 /"], _same),
        "surfpar": ([beads + "surface_drag_parallel = .true. /"], _same),
        "phi30": ([beads + "friction_angle = 30.0 /"], _same),
        "phi15": ([beads + "friction_angle = 15.0 /"], _same),
        "phi5": ([beads + "friction_angle = 5.0 /"], _same),
        "dilate": ([beads + "dilation_angle = 5.0 /"], _same),
        "css": ([CSS], _same),
        "css_mu025": ([CSS, "&mpm contact_friction = 0.25 /"], _same),
        "loose": ([beads + "porosity = 0.42 /"], _same),
        "air007": ([], _domain_top(0.40)),
        "air019": ([], _domain_top(0.52)),
    }
    CASES.update(table)


_register()


def case_inputs(case: str, cells_mm: float) -> tuple[str, list[str]]:
    """(namelist text, --set options) of a case ('+'-combined) at cell size cells_mm [mm]."""
    with open(NAMELIST, encoding="utf-8") as f:
        text = f.read()
    sets = [BEADS_E]
    top = 0.44
    for part in case.split("+"):
        if part not in CASES:
            raise SystemExit(f"unknown case '{part}' (--list)")
        extra, edit = CASES[part]
        text = edit(text)
        sets += extra
        if part.startswith("air"):
            top = {"air007": 0.40, "air019": 0.52}[part]
    nx = round(5.6 / (cells_mm * 1e-3))
    ny = round(top / (cells_mm * 1e-3))
    sets.append(f"&grid ncells = {nx}, {ny}, 1 /")
    return text, sets


def run_case(case: str, cells_mm: float, end: float, root: str, nranks: int = 1,
             niceness: int = 10, dry_run: bool = False) -> tuple[str, int | None, float]:
    """Write and run one case; return (its output folder, the exit status, the wall time [s] of
    the call); (folder, None, nan) when a finished run was there already or with dry_run."""
    tag = f"{case.replace('+', '_')}_{cells_mm:g}mm"
    out = os.path.abspath(os.path.join(root, tag))
    text, sets = case_inputs(case, cells_mm)
    status = os.path.join(out, "grilli.status")
    if os.path.isfile(status) and "state = finished" in open(status, encoding="utf-8").read():
        print(f"{tag}: finished run present, skipped")
        return out, None, float("nan")
    os.makedirs(out, exist_ok=True)
    nml = os.path.join(out, "grilli.nml")
    with open(nml, "w", encoding="utf-8") as f:
        f.write(text)
    sets.append(f"&run output_dir = '{out}', end_time = {end:g}, overwrite = .true. /")
    exe = os.environ.get("MPMICE_EXE", os.path.join(ROOT, "build", "bin", "mpmice"))
    cmd = ["nice", "-n", str(niceness)]
    if nranks > 1:
        cmd += ["mpirun", "-n", str(nranks)]
    cmd += [exe, nml]
    for s in sets:
        cmd += ["--set", s]
    print(f"{tag}: {shlex.join(cmd)}", flush=True)
    if dry_run:
        return out, None, float("nan")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    start = time.perf_counter()
    with open(out + ".log", "w", encoding="utf-8") as log:
        result = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, check=False)
    wall = time.perf_counter() - start
    print(f"{tag}: exit status {result.returncode}, {wall:.0f} s (log {out}.log)", flush=True)
    return out, result.returncode, wall


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--cells", type=float, default=20.0, help="cell size [mm]")
    parser.add_argument("--end", type=float, default=0.7, help="model end time [s]")
    parser.add_argument("--root", default=os.path.join(ROOT, "output", "grilli_cases"))
    parser.add_argument("--nranks", type=int, default=1)
    parser.add_argument("--nice", type=int, default=10)
    parser.add_argument("--dry-run", action="store_true", help="write and print, do not run")
    args = parser.parse_args(argv)
    if args.list or not args.cases:
        print(__doc__)
        return 0
    for case in args.cases:
        run_case(case, args.cells, args.end, args.root, args.nranks, args.nice, args.dry_run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
