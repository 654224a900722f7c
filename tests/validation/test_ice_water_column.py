"""ICE scene, water column at rest under air under gravity (namelists/ice_water_column.nml,
postproc.ice_water_column): after 1000 steps of 1 ms every velocity stays below 1e-8 m/s and the
pressure matches the exact hydrostatic profile to 1e-10 relative (targets 1e-8 m/s and
1e-6; measured 6.2e-9 m/s and 3.5e-11 in 1D, 2D on 2 ranks and with the open top)."""
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
    assert m["pressure_error_initial"] < 1e-10, m
    assert m["pressure_error_final"] < 1e-10, m


def _open_top(tmp_path, top_pressure):
    """The column with a 'pressure' face on top (the namelist plus a &boundary group)."""
    out = tmp_path / f"open_{top_pressure:.0f}"
    case = tmp_path / f"open_{top_pressure:.0f}.nml"
    with open(ice_water_column.NAMELIST) as f:
        text = f.read()
    case.write_text(text + f"&boundary\n  face = 'x+'\n  fluid = 'pressure'\n"
                    f"  pressure = {top_pressure}\n/\n")
    ice_water_column.run_mpmice([str(case), "--set", f"&run output_dir = '{out}' /"],
                                nranks=1, cwd=str(tmp_path))
    dumps = ice_water_column.list_dumps(str(out), "column")
    return ice_water_column.read_dump(dumps[0]), ice_water_column.read_dump(dumps[-1])


def test_water_column_open_top(tmp_path):
    """'pressure' boundary at the top at the initial 101325 Pa: still at rest (< 1e-8 m/s,
    measured 5.4e-9) after 1000 steps; raising it to 102325 Pa raises the bottom pressure by
    1000 Pa within 0.1 Pa (measured +1000.033 Pa: the compressed air weighs a little more)."""
    first, last = _open_top(tmp_path, 101325.0)
    m = ice_water_column.measures(first, last)
    assert max(m["max_speed_air"], m["max_speed_water"]) < 1e-8, m
    assert m["pressure_error_final"] < 1e-10, m
    first, last = _open_top(tmp_path, 102325.0)
    rise = last["cell"]["pressure"][0, 0, 0] - first["cell"]["pressure"][0, 0, 0]
    assert abs(rise - 1000.0) < 0.1, rise
