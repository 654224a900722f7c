"""ICE scene, water column at rest under air under gravity (namelists/ice_water_column.nml,
postproc.ice_water_column): after 1000 steps of 1 ms every velocity stays below 1e-8 m/s and the
pressure matches the exact hydrostatic profile to 1e-6 relative (issue targets; measured
6.1e-9 m/s and 3.5e-11 in 1D and 2D)."""
import pytest

from postproc import ice_water_column


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.mark.parametrize("ny,nranks", [(1, 1), (8, 2)])
def test_water_column_at_rest(tmp_path, ny, nranks):
    first, last = ice_water_column.run(str(tmp_path), ny=ny, nranks=nranks)
    m = ice_water_column.measures(first, last)
    assert m["steps"] == 1000, m
    assert m["max_speed_air"] < 1e-8, m
    assert m["max_speed_water"] < 1e-8, m
    assert m["pressure_error_initial"] < 1e-6, m
    assert m["pressure_error_final"] < 1e-6, m
