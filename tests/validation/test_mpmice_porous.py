"""Porous-media validations of the coupled MPMICE scene: steady Darcy flow through a rigid
porous column (paper eq. 77, postproc/mpmice_darcy.py) and 1D isothermal consolidation (eq. 78
with the fluid compressibility, postproc/mpmice_terzaghi.py).

The analytic pieces and the analysis of dumps (on synthetic HDF5 dumps written here in the
solver's layout) are tested always. The scene tests are skipped, with the solver's message,
while `mpmice --check` of the namelist fails or the build answers that the scene is not
available / not implemented (probed once per session with a one-step run); under
scripts/test.sh (MPMICE_REQUIRE_ALL=1) they fail instead."""
from __future__ import annotations

import math
import os
import re
import subprocess

import h5py
import numpy as np
import pytest

from postproc import mpmice_darcy, mpmice_terzaghi
from postproc.analytic import (carman_kozeny_conductivity, consolidation_coefficient,
                               darcy_pore_velocity, oedometer_modulus,
                               terzaghi_degree_of_consolidation)
from postproc.run_case import mpi_environment, mpirun_command

P = mpmice_terzaghi.PARAMS


# --------------------------------------------------------------------------- analytic pieces

def test_biot_cv_reduces_to_paper_cv_for_incompressible_fluid():
    """K_f -> infinity: c_v = (k/mu) E_v = E_v n^3 d^2 / (180 (1 - n)^2 mu) (paper, eq. 78)."""
    args = (P["youngs_modulus"], P["poisson_ratio"], P["porosity"], P["grain_size"],
            P["viscosity"])
    paper = consolidation_coefficient(*args)
    assert mpmice_terzaghi.biot_consolidation_coefficient(*args) == pytest.approx(paper, rel=1e-14)
    assert mpmice_terzaghi.biot_consolidation_coefficient(*args, bulk_modulus=1e30) \
        == pytest.approx(paper, rel=1e-14)
    # K_f = 2 GPa: 1/E_v + n/K_f is larger by n E_v / K_f = 0.2 %
    e_v = oedometer_modulus(P["youngs_modulus"], P["poisson_ratio"])
    biot = mpmice_terzaghi.biot_consolidation_coefficient(*args, bulk_modulus=P["bulk_modulus"])
    assert paper / biot == pytest.approx(1.0 + P["porosity"] * e_v / P["bulk_modulus"], rel=1e-14)
    assert mpmice_terzaghi.undrained_pressure(1e4, *args[:3]) == 1e4
    assert mpmice_terzaghi.undrained_pressure(1e4, *args[:3], bulk_modulus=P["bulk_modulus"]) \
        == pytest.approx(1e4 / (1.0 + P["porosity"] * e_v / P["bulk_modulus"]), rel=1e-14)


def test_paper_consolidation_coefficient_value():
    """Errata derived check: E = 10 MPa, nu = 0.3, n = 0.3, d = 1 mm, mu = 1 mPa s give
    c_v ~ 4.12 m^2/s (4.121 incompressible, 4.113 with K_f = 2 GPa)."""
    c_v = consolidation_coefficient(1e7, 0.3, 0.3, 1e-3, 1e-3)
    assert c_v == pytest.approx(4.12, abs=5e-3)
    c_v_biot, p0 = mpmice_terzaghi.consolidation_constants()
    assert c_v_biot == pytest.approx(4.1126, abs=1e-4)
    assert p0 == pytest.approx(9979.85, abs=0.01)


def test_degree_of_consolidation_values():
    """U(0.2) = 0.504 (textbook table), U(0.848) = 0.90, and U = 1 - mean(p)/p0 of the series."""
    assert terzaghi_degree_of_consolidation(0.2) == pytest.approx(0.504, abs=1e-3)
    assert terzaghi_degree_of_consolidation(0.848) == pytest.approx(0.90, abs=1e-3)
    y = (np.arange(20000) + 0.5) / 20000
    c_v, p0 = mpmice_terzaghi.consolidation_constants()
    for time in (0.01, 0.05, 0.12):
        p = mpmice_terzaghi.exact_excess_pressure(y, time)
        assert 1.0 - np.mean(p) / p0 == pytest.approx(
            terzaghi_degree_of_consolidation(c_v * time), abs=1e-8)


def test_kozeny_carman_drag_gives_eq77_at_steady_state():
    """Drag per unit mixture volume, eq. 18 with F = 10 phi_s/(1 - phi_s)^2 (errata E7):
    f_d = K_d (U_s - U_f), K_d = 18 phi_s (1 - phi_s) mu / d^2 F = 180 phi_s^2 mu /
    (d^2 (1 - phi_s)). Steady fluid momentum per mixture volume in a rigid column (U_s = 0):
    0 = -n dp/dx - K_d U_f, so U_f = n dp / (L K_d) = n^2 d^2 dp / (180 mu phi_s^2 L), which is
    eq. 77 (1/n) K dp/L with K = d^2 n^3 / (180 mu phi_s^2); the Darcy flux n U_f = K dp/L
    (eq. 76 read as a flux, errata E11). (Balancing n dp/L against n K_d U_f instead would be off
    by the factor 1/n: the drag of eq. 18 is already per mixture volume.)"""
    d, mu, length = 1e-3, 1e-3, 1.0
    for phi in mpmice_darcy.SOLID_FRACTIONS:
        n = 1.0 - phi
        f_kc = 10.0 * phi / (1.0 - phi) ** 2
        k_d = 18.0 * phi * (1.0 - phi) * mu / d**2 * f_kc
        assert k_d == pytest.approx(180.0 * phi**2 * mu / (d**2 * (1.0 - phi)), rel=1e-14)
        for dp_atm in mpmice_darcy.PRESSURE_DROPS_ATM:
            dp = dp_atm * 101325.0
            u_balance = n * dp / length / k_d
            assert u_balance == pytest.approx(darcy_pore_velocity(phi, d, mu, dp, length),
                                              rel=1e-13)
            assert n * u_balance == pytest.approx(
                carman_kozeny_conductivity(phi, d, mu) * dp / length, rel=1e-13)
            assert mpmice_darcy.exact_pore_velocity(phi, dp_atm) == pytest.approx(u_balance,
                                                                                  rel=1e-13)
    # phi_s = 0.6, 0.5 atm (the namelist's case): U_f = 0.125 m/s
    assert mpmice_darcy.exact_pore_velocity(0.6, 0.5) == pytest.approx(0.12509, abs=1e-5)


# --------------------------------------------------------------------------- synthetic dumps

def write_dump(path, time, step, ncells, lower, upper, cell_fields):
    """A dump in the solver's layout (docs/io.md): root attributes, /cell/<name> stored with
    the Fortran extent (ni, nj, nk), i.e. shape (nk, nj, ni) in h5py."""
    ncells = np.asarray(ncells, dtype=np.int32)
    lower = np.asarray(lower, dtype=float)
    dx = (np.asarray(upper, dtype=float) - lower) / ncells
    with h5py.File(path, "w") as f:
        f.attrs["time"] = float(time)
        f.attrs["step"] = int(step)
        f.attrs["ncells"] = ncells
        f.attrs["lower"] = lower
        f.attrs["dx"] = dx
        for name, values in cell_fields.items():
            f.create_dataset(f"cell/{name}", data=np.asarray(values, dtype=float).T)


def set_value(args, group, variable):
    """The value text of `variable` in the last --set group `group` of a command line."""
    found = None
    for text in args:
        if isinstance(text, str) and text.lstrip().startswith("&" + group):
            match = re.search(variable + r"\s*=\s*('[^']*'|[^/']*?)\s*(?:,\s*[a-z_]+\s*=|/\s*$)",
                              text)
            if match:
                found = match.group(1)
    return found


def fake_terzaghi_run(relative_error):
    """A stand-in for run_mpmice writing dumps p_exact (1 + relative_error(h)) - like a
    scheme of known order - at the namelist's output interval."""
    def run(args, nranks=1, cwd=None, **_):
        out = set_value(args, "run", "output_dir").strip("'")
        cells = int(set_value(args, "grid", "ncells").split(",")[1])
        end = set_value(args, "run", "end_time")
        end = float(end) if end else 0.25
        os.makedirs(out, exist_ok=True)
        h = 1.0 / cells
        y = (np.arange(cells) + 0.5) * h
        for step, t in enumerate(np.arange(0.0, end + 1e-9, 0.0125)):
            if t > 0.0:
                p = mpmice_terzaghi.exact_excess_pressure(y, t) * (1.0 + relative_error(h))
            else:
                p = np.full(cells, mpmice_terzaghi.consolidation_constants()[1])
            pressure = (101325.0 + p).reshape(1, cells, 1)
            write_dump(os.path.join(out, f"terzaghi_{step * 100:06d}.h5"), t, step * 100,
                       (1, cells, 1), (0, 0, 0), (0.01, 1.0, 0.01), {"pressure": pressure})
        return subprocess.CompletedProcess(args, 0, "", "")
    return run


def test_terzaghi_analysis_on_synthetic_dumps(tmp_path, monkeypatch):
    """run_terzaghi through the real reader on dumps with a relative error 2 h^2: errors,
    observed order 2, T_v picks and U(T_v) are what they must be."""
    monkeypatch.setattr(mpmice_terzaghi, "run_mpmice", fake_terzaghi_run(lambda h: 2.0 * h**2))
    study = mpmice_terzaghi.run_terzaghi(str(tmp_path), cells=[25, 50, 100])
    for n, err in zip(study["cells"], study["max_error"]):
        assert err == pytest.approx(2.0 / n**2, rel=1e-9)
    assert study["order_max"] == pytest.approx([2.0, 2.0], abs=1e-9)
    r = study["runs"][100]
    assert sorted(r["at_tv"]) == list(mpmice_terzaghi.TV_REPORT)
    c_v, p0 = mpmice_terzaghi.consolidation_constants()
    for target, a in r["at_tv"].items():
        assert abs(a["tv"] - target) <= 0.5 * c_v * 0.0125 + 1e-12
        assert a["tv"] == pytest.approx(c_v * a["time"], rel=1e-12)
        assert a["u_exact"] == pytest.approx(terzaghi_degree_of_consolidation(a["tv"]), abs=1e-12)
        # midpoint mean of the exact profile at 100 cells against the series: O(h^2)
        assert a["u_numeric"] == pytest.approx(a["u_exact"], abs=2e-3)
        assert np.max(np.abs(a["p_over_p0"] / a["exact_over_p0"] - 1.0)) < 2.1e-4
    assert math.isnan(r["l2_error"][0])     # t = 0 is not compared
    assert r["wall_time"] >= 0.0
    assert study["order_at_tv"][0.2] == pytest.approx([2.0, 2.0], abs=1e-9)
    # report, plot and CSV run on it
    mpmice_terzaghi.print_report(study)
    mpmice_terzaghi.plot(study, str(tmp_path / "t.png"))
    mpmice_terzaghi.write_csv(study, str(tmp_path / "t.csv"))
    rows = (tmp_path / "t.csv").read_text().splitlines()
    assert len(rows) == 1 + 3 * len(mpmice_terzaghi.TV_REPORT)
    assert (tmp_path / "t.png").stat().st_size > 0


def test_terzaghi_short_run_reports_only_reached_time_factors(tmp_path, monkeypatch):
    monkeypatch.setattr(mpmice_terzaghi, "run_mpmice", fake_terzaghi_run(lambda h: 0.0))
    study = mpmice_terzaghi.run_terzaghi(str(tmp_path), 50, extra_set=["&run end_time = 0.1 /"])
    r = study["runs"][50]
    assert sorted(r["at_tv"]) == [0.05, 0.1, 0.2]    # T_v(0.1 s) = 0.41 < 0.5
    assert r["max_error"] < 1e-12


def fake_darcy_run(scale):
    """A stand-in for run_mpmice: water velocity U_f(1 + scale) inside the column and
    n U_f outside, with a 1e-6 relative change between the last two dumps."""
    def run(args, nranks=1, cwd=None, **_):
        out = set_value(args, "run", "output_dir").strip("'")
        n = float(set_value(args, "solid", "porosity"))
        dp = float(set_value(args, "boundary", "pressure")) - 101325.0
        os.makedirs(out, exist_ok=True)
        x = (np.arange(20) + 0.5) * 0.1
        inside = (x > 0.5) & (x < 1.5)
        u_f = darcy_pore_velocity(1.0 - n, 1e-3, 1e-3, dp, 1.0) * (1.0 + scale)
        for step, t in enumerate(np.arange(0.0, 0.1 + 1e-9, 0.01)):
            factor = 1.0 - 1e-6 * (10 - step)
            u = np.where(inside, u_f, n * u_f) * factor
            write_dump(os.path.join(out, f"darcy_{step * 10:06d}.h5"), t, step * 10,
                       (20, 1, 1), (0, 0, 0), (2.0, 0.1, 0.1),
                       {"water/velocity_x": u.reshape(20, 1, 1),
                        "porous/volume_fraction": np.where(inside, 1.0 - n, 0.0).reshape(20, 1, 1),
                        "pressure": np.full((20, 1, 1), 101325.0)})
        return subprocess.CompletedProcess(args, 0, "", "")
    return run


def test_darcy_analysis_on_synthetic_dumps(tmp_path, monkeypatch):
    monkeypatch.setattr(mpmice_darcy, "run_mpmice", fake_darcy_run(1e-3))
    results = mpmice_darcy.run_darcy(str(tmp_path))
    assert [(r["phi_s"], r["dp_atm"]) for r in results] == list(mpmice_darcy.CASES)
    assert len(results) == 15
    for r in results:
        assert r["rel_error"] == pytest.approx(1e-3, abs=1e-12)
        assert r["steady_change"] == pytest.approx(1e-6, rel=1e-3)
        assert r["u_outside"] / r["darcy_flux_exact"] == pytest.approx(1.001, rel=1e-12)
        assert r["solid_fraction_cells"] == pytest.approx(r["phi_s"], abs=1e-12)
        assert r["time"] == pytest.approx(0.1)
        assert r["cell_error_max"] == pytest.approx(1e-3, rel=1e-9)
        assert r["cell_error_interior"] == pytest.approx(1e-3, rel=1e-9)
        assert r["steady_change_cells"] == pytest.approx(1e-6, rel=1e-3)
    mpmice_darcy.print_table(results)
    mpmice_darcy.plot(results, str(tmp_path / "d.png"))
    mpmice_darcy.write_csv(results, str(tmp_path / "d.csv"))
    assert len((tmp_path / "d.csv").read_text().splitlines()) == 16


# --------------------------------------------------------------------------- scene runs

_PROBES: dict[str, str | None] = {}
_UNAVAILABLE = re.compile(r"not available in this build|not implemented", re.I)


def scene_unavailable(exe, namelist, workdir) -> str | None:
    """Why the scene of `namelist` cannot run yet (None if it can), probed once per session:
    `mpmice --check` must pass, and a one-step run must not stop with 'not available in this
    build' / 'not implemented' (any other failure is left to the test, which will show it)."""
    if namelist in _PROBES:
        return _PROBES[namelist]
    env = mpi_environment()
    reason = None
    check = subprocess.run(mpirun_command(exe, ["--check", namelist], 1), cwd=workdir, env=env,
                           text=True, capture_output=True, timeout=120, check=False)
    if check.returncode != 0:
        lines = (check.stderr or check.stdout).strip().splitlines()
        reason = f"mpmice --check {os.path.basename(namelist)} fails: " \
                 f"{lines[0] if lines else check.returncode}"
    else:
        out = os.path.join(workdir, "probe_" + os.path.basename(namelist)[:-4])
        probe = subprocess.run(
            mpirun_command(exe, [namelist, "--set", f"&run output_dir = '{out}', max_steps = 1 /"],
                           1), cwd=workdir, env=env, text=True, capture_output=True, timeout=300,
            check=False)
        if probe.returncode != 0:
            lines = [l for l in (probe.stdout + probe.stderr).splitlines()
                     if _UNAVAILABLE.search(l)]
            if lines:
                reason = f"{os.path.basename(namelist)}: {lines[0].strip()}"
    _PROBES[namelist] = reason
    return reason


@pytest.fixture(scope="module")
def _scene_probe_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("mpmice_porous_probe"))


@pytest.fixture
def darcy_scene(mpmice_exe, monkeypatch, _scene_probe_dir, unavailable):
    reason = scene_unavailable(str(mpmice_exe), mpmice_darcy.NAMELIST, _scene_probe_dir)
    if reason:
        unavailable(reason)
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.fixture
def terzaghi_scene(mpmice_exe, monkeypatch, _scene_probe_dir, unavailable):
    reason = scene_unavailable(str(mpmice_exe), mpmice_terzaghi.NAMELIST, _scene_probe_dir)
    if reason:
        unavailable(reason)
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


#: Measured on the 15 cases (python -m postproc.mpmice_darcy): the largest |relative error|
#: of the column mean 1.50e-4, of any cell 1.53e-3 (the column's first cell and the first free
#: cell after it, at 1 atm; linear in dp), of the cells away from the column's ends 2.50e-5
#: (the water's compressibility: the density falls by dp / K_f = 5e-5 per atm along the
#: column), the largest change of a cell between the last two dumps 1.31e-8 of the largest
#: velocity and of the column mean 5.8e-10. Each bound is 2-3x its measurement.
DARCY_BOUNDS = {"mean": 3e-4, "cell": 3e-3, "interior": 5e-5, "steady_cells": 3e-8,
                "steady_mean": 1.5e-9}


def check_darcy(results, bounds=None):
    """Every cell against eq. 77 (pore velocity U_f inside the column, the Darcy flux n U_f in
    the free water, errata E11), the column mean, and how steady every cell is between the last
    two dumps, within DARCY_BOUNDS. Per cell, because the column mean of an odd-even velocity
    pattern cancels (docs/validation/mpmice_darcy.md)."""
    bounds = DARCY_BOUNDS if bounds is None else bounds
    for r in results:
        assert abs(r["rel_error"]) < bounds["mean"], r
        assert abs(r["u_outside"] / r["darcy_flux_exact"] - 1.0) < bounds["mean"], r
        assert r["cell_error_max"] < bounds["cell"], r
        assert r["cell_error_interior"] < bounds["interior"], r
        assert r["steady_change_cells"] < bounds["steady_cells"], r
        assert r["steady_change"] < bounds["steady_mean"], r


def test_darcy_check_fails_on_an_odd_even_pattern(tmp_path, monkeypatch):
    """A +-1 % odd-even pattern on eq. 77 leaves the column mean exact and fails check_darcy."""
    monkeypatch.setattr(mpmice_darcy, "run_mpmice", fake_darcy_run(0.0))
    result = mpmice_darcy.run_darcy(str(tmp_path), [(0.6, 0.5)])
    good = dict(result[0], steady_change=0.0, steady_change_cells=0.0)  # the fake drifts 1e-6
    assert good["cell_error_max"] < 1e-12
    check_darcy([good])
    dump = mpmice_darcy.read_run_dumps(good["output_dir"], mpmice_darcy.NAME, last=1)[0]
    u = dump["cell"]["water/velocity_x"]
    u[:, 0, 0] *= 1.0 + 0.01 * (-1.0) ** np.arange(u.shape[0])
    odd_even = mpmice_darcy.analyse_case([dump], 0.6, 0.5)
    assert abs(odd_even["rel_error"]) < 1e-12
    assert odd_even["cell_error_max"] == pytest.approx(0.01, rel=1e-9)
    with pytest.raises(AssertionError):
        check_darcy([dict(good, **{k: odd_even[k] for k in ("cell_error_max",
                                                            "cell_error_interior")})])


def test_darcy_all_cases(darcy_scene, tmp_path):
    """The paper's 15 cases (Fig. 4) against eq. 77 in every cell, within DARCY_BOUNDS."""
    check_darcy(mpmice_darcy.run_darcy(str(tmp_path)))


def test_terzaghi_100_cells(terzaghi_scene, tmp_path):
    """The paper's column (100 cells, step load, the paper's densities) to t = 0.25 s
    (T_v = 1.03) against eq. 78 with the fluid compressibility: relative L2 error of the excess
    pore pressure < 1.5 % at every dump with 0.1 <= T_v <= 0.6 (measured at most 1.30 %, at
    T_v = 0.1), < 2.5 % up to T_v = 1.03 (measured 2.16 %, where the pressure is 8 % of p0:
    Biot's inertia, ~0.35 % of c_v, and the first-order upwind pore fraction of the pressure
    equation's water flux, which the water's mass flux follows inside the soil since
    docs/mpmice.md departure 16 was extended to it; 1.75 % before), and the degree of
    consolidation within 0.005 of U(T_v) at every dump with T_v >= 0.05. Earlier dumps hold the
    ringing of the column's undrained P-wave that the quasi-static eq. 78 lacks. The late error
    converges: 200 cells (~3 s) < 1.2 % from T_v = 0.1 to 1.03 (measured 0.96 %; 0.61 % before)
    and at most 0.55 of the 100-cell error at T_v >= 0.6 (measured 0.44)."""
    study = mpmice_terzaghi.run_terzaghi(str(tmp_path), (100, 200))
    r = study["runs"][100]
    mid = (r["tv"] >= 0.1) & (r["tv"] <= 0.6)
    late = r["tv"] >= 0.1
    assert np.count_nonzero(mid) >= 8, r["tv"]
    assert np.max(r["l2_error"][mid]) < 1.5e-2, dict(zip(r["tv"], r["l2_error"]))
    assert np.max(r["l2_error"][late]) < 2.5e-2, dict(zip(r["tv"], r["l2_error"]))
    ok = r["tv"] >= 0.05
    assert np.max(np.abs(r["u_numeric"][ok] - r["u_exact"][ok])) < 5e-3
    fine = study["runs"][200]
    assert np.allclose(fine["tv"], r["tv"])
    assert np.max(fine["l2_error"][late]) < 1.2e-2, dict(zip(fine["tv"], fine["l2_error"]))
    tail = r["tv"] >= 0.6
    assert np.max(fine["l2_error"][tail] / r["l2_error"][tail]) < 0.55


def test_terzaghi_quasi_static_100_cells(terzaghi_scene, tmp_path):
    """The target, <= 1 % relative L2 error at 100 cells, at every dump from T_v = 0.05
    to 1.03, in the quasi-static limit eq. 78 describes (densities / 100, which eq. 78 does not
    contain: no P-wave ringing, no inertia; measured at most 0.80 %)."""
    study = mpmice_terzaghi.run_terzaghi(str(tmp_path), 100,
                                         extra_set=mpmice_terzaghi.QUASI_STATIC_SET)
    r = study["runs"][100]
    ok = r["tv"] >= 0.05
    assert np.count_nonzero(ok) >= 19, r["tv"]
    assert np.max(r["l2_error"][ok]) <= 1e-2, dict(zip(r["tv"], r["l2_error"]))


def test_terzaghi_converges(terzaghi_scene, tmp_path):
    """At T_v = 0.5 the error falls with the cell count: 50 -> 100 cells, at least by 2x, an
    observed order above 1 (measured 1.99 % -> 0.69 %, 2.9x, order 1.5)."""
    study = mpmice_terzaghi.run_terzaghi(str(tmp_path), (50, 100),
                                         extra_set=["&run end_time = 0.125 /"])
    e50, e100 = study["error_at_tv"][0.5]
    assert e100 < e50 / 2.0, (e50, e100)


# Rank invariance of the Terzaghi column (1 against 2 and 4 ranks): test_mpmice_parallel.py.
