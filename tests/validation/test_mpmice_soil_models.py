"""The soil models (docs/soil_models.md) in the coupled scene: the consolidation column
(namelists/mpmice_terzaghi_1d.nml) with `&solid model = 'cam_clay'` set on the command line.

* Undrained loading (impermeable platen on top, wall base; docs/mpmice.md): the sudden 10 kPa
  load builds an excess pore pressure B F with Skempton's B = 1 / (1 + n E_oed / K_f) of the
  clay's tangent modulus at p' < p'_min, E_oed = K + 4G/3, K = v0 p'_min / kappa,
  G = 3K (1 - 2 nu) / (2 (1 + nu)): B = 0.9999914 (linear elastic soil of the scene: 0.998).
* Drained top: a clay held inside its yield surface (p_c0 = 1 MPa) and below p'_min = 100 kPa
  has the constant K = v0 p'_min / kappa, so the column consolidates as Terzaghi's (eq. 78)
  with that oedometric modulus (E = 3K (1 - 2 nu) = 4.29 MPa instead of the scene's 10 MPa).

* Undrained cyclic simple shear (namelists/mpmice_cyclic_shear_column_1d.nml): a normally
  consolidated clay and a loose sand build excess pore pressure (the loose sand liquefies), a
  dense sand sucks, a linear elastic skeleton builds none.

Runs (2 shared cores under load): ~3.5 s (Cam-Clay restart, scene mpm), ~1.5 s (undrained),
~11 s (consolidation, densities / 100 at dt = 10 us), ~4 s (Cam-Clay, elastic) and ~9 s
(sand) per cyclic shear run, 2 per test.
"""
from __future__ import annotations

import pathlib

import numpy as np
import pytest

from postproc import mpmice_terzaghi
from postproc.dump_compare import assert_dumps_identical
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice

P = mpmice_terzaghi.PARAMS
PLATEN = "&boundary face = 'y+', fluid = 'wall' /"
KAPPA = 0.04           # &solid swelling_index default


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def clay_moduli(min_pressure: float, porosity: float = P["porosity"],
                nu: float = P["poisson_ratio"]) -> tuple[float, float]:
    """(K, G) [Pa] of the Cam-Clay skeleton below p'_min at J = 1."""
    bulk = min_pressure / ((1.0 - porosity) * KAPPA)
    return bulk, 1.5 * bulk * (1.0 - 2.0 * nu) / (1.0 + nu)


def test_clay_moduli_and_skempton_b():
    """K = (1/0.7) 1000 / 0.04 = 35.7 kPa, E_oed = 57.7 kPa, B = 0.9999914."""
    bulk, shear = clay_moduli(1.0e3)
    assert bulk == pytest.approx(35714.29, rel=1e-6)
    e_oed = bulk + 4.0 / 3.0 * shear
    b = 1.0 / (1.0 + P["porosity"] * e_oed / P["bulk_modulus"])
    assert b == pytest.approx(0.9999913, abs=1e-7)


def test_cam_clay_undrained_column_builds_pore_pressure(solver, tmp_path):
    """Platen on top, wall base, Cam-Clay at zero initial stress (p' < p'_min = 1 kPa): from
    t = 30 ms (after the undrained wave) the excess pore pressure of every cell of the lower
    half is B F to 2e-6 F (measured 1.4e-7 F; B = 1 would be 8.6e-6 F off, the scene's linear
    elastic soil 2e-3 F), of every cell to 5e-5 F (the cells under the platen: measured
    1.4e-5 F at 30 ms, 2.1e-5 F at 45 ms), and the skeleton carries the rest:
    |sigma'_yy| < 1e-3 F."""
    out = str(tmp_path / "undrained")
    run_mpmice([mpmice_terzaghi.NAMELIST, "--set", PLATEN,
                "--set", "&solid name = 'soil', model = 'cam_clay' /",
                "--set", f"&run end_time = 0.05, output_interval = 0.005, output_dir = '{out}' /"],
               cwd=str(tmp_path), timeout=300)
    bulk, shear = clay_moduli(1.0e3)
    b = 1.0 / (1.0 + P["porosity"] * (bulk + 4.0 / 3.0 * shear) / P["bulk_modulus"])
    profiles = mpmice_terzaghi.excess_profiles(out)
    late = [(t, p) for t, _, p in profiles if t >= 0.03 - 1e-12]
    assert len(late) >= 4
    for time, excess in late:
        deviation = np.abs(excess / P["load"] - b)
        assert np.max(deviation[:len(deviation) // 2]) < 2e-6, (time, excess[[0, 50, -1]])
        assert np.max(deviation) < 5e-5, (time, excess[[0, 50, -1]])
    dump = read_dump(list_dumps(out, mpmice_terzaghi.NAME)[-1])
    stress = dump["particles"]["soil"]["stress_yy"]
    assert np.max(np.abs(stress)) < 1e-3 * P["load"]


def test_cam_clay_below_p_min_consolidates_as_terzaghi(solver, tmp_path):
    """Drained top, densities / 100, dt = 10 us, 100 cells, to T_v = 0.44: p'_min = 100 kPa and
    p_c0 = 1 MPa keep the clay elastic with K = v0 p'_min / kappa = 3.57 MPa; relative L2 error
    of the excess pore pressure against eq. 78 with E = 3K (1 - 2 nu) <= 1 % at every dump from
    T_v = 0.05 (measured 0.38-0.50 %, 18 dumps; the scene's linear elastic soil at dt = 5 us:
    0.26-0.35 %), and the largest particle p' stays below p'_min."""
    out = str(tmp_path / "consolidation")
    run_mpmice(mpmice_terzaghi.fixed_dt_args(100, P["grain_size"], 1.0e-5, 0.25, 0.0125, out)
               + ["--set", "&solid name = 'soil', model = 'cam_clay', min_pressure = 1.0e5, "
                           "preconsolidation_pressure = 1.0e6 /"],
               cwd=str(tmp_path), timeout=300)
    bulk, _ = clay_moduli(1.0e5)
    params = dict(P, youngs_modulus=3.0 * bulk * (1.0 - 2.0 * P["poisson_ratio"]))
    c_v, p0 = mpmice_terzaghi.consolidation_constants(params)
    profiles = mpmice_terzaghi.excess_profiles(out)
    assert profiles[-1][0] == pytest.approx(0.25)
    checked = 0
    for time, y, excess in profiles:
        if c_v * time / P["height"]**2 < 0.05:
            continue
        exact = mpmice_terzaghi.exact_excess_pressure(y, time, params)
        error = np.linalg.norm(excess - exact) / np.linalg.norm(exact)
        assert error <= 1e-2, (time, c_v * time, error, excess[[0, 50, -1]] / p0)
        checked += 1
    assert checked >= 15
    dump = read_dump(list_dumps(out, mpmice_terzaghi.NAME)[-1])
    soil = dump["particles"]["soil"]
    mean = -(soil["stress_xx"] + soil["stress_yy"] + soil["stress_zz"]) / 3.0
    assert np.max(mean) < 1.0e5


# --------------------------------------------------------------------------- cyclic shear column

SHAKE = str(mpmice_terzaghi.ROOT) + "/namelists/mpmice_cyclic_shear_column_1d.nml"
SHAKE_NAME = "shake_column"
MID = slice(5, 15)     # cells 0.5 <= y <= 1.5 m (of 20)


def shake_run(tmp_path, label, solid_set):
    """Run the cyclic shear column with `&solid` overrides; per dump: time, the excess pore
    pressure (cell pressure minus its initial value, x-averaged) and the change of the mean
    effective stress p' and of sigma'_yy of the particles in each cell, and the initial p'."""
    out = str(tmp_path / label)
    run_mpmice([SHAKE, "--set", f"&solid name = 'soil', {solid_set} /",
                "--set", f"&run output_dir = '{out}' /"], cwd=str(tmp_path), timeout=300)
    dumps = [read_dump(path) for path in list_dumps(out, SHAKE_NAME)]

    def cell_means(dump):
        soil = dump["particles"]["soil"]
        cell = np.floor(soil["y"] / 0.1).astype(int)
        mean = -(soil["stress_xx"] + soil["stress_yy"] + soil["stress_zz"]) / 3.0
        return (np.array([mean[cell == k].mean() for k in range(20)]),
                np.array([soil["stress_yy"][cell == k].mean() for k in range(20)]))

    p_start = dumps[0]["cell"]["pressure"][:, :, 0].mean(axis=0)
    mean0, syy0 = cell_means(dumps[0])
    rows = []
    for dump in dumps:
        mean, syy = cell_means(dump)
        excess = dump["cell"]["pressure"][:, :, 0].mean(axis=0) - p_start
        rows.append((float(dump["time"]), excess, mean - mean0, syy - syy0))
    return rows, mean0


def check_effective_stress_split(rows, mean0):
    """The column's total vertical stress is its weight: every excess pore pressure is the loss
    of vertical effective stress, u_e = d sigma'_yy (tension positive), to 1e-2 p'_0."""
    for time, excess, _, dsyy in rows:
        assert np.all(np.abs(excess[MID] - dsyy[MID]) <= 1e-2 * mean0[MID]), time


def test_cam_clay_cyclic_shear_builds_pore_pressure(solver, tmp_path):
    """Normally consolidated Cam-Clay (K0 = 1), two cycles of undrained base shaking: excess pore
    pressure at 1 s >= 0.1 p'_0 in every cell of 0.5 <= y <= 1.5 m (measured 0.15-0.40 p'_0),
    larger after the second cycle than after the first (cell mean +0.03 p'_0 at least; measured
    0.25 -> 0.29 p'_0 at y = 1.05 m), p' never below the undrained critical-state bound
    p'_0 2^-Lambda = 0.574 p'_0 (Lambda = 0.8; measured 0.594), and every particle deeper than
    0.24 m (p'_0 > 2 kPa) on the undrained relation kappa ln(p'/p'_0) + (lambda - kappa) ln(p_c/p'_0) = 0 to
    1e-4 (measured 3.7e-6) with its dumped p_c grown by ln(p_c/p'_0) > 0.02 (measured
    0.025-0.139); a linear elastic skeleton of similar stiffness builds none: |u_e| <= 0.02
    p'_0 at every dump (measured 0.007)."""
    rows, mean0 = shake_run(tmp_path, "cam_clay", "model = 'cam_clay'")
    assert rows[-1][0] == pytest.approx(1.0)
    check_effective_stress_split(rows, mean0)
    end = rows[-1][1][MID] / mean0[MID]
    assert np.all(end >= 0.1), end
    half = [r for r in rows if abs(r[0] - 0.5) < 1e-9][0][1][MID] / mean0[MID]
    assert np.mean(end) >= np.mean(half) + 0.03, (np.mean(half), np.mean(end))
    lowest = min(np.min(1.0 + r[2][MID] / mean0[MID]) for r in rows)
    assert lowest >= 2.0**-0.8, lowest
    # undrained (constant volume): kappa ln(p'/p'_0) + (lambda - kappa) ln(p_c/p_c0) = 0 for
    # every particle, p_c0 = p'_0 (normally consolidated, isotropic); the dumped p_c
    paths = list_dumps(str(tmp_path / "cam_clay"), SHAKE_NAME)
    first = read_dump(paths[0])["particles"]["soil"]
    last = read_dump(paths[-1])["particles"]["soil"]
    order0, order1 = np.argsort(first["id"]), np.argsort(last["id"])
    p_start = -(first["stress_xx"] + first["stress_yy"] + first["stress_zz"])[order0] / 3.0
    p_end = -(last["stress_xx"] + last["stress_yy"] + last["stress_zz"])[order1] / 3.0
    hardening = last["hardening"][order1]
    deep = p_start > 2.0e3                    # p_c0 = p'_0 above p'_min = 1 kPa
    growth = np.log(hardening[deep] / p_start[deep])
    assert np.min(growth) > 0.02, np.min(growth)
    invariant = 0.04 * np.log(p_end[deep] / p_start[deep]) + 0.16 * growth
    assert np.max(np.abs(invariant)) < 1e-4, np.max(np.abs(invariant))
    rows, mean0 = shake_run(tmp_path, "elastic", "model = 'linear_elastic', youngs_modulus = 6.0e5")
    largest = max(np.max(np.abs(r[1][MID] / mean0[MID])) for r in rows)
    assert largest <= 0.02, largest


def test_sand_cyclic_shear_loose_liquefies_dense_sucks(solver, tmp_path):
    """Critical-state sand (quasi-static, E = 10 MPa, K0 = 1), the same shaking: a loose packing
    (porosity 0.45, phi = 0.55 < phi_m = 0.585) builds excess pore pressure >= 0.1 p'_0 in every
    mid cell at 1 s (measured 0.11-1.0) and liquefies somewhere (r_u = u_e / p'_0 >= 0.9;
    measured 1.0, p' = 0); a dense one (porosity 0.38, phi = 0.62) sucks: u_e <= -0.02 p'_0 in
    every mid cell (measured -0.035 to -0.080)."""
    sand = "model = 'critical_state_sand', max_porosity = 0.5, porosity = "
    rows, mean0 = shake_run(tmp_path, "loose", sand + "0.45")
    check_effective_stress_split(rows, mean0)
    end = rows[-1][1][MID] / mean0[MID]
    assert np.all(end >= 0.1), end
    assert max(np.max(r[1][MID] / mean0[MID]) for r in rows) >= 0.9
    rows, mean0 = shake_run(tmp_path, "dense", sand + "0.38")
    check_effective_stress_split(rows, mean0)
    end = rows[-1][1][MID] / mean0[MID]
    assert np.all(end <= -0.02), end


# --------------------------------------------------------------------------- checkpoint

def test_cam_clay_restart_is_bitwise_identical(solver, tmp_path):
    """namelists/mpm_slide_2d.nml with the block as Cam-Clay (scene mpm): run 60 steps, restart
    from the checkpoint and finish; every dump equals the uninterrupted run bit for bit, so the
    preconsolidation pressure p_c of each particle (`checkpoint/particles/<solid>/hardening`)
    is carried (set afresh from the stress at the restart, the plastic strain would differ).
    The block yields: the largest plastic strain at the end is > 1e-3."""
    import h5py
    namelist = str(mpmice_terzaghi.ROOT) + "/namelists/mpm_slide_2d.nml"
    clay = ("&solid name = 'block', model = 'cam_clay', porosity = 0.4, "
            "preconsolidation_pressure = 2.0e3 /")
    full = tmp_path / "full"
    run_mpmice([namelist, "--set", clay, "--set", f"&run output_dir = '{full}' /"],
               cwd=str(tmp_path))
    half = tmp_path / "half"
    run_mpmice([namelist, "--set", clay, "--set", f"&run output_dir = '{half}', max_steps = 60 /"],
               cwd=str(tmp_path))
    checkpoint = half / "slide2d_checkpoint_000060.h5"
    assert checkpoint.is_file()
    run_mpmice(["--restart", str(checkpoint), "--set", "&run max_steps = 0 /"], cwd=str(tmp_path))
    paths = list_dumps(str(full), "slide2d")
    assert len(paths) == 3
    for path in paths:
        assert_dumps_identical(path, half / pathlib.Path(path).name)
    with h5py.File(paths[-1]) as a:
        assert np.max(a["particles/block/plastic_strain"][...]) > 1e-3
