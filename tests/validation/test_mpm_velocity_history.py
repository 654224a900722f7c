"""Prescribed face velocity history (`&boundary solid_velocity_times / solid_velocity_history`):
an elastic bar pushed by its x- face with a ramp-and-hold velocity (namelists/
mpm_velocity_history_1d.nml). The particle next to the face (the series' xmin, l_p = h/4 = 6.25
mm from the face) follows the integrated history U(t) = V t^2/(2T) (t <= T), V (t - T/2) after.

Error budget: the face moves with the history at the END of each step (v^L = V(t + dt)), so the
particle's displacement is the right-endpoint sum sum dt V(t_n+1), which exceeds U by at most
dt V / 2 = 1.25e-6 m (dt <= cfl h / c = 5e-5 s); the bar's inertial strain a L / c^2 = 1e-4
(a = V/T = 1 m/s^2) over l_p, doubled by the wave the ramp start sends, adds 2 a L l_p / c^2 =
1.25e-6 m. Measured: max |u - U| = 2.28e-6 m (6.1e-4 of U(0.1 s) = 3.75 mm), max |u - sum| =
1.23e-6 m, while against the start-of-step sum sum dt V(t_n) it is 3.52e-6 m (so the test
tells the two apart). Scene 'mpmice' takes the same path: `test_mpmice_face_history`. The
three tests run in about 2.5 s together.
"""
import glob

import h5py
import numpy as np
import pytest

from postproc.mpm_common import series
from postproc.run_case import ROOT, run_mpmice

NAMELIST = f"{ROOT}/namelists/mpm_velocity_history_1d.nml"
V, T = 0.05, 0.05          # m/s, s: ramp to V over T, then held
L, C = 1.0, 100.0          # bar length [m], wave speed sqrt(E / rho) [m/s]
X0 = 0.00625               # first particle: h/4 from the face [m]
DT_MAX = 0.2 * 0.025 / C   # cfl h / c [s]


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def history(t):
    return np.interp(t, [0.0, T, 1.0], [0.0, V, V])


@pytest.mark.parametrize("nranks", [1, 2])
def test_face_particle_follows_integrated_history(tmp_path, nranks):
    out = str(tmp_path / "out")
    run_mpmice([NAMELIST, "--set", f"&run output_dir = '{out}' /"], nranks=nranks,
               cwd=str(tmp_path))
    s = series(out, "velhist")
    t = np.concatenate([[0.0], s["time"]])
    u = np.concatenate([[X0], s["xmin"]]) - X0
    assert t[-1] == pytest.approx(0.1)
    exact = np.where(t <= T, V * t**2 / (2.0 * T), V * (t - T / 2.0))
    end_sum = np.concatenate([[0.0], np.cumsum(np.diff(t) * history(t[1:]))])
    elastic = 2.0 * (V / T) * L * X0 / C**2
    bound = DT_MAX * V / 2.0 + elastic
    assert np.max(np.abs(u - exact)) < 1.2 * bound, np.max(np.abs(u - exact))
    assert np.max(np.abs(u - end_sum)) < 1.2 * elastic, np.max(np.abs(u - end_sum))
    assert abs(u[-1] - exact[-1]) < 1.0e-3 * exact[-1], (u[-1], exact[-1])


#: Scene 'mpmice' (namelists/mpmice_terzaghi_1d.nml shortened: 20 cells, soil up to y = 0.5,
#: no load) with its y- face driven upward: the same face conditions as scene 'mpm'.
MPMICE_NAMELIST = f"{ROOT}/namelists/mpmice_terzaghi_1d.nml"
MPMICE_SETS = ["&grid ncells = 1, 20, 1 /", "&run end_time = 0.02, output_interval = 0.02 /",
               "&solid name = 'soil', upper = 0.01, 0.5, 0.01, traction = 0, 0, 0 /"]


def _mpmice_final(tmp_path, name, boundary):
    out = str(tmp_path / name)
    args = [MPMICE_NAMELIST]
    for text in MPMICE_SETS + [f"&run output_dir = '{out}' /", boundary]:
        args += ["--set", text]
    run_mpmice(args, cwd=str(tmp_path))
    path = sorted(glob.glob(f"{out}/terzaghi_*.h5"))[-1]
    data = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: data.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset)
                     and o.dtype.kind == "f" else None)
    return data


def test_mpmice_face_history(tmp_path):
    """A one-point history equals the constant solid_velocity bitwise (every float dataset of
    the final dump); a ramp to the same 0.01 m/s over 0.01 s lowers the bottom particle's
    displacement at t = 0.02 s by 5.0e-5 m, the difference of the integrals (measured 4.70e-5,
    -6 %: the saturated soil next to the face compresses, as it does under the constant
    velocity, 1.82e-4 m against 2.0e-4)."""
    face = "&boundary face = 'y-', solid = 'velocity',"
    const = _mpmice_final(tmp_path, "const", f"{face} solid_velocity = 0, 0.01, 0 /")
    one = _mpmice_final(tmp_path, "one", f"{face} solid_velocity_times = 0.0, "
                        "solid_velocity_history = 0, 0.01, 0 /")
    ramp = _mpmice_final(tmp_path, "ramp", f"{face} solid_velocity_times = 0.0, 0.01, "
                         "solid_velocity_history = 0, 0, 0, 0, 0.01, 0 /")
    assert const.keys() == one.keys() and len(const) > 10
    for key in const:
        assert np.array_equal(const[key], one[key]), key
    y_key = "particles/soil/y"
    drop = const[y_key].min() - ramp[y_key].min()
    assert drop == pytest.approx(0.01 * 0.01 / 2.0, rel=0.1), drop
