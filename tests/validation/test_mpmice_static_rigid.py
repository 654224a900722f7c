"""The kept grid share of static rigid solids (`&mpm cache_static_rigid`, default on;
docs/performance.md "Static rigid solids"): a rigid solid with no velocity and no shaking puts
the same mass, mass gradient and cell deposit on the grid every step, so both are computed once
and added on later steps. These runs compare it with the per-step computation
(`cache_static_rigid = .false.`, the code before it):

* the pure MPM scene (frictional block on a rigid bed): bitwise identical (the nodes' rigid
  share is summed in the same order);
* the thermal cavity (a static rigid porous medium whose temperature changes every step, so
  its kept deposit is renewed every step): bitwise identical;
* the 40 mm debris flow to 0.1 s (the sand's deposit is now added to the bed's instead of the
  bed's to the sand's): every compared field within 1e-8 of its largest value (measured
  at most 1.7e-10, the water velocity).

Runs: ~1 s, ~2 s, ~8 s (1 rank).
"""
from __future__ import annotations

import numpy as np

from postproc.mpmice_io import list_dumps, read_dump
from postproc.run_case import ROOT

OFF = "&mpm cache_static_rigid = .false. /"


def run_pair(run_mpmice, tmp_path, namelist, name, settings):
    """Dumps of the run with the kept share (on) and without it (off)."""
    dumps = {}
    for label, extra in (("on", []), ("off", ["--set", OFF])):
        out = str(tmp_path / label)
        args = [f"{ROOT}/namelists/{namelist}", *extra]
        for text in settings:
            args += ["--set", text]
        args += ["--set", f"&run output_dir = '{out}' /"]
        run_mpmice(args, cwd=tmp_path, timeout=600, check=True)
        dumps[label] = [read_dump(p) for p in list_dumps(out, name)]
    assert len(dumps["on"]) == len(dumps["off"]) >= 2
    return dumps["on"], dumps["off"]


def flat_fields(dump):
    """{path: array} of every floating-point cell and particle field of a dump."""
    fields = {}
    for group in ("cell", "particles"):
        for key, value in dump.get(group, {}).items():
            if isinstance(value, dict):
                for sub, array in value.items():
                    fields[f"{group}/{key}/{sub}"] = np.asarray(array)
            else:
                fields[f"{group}/{key}"] = np.asarray(value)
    return {k: v for k, v in fields.items() if v.dtype.kind == "f"}


def assert_identical(on, off):
    for a, b in zip(on, off):
        assert a["time"] == b["time"]
        fa, fb = flat_fields(a), flat_fields(b)
        assert fa.keys() == fb.keys() and fa
        for key in fa:
            assert np.array_equal(fa[key], fb[key], equal_nan=True), (a["time"], key)


def test_mpm_block_on_static_bed_is_bitwise_unchanged(run_mpmice, tmp_path):
    on, off = run_pair(run_mpmice, tmp_path, "mpm_friction_block_2d.nml", "friction",
                       ["&run end_time = 0.05, output_interval = 0.025 /"])
    assert_identical(on, off)


def test_heated_static_porous_medium_is_bitwise_unchanged(run_mpmice, tmp_path):
    on, off = run_pair(run_mpmice, tmp_path, "mpmice_thermal_cavity_2d.nml", "cavity",
                       ["&run end_time = 6.0e4, output_interval = 3.0e4 /"])
    assert_identical(on, off)
    # the medium did change temperature: the kept deposit had to be renewed
    t0 = on[0]["cell"]["water/temperature"]
    assert np.max(np.abs(on[-1]["cell"]["water/temperature"] - t0)) > 1e-4


def test_debris_flow_with_kept_bed_share_agrees(run_mpmice, tmp_path):
    on, off = run_pair(run_mpmice, tmp_path, "mpmice_debris_flow_2d.nml", "debris",
                       ["&solid name = 'sand', youngs_modulus = 5.0e6 /",
                        "&run end_time = 0.1, output_interval = 0.05 /"])
    compared = ("cell/pressure", "cell/water/velocity_x", "cell/water/velocity_y",
                "cell/water/density", "cell/solid_volume_fraction", "particles/sand/x",
                "particles/sand/y", "particles/sand/stress_xx", "particles/sand/pore_pressure")
    for a, b in zip(on, off):
        assert a["time"] == b["time"]
        fa, fb = flat_fields(a), flat_fields(b)
        for key in compared:
            scale = np.max(np.abs(fb[key]))
            assert np.max(np.abs(fa[key] - fb[key])) <= 1e-8 * scale, (a["time"], key)
