"""ICE scene, viscosity and heat conduction (namelists/ice_shear_layer.nml, postproc.ice_diffusion):
a velocity step and a temperature step in a periodic 1D gas diffuse as exact square-wave Fourier
series. Second order: observed order 64 -> 128 cells above 1.8 (measured 2.01 velocity, 2.17
temperature) and relative L2 error at 128 cells below 2.5e-4 (measured 1.96e-4, 1.60e-4)."""
import math

import pytest

from postproc import ice_diffusion


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.mark.parametrize("case", ["velocity", "temperature"])
def test_diffusion_second_order(tmp_path, case):
    e64 = ice_diffusion.error(ice_diffusion.run(str(tmp_path), 64, case), case)
    e128 = ice_diffusion.error(ice_diffusion.run(str(tmp_path), 128, case), case)
    assert math.log2(e64 / e128) > 1.8, (e64, e128)
    assert e128 < 2.5e-4, (e64, e128)
