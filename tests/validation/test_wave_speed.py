"""postproc.wave_speed: the particles' drained P-wave speeds and the cell-averaged bound, on a
made-up dump whose numbers follow by hand."""
import numpy as np
import pytest

from postproc.wave_speed import dump_rows, solid_params

NAMELIST = """&grid ncells = 4, 2, 1 /
&solid
  name = 'sand'
  model = 'mohr_coulomb'
  density = 2500.0
  youngs_modulus = 5.0e7
  poisson_ratio = 0.25
  porosity = 0.4
  max_porosity = 0.7
/
&solid
  name = 'bed'
  model = 'rigid'
  density = 2650.0
  youngs_modulus = 1.0e7
  poisson_ratio = 0.3
  porosity = 0.0
/
"""
RHO0 = 0.6 * 2500.0                 # (1 - n) rho_grains
MODULUS = 6.0e7                     # lambda + 2 mu of E = 50 MPa, nu = 0.25
C0 = np.sqrt(MODULUS / RHO0)        # intact sand


def make_dump(jac, x, vx):
    """Four particles of 1 kg in cells 0.5 m wide, at y = 0.25 (the first row)."""
    jac, x, vx = (np.asarray(a, dtype=float) for a in (jac, x, vx))
    zero = np.zeros_like(x)
    sand = {"mass": np.ones_like(x), "volume": jac / RHO0, "x": x, "y": zero + 0.25, "z": zero,
            "velocity_x": vx, "velocity_y": zero, "velocity_z": zero}
    bed = dict(sand)
    attrs = {"namelist": NAMELIST, "lower": [0.0, 0.0, 0.0], "dx": [0.5, 0.5, 1.0],
             "ncells": [4, 2, 1]}
    return {"time": 0.5, "attrs": attrs, "particles": {"sand": sand, "bed": bed}}


def test_params_from_the_resolved_input():
    par = solid_params(make_dump([1.0], [0.1], [0.0]), "sand")
    assert par["rho0"] == pytest.approx(RHO0)
    assert par["modulus"] == pytest.approx(MODULUS)
    assert par["j_loose"] == pytest.approx(2.0)
    assert solid_params(make_dump([1.0], [0.1], [0.0]), "bed") is None   # rigid: no wave


def test_speeds_per_particle_and_per_cell():
    # cell 0: an intact particle (J = 1, at rest) and one dilated to J = 1.8 moving at 2 m/s;
    # cell 2: a compacted particle (J = 0.9: floored at 1) and one past the loose limit (none)
    dump = make_dump([1.0, 1.8, 0.9, 2.5], [0.1, 0.2, 1.1, 1.2], [0.0, 2.0, 1.0, 3.0])
    (row,) = dump_rows(dump)             # the rigid bed is left out
    assert row["solid"] == "sand"
    assert row["max"] == pytest.approx(C0 * np.sqrt(1.8) + 2.0)
    assert row["dilated"] == pytest.approx(0.5)          # J = 1.8 and 2.5
    cell0 = np.sqrt((C0 ** 2 + 1.8 * C0 ** 2) / 2.0) + 2.0
    cell2 = np.sqrt(C0 ** 2 / 2.0) + 3.0
    assert row["cell_max"] == pytest.approx(max(cell0, cell2))
    assert row["cell_max"] < row["max"]
    assert row["median"] == pytest.approx(np.median([C0, C0 * np.sqrt(1.8) + 2.0, C0 + 1.0, 3.0]))


def test_command_names_a_missing_solid(tmp_path):
    import subprocess
    import sys

    import h5py
    dump = make_dump([1.0], [0.1], [0.0])
    with h5py.File(tmp_path / "run_000000.h5", "w") as f:
        for key, value in dump["attrs"].items():
            f.attrs[key] = value
        f.attrs["time"] = 0.0
        f.attrs["step"] = 0
        for name, parts in dump["particles"].items():
            for field, values in parts.items():
                f[f"particles/{name}/{field}"] = values
    run = [sys.executable, "-m", "postproc.wave_speed", str(tmp_path)]
    good = subprocess.run(run, capture_output=True, text=True, check=False)
    assert good.returncode == 0, good.stderr
    assert f"{C0:10.1f}" in good.stdout
    bad = subprocess.run(run + ["--solid", "bed"], capture_output=True, text=True, check=False)
    assert bad.returncode == 1
    assert "no solid 'bed'" in bad.stderr and len(bad.stderr.strip().splitlines()) == 1
