"""The local damping in the coupled scene (`&mpm local_damping_force`, `local_damping_end`;
docs/earthquake_liquefaction.md "Damped settle"), on the submerged layer of test_mpmice_geostatic.py
(namelists/mpmice_submerged_block_2d.nml with the sand block widened to a 0.2 m layer, started
with its geostatic effective stress and hydrostatic water: in equilibrium, particle speeds below
4e-7 m/s undamped) over 0.05 s, with alpha = 0.75.

At rest the solid's own nodal force (internal force plus weight) is the part of the grains'
weight that the pore water's pressure carries, rho_w / rho_s = 0.38 of it. The 'solid' damping
acts on that force, so it pushes against any motion even at equilibrium and the layer's
particles move at ~1e-4 m/s; the 'total' damping acts on the node's whole increment after the
fluids' forces, which is zero at equilibrium, so the layer stays at rest, and it damps the same
layer settling from a stress-free start. With the 'solid' damping ended at 0.02 s the motion
decays afterwards."""
import os

import h5py
import numpy as np

from postproc.mpmice_io import list_dumps
from postproc.run_case import ROOT

BLOCK = os.path.join(ROOT, "namelists", "mpmice_submerged_block_2d.nml")


def _speeds(run_mpmice, tmp_path, tag: str, damping: str, geostatic: bool = True,
            alpha: float = 0.75) -> list[float]:
    """The largest particle speed [m/s] of each dump (every 0.01 s to 0.05 s)."""
    out = os.path.join(str(tmp_path), tag)
    start = ".true." if geostatic else ".false."
    run_mpmice([BLOCK, "--set", f"&run output_dir = '{out}', end_time = 0.05, "
                "output_interval = 0.01 /",
                "--set", f"&solid name = 'sand', upper = 1.0, 0.2, 0.025, geostatic = {start} /",
                "--set", f"&mpm local_damping = {alpha}, {damping} /"],
               nranks=1, cwd=str(tmp_path), check=True)
    speeds = []
    for path in list_dumps(out, "block2d"):
        with h5py.File(path, "r") as f:
            part = f["particles/sand"]
            speeds.append(float(np.hypot(part["velocity_x"][...], part["velocity_y"][...]).max()))
    return speeds


def test_total_damping_leaves_a_submerged_layer_at_rest(run_mpmice, tmp_path):
    """'total': every dump's largest speed below 1e-6 m/s (measured 1.1e-7). 'solid': above
    5e-5 m/s in every dump after the start (measured 1.2-1.9e-4). 'solid' ended at 0.02 s:
    above 5e-5 m/s at 0.01 and 0.02 s, then falling, below 1e-5 m/s at 0.05 s (measured
    2.8e-6)."""
    total = _speeds(run_mpmice, tmp_path, "total", "local_damping_force = 'total'")
    assert len(total) == 6
    assert max(total) < 1e-6, total
    solid = _speeds(run_mpmice, tmp_path, "solid", "local_damping_force = 'solid'")
    assert min(solid[1:]) > 5e-5, solid
    ended = _speeds(run_mpmice, tmp_path, "ended", "local_damping_end = 0.02")
    assert min(ended[1:3]) > 5e-5, ended
    assert ended[5] < ended[4] < ended[3] < ended[2], ended
    assert ended[5] < 1e-5, ended


def test_total_damping_damps_a_settling_layer(run_mpmice, tmp_path):
    """The same layer started stress-free settles under its weight (8.4e-4 m/s at 0.01 s); with
    the 'total' damping its largest speed at 0.05 s is below half the undamped one (measured
    1.1e-7 against 5.6e-7 m/s)."""
    free = _speeds(run_mpmice, tmp_path, "free", "local_damping_force = 'total'",
                   geostatic=False, alpha=0.0)
    damped = _speeds(run_mpmice, tmp_path, "damped", "local_damping_force = 'total'",
                     geostatic=False)
    assert free[1] > 1e-4, free
    assert damped[5] < 0.5 * free[5], (damped, free)
