"""The undrained (Biot fast) P-wave of the consolidation column at a fixed small time step
(docs/accuracy.md, stability map (a)): 50 cells, grain size 0.1 mm, densities / 100
(mpmice_terzaghi.QUASI_STATIC_SET), implicit drag, dt = 2^-20 and 2^-22 s, to t = 2^-10 s,
dumps every 2^-16 s.

Physics: the water is locked to the skeleton at this permeability (drag rate beta = 9.8e6 1/s
against a wave frequency of 2.8e4 rad/s), so the step load launches the undrained P-wave,
c_u = sqrt((E_v + K_f / n) / rho) = 17.6 km/s, quarter-wave period 4 H / c_u = 0.227 ms, whose
Biot damping time is 139 ms (the complex root of Biot's 1D dispersion relation). The base
pressure is then the fixed end of a loaded rod: a square wave between 0 and 2 p0 for the whole
run. At 2^-20 s (c_u dt / dx = 0.84) the run shows exactly that, and so must 2^-22 s (0.21).
There an odd-even pressure pattern grew from the drained top cells once the wave first returned
there (0.12 ms) and the base swung between -0.64 and 3.5 p0 by 1 ms: the fluid crossing the open
face took the reservoir's fraction 1 instead of the porosity whenever the flow turned inward.
The pressure equation and the advected mass now take the inner cell's fraction at an open face
in either direction (ice_pressure open_face_shift, ice_advection open_face_inflow): -0.01 ..
2.01 p0.

Two runs, ~3 s in all.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from postproc import mpmice_terzaghi
from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import run_mpmice

GRAIN = 1.0e-4                      # m: beta dt = 2.3 at dt = 2^-22 s
END = 2.0**-10                      # s, ~4 periods of the undrained wave
DUMPS = 2.0**-16                    # s, 15 dumps per period
P_REF = 101325.0


def undrained_period(cells_height: float = 1.0) -> float:
    """4 H / c_u of the quasi-static column [s] (incompressible grains, alpha = 1)."""
    porosity, k_f = 0.3, 2.0e9
    e_v = 1.0e7 * 0.7 / (1.3 * 0.4)
    rho = 0.7 * 26.5 + 0.3 * 9.998
    return 4.0 * cells_height / math.sqrt((e_v + k_f / porosity) / rho)


def base_history(tmp_path, exponent: int):
    """(time [s], base excess pressure / p0, final excess pressure profile / p0)."""
    dt = 2.0**-exponent
    out = str(tmp_path / f"dt{exponent}")
    args = mpmice_terzaghi.fixed_dt_args(50, GRAIN, dt, END, DUMPS, out)
    run_mpmice(args, cwd=str(tmp_path), timeout=120)
    _, p0 = mpmice_terzaghi.consolidation_constants()
    dumps = [read_dump(p) for p in list_dumps(out, mpmice_terzaghi.NAME)]
    time = np.array([float(d["time"]) for d in dumps])
    base = np.array([d["cell"]["pressure"][0, 0, 0] - P_REF for d in dumps]) / p0
    return time, base, (dumps[-1]["cell"]["pressure"][0, :, 0] - P_REF) / p0


def assert_square_wave(time, base):
    """Base pressure within [0, 2] p0 (5 % slack for the grid's dispersion), period 4 H / c_u."""
    assert base[1:].min() > -0.05, base.min()
    assert base.max() < 2.05, base.max()
    assert base.max() > 1.9, base.max()          # the doubled wave does reach the base
    up = np.where((base[:-1] < 1.0) & (base[1:] >= 1.0))[0]
    period = float(np.mean(np.diff(time[up])))
    assert abs(period / undrained_period() - 1.0) < 0.05, (period, undrained_period())


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_undrained_wave_at_dt_2e20(solver, tmp_path):
    """dt = 2^-20 s: the physical square wave between 0 and 2 p0, period 0.227 ms."""
    time, base, _ = base_history(tmp_path, 20)
    assert_square_wave(time, base)


def test_undrained_wave_at_dt_2e22(solver, tmp_path):
    """dt = 2^-22 s: the same answer as at 2^-20 s (the solution must converge as dt -> 0)."""
    time, base, _ = base_history(tmp_path, 22)
    assert_square_wave(time, base)
