"""The resolution study of the sand slide (postproc/mpmice_debris_ladder.py) on three fake runs
written with h5py (no solver): a free surface eta_h(x) = a + b x + C h^2 on cells of h = 0.2,
0.1 and 0.05 m gives eta differences C (h1^2 - h2^2) between successive runs and the observed
order 2 (also of a front advance 0.2 m + h^2); a column without an interface is left out of the
comparison; the excess pore pressure and the nearest-dump choice are checked against the values
put in."""
import math

import h5py
import numpy as np

from postproc import mpmice_debris_ladder as ladder

A, B, C = 0.01, 0.005, 1.0       # eta_h(x) = A + B x + C h^2   [m]
CELLS = (0.2, 0.1, 0.05)         # m
EXCESS_PER_X = 1000.0            # Pa/m: the sand's excess pore pressure put in is 1000 x
NAN_COLUMN = 10                  # in the 0.1 m run, this column holds water only (no interface)
ADVANCE = 0.2                    # m: the front moves by ADVANCE + h^2 from t = 0 to 0.4 s


def _write_dump(path, h, time, with_hole):
    ni, nj = round(4.0 / h), round(2.0 / h)
    xc = (np.arange(ni) + 0.5) * h
    yc = (np.arange(nj) + 0.5) * h
    surface = ladder.STILL_LEVEL + A + B * xc + C * h**2
    # water share linear over +-2 cells around the surface: its 0.5 crossing between cell
    # centres is exactly the surface
    share = np.clip(0.5 + (surface[:, None] - yc[None, :]) / (4.0 * h), 0.0, 1.0)
    if with_hole:
        share[NAN_COLUMN, :] = 1.0
    px = np.array([1.1, 1.2, 1.3 + (ADVANCE + h**2) * (time > 0.0)])
    py = np.array([1.0, 1.2, 1.7])
    hydrostatic = ladder.P_ATM + ladder.RHO_W * ladder.G * np.clip(1.6 - py, 0.0, None)
    with h5py.File(path, "w") as f:
        f.attrs["time"] = time
        f.attrs["step"] = 0
        f.attrs["dx"] = np.array([h, h, h])
        f.attrs["ncells"] = np.array([ni, nj, 1], dtype=np.int32)
        f.attrs["lower"] = np.zeros(3)
        # grid fields as the Fortran writer stores them: (nk, nj, ni)
        f["cell/water/volume_fraction"] = share.T[None, :, :]
        f["cell/air/volume_fraction"] = (1.0 - share).T[None, :, :]
        f["cell/water/density"] = 999.8 * share.T[None, :, :]
        sand = f.create_group("particles/sand")
        sand["x"], sand["y"], sand["mass"] = px, py, np.ones(3)
        sand["pore_pressure"] = hydrostatic + EXCESS_PER_X * px


def _fake_runs(tmp_path):
    dirs = []
    for h in CELLS:
        d = tmp_path / f"run{round(h * 1000)}"
        d.mkdir()
        for step, t in ((0, 0.0), (100, 0.4)):
            _write_dump(d / f"debris_{step:06d}.h5", h, t, with_hole=(h == 0.1))
        (d / "debris_checkpoint_000100.h5").write_bytes(b"not a dump")
        dirs.append(str(d))
    return dirs


def test_ladder_differences_and_order(tmp_path):
    """eta differences 3 cm and 0.75 cm (RMS and max) over 37 and 74 common columns, order 2 of
    eta and of the front, excess pore pressure 1000 x, 0.8 s not reached, three PNGs."""
    dirs = _fake_runs(tmp_path)
    runs = sorted((ladder.read_run(d, [0.4, 0.8]) for d in reversed(dirs)), key=lambda r: -r["h"])
    assert [r["h"] for r in runs] == list(CELLS)
    for r in runs:
        assert r["at"][0.8] is None and r["at"][0.4]["time"] == 0.4
        assert abs(r["at"][0.4]["advance"] - (ADVANCE + r["h"]**2)) < 1e-12
        np.testing.assert_allclose(r["at"][0.4]["excess"], EXCESS_PER_X * r["at"][0.4]["px"],
                                   rtol=0, atol=1e-8)
    study = ladder.compare(runs, [0.4, 0.8])
    assert study[0.8]["runs"] == [] and study[0.8]["orders"] == []
    entry = study[0.4]
    (rms12, max12, n12), (rms23, max23, n23) = entry["diffs"][1], entry["diffs"][2]
    e12, e23 = C * (0.2**2 - 0.1**2), C * (0.1**2 - 0.05**2)
    assert abs(rms12 - e12) < 1e-12 and abs(max12 - e12) < 1e-12
    assert abs(rms23 - e23) < 1e-12 and abs(max23 - e23) < 1e-12
    # 0.1 m columns inside the 0.2 m run's centres [0.1, 3.9]: 38, less the hole; 0.05 m
    # columns inside [0.05, 3.95]: 78, less the 4 between the hole's neighbours 0.95 and 1.15
    assert (n12, n23) == (37, 74)
    (_, p_rms, p_max, p_front), = entry["orders"]
    assert abs(p_rms - 2.0) < 1e-9 and abs(p_max - 2.0) < 1e-9 and abs(p_front - 2.0) < 1e-9
    assert ladder.main(["--dir", dirs[0], "--dir", dirs[1], "--dir", dirs[2],
                        "--times", "0.4", "0.8", "--out", str(tmp_path)]) == 0
    for name in ("eta", "front", "pore"):
        assert (tmp_path / f"debris_ladder_{name}.png").stat().st_size > 0


def test_observed_order_uneven_ratio_and_undefined():
    """Cell sizes 0.3 / 0.1 / 0.05 with differences of an h^1.5 error give 1.5 (bisection);
    equal differences at ratio 2 give 0; a zero difference gives NaN."""
    h = (0.3, 0.1, 0.05)
    e = (h[0]**1.5 - h[1]**1.5, h[1]**1.5 - h[2]**1.5)
    assert abs(ladder.observed_order(h, e) - 1.5) < 1e-9
    assert abs(ladder.observed_order((0.4, 0.2, 0.1), (1.0, 1.0))) < 1e-12
    assert math.isnan(ladder.observed_order((0.4, 0.2, 0.1), (1.0, 0.0)))


def test_entrained_air_counts_the_air_below_the_shelf(tmp_path):
    """On the 0.2 m fake run the water share ramps over +-2 cells around eta = 1.65 + 0.005 x,
    so the only cells below the shelf (centres below 1.5 m) holding air are those at y = 1.3 m,
    with air 0.0625 - 0.00625 x: over the 20 columns (sum x = 40 m) 1.25 - 0.25 = 1.0, times the
    cell area 0.04 m^2 gives 0.04 m^2 per metre."""
    from postproc.mpmice_debris_flow import entrained_air
    from postproc.mpmice_io import read_dump
    path = tmp_path / "debris_000000.h5"
    _write_dump(path, 0.2, 0.0, with_hole=False)
    assert math.isclose(entrained_air(read_dump(str(path))), 0.04, rel_tol=1e-12)
