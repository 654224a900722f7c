"""The time window of the local damping (`&mpm local_damping_end`, docs/earthquake_liquefaction.md
"Damped settle"): the damping acts on the steps that begin before the end time and not after.

The elastic column of namelists/mpm_column_1d.nml (H = 1 m, E = 10 MPa, nu = 0.3, rho = 2000
kg/m^3, first period T = 4 H / c = 0.049 s) loaded by its full weight at once (`gravity_ramp_time
= 0`) oscillates about the static state with the static top displacement as its amplitude. Local
(Cundall) damping alpha takes alpha |f| off each node's unbalanced force against its velocity, so
for a single mode the node gains (1 - alpha) of the spring energy while it moves toward the static
state and gives (1 + alpha) of it while it moves away: the amplitude falls by (1 - alpha) / (1 +
alpha) per period (0.818 at alpha = 0.1), the peak kinetic energy by its square. After the end
time the column is undamped (FLIP 1): the amplitude stays.
"""
import os

import numpy as np
import pytest

from postproc.mpm_common import series
from postproc.run_case import ROOT, run_mpmice

ALPHA = 0.1
T_END = 0.25      # s: the damping's end time, about 5 periods
PERIOD = 0.049    # s: 4 H / c of the column's first mode
END = 0.5         # s


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def run(workdir, damping: str) -> dict:
    """The column suddenly loaded, with the `&mpm` damping text; its per-step series."""
    out = os.path.join(str(workdir), damping.replace(" ", "").replace(",", "_").replace("=", ""))
    run_mpmice([os.path.join(ROOT, "namelists", "mpm_column_1d.nml"),
                "--set", f"&run output_dir = '{out}', end_time = {END} /",
                "--set", f"&mpm gravity_ramp_time = 0.0, {damping} /"], cwd=str(workdir))
    return series(out, "column1d")


def per_period(s: dict) -> tuple[np.ndarray, np.ndarray]:
    """Half peak-to-peak of the top position and the peak kinetic energy in each period."""
    amp, peak = [], []
    for k in range(int(END / PERIOD)):
        w = (s["time"] >= k * PERIOD) & (s["time"] < (k + 1) * PERIOD)
        amp.append(0.5 * (s["ymax"][w].max() - s["ymax"][w].min()))
        peak.append(s["kinetic_energy"][w].max())
    return np.array(amp), np.array(peak)


def test_damping_acts_before_the_end_time_only(tmp_path):
    """Periods 1-5 (before 0.25 s): the amplitude falls per period by (1 - alpha) / (1 + alpha)
    = 0.818 within 5 % (measured 0.800-0.810), the peak kinetic energy by its square 0.669 within
    10 % (measured 0.643-0.653); the series up to 0.25 s is bit for bit that of the damping over
    the whole run. Periods 7-10 (after): amplitude and peak kinetic energy stay within 1 % of
    period 7's (measured 0.6 % and 0.1 %), while the whole-run damping goes on decaying (its
    period-10 amplitude below half the windowed one's; measured 0.38)."""
    windowed = run(tmp_path, f"local_damping = {ALPHA}, local_damping_end = {T_END}")
    whole = run(tmp_path, f"local_damping = {ALPHA}")
    amp, peak = per_period(windowed)
    amp_whole, _ = per_period(whole)
    rate = (1.0 - ALPHA) / (1.0 + ALPHA)
    before = int(T_END / PERIOD)                  # periods 1-5 end before T_END
    ratios = amp[1:before] / amp[:before - 1]
    assert np.all(np.abs(ratios / rate - 1.0) < 0.05), ratios
    ke_ratios = peak[1:before] / peak[:before - 1]
    assert np.all(np.abs(ke_ratios / rate ** 2 - 1.0) < 0.10), ke_ratios
    after = slice(before + 1, None)               # periods that begin after T_END + one period
    assert np.all(np.abs(amp[after] / amp[before + 1] - 1.0) < 0.01), amp[after]
    assert np.all(np.abs(peak[after] / peak[before + 1] - 1.0) < 0.01), peak[after]
    assert amp_whole[-1] < 0.5 * amp[-1], (amp_whole[-1], amp[-1])
    n = min(len(windowed["time"]), len(whole["time"]))
    early = windowed["time"][:n] <= T_END
    for key in ("time", "kinetic_energy", "strain_energy", "ymax"):
        assert np.array_equal(windowed[key][:n][early], whole[key][:n][early]), key
    assert not np.array_equal(windowed["ymax"][:n][~early], whole["ymax"][:n][~early])


def test_end_time_beyond_the_run_is_the_whole_run(tmp_path):
    """An end time after the run's end damps every step: the series is bit for bit that of the
    default 0 (the whole run)."""
    whole = run(tmp_path, f"local_damping = {ALPHA}, local_damping_end = 0.0")
    late = run(tmp_path, f"local_damping = {ALPHA}, local_damping_end = {2.0 * END}")
    for key in ("time", "kinetic_energy", "strain_energy", "ymax"):
        assert np.array_equal(whole[key], late[key]), key
