"""The fluid's pressure force on a rigid body (`<name>_contact_force.csv`, columns
`<solid>_fluid_fx/_fy/_fz`; docs/mpmice.md "Forces on the rigid bodies"): a rigid block resting
on the floor of a tank of still water (10 x 10 cells of 0.1 m, 0.04 m deep, water to the open
top at 101325 Pa, hydrostatic start, 0.01 s). The analytic force is F_x = 0 and
F_y = -p(h) w D: the water's pressure at the block's top (p_top + the integral of rho g over the
column above it, rho the water density of the run's dump) over its width w and the depth
D = 0.04 m; nothing from below (the floor is a domain face: no fluid there). Each run < 1 s."""
import numpy as np
import pytest

from postproc.mpmice_io import list_dumps, read_dump

G = 9.81
P_TOP = 101325.0  # Pa, the open top
DEPTH = 0.04      # m
DY = 0.1          # m, the cells

NAMELIST = """
&run
  name = 'still'
  scene = 'mpmice'
  end_time = 0.01
  output_interval = 0.01
/
&grid
  ncells = 10, 10, 1
  lower = 0.0, 0.0, 0.0
  upper = 1.0, 1.0, 0.04
/
&time
  cfl = 0.5
  dt_init = 1.0e-4
  dt_max = 1.0e-3
/
&numerics
  shape_function = 'gimp'
/
&solver
  tolerance = 1.0e-12
/
&physics
  gravity = 0.0, -9.81, 0.0
  reference_pressure = 101325.0
  hydrostatic_init = .true.
/
&ice
  outer_tolerance = 1.0e-9
/
&mpm
  rigid_contact = 'friction'
  contact_friction = 0.0
/
&fluid
  name = 'water'
  eos = 'linear_water'
  heat_capacity_cv = 4181.0
  reference_density = 999.8
  reference_temperature = 283.15
  bulk_modulus = 2.0e8
  thermal_expansion = 0.18
  volume_fraction = 1.0
  temperature = 283.15
  viscosity = 1.0e-3
/
&solid
  name = 'block'
  model = 'rigid'
  density = 2650.0
  drag_law = 'impermeable'
  shape = 'box'
  lower = 0.3, 0.0, 0.0
  upper = 0.5, 0.2, 0.04
  particles_per_cell = 2, 2, 1
  temperature = 283.15
/
&boundary
  face = 'x-'
  fluid = 'wall'
  solid = 'fixed'
/
&boundary
  face = 'x+'
  fluid = 'wall'
  solid = 'fixed'
/
&boundary
  face = 'y-'
  fluid = 'wall'
  solid = 'fixed'
/
&boundary
  face = 'y+'
  fluid = 'pressure'
  pressure = 101325.0
  solid = 'free'
/
"""


def _run(run_mpmice, tmp_path, tag, nranks=1, block=(0.3, 0.5, 0.2), p_top=P_TOP, end_time=0.01):
    """Run the tank with the block [x0, x1] x [0, h]; returns (force columns, last dump)."""
    nml = tmp_path / "still.nml"
    nml.write_text(NAMELIST)
    out = str(tmp_path / tag)
    x0, x1, h = block
    run_mpmice([str(nml), "--set", f"&run output_dir = '{out}', end_time = {end_time}, "
                f"output_interval = {end_time} /", "--set",
                f"&solid name = 'block', lower = {x0}, 0.0, 0.0, upper = {x1}, {h}, 0.04 /",
                "--set", f"&boundary face = 'y+', pressure = {p_top} /"],
               nranks=nranks, cwd=str(tmp_path), timeout=120, check=True)
    data = np.genfromtxt(f"{out}/still_contact_force.csv", delimiter=",", names=True)
    force = {key: np.atleast_1d(data[key]) for key in data.dtype.names}
    return force, read_dump(list_dumps(out, "still")[-1])


def _analytic_fy(dump, block, p_top=P_TOP):
    """-p(h) w D with p(h) = p_top + the integral of rho g from the block's top h to the top of
    the tank, rho the water density of the dump's cells in a free column (x = 0.85 m)."""
    x0, x1, h = block
    rho = np.squeeze(dump["cell"]["water/density"])[8, :]
    centres = (np.arange(rho.size) + 0.5) * DY
    share = np.clip((centres + 0.5 * DY - h) / DY, 0.0, 1.0)  # of each cell above h
    return -(p_top + np.sum(share * rho * G * DY)) * (x1 - x0) * DEPTH


def test_block_on_the_floor_in_still_water_feels_the_water_above_it(run_mpmice, tmp_path):
    """Cell-aligned block 0.2 m x 0.2 m: every step F_y = -p(h) w D to 3e-13 (measured 2.4e-14:
    the hydrostatic start is exact and stays at rest; -873.37 N per 0.04 m), F_x = 0 to 1e-12 of
    F_y (measured 8e-14), no contact force (no deformable solid)."""
    block = (0.3, 0.5, 0.2)
    f, dump = _run(run_mpmice, tmp_path, "aligned", block=block)
    assert len(f["time"]) == dump["step"] and f["time"][-1] == pytest.approx(0.01)
    fy = _analytic_fy(dump, block)
    assert fy == pytest.approx(-873.37, abs=0.01)
    assert np.all(np.abs(f["block_fluid_fy"] / fy - 1.0) < 3e-13), (f["block_fluid_fy"], fy)
    assert np.all(np.abs(f["block_fluid_fx"]) < 1e-12 * abs(fy)), f["block_fluid_fx"]
    assert np.all(f["block_fluid_fz"] == 0.0)
    for key in ("block_fx", "block_fy", "block_fz"):
        assert np.all(f[key] == 0.0), key


def test_block_with_half_cells_in_still_water(run_mpmice, tmp_path):
    """Block 0.25 m x 0.25 m: its right and top cells are half filled (wall cells whose own
    pressure the force steps over, docs/mpmice.md) and the corner a quarter. The faces' shares
    0.5 p(0.2 m) + 0.5 p(0.3 m) give p(0.25 m) in a linear profile: F_y = -p(h) w D to 3e-8
    (measured 8.9e-9, -1086.81 N: the water's compressibility makes the profile slightly
    nonlinear), F_x = 0 to 1e-12 of F_y (measured 7e-14)."""
    block = (0.3, 0.55, 0.25)
    f, dump = _run(run_mpmice, tmp_path, "half", block=block)
    fy = _analytic_fy(dump, block)
    assert np.all(np.abs(f["block_fluid_fy"] / fy - 1.0) < 3e-8), (f["block_fluid_fy"], fy)
    assert np.all(np.abs(f["block_fluid_fx"]) < 1e-12 * abs(fy)), f["block_fluid_fx"]


@pytest.mark.parametrize("block", [(0.3, 0.5, 0.2), (0.3, 0.55, 0.25)],
                         ids=["aligned", "half_cells"])
def test_force_follows_the_water_not_the_blocks_own_cells(run_mpmice, tmp_path, block):
    """The open top raised to 111325 Pa: the water takes the 10 kPa within a few sound crossings,
    the block's own cells (and its half-filled wall cells) keep their initial pressure (their
    faces move with the body). At t = 0.05 s F_y = -p(h) w D to 5e-5 (measured 1.4e-5 of
    -953.36 N aligned, 1.7e-5 of -1186.79 N with half cells) and F_x = 0 to 2e-5 of F_y (measured
    2.4e-6, 6.2e-6: the sound waves' remains). Eq. 37's face pressure, the mean of the water's
    and the block's cells, would give ~40 N (4 %) less on the aligned block; the half cells' own
    pressure instead of the water's beyond them gave 1.7 % less F_y and F_x = 40 N."""
    f, dump = _run(run_mpmice, tmp_path, "pressurised", block=block, p_top=P_TOP + 1.0e4, end_time=0.05)
    fy = _analytic_fy(dump, block, p_top=P_TOP + 1.0e4)
    assert f["block_fluid_fy"][-1] / fy - 1.0 == pytest.approx(0.0, abs=5e-5), \
        (f["block_fluid_fy"][-1], fy)
    assert abs(f["block_fluid_fx"][-1]) < 2e-5 * abs(fy), f["block_fluid_fx"][-1]
    inside = np.squeeze(dump["cell"]["pressure"])[3:5, 0:2]
    assert np.all(inside < P_TOP + 1.0e4)  # the block's own cells did not follow


@pytest.mark.mpi
def test_fluid_force_on_two_ranks_equals_one_rank(run_mpmice, tmp_path):
    """The half-cell block on 2 ranks (blocks 2 x 1: the rank boundary x = 0.5 m has the block's
    full cells on rank 0 and its half cells on rank 1, so the force there needs the fractions of
    the ghost cells and the step over the half cell) equals the 1-rank force to 1e-12 of F_y
    (measured 2e-16; the aligned block, whose right face is that boundary: identical; the bound
    is the pressure solve's tolerance, which this still water does not reach)."""
    block = (0.3, 0.55, 0.25)
    one, _ = _run(run_mpmice, tmp_path, "one", block=block)
    two, _ = _run(run_mpmice, tmp_path, "two", nranks=2, block=block)
    assert len(one["time"]) == len(two["time"])
    for key in ("block_fluid_fx", "block_fluid_fy"):
        assert np.allclose(two[key], one[key], rtol=0.0,
                           atol=1e-12 * np.max(np.abs(one["block_fluid_fy"]))), key
