"""The running mean of the cell pressure (`&ice pressure_average_time` tau > 0, written to every
dump and checkpoint as `cell/pressure_average`; modules/ice/ice_scene.f90
`ice_pressure_average_step`; docs/io.md). Each step weights the old mean by w = exp(-dt / tau)
and the new pressure by 1 - w. On the Terzaghi column (namelists/mpmice_terzaghi_1d.nml, whose
pore pressure changes in every step): the limits of the weight (tau far below the step: the
pressure itself, bit for bit; tau far above the run: the initial pressure), a restart that
continues the mean bit for bit, and no field without tau. On the loose earthquake slope (the
shipped 0.1 m cells, to 0.5 s): the mean over tau = 10 ms carries less than 0.35 of the
instantaneous pressure's cell-to-cell noise over the dumps 0.2-0.5 s (measured 1.95 against
11.1 kPa p99, 0.18; docs/earthquake_liquefaction.md, "Pore-pressure noise"), and r_u taken
from it (the postproc's --average) shows the flanks' liquefied layer at 0.85-1.1. About 20 s
in all."""
import os

import h5py
import numpy as np
import pytest

from postproc import mpmice_earthquake_slope as quake
from postproc.dump_compare import assert_dumps_identical
from postproc.mpmice_io import list_dumps, read_run_dumps
from postproc.run_case import ROOT, run_into, run_mpmice

TERZAGHI = os.path.join(ROOT, "namelists", "mpmice_terzaghi_1d.nml")
QUAKE = os.path.join(ROOT, "namelists", "mpmice_earthquake_slope_loose_2d.nml")
SETS = ("&grid ncells = 1, 40, 1 /", "&run end_time = 0.012 /")


@pytest.fixture(autouse=True)
def _executable(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _run(tmp_path, namelist, label, *sets):
    out = str(tmp_path / label)
    run_into(out, namelist, *sets, cwd=str(tmp_path))
    return out


def _cell(path, key):
    with h5py.File(path) as f:
        return f[key][...] if key in f else None


def test_weight_limits_and_no_field_without_tau(tmp_path):
    fast = list_dumps(_run(tmp_path, TERZAGHI, "fast", *SETS,
                           "&ice pressure_average_time = 1.0e-12 /"), "terzaghi")
    slow = list_dumps(_run(tmp_path, TERZAGHI, "slow", *SETS,
                           "&ice pressure_average_time = 1.0e12 /"), "terzaghi")
    off = list_dumps(_run(tmp_path, TERZAGHI, "off", *SETS), "terzaghi")
    p_end = _cell(fast[-1], "cell/pressure")
    assert np.array_equal(_cell(fast[-1], "cell/pressure_average"), p_end)
    p0 = _cell(slow[0], "cell/pressure")
    assert np.max(np.abs(p_end - p0)) > 100.0                # the pressure did change
    assert np.max(np.abs(_cell(slow[-1], "cell/pressure_average") - p0)) < 1e-6
    assert _cell(off[-1], "cell/pressure_average") is None
    assert np.array_equal(_cell(off[-1], "cell/pressure"), p_end)   # the run itself unchanged


def test_restart_continues_the_mean_bitwise(tmp_path):
    tau = "&ice pressure_average_time = 0.002 /"
    full = list_dumps(_run(tmp_path, TERZAGHI, "full", *SETS, tau), "terzaghi")[-1]
    half_dir = _run(tmp_path, TERZAGHI, "half", *SETS, tau, "&run max_steps = 100 /")
    checkpoint = os.path.join(half_dir, "terzaghi_checkpoint_000100.h5")
    assert _cell(checkpoint, "checkpoint/cell/pressure_average") is not None
    run_mpmice(["--restart", checkpoint, "--set", "&run max_steps = 0 /"], cwd=str(tmp_path))
    cont = list_dumps(half_dir, "terzaghi")[-1]
    assert os.path.basename(cont) == os.path.basename(full)
    assert_dumps_identical(full, cont)
    mean, p = _cell(full, "cell/pressure_average"), _cell(full, "cell/pressure")
    assert np.max(np.abs(mean - p)) > 1.0                    # the mean lags the pressure


@pytest.mark.slow
def test_mean_of_the_shaken_layer_is_smoother(tmp_path):
    out = _run(tmp_path, QUAKE, "quake", "&run end_time = 0.5, output_interval = 0.05 /",
               "&ice pressure_average_time = 0.01 /")
    every = read_run_dumps(out, quake.NAME)
    dumps = [d for d in every if d["time"] >= 0.2 - 1e-9]
    inst = np.mean([quake.pore_pressure_roughness(d)[0] for d in dumps])
    mean = np.mean([quake.pore_pressure_roughness(d, field="pressure_average")[0]
                    for d in dumps])
    assert inst > 5.0e3, inst
    assert mean < 0.35 * inst, (mean, inst)
    # r_u from the mean (postproc --average): the liquefied flanks' layer at 0.85-1.1 over
    # 0.15-0.3 s (measured 0.91-1.05), where the cell pressure's noise gives up to 1.37
    rows = quake.analyse(every, None, "pressure_average")
    flanks = [r["ru"][k] for r in rows if 0.15 - 1e-9 <= r["time"] <= 0.3 + 1e-9
              for k in list(r["ru"])[2:]]
    assert len(flanks) == 8 and min(flanks) > 0.85 and max(flanks) < 1.1, flanks
