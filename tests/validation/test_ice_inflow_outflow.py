"""ICE scene, 'inflow' / 'outflow' / 'pressure' faces on 1D channels (postproc.ice_channel,
namelists/ice_channel_water.nml and ice_channel_air.nml; 200 fixed steps of 5 ms, a dump per
step). Measured (Debug build): water channel from rest, |u - 1| <= 1.4e-14 m/s from step 50 on,
mass balance dM - dt A (rho_1 u_in - rho_N u_N) <= 7.4e-14 of the inflow flux, |dM|/M <= 5.8e-12
per step; uniform air flow through inflow + outflow exactly preserved (0.0); air from rest
(pure-Neumann pressure problem) balance <= 1.1e-13 in every step; 1 vs 2 ranks p 3e-13 relative,
u 2.3e-13 m/s. Mist channel (namelists/ice_channel_mist.nml, 1 % water by volume in air at
1 m/s): with `inflow_fluid = 'air'` the water's mass follows M_w(0) (1 - u t / L) to 1.3e-12 and
the air's gains rho_air (u A t) less the outflowing air to 1.1e-14 (x- 'pressure'); without it
the mass stays to 7e-15."""
import numpy as np
import pytest

from postproc import ice_channel
from postproc.run_case import ROOT


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_water_channel_inflow_pressure(tmp_path):
    """Inflow u = 1 m/s into water at rest, 'pressure' face at the outlet: after the start-up
    transient u = 1 m/s everywhere to 1e-13 m/s from step 50 (measured 9.8e-15, Release), the
    step balance to 3e-13 of the inflow flux (6.9e-14), |dM|/M to 2e-11 per step (5.8e-12), the
    flux out equals the flux in to 1e-10 at the end (1.9e-11) and p = 101325 Pa to 5e-9 Pa
    (5e-10 Pa)."""
    m = ice_channel.measures(ice_channel.run(str(tmp_path), ice_channel.WATER, "water"), "water")
    assert m["steps"] == 200, m
    assert m["max_u_error_settled"] < 1e-13, m
    assert m["balance_settled"] < 3e-13, m
    assert m["mass_change_settled"] < 2e-11, m
    assert m["flux_out_over_in_final"] < 1e-10, m
    assert abs(m["p_min_final"] - 101325.0) < 5e-9 and abs(m["p_max_final"] - 101325.0) < 5e-9, m


def test_air_channel_inflow_outflow_uniform(tmp_path):
    """Uniform air flow at 1 m/s, inflow at x-, zero-gradient outflow at x+, no pressure face:
    the flow stays uniform (velocity, pressure and density) to 1e-15 (measured 0.0)."""
    dumps = ice_channel.run(str(tmp_path), ice_channel.AIR, "air")
    m = ice_channel.measures(dumps, "air")
    assert m["steps"] == 200, m
    assert m["max_u_error_final"] < 1e-15, m
    assert m["balance_all"] < 1e-15, m
    for name in ("pressure", "air/density", "air/temperature"):
        a, b = dumps[0]["cell"][name], dumps[-1]["cell"][name]
        assert np.max(np.abs(b / a - 1.0)) < 1e-15, name


def test_air_channel_from_rest_pure_neumann(tmp_path):
    """Inflow into air at rest with an outflow face and no pressure face: the pressure problem
    has Neumann conditions on every face and stays solvable through the compressibility
    (V sum phi kappa on the diagonal); every step balances the mass exactly, the flow
    accelerates towards the inflow velocity and the pressure stays uniform (the domain is
    pressurised: a zero-gradient outflow does not fix the pressure level): balance to 3e-13 of
    the inflow flux (measured 7.5e-14), pressure uniform to 5e-6 (1.5e-6)."""
    dumps = ice_channel.run(str(tmp_path), ice_channel.AIR, "air_rest",
                            sets=("&fluid name = 'air', velocity = 0, 0, 0 /",))
    m = ice_channel.measures(dumps, "air")
    assert m["steps"] == 200, m
    assert m["balance_all"] < 3e-13, m
    u = np.array([d["cell"]["air/velocity_x"][-1, 0, 0] for d in dumps])
    assert np.all(np.diff(u) >= 0.0) and 0.4 < u[-1] < 1.0, u[-1]
    assert (m["p_max_final"] - m["p_min_final"]) < 5e-6 * m["p_min_final"], m


def test_water_channel_rank_invariance(tmp_path):
    """The water channel on 1 and 2 ranks: p, density and temperature equal to 1e-10 relative,
    velocities to 1e-9 m/s in every dump."""
    one = ice_channel.run(str(tmp_path), ice_channel.WATER, "water", nranks=1)
    two = ice_channel.run(str(tmp_path), ice_channel.WATER, "water", nranks=2)
    assert len(one) == len(two) == 201
    for a, b in zip(one, two):
        assert a["step"] == b["step"]
        for name in ("pressure", "water/density", "water/temperature", "water/velocity_x"):
            x, y = a["cell"][name], b["cell"][name]
            if "velocity" in name:
                assert np.max(np.abs(x - y)) <= 1e-9, name
            else:
                assert np.max(np.abs(x - y)) <= 1e-10 * np.max(np.abs(x)), name


MIST = f"{ROOT}/namelists/ice_channel_mist.nml"


def _mist_masses(dumps):
    """Times, water and air masses and the first dump of a mist-channel run."""
    dx = np.asarray(dumps[0]["attrs"]["dx"], dtype=float).reshape(3)
    t = np.array([ice_channel.DT * d["step"] for d in dumps])
    mw = np.array([d["cell"]["water/density"].sum() for d in dumps]) * float(np.prod(dx))
    ma = np.array([d["cell"]["air/density"].sum() for d in dumps]) * float(np.prod(dx))
    return t, mw, ma, float(dx[1] * dx[2])


@pytest.mark.parametrize("face", ["pressure", "inflow"])
def test_mist_channel_inflow_fluid_flushes_the_mist(tmp_path, face):
    """A 1 % water mist in air flows at u = 1 m/s through a 1 m channel. With `&boundary
    inflow_fluid = 'air'` at x- ('pressure' face, or 'inflow' at 1 m/s) only air enters, so
    the water leaves through x+ and its mass is M_w(0) (1 - u t / L) (exact while the mist
    still reaches x+, t < 1 s); the air gains (rho_air - rho_bar_air) u A t. Both to 5e-12 of
    the initial mass (measured water 1.3e-12 / 4.2e-13, air 1.1e-14 / 5.1e-13 with a 'pressure'
    / 'inflow' face)."""
    sets = [] if face == "pressure" else [
        "&boundary face = 'x-', fluid = 'inflow', velocity = 1, 0, 0 /"]
    dumps = ice_channel.run(str(tmp_path), MIST, "mist", sets=sets)
    t, mw, ma, area = _mist_masses(dumps)
    assert dumps[-1]["step"] == 100 and t[-1] == pytest.approx(0.5)
    assert np.max(np.abs(mw / mw[0] - (1.0 - t / 1.0))) < 5e-12, mw / mw[0]
    rho_air = dumps[0]["cell"]["air/density"][0, 0, 0] / 0.99   # intrinsic, first cell
    rho_bar_out = dumps[0]["cell"]["air/density"][-1, 0, 0]      # the mixture's air leaving
    expected = ma[0] + (rho_air - rho_bar_out) * 1.0 * area * t
    assert np.max(np.abs(ma - expected)) < 5e-12 * ma[0]


def test_mist_channel_without_inflow_fluid_keeps_the_mist(tmp_path):
    """The same channel with `inflow_fluid = ''`: the inflow carries the first cell's
    composition (zero gradient), so the mist's mass stays to 5e-14 (measured 7.5e-15)."""
    dumps = ice_channel.run(str(tmp_path), MIST, "mix",
                            sets=["&boundary face = 'x-', inflow_fluid = '' /"])
    _, mw, _, _ = _mist_masses(dumps)
    assert np.max(np.abs(mw / mw[0] - 1.0)) < 5e-14
