"""Interface compression (`&ice interface_compression`, ice_interface_compression): a water-air
interface smeared over three rows (water fractions 0.8 / 0.5 / 0.2 between water and air),
carried along itself at 1 m/s (periodic in x, no gravity, 20 x 20 cells of 5 cm, 40 fixed
steps of 2.5 ms). Without compression nothing crosses the rows, so the smear stays; with C = 1
the counter-flux moves water from the 0.2 row to the 0.8 row and air back. Measured: the
smear sum phi (1 - phi) per column falls from 0.57 to 0.2501 in 0.1 s (rows 1 / 0.5 / 0: the
sharpest a mid-cell interface can be, 0.25); unchanged without compression; water mass and
momentum conserved to round-off, fractions within [-6e-133, 1]."""
import os

import numpy as np
import pytest

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice

CASE = """&run name = 'band', scene = 'ice', output_dir = '{out}', end_time = 0.1,
  output_interval = 0.05 /
&grid ncells = 20, 20, 1, lower = 0, 0, 0, upper = 1.0, 1.0, 0.05,
  periodic = .true., .false., .false. /
&time cfl = 0.5, dt_init = 2.5e-3, dt_max = 2.5e-3 /
&solver tolerance = 1.0e-12 /
&ice outer_tolerance = 1.0e-9, interface_compression = {c} /
&fluid name = 'water', eos = 'linear_water', heat_capacity_cv = 4145.4,
  reference_density = 999.8, reference_temperature = 283.15, bulk_modulus = 2.0e9,
  thermal_expansion = 0.18, volume_fraction = 0.0, temperature = 293.15,
  velocity = 1.0, 0.0, 0.0 /
&fluid name = 'air', eos = 'ideal_gas', gamma = 1.4, heat_capacity_cv = 717.5,
  volume_fraction = 1.0, temperature = 293.15, velocity = 1.0, 0.0, 0.0 /
{regions}
&boundary face = 'y-', fluid = 'free_slip' /
&boundary face = 'y+', fluid = 'free_slip' /
"""
#: water fraction of the rows 0.40-0.45 .. 0.50-0.55 m; water below, air above
ROWS = [(0.0, 0.40, 1.0), (0.40, 0.45, 0.8), (0.45, 0.50, 0.5), (0.50, 0.55, 0.2)]


def _run(tmp_path, c, nranks=1, dims=""):
    regions = "\n".join(
        f"&region material = '{m}', lower = 0, {lo}, 0, upper = 1, {hi}, 1, "
        f"volume_fraction = {f if m == 'water' else 1.0 - f}, temperature = 293.15, "
        "velocity = 1, 0, 0 /"
        for lo, hi, f in ROWS for m in ("water", "air"))
    out = os.path.join(str(tmp_path), f"c{c}_{nranks}")
    path = os.path.join(str(tmp_path), f"band_{c}.nml")
    with open(path, "w") as f:
        f.write(CASE.format(out=out, c=c, regions=regions))
    args = [path] + (["--set", f"&grid dims = {dims} /"] if dims else [])
    run_mpmice(args, nranks=nranks, cwd=str(tmp_path))
    return [read_dump(p) for p in list_dumps(out, "band")]


def _smear(d):
    phi = d["cell"]["water/volume_fraction"][:, :, 0]
    return float(np.sum(phi * (1.0 - phi))) / phi.shape[0]


def test_compression_sharpens_a_smeared_interface(tmp_path):
    """C = 0: the smear stays (1e-9); C = 1: it falls to within 1 % of the sharpest, 0.25 per
    column, water mass and x momentum conserved to 1e-12, fractions in [0, 1] (traces of
    1e-12 below) and summing to 1 to 1e-9."""
    plain = _run(tmp_path, 0.0)
    sharp = _run(tmp_path, 1.0)
    s0 = _smear(plain[0])
    assert s0 == pytest.approx(0.16 + 0.25 + 0.16, rel=1e-6)
    assert abs(_smear(plain[-1]) / s0 - 1.0) < 1e-9
    assert 0.25 <= _smear(sharp[-1]) < 0.2525, _smear(sharp[-1])
    for d in sharp:
        w = d["cell"]["water/volume_fraction"]
        a = d["cell"]["air/volume_fraction"]
        assert w.min() >= -1e-12 and w.max() <= 1.0
        assert np.max(np.abs(w + a - 1.0)) < 1e-9
    mass = [d["cell"]["water/density"].sum() for d in sharp]
    assert abs(mass[-1] / mass[0] - 1.0) < 1e-12
    mom = [sum((d["cell"][f"{m}/density"] * d["cell"][f"{m}/velocity_x"]).sum()
               for m in ("water", "air")) for d in sharp]
    assert abs(mom[-1] / mom[0] - 1.0) < 1e-12


@pytest.mark.mpi
def test_compression_rank_invariant(tmp_path):
    """The same band on 2 ranks split across the interface (rank boundary at y = 0.5 m, inside
    the smear): fractions equal to the 1-rank run to 1e-12."""
    one = _run(tmp_path, 1.0)
    two = _run(tmp_path, 1.0, nranks=2, dims="1, 2, 1")
    assert len(one) == len(two)
    for a, b in zip(one, two):
        x, y = a["cell"]["water/volume_fraction"], b["cell"]["water/volume_fraction"]
        assert np.max(np.abs(x - y)) < 1e-12
