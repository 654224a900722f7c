"""Coupled scene (`mpmice`) on several ranks and in more dimensions than the physics needs:
decomposition invariance (1, 2, 4 ranks), a 2D column equal to the 1D one, and a bitwise-identical
continuation from a checkpoint."""
import os

import h5py
import numpy as np
import pytest

from postproc.dump_compare import (assert_dumps_identical, assert_field_close,
                                   assert_particles_close)
from postproc.mpm_common import particles
from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT, run_into, run_mpmice

TERZAGHI = os.path.join(ROOT, "namelists", "mpmice_terzaghi_1d.nml")
DARCY = os.path.join(ROOT, "namelists", "mpmice_darcy_1d.nml")
P_REF = 101325.0
P0 = 1.0e4

#: side walls that turn the 1D column into a 2D one with the same physics
SIDE_WALLS = """
&boundary
  face = 'x-'
  fluid = 'free_slip'
  solid = 'roller'
/
&boundary
  face = 'x+'
  fluid = 'free_slip'
  solid = 'roller'
/
"""


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _run(tmp_path, namelist, label, nranks, *sets):
    out = str(tmp_path / label)
    run_into(out, namelist, *sets, nranks=nranks, cwd=str(tmp_path))
    return out


def _fields(path, solid):
    with h5py.File(path) as f:
        cells = {k: f[k][...] for k in ("cell/pressure", "cell/water/velocity_x",
                                        "cell/water/velocity_y", "cell/solid_volume_fraction")}
        order = np.lexsort((f[f"particles/{solid}/x"][...], f[f"particles/{solid}/y"][...]))
        parts = {k: f[f"particles/{solid}/{k}"][...][order] for k in ("x", "y", "velocity_y",
                                                                       "stress_yy")}
    return cells, parts


@pytest.mark.mpi
@pytest.mark.parametrize("nranks", [2, 4])
def test_terzaghi_rank_invariance(tmp_path, nranks):
    """40-cell column to t = 0.02 s on 2 and 4 ranks equals 1 rank: pressure to 1e-9 p0 (1 rank
    solves the tridiagonal system directly, more ranks with hypre PCG: their difference is the
    solver tolerance), particle positions to 1e-13 m, effective stress to 1e-9 p0."""
    sets = ("&grid ncells = 1, 40, 1 /", "&run end_time = 0.02, output_interval = 0.01 /")
    one = list_dumps(_run(tmp_path, TERZAGHI, "r1", 1, *sets), "terzaghi")
    many = list_dumps(_run(tmp_path, TERZAGHI, f"r{nranks}", nranks, *sets), "terzaghi")
    assert len(one) == len(many) == 3
    c1, p1 = _fields(one[-1], "soil")
    cn, pn = _fields(many[-1], "soil")
    assert np.max(np.abs(c1["cell/pressure"] - cn["cell/pressure"])) < 1e-9 * P0
    assert np.max(np.abs(p1["y"] - pn["y"])) < 1e-13
    assert np.max(np.abs(p1["stress_yy"] - pn["stress_yy"])) < 1e-9 * P0
    # the load acted: the base carries a pore pressure near p0
    assert np.max(c1["cell/pressure"]) - P_REF > 0.5 * P0


@pytest.mark.mpi
@pytest.mark.parametrize("nranks", [2, 4])
def test_darcy_rank_invariance(tmp_path, nranks):
    """20-cell Darcy channel to t = 0.02 s on 2 and 4 ranks (blocks split inside the porous
    column) equals 1 rank: pressure to 1e-9 of the drop, velocities to 1e-12 m/s."""
    sets = ("&run end_time = 0.02, output_interval = 0.01 /",)
    one = list_dumps(_run(tmp_path, DARCY, "r1", 1, *sets), "darcy")[-1]
    many = list_dumps(_run(tmp_path, DARCY, f"r{nranks}", nranks, *sets), "darcy")[-1]
    with h5py.File(one) as a, h5py.File(many) as b:
        dp = 0.5 * P_REF
        assert np.max(np.abs(a["cell/pressure"][...] - b["cell/pressure"][...])) < 1e-9 * dp
        assert np.max(np.abs(a["cell/water/velocity_x"][...]
                             - b["cell/water/velocity_x"][...])) < 1e-12


@pytest.mark.mpi
@pytest.mark.parametrize("nranks,blocks", [(2, "7, 33"), (4, "3, 20, 10, 7")])
def test_terzaghi_given_blocks(tmp_path, nranks, blocks):
    """Uneven blocks (`&grid block_cells_y`) give the 1-rank column to the same tolerances as the
    even split: pressure to 1e-9 p0, particle positions to 1e-13 m, effective stress to 1e-9 p0."""
    sets = ("&grid ncells = 1, 40, 1 /", "&run end_time = 0.02, output_interval = 0.02 /")
    one = list_dumps(_run(tmp_path, TERZAGHI, "r1", 1, *sets), "terzaghi")[-1]
    out = str(tmp_path / f"b{nranks}")
    args = [TERZAGHI, "--set", f"&run output_dir = '{out}' /"]
    for text in (*sets, f"&grid block_cells_y = {blocks} /"):
        args += ["--set", text]
    result = run_mpmice(args, nranks=nranks, cwd=str(tmp_path))
    assert f"blocks 1 x {nranks} x 1" in result.stdout
    c1, p1 = _fields(one, "soil")
    cn, pn = _fields(list_dumps(out, "terzaghi")[-1], "soil")
    assert np.max(np.abs(c1["cell/pressure"] - cn["cell/pressure"])) < 1e-9 * P0
    assert np.max(np.abs(p1["y"] - pn["y"])) < 1e-13
    assert np.max(np.abs(p1["stress_yy"] - pn["stress_yy"])) < 1e-9 * P0


@pytest.mark.mpi
def test_restart_on_other_blocks(tmp_path):
    """A checkpoint of an even 2-rank split continued on uneven blocks (&grid block_cells_y on
    the restart's command line) ends where the uninterrupted run ends, to the rank-invariance
    tolerances (the fields are read by global index, the particles migrate to their new owners)."""
    sets = ("&grid ncells = 1, 40, 1 /", "&run end_time = 0.012 /")
    full = list_dumps(_run(tmp_path, TERZAGHI, "full", 2, *sets), "terzaghi")[-1]
    half_dir = _run(tmp_path, TERZAGHI, "half", 2, *sets, "&run max_steps = 100 /")
    checkpoint = os.path.join(half_dir, "terzaghi_checkpoint_000100.h5")
    run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 0 /",
                "--set", "&grid block_cells_y = 31, 9 /"], nranks=2, cwd=str(tmp_path))
    cont = list_dumps(half_dir, "terzaghi")[-1]
    assert os.path.basename(cont) == os.path.basename(full)
    c1, p1 = _fields(full, "soil")
    c2, p2 = _fields(cont, "soil")
    assert np.max(np.abs(c1["cell/pressure"] - c2["cell/pressure"])) < 1e-9 * P0
    assert np.max(np.abs(p1["y"] - p2["y"])) < 1e-13
    assert np.max(np.abs(p1["stress_yy"] - p2["stress_yy"])) < 1e-9 * P0


@pytest.mark.mpi
@pytest.mark.parametrize("nranks,dims", [(1, "1, 1, 1"), (2, "2, 1, 1"), (4, "2, 2, 1")])
def test_terzaghi_2d_equals_1d(tmp_path, nranks, dims):
    """The column as a 2D scene (4 x 40 cells, 2 x 1 particles per cell, free-slip/roller side
    walls) on 1, 2 and 4 ranks: every column of cells equals the 1D run (pressure to 1e-8 p0)."""
    nml = tmp_path / "terzaghi_2d.nml"
    with open(TERZAGHI) as src:
        nml.write_text(src.read() + SIDE_WALLS)
    sets = ("&run end_time = 0.02, output_interval = 0.02 /",)
    ref = list_dumps(_run(tmp_path, TERZAGHI, "r1d", 1, "&grid ncells = 1, 40, 1 /", *sets),
                     "terzaghi")[-1]
    out = _run(tmp_path, str(nml), f"2d_r{nranks}", nranks,
               f"&grid ncells = 4, 40, 1, upper = 0.1, 1.0, 0.01, dims = {dims} /",
               "&solid name='soil', upper = 0.1, 1.0, 0.01, particles_per_cell = 2, 1, 1 /",
               *sets)
    two = list_dumps(out, "terzaghi")[-1]
    with h5py.File(ref) as a, h5py.File(two) as b:
        p1 = a["cell/pressure"][...].reshape(40)
        p2 = b["cell/pressure"][...].reshape(40, 4)
        assert np.max(np.abs(p2 - p1[:, None])) < 1e-8 * P0
        assert np.max(np.abs(b["cell/water/velocity_x"][...])) < 1e-12


@pytest.mark.mpi
@pytest.mark.parametrize("nranks", [1, 2])
def test_restart_is_bitwise_identical(tmp_path, nranks):
    """Run to t = 0.012 s; run 100 steps (checkpoint at the stop), restart, finish: the last
    dump's fields are bitwise equal (cells, particles and the solid fraction the fluids see)."""
    sets = ("&grid ncells = 1, 40, 1 /", "&run end_time = 0.012 /")
    full = list_dumps(_run(tmp_path, TERZAGHI, f"full{nranks}", nranks, *sets), "terzaghi")[-1]
    half_dir = _run(tmp_path, TERZAGHI, f"half{nranks}", nranks, *sets, "&run max_steps = 100 /")
    checkpoint = os.path.join(half_dir, "terzaghi_checkpoint_000100.h5")
    assert os.path.isfile(checkpoint)
    run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 0 /"], nranks=nranks,
               cwd=str(tmp_path))
    cont = list_dumps(half_dir, "terzaghi")[-1]
    assert os.path.basename(cont) == os.path.basename(full)
    assert_dumps_identical(full, cont)


SLIDE_BLOCK = os.path.join(ROOT, "namelists", "mpmice_slide_block_2d.nml")


@pytest.mark.mpi
def test_sliding_contact_restart_is_bitwise_identical(tmp_path):
    """The block sliding on the rigid bed (`&mpm rigid_contact = 'friction'`), stopped at step
    400 (the block has slid into cells it did not cover at the start) and continued: the next
    step's dump is bitwise equal to the uninterrupted run's. The contact's first stage reads the
    deformable solids' fraction and specific volume of the step before, which the checkpoint
    carries (without them the continuation differed by 1e-13 of the particle velocities at step
    401 and by 5e-9 of the pressure at step 1105)."""
    full = _run(tmp_path, SLIDE_BLOCK, "full", 1, "&run max_steps = 401 /")
    half = _run(tmp_path, SLIDE_BLOCK, "half", 1, "&run max_steps = 400 /")
    checkpoint = os.path.join(half, "slide_checkpoint_000400.h5")
    assert os.path.isfile(checkpoint)
    run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 1 /"], cwd=str(tmp_path))
    a = os.path.join(full, "slide_000401.h5")
    b = os.path.join(half, "slide_000401.h5")
    assert_dumps_identical(a, b)


@pytest.mark.mpi
def test_sliding_contact_rank_invariance(tmp_path):
    """The block sliding on the rigid bed to its end (0.12 s) on 2 ranks cut in y between rows
    18 and 19, so that the block crosses the cut where it rests on the bed, equals 1 rank:
    pressure to 1e-9 of its largest value, block particle positions to 1e-11 m, velocities to
    1e-9 m/s, stresses to 1e-9 of the largest (measured 9e-13 of the pressure). The bed's
    interior nodes have a rigid mass gradient of round-off only; taken as the contact normal,
    its random direction (set by the ranks' order of the sum) turned a block particle's stress
    by 1e-3 at step 92 and the runs parted to 2.6e-4 of the pressure (`mpm_nodal%contact_normal`
    now takes a gradient below 1e-10 m / dx as none). ~5 s."""
    sets = ("&run output_interval = 0.12 /",)
    one = list_dumps(_run(tmp_path, SLIDE_BLOCK, "r1", 1, *sets), "slide")
    two = list_dumps(_run(tmp_path, SLIDE_BLOCK, "r2", 2, *sets,
                          "&grid dims = 1, 2, 1, block_cells_y = 18, 17 /"), "slide")
    assert os.path.basename(one[-1]) == os.path.basename(two[-1])
    assert_field_close(one[-1], two[-1], "cell/pressure", 1e-9)
    assert_particles_close(one[-1], two[-1], "block", 1e-11, 1e-9, 1e-9)


def test_restart_may_change_the_outer_iteration(tmp_path):
    """`&ice outer_tolerance` and `max_outer_iterations` set the pressure's outer iteration and
    hold no state: a restart accepts them (docs/batch.md) and runs with them (the resolved
    input it writes names the new values)."""
    half = _run(tmp_path, SLIDE_BLOCK, "half", 1, "&run max_steps = 20 /")
    checkpoint = os.path.join(half, "slide_checkpoint_000020.h5")
    assert os.path.isfile(checkpoint)
    run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 5 /", "--set",
                "&ice outer_tolerance = 2.5e-6, max_outer_iterations = 7 /"], cwd=str(tmp_path))
    with open(os.path.join(half, "slide.used.nml"), encoding="utf-8") as f:
        used = f.read()
    assert "outer_tolerance = 2.5" in used and "max_outer_iterations = 7" in used, used


def _one_and_two_ranks(tmp_path, namelist, stem, dims, steps=20):
    """The last dumps of `namelist` after `steps` steps on 1 rank and on 2 ranks with `&grid
    dims`; their pressures agree to 1e-11 of the largest value."""
    path = os.path.join(ROOT, "namelists", namelist)
    sets = (f"&run max_steps = {steps} /",)
    one = list_dumps(_run(tmp_path, path, "r1", 1, *sets), stem)[-1]
    two = list_dumps(_run(tmp_path, path, "r2", 2, *sets, f"&grid dims = {dims} /"), stem)[-1]
    assert os.path.basename(one) == os.path.basename(two) == f"{stem}_{steps:06d}.h5"
    assert_field_close(one, two, "cell/pressure", 1e-11)
    return one, two


def test_forchheimer_drag_rank_invariance(tmp_path):
    """The Grilli slide (Forchheimer drag, whose coefficient depends on the slip of solid and
    water) on 2 ranks cut in y through the bead wedge equals 1 rank after 20 steps: pressure to
    1e-11 of its largest value (measured 2.6e-13), bead velocities to 1e-12 m/s. The drag in
    the ghost cells takes its slip from the solid's cell velocity there, which was not
    exchanged: the cut's faces saw another drag than 1 rank's (2.3e-9 of the pressure at step
    20, 1.7e-5 at step 300)."""
    one, two = _one_and_two_ranks(tmp_path, "mpmice_grilli2017_2d.nml", "grilli", "1, 2, 1")
    assert_particles_close(one, two, "beads", 1e-14, 1e-12, 1e-9)


def test_sliding_deposit_rank_invariance(tmp_path):
    """The slab on the bathymetry bed (frictional contact with a rigid bed) on 2 ranks cut in
    x equals 1 rank after 20 steps: pressure to 1e-11 of its largest value (measured 3e-13 at
    step 50), water velocities to 1e-9 of their largest. With sliding rigid bodies a particle's
    deposit over a wall cell goes on to that cell's neighbours, two cells from the particle's
    own; the reverse halo summed one ghost layer only, so what went to the second was lost on
    2 ranks (1.4e-5 of the pressure at step 10, 6e-4 at step 50)."""
    one, two = _one_and_two_ranks(tmp_path, "mpmice_bathymetry_2d.nml", "bathy", "2, 1, 1")
    for c in ("x", "y"):
        assert_field_close(one, two, f"cell/water/velocity_{c}", 1e-9)


def test_impermeable_base_rank_invariance(tmp_path):
    """The loose earthquake slope (a critical-state sand on a shaken impermeable base) on 2
    ranks cut in x equals 1 rank after 20 steps: pressure to 1e-11 of its largest value
    (measured 3.8e-13), water velocities to 1e-8 of their largest (measured 1.4e-10). The
    sand's particle domains reach over the base's top cells by round-off (2.5e-16 of a cell),
    and whether that made a cell "mixed" (the water in the base's cells free instead of
    moving with it) depended on the order of the sums: the cut's column differed (water
    6e-6 of its largest, pressure 3.6e-9 at step 20). A permeable share below 1e-10 of the
    cell no longer counts."""
    one, two = _one_and_two_ranks(tmp_path, "mpmice_earthquake_slope_loose_2d.nml", "quake",
                                  "2, 1, 1")
    for c in ("x", "y"):
        assert_field_close(one, two, f"cell/water/velocity_{c}", 1e-8)


BLOCK = os.path.join(ROOT, "namelists", "mpmice_submerged_block_2d.nml")


@pytest.mark.mpi
def test_submerged_block_2d(tmp_path):
    """Water, air and a porous Mohr-Coulomb block in 2D to t = 0.1 s on 1 and 2 ranks: the water
    mass of the closed-bottom tank constant to 1e-12 (measured 6e-16), the sand mass exact, every
    field finite, the water velocity below 0.2 m/s away from the free surface, and the 2-rank
    run equal to the 1-rank one (pressure to 1e-9 of its range, particle positions to 1e-12 m)."""
    sets = ("&run end_time = 0.1, output_interval = 0.05 /",)
    runs = [list_dumps(_run(tmp_path, BLOCK, f"r{n}", n, *sets), "block2d") for n in (1, 2)]
    with h5py.File(runs[0][0]) as first, h5py.File(runs[0][-1]) as last:
        w0 = first["cell/water/density"][...].sum()
        assert abs(last["cell/water/density"][...].sum() / w0 - 1.0) < 1e-12
        assert last["particles/sand/mass"][...].sum() == first["particles/sand/mass"][...].sum()
        for key in ("cell/pressure", "cell/water/velocity_x", "cell/air/temperature"):
            assert np.all(np.isfinite(last[key][...])), key
        water = last["cell/water/density"][...] > 900.0 * (1.0 - 0.6)
        speed = np.hypot(last["cell/water/velocity_x"][...], last["cell/water/velocity_y"][...])
        assert np.max(speed[water]) < 0.2
    c1, p1 = _fields(runs[0][-1], "sand")
    c2, p2 = _fields(runs[1][-1], "sand")
    prange = np.ptp(c1["cell/pressure"])
    assert np.max(np.abs(c1["cell/pressure"] - c2["cell/pressure"])) < 1e-9 * prange
    assert np.max(np.abs(p1["y"] - p2["y"])) < 1e-12


@pytest.mark.mpi
def test_apic_with_cyclic_state_rank_invariance(tmp_path):
    """The loose earthquake slope (1 g, periodic in x) with the APIC transfer and the sand's
    cyclic densification, so that each particle carries both optional states (`affine` and
    `cyclic`), to t = 0.25 s on 2 ranks split at x = 6.5 m equals 1 rank: particle positions to
    1e-11 m, velocities to 1e-9 m/s, stresses to 1e-9 of the largest (measured 1.1e-12 m,
    6.9e-12 m/s, 1.9e-10); more than 10 sediment particles change block (measured 28, across
    x = 6.5 m or the periodic x = 0). ~20 s."""
    slope = os.path.join(ROOT, "namelists", "mpmice_earthquake_slope_loose_2d.nml")
    sets = ("&run end_time = 0.25, output_interval = 0.25 /",
            "&solid name = 'sediment', densification_c1 = 0.5 /",
            "&mpm velocity_transfer = 'apic' /")
    one = list_dumps(_run(tmp_path, slope, "r1", 1, *sets), "quake")
    two = list_dumps(_run(tmp_path, slope, "r2", 2, *sets), "quake")
    _, start = particles(one[0], "sediment")
    _, p1 = particles(one[-1], "sediment")
    side = (np.mod(start["x"], 13.0) < 6.5) != (np.mod(p1["x"], 13.0) < 6.5)
    assert np.sum(side) > 10, np.sum(side)
    assert_particles_close(one[-1], two[-1], "sediment", 1e-11, 1e-9, 1e-9)
