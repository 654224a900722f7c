"""Geometry from files (docs/geometry.md): `&solid` and `&region` shapes read from CSV files.

* A disc seeded from a 200-vertex CSV polygon (more than the 32 inline vertices): the particle
  area equals the polygon's area within the seeding's resolution (sub-cell centres inside),
  and on 2 ranks (files read on rank 0 and broadcast) the same particles are seeded.
* Bathymetry on a 20 x 20 grid (scene mpmice): a rigid bed below a CSV profile, a sediment layer
  of 0.1 m on it (`profile_lower_file`, `layer_thickness`) and water above the bed up to
  0.7 m (`&region shape = 'profile'`): every particle lies where its shape holds, the particle
  areas match the shapes' areas, and the water share of the fluids is 1 exactly in the cells
  whose centre lies above the bed and below 0.7 m, 0 elsewhere; 2 ranks give the same.
* A restart from another working folder reads the files again from their stored absolute paths.
* Malformed input (missing file, non-numeric value, three values on a line, fewer than 3
  vertices, a self-intersecting polygon, a profile whose x is not strictly increasing, a
  repeated vertex, a polygon outside the domain): exit 1, one stderr line naming the file and the line, nothing written;
  the same under --check.
Each run takes well under a second."""
import math

import h5py
import numpy as np
import pytest

from postproc.mpmice_io import list_dumps

GRID = """&grid
  ncells = 20, 20, 1
  lower = 0.0, 0.0, 0.0
  upper = 1.0, 1.0, 0.05
/
"""

CIRCLE_R, CIRCLE_C = 0.3, (0.5, 0.5)
PPC = 2
H = 1.0 / 20 / PPC          # particle spacing [m]


def _write_circle(path, n=200):
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    with open(path, "w") as f:
        f.write(f"# {n}-vertex circle, r = {CIRCLE_R} m\nx, y\n")
        for a in t:
            f.write(f"{CIRCLE_C[0] + CIRCLE_R * math.cos(a):.15g}, "
                    f"{CIRCLE_C[1] + CIRCLE_R * math.sin(a):.15g}\n")
    return np.column_stack([CIRCLE_C[0] + CIRCLE_R * np.cos(t), CIRCLE_C[1] + CIRCLE_R * np.sin(t)])


def _bed(x):
    """The bathymetry profile [m] (also written as a 41-point CSV)."""
    return 0.2 + 0.2 * (1.0 - x) + 0.03 * np.sin(8.0 * x)


BED_X = np.linspace(0.0, 1.0, 41)


def _write_bed(path):
    with open(path, "w") as f:
        f.write("x,y\n")
        for a in BED_X:
            f.write(f"{a:.15g},{_bed(a):.15g}\n")


def _bed_interp(x):
    """The piecewise-linear profile the code uses."""
    return np.interp(x, BED_X, _bed(BED_X))


def _circle_case(out, extra=""):
    return f"""&run
  name = 'circ'
  scene = 'mpm'
  output_dir = '{out}'
  end_time = 1.0e-4
  output_interval = 1.0
  {extra}
/
{GRID}&solid
  name = 'disc'
  shape = 'polygon'
  polygon_file = 'circle.csv'
  particles_per_cell = {PPC}, {PPC}, 1
/
"""


def _particles(path, name):
    with h5py.File(path, "r") as f:
        p = f[f"particles/{name}"]
        return {k: p[k][...] for k in ("x", "y", "volume", "id")}


def _polygon_contains(poly, x, y):
    """Even-odd rule, as the code."""
    inside = np.zeros_like(x, dtype=bool)
    n = len(poly)
    for i in range(n):
        (xi, yi), (xj, yj) = poly[i], poly[i - 1]
        cross = (yi > y) != (yj > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = (xj - xi) * (y - yi) / (yj - yi) + xi
        inside ^= cross & (x < xc)
    return inside


def test_polygon_file_of_200_vertices(run_mpmice, tmp_case_dir):
    """A 200-vertex CSV circle: the particles are exactly the sub-cell centres inside the
    polygon, their area is the polygon's area within the seeding resolution (one particle
    area per particle spacing of perimeter: 2 pi r h), and 2 ranks seed the same particles."""
    poly = _write_circle(tmp_case_dir / "circle.csv")
    (tmp_case_dir / "circle.nml").write_text(_circle_case("out1"))
    result = run_mpmice(["circle.nml"])
    assert result.returncode == 0, result.stdout + result.stderr
    p = _particles(list_dumps(str(tmp_case_dir / "out1"), "circ")[0], "disc")
    # the lattice of sub-cell centres, tested with the polygon's own rule
    c = (np.arange(20 * PPC) + 0.5) * H
    gx, gy = np.meshgrid(c, c, indexing="ij")
    expected = _polygon_contains(poly, gx.ravel(), gy.ravel()).sum()
    assert len(p["x"]) == expected
    assert np.all(_polygon_contains(poly, p["x"], p["y"]))
    area = p["volume"].sum() / 0.05
    exact = 0.5 * abs(np.sum(poly[:, 0] * np.roll(poly[:, 1], -1)
                             - np.roll(poly[:, 0], -1) * poly[:, 1]))
    assert abs(exact / (math.pi * CIRCLE_R**2) - 1.0) < 1e-3
    assert abs(area - exact) < 2.0 * math.pi * CIRCLE_R * H, (area, exact)
    # the files are read on rank 0 and broadcast: 2 ranks seed the same particles
    (tmp_case_dir / "circle2.nml").write_text(_circle_case("out2"))
    result = run_mpmice(["circle2.nml"], nranks=2)
    assert result.returncode == 0, result.stdout + result.stderr
    p2 = _particles(list_dumps(str(tmp_case_dir / "out2"), "circ")[0], "disc")
    assert np.array_equal(np.sort(p2["id"]), np.sort(p["id"]))


def test_polygon_file_restart_from_another_folder(run_mpmice, tmp_case_dir):
    """The resolved input stores the CSV's absolute path; a restart started in another
    folder reads it again and finishes."""
    _write_circle(tmp_case_dir / "circle.csv")
    out = tmp_case_dir / "out"
    (tmp_case_dir / "circle.nml").write_text(
        _circle_case(str(out), "checkpoint_interval = 5.0e-5").replace(
            "end_time = 1.0e-4", "end_time = 2.0e-4"))
    result = run_mpmice(["circle.nml"])
    assert result.returncode == 0, result.stdout + result.stderr
    used = (out / "circ.used.nml").read_text()
    assert f"polygon_file = '{tmp_case_dir / 'circle.csv'}'" in used
    checkpoint = sorted(out.glob("circ_checkpoint_*.h5"))[0]
    elsewhere = tmp_case_dir.parent / "elsewhere"
    elsewhere.mkdir()
    restart = run_mpmice(["--restart", str(checkpoint)], cwd=elsewhere)
    assert restart.returncode == 0, restart.stdout + restart.stderr


BATHYMETRY = """&run
  name = 'bed'
  scene = 'mpmice'
  output_dir = 'out'
  end_time = 1.0e-5
  output_interval = 1.0
/
{grid}&time
  dt_init = 1.0e-5
  dt_max = 1.0e-5
/
&physics
  gravity = 0.0, -9.81, 0.0
  hydrostatic_init = .true.
/
&fluid
  name = 'air'
  volume_fraction = 1.0
/
&fluid
  name = 'water'
  eos = 'linear_water'
  volume_fraction = 0.0
/
&region
  material = 'water'
  lower = 0.0, 0.0, 0.0
  upper = 1.0, {level}, 0.05
  shape = 'profile'
  profile_lower_file = 'bed.csv'
  volume_fraction = 1.0
/
&region
  material = 'air'
  lower = 0.0, 0.0, 0.0
  upper = 1.0, {level}, 0.05
  shape = 'profile'
  profile_lower_file = 'bed.csv'
  volume_fraction = 0.0
/
&solid
  name = 'bed'
  model = 'rigid'
  drag_law = 'impermeable'
  shape = 'profile'
  profile_file = 'bed.csv'
  particles_per_cell = 2, 2, 1
/
&solid
  name = 'sediment'
  model = 'mohr_coulomb'
  porosity = 0.4
  shape = 'profile'
  profile_lower_file = 'bed.csv'
  layer_thickness = {thickness}
  particles_per_cell = 2, 2, 1
/
"""
LEVEL, THICKNESS = 0.7, 0.1


def test_bathymetry_bed_layer_and_water(run_mpmice, tmp_case_dir):
    """Bed below a CSV profile, a 0.1 m layer on it, water above the bed up to 0.7 m."""
    _write_bed(tmp_case_dir / "bed.csv")
    (tmp_case_dir / "bed.nml").write_text(
        BATHYMETRY.format(grid=GRID, level=LEVEL, thickness=THICKNESS))
    result = run_mpmice(["bed.nml"])
    assert result.returncode == 0, result.stdout + result.stderr
    dump = list_dumps(str(tmp_case_dir / "out"), "bed")[0]
    c = (np.arange(20 * PPC) + 0.5) * H
    gx, gy = np.meshgrid(c, c, indexing="ij")
    gx, gy = gx.ravel(), gy.ravel()
    for name, lo, hi in (("bed", lambda x: -np.inf, _bed_interp),
                         ("sediment", _bed_interp, lambda x: _bed_interp(x) + THICKNESS)):
        p = _particles(dump, name)
        assert np.all(p["y"] <= hi(p["x"]) + 1e-12), name
        assert np.all(p["y"] >= lo(p["x"]) - 1e-12), name
        # exactly the lattice points in the band
        assert len(p["x"]) == np.sum((gy <= hi(gx)) & (gy >= lo(gx))), name
        # area against the band's area (integral of the profile), within the resolution
        xs = np.linspace(0.0, 1.0, 20001)
        band = np.trapezoid(np.minimum(hi(xs), 1.0) - np.maximum(lo(xs), 0.0), xs)
        assert abs(p["volume"].sum() / 0.05 - band) < 2.0 * H, name
    with h5py.File(dump, "r") as f:
        water = f["cell/water/volume_fraction"][0].T      # (x, y)
        air = f["cell/air/volume_fraction"][0].T
    share = water / (water + air)
    xc = (np.arange(20) + 0.5) / 20
    cx, cy = np.meshgrid(xc, xc, indexing="ij")
    wet = (cy >= _bed_interp(cx)) & (cy <= LEVEL)
    assert wet.sum() > 100 and (~wet).sum() > 100
    assert np.array_equal(share == 1.0, wet)
    assert np.all(share[~wet] == 0.0)
    # 2 ranks (shapes read on rank 0, broadcast): the same fractions and particles
    result = run_mpmice(["bed.nml", "--set", "&run output_dir = 'out2' /"], nranks=2)
    assert result.returncode == 0, result.stdout + result.stderr
    dump2 = list_dumps(str(tmp_case_dir / "out2"), "bed")[0]
    with h5py.File(dump2, "r") as f:
        assert np.array_equal(f["cell/water/volume_fraction"][0].T, water)
    for name in ("bed", "sediment"):
        assert np.array_equal(np.sort(_particles(dump2, name)["id"]),
                              np.sort(_particles(dump, name)["id"]))


@pytest.fixture(autouse=True)
def quiet_launcher(monkeypatch):
    """Open MPI's mpirun reports a non-zero exit on standard error; `orte_execute_quiet` turns
    that off so standard error holds only what mpmice prints (as in test_input_errors.py)."""
    monkeypatch.setenv("OMPI_MCA_orte_execute_quiet", "1")


# (file content, line named in the message, words of the message)
MALFORMED = {
    "non_numeric": ("x,y\n0.2,0.2\n0.8,abc\n0.5,0.8\n", 3, "not a finite number: 'abc'"),
    "three_values": ("0.2,0.2\n0.8,0.2,1.0\n0.5,0.8\n", 2, "expected two values"),
    "two_vertices": ("# too few\n0.2,0.2\n0.8,0.2\n", 3, "at least 3 vertices, found 2"),
    "bow_tie": ("0.2,0.2\n0.8,0.8\n0.8,0.2\n0.2,0.8\n", 3,
                "intersects itself: the edge from this line's vertex crosses the edge from line 1"),
    "repeated": ("0.2,0.2\n0.8,0.2\n0.8,0.2\n0.5,0.8\n", 3, "vertex repeats the one on line 2"),
    "outside": ("5,5\n6,5\n5,6\n", 0, "the polygon (x 5.0..6.0, y 5.0..6.0) lies outside the domain"),
}


def _assert_input_error(result, path, line, words, out):
    assert result.returncode == 1, result.stdout + result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    expected = f"{path}: line {line}: " if line else f"{path}: "
    assert lines[0].startswith(f"mpmice: input error: {expected}"), lines[0]
    assert words in lines[0], lines[0]
    assert not out.exists()


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_polygon_file(run_mpmice, tmp_case_dir, case):
    """Each malformed polygon: exit 1, one line with the file, the line and the problem,
    nothing written; the same under --check."""
    text, line, words = MALFORMED[case]
    csv = tmp_case_dir / f"{case}.csv"
    csv.write_text(text)
    (tmp_case_dir / "case.nml").write_text(_circle_case("out").replace("circle.csv", csv.name))
    for extra in ([], ["--check"]):
        result = run_mpmice(["case.nml"] + extra)
        _assert_input_error(result, csv, line, words, tmp_case_dir / "out")
        assert "polygon_file" in result.stderr


def test_profile_x_not_increasing_and_missing_file(run_mpmice, tmp_case_dir):
    """A profile whose x goes back, and a profile file that does not exist: exit 1, one line."""
    (tmp_case_dir / "bed.csv").write_text("x,y\n0.0,0.5\n0.5,0.4\n0.5,0.3\n1.0,0.2\n")
    case = BATHYMETRY.format(grid=GRID, level=LEVEL, thickness=THICKNESS)
    (tmp_case_dir / "case.nml").write_text(case)
    for extra in ([], ["--check"]):
        result = run_mpmice(["case.nml"] + extra)
        _assert_input_error(result, tmp_case_dir / "bed.csv", 4,
                            "x = 0.5 is not greater than x = 0.5 on line 3",
                            tmp_case_dir / "out")
    (tmp_case_dir / "case.nml").write_text(case.replace("'bed.csv'", "'missing/bed.csv'"))
    result = run_mpmice(["case.nml"])
    _assert_input_error(result, tmp_case_dir / "missing" / "bed.csv", 0, "no such file",
                        tmp_case_dir / "out")


def test_geometry_variable_errors(run_mpmice, tmp_case_dir):
    """Variables that do not fit the shape: one input-error line naming group and variable."""
    _write_bed(tmp_case_dir / "bed.csv")
    case = BATHYMETRY.format(grid=GRID, level=LEVEL, thickness=THICKNESS)
    (tmp_case_dir / "case.nml").write_text(case)
    for setting, words in (
            ("&solid name = 'sediment', profile_file = 'bed.csv' /",
             "&solid(2) layer_thickness = 0.1"),
            ("&solid name = 'sediment', layer_thickness = -1.0 /",
             "&solid(2) layer_thickness = -1.0: >= 0 [m]"),
            ("&solid name = 'bed', shape = 'box', upper = 1.0, 0.2, 0.05 /",
             "&solid(1) shape = 'box': 'profile' when profile_file"),
            ("&region material = 'water', upper = 1.0, 0.5, 0.05, shape = 'circle' /",
             "--set: &region(3) shape = 'circle': one of 'box', 'polygon', 'profile'")):
        result = run_mpmice(["case.nml", "--check", "--set", setting])
        assert result.returncode == 1, setting
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and words in lines[0], (setting, result.stderr)


def _map_height(x, y):
    return 0.4 + 0.1 * np.sin(3.0 * x) * np.cos(2.0 * y)


MAP_X, MAP_Y = np.linspace(0.0, 1.0, 21), np.linspace(0.0, 1.0, 11)


def _bilinear(px, py):
    """Bilinear interpolation of the map on its grid, as the code."""
    z = _map_height(*np.meshgrid(MAP_X, MAP_Y, indexing="ij"))
    i = np.clip(np.searchsorted(MAP_X, px, side="right") - 1, 0, len(MAP_X) - 2)
    j = np.clip(np.searchsorted(MAP_Y, py, side="right") - 1, 0, len(MAP_Y) - 2)
    s = (px - MAP_X[i]) / (MAP_X[i + 1] - MAP_X[i])
    t = (py - MAP_Y[j]) / (MAP_Y[j + 1] - MAP_Y[j])
    return ((1 - s) * (1 - t) * z[i, j] + s * (1 - t) * z[i + 1, j]
            + (1 - s) * t * z[i, j + 1] + s * t * z[i + 1, j + 1])


def test_height_map_bed_in_3d(run_mpmice, tmp_case_dir):
    """A 3D bed below a height map z(x, y) (a 21 x 11 CSV grid, rows of constant y): exactly
    the sub-cell centres below the bilinear surface are seeded; a map missing a point and a
    map in a 2D grid are input errors naming the file (and the line)."""
    with open(tmp_case_dir / "map.csv", "w") as f:
        f.write("x,y,z\n")
        for y in MAP_Y:
            for x in MAP_X:
                f.write(f"{x:.15g},{y:.15g},{_map_height(x, y):.15g}\n")
    case = """&run
  name = 'map'
  scene = 'mpm'
  output_dir = 'out'
  end_time = 1.0e-4
  output_interval = 1.0
/
&grid
  ncells = 10, 10, 10
  lower = 0.0, 0.0, 0.0
  upper = 1.0, 1.0, 1.0
/
&solid
  name = 'bed'
  shape = 'profile'
  profile_file = 'map.csv'
  particles_per_cell = 2, 2, 2
/
"""
    (tmp_case_dir / "map.nml").write_text(case)
    result = run_mpmice(["map.nml"])
    assert result.returncode == 0, result.stdout + result.stderr
    with h5py.File(list_dumps(str(tmp_case_dir / "out"), "map")[0], "r") as f:
        p = {k: f[f"particles/bed/{k}"][...] for k in ("x", "y", "z")}
    assert np.all(p["z"] <= _bilinear(p["x"], p["y"]) + 1e-12)
    c = (np.arange(20) + 0.5) * 0.05
    gx, gy, gz = (a.ravel() for a in np.meshgrid(c, c, c, indexing="ij"))
    assert len(p["x"]) == np.sum(gz <= _bilinear(gx, gy))
    # a row short of a point
    text = (tmp_case_dir / "map.csv").read_text().splitlines()
    del text[30]                       # line 31: x = 0.4 of the second row (y = 0.1)
    (tmp_case_dir / "map.csv").write_text("\n".join(text) + "\n")
    result = run_mpmice(["map.nml", "--check"])
    _assert_input_error(result, tmp_case_dir / "map.csv", 31, "expected the point x = 0.4, y = 0.1, found x = 0.45",
                        tmp_case_dir / "out_none")
    # the map back (no header), in a 2D grid
    with open(tmp_case_dir / "map.csv", "w") as f:
        for y in MAP_Y:
            for x in MAP_X:
                f.write(f"{x},{y},{_map_height(x, y)}\n")
    (tmp_case_dir / "map.nml").write_text(case.replace("10, 10, 10", "10, 10, 1"))
    result = run_mpmice(["map.nml", "--check"])
    _assert_input_error(result, tmp_case_dir / "map.csv", 0, "needs a 3D grid",
                        tmp_case_dir / "out_none")
