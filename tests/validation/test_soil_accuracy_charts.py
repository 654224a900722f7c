"""Soil entries of the speed-against-accuracy study (bench/accuracy_charts.py,
bench/stability_maps.py, docs/accuracy.md): the Rondon chart's error against the experiment
(postproc.mpmice_rondon.data_errors) on synthetic series, and the soil models' stability limit
in the step (soil_cfl_map) on four short column runs (~4 s): stable and accurate at cfl 0.5,
failed at cfl 1.
"""
from __future__ import annotations

import numpy as np
import pytest

from bench import accuracy_runs as runs
from bench import stability_maps as maps
from postproc import mpmice_rondon as rondon
from postproc import mpmice_rondon_diagnose as diagnose


def _reference() -> dict:
    """A small experiment in the format of rondon.read_reference: front starting 1 cm ahead of
    L0 (the stored files' offset), pressure from 1.1 s."""
    t_f = np.array([0.05, 0.55, 1.2, 3.0])
    x_f = rondon.L0 + 0.01 + np.array([0.0, 0.02, 0.03, 0.05])
    return {"front": (t_f, x_f), "front_offset": 0.01,
            "pressure": (np.array([1.1, 2.0]), np.array([-120.0, -60.0])), "profiles": {}}


def test_data_errors_zero_for_the_experiment_itself():
    """A model that follows the experiment (front shifted back to L0) has zero error at every
    data point of the window; the file's first front point (the shift's origin) is left out and
    points after the window or after the run's end are not counted."""
    ref = _reference()
    t = np.linspace(0.0, 1.5, 31)
    series = {"t": t,
              "front": np.interp(t, ref["front"][0], ref["front"][1] - ref["front_offset"]),
              "pressure": np.interp(t, *ref["pressure"])}
    errs = rondon.data_errors(series, ref, 1.15)
    assert [round(r[0], 3) for r in errs["runout"]] == [0.55]
    assert [round(r[0], 3) for r in errs["pressure"]] == [1.1]
    assert errs["runout"][0][3] == pytest.approx(0.0, abs=1e-12)
    assert errs["pressure"][0][3] == pytest.approx(0.0, abs=1e-9)
    assert len(rondon.data_errors(series, ref, 10.0)["runout"]) == 2      # 3.0 s > run's end


def test_data_errors_relative_to_the_run_out_and_pressure():
    """Twice the measured run-out is an error of 1; a base pressure of the wrong sign and the
    same size an error of 2."""
    ref = _reference()
    t = np.array([0.0, 0.55, 1.1, 1.2])
    series = {"t": t, "front": rondon.L0 + 2.0 * np.array([0.0, 0.02, 0.025, 0.03]),
              "pressure": np.array([0.0, 50.0, 120.0, 100.0])}
    errs = rondon.data_errors(series, ref, 1.15)
    assert errs["runout"][0][3] == pytest.approx(1.0)
    assert errs["pressure"][0][3] == pytest.approx(2.0)


def test_mass_front():
    """The x behind which a share of the mass lies."""
    parts = {"x": np.array([0.3, 0.1, 0.2, 0.4]), "mass": np.array([1.0, 1.0, 1.0, 1.0])}
    assert diagnose.mass_front(parts, 0.5) == pytest.approx(0.2)
    assert diagnose.mass_front(parts, 0.99) == pytest.approx(0.4)


@pytest.mark.parametrize("model, stiffness", [("critical_state_sand", 1.0e6),
                                              ("cam_clay", 0.01)])
def test_soil_column_stable_at_half_cfl_fails_at_one(model, stiffness, mpmice_exe, tmp_path,
                                                     monkeypatch):
    """soil_cfl_map's classification: at cfl 0.5 the geostatic column holds its weight
    (stress error < 5 % of sigma'_v at the base, oscillation < 5 %, measured ~1 % and 0.3 %);
    at cfl 1 the sand is stopped by the energy check and the clay is noisy (measured: 66 steps;
    oscillation 91 %)."""
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))
    ok = maps.run_soil_column(str(tmp_path), model, stiffness, 0.5)
    assert ok["run"]["exit_code"] == 0 and ok["particles_lost"] == 0
    assert ok["stress_error"] < maps.SOIL_ERROR_LIMIT
    assert ok["oscillation"] < maps.NOISE_LIMIT
    bad = maps.run_soil_column(str(tmp_path), model, stiffness, 1.0)
    if model == "critical_state_sand":
        assert runs.stop_kind(bad["run"]) == "energy growth"
    else:
        assert bad["run"]["exit_code"] == 0
        assert bad["oscillation"] > maps.NOISE_LIMIT
