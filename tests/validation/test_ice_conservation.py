"""ICE scene, closed-box conservation (namelists/ice_slosh.nml, postproc.ice_conservation):
sloshing water under air in a box with walls, on 1 and 2 ranks. The mass of each fluid and the
total energy (internal, kinetic and potential) change by less than 2e-16 relative per step
(target 1e-12; measured <= 4.4e-17 on 1 and 2 ranks: one rounding of the sum over ~5 steps)
and by less than 2e-15 over the run's 67 steps (measured 6.7e-16): the Lagrangian step adds the
cell's energy defect
against the conservative face-pressure work to the fluids by mass, and the advection carries
cv T + |u|^2/2 - g.x (docs/ice.md)."""
import pytest

from postproc import ice_conservation


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


@pytest.mark.parametrize("nranks", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_closed_box_conservation(tmp_path, nranks):
    rows = ice_conservation.study(str(tmp_path), nranks)
    assert len(rows) == 11, [r["step"] for r in rows]
    for row in rows[1:]:
        assert row["mass_change_per_step"] < 2e-16, row
        assert row["energy_change_per_step"] < 2e-16, row
    assert abs(rows[-1]["energy"] / rows[0]["energy"] - 1.0) < 2e-15
    for fluid, mass in rows[0]["masses"].items():
        assert abs(rows[-1]["masses"][fluid] / mass - 1.0) < 2e-15, fluid
