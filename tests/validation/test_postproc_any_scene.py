"""The scene-independent postprocessing (postproc/snapshots.py, postproc/slide.py,
postproc/series.py, postproc/measures.py, postproc/run_files.py; docs/postprocessing.md).

Fake runs are written with h5py in the dump layout of docs/io.md (grid fields stored (nk, nj, ni),
root attributes time/step/ncells/lower/dx, the resolved input as the attribute ``namelist``):
snapshots of 1D, 2D and 3D runs (one non-empty PNG per chosen dump); the front and run-out of a
solid translated by a known distance toward -x, +x and, in 3D with gravity along -z, -y; the
free surface of a known interface, by both methods, in 2D, in 3D and with gravity pointing up;
the per-step CSV series. One real run (seconds): the elastic block of
namelists/mpm_slide_2d.nml thrown toward -x instead of +x."""
import math
import os

import h5py
import numpy as np
import pytest

from postproc import measures, run_files, series, slide, snapshots
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice


def namelist_text(fluids=(), solids=(), rigid=(), gravity=(0.0, -9.81, 0.0)) -> str:
    """A resolved-input text with the groups the tools read."""
    groups = ["&run\n  name = 'fake'\n/",
              "&physics\n  gravity = " + ", ".join(repr(float(g)) for g in gravity) + "\n/"]
    groups += [f"&fluid\n  name = '{f}'\n  eos = 'linear_water'\n/" for f in fluids]
    groups += [f"&solid\n  name = '{s}'\n  model = '{'rigid' if s in rigid else 'linear_elastic'}'"
               "\n/" for s in solids]
    return "\n".join(groups) + "\n"


def write_dump(path, time, step, ncells, lower, dx, cell=None, particles=None, namelist=None):
    """One dump: cell fields given as [i, j, k] arrays (stored transposed, as the Fortran writer
    does), particle sets as {set: {field: array}}."""
    with h5py.File(path, "w") as f:
        f.attrs["time"] = float(time)
        f.attrs["step"] = int(step)
        f.attrs["ncells"] = np.asarray(ncells, dtype=np.int32)
        f.attrs["lower"] = np.asarray(lower, dtype=float)
        f.attrs["dx"] = np.asarray(dx, dtype=float)
        f.attrs["upper"] = np.asarray(lower) + np.asarray(ncells) * np.asarray(dx)
        f.attrs["ndim"] = int(sum(n > 1 for n in ncells))
        if namelist is not None:
            f.attrs["namelist"] = np.bytes_(namelist.encode("ascii"))
        for key, value in (cell or {}).items():
            f[f"cell/{key}"] = np.asarray(value, dtype=float).T
        for name, fields in (particles or {}).items():
            for key, value in fields.items():
                f[f"particles/{name}/{key}"] = np.asarray(value)
            n = len(next(iter(fields.values())))
            f[f"particles/{name}/rank_counts"] = np.array([n], dtype=np.int64)


def block_particles(lo, hi, n, shift=(0.0, 0.0, 0.0), grow=0.0, axis=0):
    """Particles on a regular lattice in the box lo..hi (n per axis), moved by `shift` and
    stretched by `grow` (fraction) along `axis` about the box's low end."""
    axes = [np.linspace(lo[d], hi[d], n[d]) for d in range(3)]
    x, y, z = (a.ravel() for a in np.meshgrid(*axes, indexing="ij"))
    coords = [x, y, z]
    coords[axis] = lo[axis] + (coords[axis] - lo[axis]) * (1.0 + grow)
    coords = [c + s for c, s in zip(coords, shift)]
    count = len(x)
    return {"x": coords[0], "y": coords[1], "z": coords[2], "id": np.arange(count, dtype=np.int64),
            "mass": np.full(count, 2.0), "velocity_x": np.full(count, shift[0]),
            "velocity_y": np.full(count, shift[1]), "velocity_z": np.zeros(count),
            "pore_pressure": coords[1] * 10.0}


def fluid_fields(share, fluids=("water", "air")):
    """Cell fields of two fluids whose volume fractions are `share` and 1 - share."""
    out = {"pressure": 1.0e5 + 100.0 * share}
    for name, phi in zip(fluids, (share, 1.0 - share)):
        out[f"{name}/volume_fraction"] = phi
        out[f"{name}/density"] = 1000.0 * phi
        for a in "xyz":
            out[f"{name}/velocity_{a}"] = 0.1 * phi
    return out


def ramp_share(surface, zc, h):
    """Water share rising linearly over +-2 cells below the surface: its 0.5 crossing between
    two cell centres is exactly the surface."""
    return np.clip(0.5 + (surface - zc) / (4.0 * h), 0.0, 1.0)


def sharp_share(surface, zc, h):
    """The cell-average water share of a sharp surface (exact for the height method)."""
    return np.clip((surface - (zc - 0.5 * h)) / h, 0.0, 1.0)


# ---------------------------------------------------------------------------------------- runs
def fake_run_2d(directory, shifts, name="fake", grow=0.0, gravity=(0.0, -9.81, 0.0)):
    """A 2D run (4 m x 2 m, 0.1 m cells) with water under air at y = 1.2 m, a deformable solid
    'sand' moved by shifts[n] in dump n and a rigid solid 'bed'."""
    os.makedirs(directory, exist_ok=True)
    h = 0.1
    ncells = (40, 20, 1)
    xc = (np.arange(40) + 0.5) * h
    yc = (np.arange(20) + 0.5) * h
    share = ramp_share(1.2, yc[None, :], h) * np.ones((40, 1))
    text = namelist_text(("air", "water"), ("sand", "bed"), ("bed",), gravity)
    for n, shift in enumerate(shifts):
        sand = block_particles((1.5, 0.5, 0.0), (2.5, 1.0, 0.0), (11, 6, 1), shift,
                               grow * n, axis=0)
        bed = block_particles((0.0, 0.0, 0.0), (4.0, 0.1, 0.0), (41, 2, 1))
        write_dump(os.path.join(directory, f"{name}_{100 * n:06d}.h5"), 0.1 * n, 100 * n, ncells,
                   (0.0, 0.0, 0.0), (h, h, 0.1), fluid_fields(share[:, :, None]),
                   {"sand": sand, "bed": bed}, text)
    with open(os.path.join(directory, f"{name}.used.nml"), "w", encoding="utf-8") as f:
        f.write(text)
    return str(directory), xc


def fake_run_1d(directory, ndumps=3):
    """A 1D column along x (gravity -x), water below x = 0.6 m, a solid with 8 particles."""
    os.makedirs(directory, exist_ok=True)
    h = 0.05
    xc = (np.arange(20) + 0.5) * h
    share = ramp_share(0.6, xc, h)[:, None, None]
    text = namelist_text(("water", "air"), ("soil",), (), (-9.81, 0.0, 0.0))
    for n in range(ndumps):
        soil = block_particles((0.0, 0.5, 0.5), (0.3, 0.5, 0.5), (8, 1, 1), (0.0, 0.0, 0.0))
        soil["x"] = soil["x"] * (1.0 - 0.01 * n)
        write_dump(os.path.join(directory, f"col_{10 * n:06d}.h5"), 0.5 * n, 10 * n, (20, 1, 1),
                   (0.0, 0.0, 0.0), (h, 1.0, 1.0), fluid_fields(share), {"soil": soil}, text)
    return str(directory)


def fake_run_3d(directory, shifts, surface=None):
    """A 3D run (1 x 2 x 1 m, 0.1 m cells, gravity -z): water share of the sharp surface
    z = surface(x, y) (default 0.5 m), a solid 'sand' moved by shifts[n], rigid 'wall'."""
    os.makedirs(directory, exist_ok=True)
    h = 0.1
    n3 = (10, 20, 10)
    c = [(np.arange(n) + 0.5) * h for n in n3]
    x, y, z = np.meshgrid(*c, indexing="ij")
    level = surface(x, y) if surface else np.full(x.shape, 0.5)
    share = sharp_share(level, z, h)
    text = namelist_text(("water", "air"), ("sand", "wall"), ("wall",), (0.0, 0.0, -9.81))
    for n, shift in enumerate(shifts):
        sand = block_particles((0.32, 0.8, 0.05), (0.72, 1.2, 0.35), (5, 5, 4), shift)
        wall = block_particles((0.0, 1.9, 0.0), (1.0, 2.0, 1.0), (6, 2, 6))
        write_dump(os.path.join(directory, f"cube_{n:06d}.h5"), 0.2 * n, n, n3, (0.0, 0.0, 0.0),
                   (h, h, h), fluid_fields(share), {"sand": sand, "wall": wall}, text)
    return str(directory)


def pngs(directory):
    return sorted(p for p in os.listdir(directory) if p.endswith(".png"))


# ----------------------------------------------------------------------------------- snapshots
def test_snapshots_of_1d_2d_and_3d_runs(tmp_path, capsys):
    """One non-empty PNG per chosen dump: a 1D column of 3 dumps (--times 0 0.5 0.52: the last
    two pick the same dump, 2 files; 'all' with chosen fields and particle colour: 3), a 2D run
    with 5 dumps (default: 4 evenly spaced, the first and the last among them) and a 3D run with
    a named slice (3 dumps, 3 files); without --out they go to RUN_DIR/postproc. (One or two
    cell fields in 2D and 3D keep the test short; the default fields are checked below.)"""
    d1 = fake_run_1d(tmp_path / "run1d")
    out1 = tmp_path / "snap1d"
    assert snapshots.main([d1, "--times", "0", "0.5", "0.52", "--out", str(out1)]) == 0
    assert pngs(out1) == ["col_snapshot_000000.png", "col_snapshot_000010.png"]

    d2, _ = fake_run_2d(tmp_path / "run2d", [(0.1 * n, 0.0, 0.0) for n in range(5)])
    out2 = tmp_path / "snap2d"
    assert snapshots.main([d2, "--out", str(out2), "--particles-colour", "pore_pressure",
                           "--fields", "water/speed"]) == 0
    assert pngs(out2) == [f"fake_snapshot_{s:06d}.png" for s in (0, 100, 300, 400)]
    out1all = tmp_path / "snap1d_all"
    assert snapshots.main([d1, "--out", str(out1all), "--times", "all", "--fields",
                           "water/volume_fraction", "air/speed", "--particles-colour",
                           "displacement"]) == 0
    assert len(pngs(out1all)) == 3

    d3 = fake_run_3d(tmp_path / "run3d", [(0.0, -0.1 * n, 0.0) for n in range(3)])
    out3 = tmp_path / "snap3d"
    assert snapshots.main([d3, "--out", str(out3), "--slice", "x=0.45", "--fields",
                           "water/volume_fraction"]) == 0
    assert len(pngs(out3)) == 3
    # the 3D map shows the particles of the cut cell layer 0.4 <= x < 0.5: one lattice plane
    dump = read_dump(list_dumps(d3, "cube")[0])
    shown, normal, index = snapshots.plane(dump, "x=0.45")
    assert int(np.sum(snapshots._in_layer(dump, dump["particles"]["sand"], normal, index))) == 20
    printed = capsys.readouterr().out
    for directory in (out1, out2, out1all, out3):
        for name in pngs(directory):
            path = directory / name
            assert path.stat().st_size > 10000, path
            assert str(path) in printed
    # the default output folder is RUN_DIR/postproc
    assert snapshots.main([d1, "--times", "1.0"]) == 0
    assert pngs(os.path.join(d1, "postproc")) == ["col_snapshot_000020.png"]


def test_snapshot_plane_and_fields():
    """The 3D default plane holds the vertical (z) and the first other axis (x), normal y through
    the middle cell; --slice names the normal and the cell layer; the 2D plane puts the vertical
    axis on the plot's y; the default fields are every fluid's fraction, the pressure and every
    fluid's speed."""
    d3 = {"attrs": {"ncells": [10, 20, 10], "lower": [0.0] * 3, "dx": [0.1] * 3,
                    "namelist": namelist_text(gravity=(0.0, 0.0, -9.81))}, "cell": {}}
    assert snapshots.plane(d3, None) == ([0, 2], 1, 10)
    assert snapshots.plane(d3, "x=0.45") == ([1, 2], 0, 4)
    assert snapshots.plane(d3, "z") == ([0, 1], 2, 5)
    d2 = {"attrs": {"ncells": [1, 20, 10], "lower": [0.0] * 3, "dx": [0.1] * 3,
                    "namelist": namelist_text(gravity=(0.0, -9.81, 0.0))}, "cell": {}}
    assert snapshots.plane(d2, None) == ([2, 1], 0, 0)
    share = np.full((4, 3, 1), 0.5)
    dump = {"attrs": {"ncells": [4, 3, 1], "namelist": namelist_text(("water", "air"))},
            "cell": fluid_fields(share), "particles": {}, "path": "fake"}
    assert snapshots.resolve_fields(dump, None) == [
        "water/volume_fraction", "air/volume_fraction", "pressure", "water/speed", "air/speed"]
    speed = snapshots.cell_field(dump, "water/speed")
    assert np.allclose(speed, math.sqrt(3.0) * 0.05)
    with pytest.raises(KeyError, match="field 'sand/volume_fraction' is not in fake"):
        snapshots.resolve_fields(dump, ["sand/volume_fraction"])


def test_snapshots_bad_input_writes_nothing(tmp_path):
    """An unknown field or particle colour, a missing directory: one message, exit status 1 (a
    SystemExit with a string), no output folder made."""
    d2, _ = fake_run_2d(tmp_path / "run2d", [(0.0, 0.0, 0.0), (0.1, 0.0, 0.0)])
    out = tmp_path / "never"
    with pytest.raises(SystemExit, match="field 'velocity_q' is not in"):
        snapshots.main([d2, "--out", str(out), "--fields", "velocity_q"])
    with pytest.raises(SystemExit, match="particle field 'strain' is not in solid 'sand'"):
        snapshots.main([d2, "--out", str(out), "--particles-colour", "strain"])
    with pytest.raises(SystemExit, match="no such directory"):
        snapshots.main([str(tmp_path / "missing"), "--out", str(out)])
    assert not out.exists()


# --------------------------------------------------------------------------------------- slide
@pytest.mark.parametrize("sign", [-1, +1])
def test_slide_front_and_runout_along_x(tmp_path, sign):
    """The sand (x from 1.5 to 2.5 m) moves by 0.1 m per dump in direction `sign` and stretches
    by 5 % per dump from its low-x end: the direction found is (x, sign); the front is the min x
    of the particles for -x (1.5 - 0.1 n) and the max x for +x (1.5 + (1 + 0.05 n) + 0.1 n); the
    run-out is the front's advance since the first dump (positive both ways); top 1 m, height
    0.5 m above the initial base; the water surface stays at its initial level 1.2 m."""
    shifts = [(sign * 0.1 * n, 0.0, 0.0) for n in range(4)]
    directory, _ = fake_run_2d(tmp_path / "run", shifts, grow=0.05)
    dumps = [read_dump(p) for p in list_dumps(directory, "fake")]
    result = slide.analyse(dumps, "sand", liquid="water")
    assert result["direction"] == (0, sign)
    assert result["vertical"] == (1, 1)
    for n, row in enumerate(result["rows"]):
        x = dumps[n]["particles"]["sand"]["x"]
        if sign < 0:
            expected_front = 1.5 - 0.1 * n
            assert row["front"] == pytest.approx(np.min(x), abs=0)
            assert row["runout"] == pytest.approx(0.1 * n, abs=1e-12)
        else:
            expected_front = 1.5 + 1.0 * (1.0 + 0.05 * n) + 0.1 * n
            assert row["front"] == pytest.approx(np.max(x), abs=0)
            assert row["runout"] == pytest.approx(expected_front - 2.5, abs=1e-12)
        assert row["front"] == pytest.approx(expected_front, abs=1e-12)
        assert row["top"] == pytest.approx(1.0, abs=1e-12)
        assert row["height"] == pytest.approx(0.5, abs=1e-12)
        # the water surface at y = 1.2 m, level from the first dump
        assert row["eta_max"] == pytest.approx(0.0, abs=1e-12)
    assert result["level"] == pytest.approx(1.2, abs=1e-12)


def test_slide_command_toward_minus_x(tmp_path, capsys):
    """`python -m postproc.slide RUN --solid sand` on a slide toward -x: prints the direction -x,
    writes the CSV (front = min x, run-out from the initial front) and the PNG; --direction +x
    imposes the other direction (the run-out is then negative); a solid that did not move needs
    --direction (exit message), an unknown solid is named."""
    shifts = [(-0.25 * n, 0.0, 0.0) for n in range(3)]
    directory, _ = fake_run_2d(tmp_path / "run", shifts)
    out = tmp_path / "plots"
    assert slide.main([directory, "--solid", "sand", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "moving -x (from its displacement)" in text
    table = np.genfromtxt(out / "fake_slide_sand.csv", delimiter=",", names=True)
    assert np.allclose(table["front"], [1.5, 1.25, 1.0], atol=1e-12, rtol=0)
    assert np.allclose(table["runout"], [0.0, 0.25, 0.5], atol=1e-12, rtol=0)
    assert (out / "fake_slide_sand.png").stat().st_size > 10000
    assert slide.main([directory, "--solid", "sand", "--out", str(out), "--direction", "+x"]) == 0
    table = np.genfromtxt(out / "fake_slide_sand.csv", delimiter=",", names=True)
    assert np.allclose(table["front"], [2.5, 2.25, 2.0], atol=1e-12, rtol=0)
    assert np.allclose(table["runout"], [0.0, -0.25, -0.5], atol=1e-12, rtol=0)
    with pytest.raises(SystemExit, match="did not move .*give --direction"):
        slide.main([directory, "--solid", "bed", "--out", str(out)])
    with pytest.raises(SystemExit, match="solid 'gravel' has no particles"):
        slide.main([directory, "--solid", "gravel", "--out", str(out)])
    with pytest.raises(SystemExit, match="--direction up"):
        slide.main([directory, "--solid", "sand", "--direction", "up"])


def test_slide_along_y_in_3d(tmp_path):
    """3D, gravity along -z: the sand moves -0.1 m along y per dump (and 0.02 m along x, less):
    direction (y, -1), front = min y = 0.8 - 0.1 n, run-out 0.1 n, top 0.35 m."""
    directory = fake_run_3d(tmp_path / "run", [(0.02 * n, -0.1 * n, 0.0) for n in range(3)])
    dumps = [read_dump(p) for p in list_dumps(directory, "cube")]
    result = slide.analyse(dumps, "sand", liquid="water")
    assert result["direction"] == (1, -1)
    assert result["vertical"] == (2, 1)
    for n, row in enumerate(result["rows"]):
        assert row["front"] == pytest.approx(0.8 - 0.1 * n, abs=1e-12)
        assert row["runout"] == pytest.approx(0.1 * n, abs=1e-12)
        assert row["top"] == pytest.approx(0.35, abs=1e-12)
    assert result["level"] == pytest.approx(0.5, abs=1e-12)
    assert slide.main([directory, "--solid", "sand", "--out", str(tmp_path / "p")]) == 0


# -------------------------------------------------------------------------------- free surface
def test_free_surface_of_a_known_interface_2d():
    """2D, 0.1 m cells, water below eta(x) = 1.2 + 0.05 sin(x) [m]: the crossing method on a
    share ramp over +-2 cells, and the height method on the sharp cell averages, give eta(x)
    back to 1e-12; a column of water only has no crossing (NaN) and its full height (2 m) by
    the height method."""
    h = 0.1
    xc = (np.arange(40) + 0.5) * h
    yc = (np.arange(20) + 0.5) * h
    surface = 1.2 + 0.05 * np.sin(xc)
    base = {"attrs": {"ncells": [40, 20, 1], "lower": [0.0, 0.0, 0.0], "dx": [h, h, h],
                      "namelist": namelist_text(("water", "air"))}, "particles": {}}
    ramp = ramp_share(surface[:, None], yc[None, :], h)
    ramp[7, :] = 1.0
    dump = dict(base, cell=fluid_fields(ramp[:, :, None]))
    (x,), eta = measures.free_surface(dump, "water", level=1.2)
    assert np.allclose(x, xc)
    ok = np.arange(40) != 7
    assert np.max(np.abs(eta[ok] - (surface[ok] - 1.2))) < 1e-12
    assert math.isnan(eta[7])
    sharp = sharp_share(surface[:, None], yc[None, :], h)
    sharp[7, :] = 1.0
    dump = dict(base, cell=fluid_fields(sharp[:, :, None]))
    (x,), eta = measures.free_surface(dump, "water", method="height")
    assert np.max(np.abs(eta[ok] - surface[ok])) < 1e-12
    assert eta[7] == pytest.approx(2.0, abs=1e-12)


def test_free_surface_3d_map_and_gravity_up():
    """3D, gravity -z: the height method gives the map eta(x, y) = 0.5 + 0.1 x - 0.05 y over
    every column (1e-12). 2D with gravity +y (up is -y): the liquid lies on the high-y side; the
    surface found from that side is y = 0.7 m by both methods (1e-12)."""
    h = 0.1
    c = [(np.arange(n) + 0.5) * h for n in (10, 20, 10)]
    x, y, z = np.meshgrid(*c, indexing="ij")
    level = 0.5 + 0.1 * x - 0.05 * y
    dump = {"attrs": {"ncells": [10, 20, 10], "lower": [0.0] * 3, "dx": [h] * 3,
                      "namelist": namelist_text(("water", "air"), gravity=(0.0, 0.0, -9.81))},
            "cell": fluid_fields(sharp_share(level, z, h)), "particles": {}}
    coords, eta = measures.free_surface(dump, "water", method="height")
    assert [len(a) for a in coords] == [10, 20]
    assert eta.shape == (10, 20)
    assert np.max(np.abs(eta - level[:, :, 0])) < 1e-12

    yc = (np.arange(20) + 0.5) * h
    flipped = {"attrs": {"ncells": [5, 20, 1], "lower": [0.0] * 3, "dx": [h] * 3,
                         "namelist": namelist_text(("water", "air"), gravity=(0.0, 9.81, 0.0))},
               "particles": {}}
    # water above y = 0.7 (gravity +y pulls it there): mirrored ramp and sharp shares
    ramp = np.clip(0.5 + (yc - 0.7) / (4.0 * h), 0.0, 1.0)
    sharp = np.clip((yc + 0.5 * h - 0.7) / h, 0.0, 1.0)
    for share, method in ((ramp, "crossing"), (sharp, "height")):
        d = dict(flipped, cell=fluid_fields(np.broadcast_to(share, (5, 20))[:, :, None].copy()))
        (_,), eta = measures.free_surface(d, "water", method=method)
        assert np.max(np.abs(eta - 0.7)) < 1e-12, (method, eta)


# -------------------------------------------------------------------------------- run files
def test_run_name_and_series(tmp_path, capsys):
    """The run name from <name>.used.nml or the dump files (checkpoints and failure dumps left
    out; two runs need --name); the per-step CSV read column by column (a header-only file gives
    empty columns); `python -m postproc.series` prints every column and plots each file."""
    d = tmp_path / "run"
    d.mkdir()
    for name in ("a_000000.h5", "a_000010.h5", "a_checkpoint_000010.h5", "a_failed_000011.h5"):
        write_dump(d / name, 0.0, 0, (4, 1, 1), (0.0,) * 3, (1.0,) * 3)
    assert run_files.run_name(str(d)) == "a"
    write_dump(d / "b_000000.h5", 0.0, 0, (4, 1, 1), (0.0,) * 3, (1.0,) * 3)
    with pytest.raises(SystemExit, match="several runs .*choose one with --name"):
        run_files.run_name(str(d))
    (d / "b.used.nml").write_text("&run\n  name = 'b'\n/\n")
    assert run_files.run_name(str(d)) == "b"
    assert run_files.run_name(str(d), "a") == "a"

    (d / "a_mpm_series.csv").write_text(
        "time,kinetic_energy,xmax\n 1.0E-003, 2.5E+000, 1.0\n 2.0E-003, 2.0E+000, 1.5\n")
    (d / "a_contact_force.csv").write_text("time,bed_fx,bed_fy,bed_fz\n")
    assert run_files.step_files(str(d), "a") == {
        "contact_force": str(d / "a_contact_force.csv"), "mpm_series": str(d / "a_mpm_series.csv")}
    cols = run_files.read_step_csv(str(d / "a_mpm_series.csv"))
    assert list(cols) == ["time", "kinetic_energy", "xmax"]
    assert np.array_equal(cols["kinetic_energy"], [2.5, 2.0])
    empty = run_files.read_step_csv(str(d / "a_contact_force.csv"))
    assert [len(v) for v in empty.values()] == [0, 0, 0, 0]
    out = tmp_path / "plots"
    assert series.main([str(d), "--name", "a", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "a_mpm_series.csv: 2 rows, t = 0.001 .. 0.002 s" in text
    assert "a_contact_force.csv: 0 rows, no rows yet" in text
    line = [entry for entry in text.splitlines() if "kinetic_energy:" in entry][0]
    assert line.split() == ["kinetic_energy:", "min", "2", "max", "2.5", "last", "2"]
    assert pngs(out) == ["a_mpm_series.png"]
    with pytest.raises(SystemExit, match="--columns energy: in none of"):
        series.main([str(d), "--name", "a", "--out", str(out), "--columns", "energy"])


# ---------------------------------------------------------------------------------- real run
def test_real_block_thrown_toward_minus_x(tmp_path, mpmice_exe, monkeypatch, capsys):
    """namelists/mpm_slide_2d.nml with the block thrown at (-4, -1.5) m/s instead of (4, -1.5)
    to t = 0.04 s (about 1 s): the slide command finds -x, its front is the min x of the block's
    particles and the run-out after 0.04 s of free flight is 4 m/s * 0.04 s = 0.16 m (to 2 mm:
    measured 0.16000); snapshots give one PNG per dump; the series file has a row per step."""
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))
    out = tmp_path / "slide"
    run_mpmice([os.path.join(ROOT, "namelists", "mpm_slide_2d.nml"), "--set",
                f"&run output_dir = '{out}', end_time = 0.04, output_interval = 0.02 / "
                "&solid name = 'block', velocity = -4.0, -1.5, 0.0 /"], cwd=str(tmp_path),
               timeout=300)
    plots = tmp_path / "plots"
    assert slide.main([str(out), "--solid", "block", "--out", str(plots)]) == 0
    assert "moving -x (from its displacement)" in capsys.readouterr().out
    table = np.genfromtxt(plots / "slide2d_slide_block.csv", delimiter=",", names=True)
    dumps = [read_dump(p) for p in list_dumps(str(out), "slide2d")]
    assert len(dumps) == 3
    assert np.allclose(table["front"], [np.min(d["particles"]["block"]["x"]) for d in dumps],
                       rtol=0, atol=1e-8)
    assert table["runout"][-1] == pytest.approx(0.16, abs=2e-3)
    assert snapshots.main([str(out), "--out", str(plots)]) == 0
    assert len([p for p in pngs(plots) if "snapshot" in p]) == 3
    assert series.main([str(out), "--out", str(plots)]) == 0
    assert (plots / "slide2d_mpm_series.png").stat().st_size > 0
