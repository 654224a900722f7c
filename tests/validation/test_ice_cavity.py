"""ICE scene, natural convection in a differentially heated cavity (de Vahl Davis), small version:
Ra = 1e3 on 16 x 16 cells to t = 30 s. Mean hot-wall Nusselt number within 2 % of the benchmark
1.118 (issue target; measured 1.1303, +1.1 %, steady to 5e-4), and still changing by less than
1e-3 over the last 3 s. The 32^2 study for Ra = 1e3..1e5 is docs/validation/ice_cavity.md."""
import pytest

from postproc import ice_cavity


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_cavity_ra1e3_nusselt(tmp_path):
    dumps = ice_cavity.run(str(tmp_path), 1e3, 16, 30.0)
    nu = ice_cavity.nusselt(dumps[-1])
    assert abs(nu / 1.118 - 1.0) < 0.02, nu
    assert abs(nu - ice_cavity.nusselt(dumps[-2])) < 1e-3, nu
