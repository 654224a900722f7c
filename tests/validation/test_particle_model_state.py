"""The model-specific particle state is kept only for a solid whose model uses it
(docs/io.md "Checkpoints", docs/mpm.md `particles_store`): namelists/mpm_slide_2d.nml (scene
mpm, 20 steps) with its block as

* linear elastic: the checkpoint holds none of `hardening`, `cyclic`/`cyclic_half_time`, `gap`,
  the dump still holds `hardening` (zeros, the dump layout is the same for every model);
* Cam-Clay: the checkpoint holds `hardening` (p_c > 0 after the first update), no `cyclic`;
  the same checkpoint without `hardening` is refused on restart: exit status 1, one input-error
  line naming the dataset and the solid, nothing written.

The bitwise restarts of the models that carry state are test_mpmice_soil_models.py (Cam-Clay)
and test_mpmice_css_densification.py (sand). Runs: ~1 s each (2 shared cores), 3 runs.
"""
from __future__ import annotations

import os
import shutil

import h5py
import numpy as np
import pytest

from postproc import mpmice_terzaghi
from postproc.mpmice_io import list_dumps
from postproc.run_case import run_mpmice

NAMELIST = str(mpmice_terzaghi.ROOT) + "/namelists/mpm_slide_2d.nml"
CLAY = ("&solid name = 'block', model = 'cam_clay', porosity = 0.4, "
        "preconsolidation_pressure = 2.0e3 /")
STATE = ("hardening", "cyclic", "cyclic_half_time", "gap")


@pytest.fixture
def solver(mpmice_exe, monkeypatch):
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))


def _checkpoint(tmp_path, name, sets):
    out = tmp_path / name
    run_mpmice([NAMELIST] + sets + ["--set", f"&run output_dir = '{out}', max_steps = 20 /"],
               cwd=str(tmp_path))
    path = out / "slide2d_checkpoint_000020.h5"
    assert path.is_file()
    return out, path


def test_elastic_checkpoint_holds_no_model_state(solver, tmp_path):
    out, path = _checkpoint(tmp_path, "elastic", [])
    with h5py.File(path) as f:
        held = set(f["checkpoint/particles/block"].keys())
    assert {"x", "stress_unrot", "plastic_strain", "id"} <= held
    assert not held & set(STATE), held & set(STATE)
    with h5py.File(list_dumps(str(out), "slide2d")[-1]) as f:
        assert np.all(f["particles/block/hardening"][...] == 0.0)


def test_cam_clay_restart_without_hardening_is_refused(solver, tmp_path):
    _, path = _checkpoint(tmp_path, "clay", ["--set", CLAY])
    with h5py.File(path) as f:
        group = f["checkpoint/particles/block"]
        assert "hardening" in group and "cyclic" not in group and "cyclic_half_time" not in group
        assert np.max(group["hardening"][...]) > 0.0
    bad = tmp_path / "bad"
    bad.mkdir()
    copy = bad / path.name
    shutil.copy(path, copy)
    with h5py.File(copy, "a") as f:
        del f["checkpoint/particles/block/hardening"]
    before = sorted(os.listdir(bad))
    result = run_mpmice(["--restart", str(copy), "--set", "&run max_steps = 0 /"],
                        cwd=str(tmp_path), check=False, overwrite=False)
    assert result.returncode == 1, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.startswith("mpmice:")]
    assert len(lines) == 1, result.stderr
    assert "input error" in lines[0] and "checkpoint/particles/block/hardening" in lines[0]
    assert "&solid block" in lines[0] and "cam_clay" in lines[0]
    assert sorted(os.listdir(bad)) == before
