"""`&solid surface_drag_parallel` (the drag of cells crossed by a solid's free surface read in
parallel instead of in series; mpmice_solid_coupling `surface_drag_scale`) leaves fully filled
cells alone: the Forchheimer gravel columns (rigid porous column filling its cells, Re_p = 1730
and 761; postproc/mpmice_forchheimer.py) give the same pore velocity, outside flux and
steadiness with it as without, to the last bit, and still match the closed-form root of the
quadratic law. About 2 s of scene runs.
"""
from __future__ import annotations

import pytest

from postproc import mpmice_darcy, mpmice_forchheimer as forch

PARALLEL = f"&solid name='{mpmice_darcy.SOLID}', surface_drag_parallel = .true. /"


def test_parallel_surface_drag_keeps_full_columns(tmp_path, mpmice_exe):
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("MPMICE_EXE", str(mpmice_exe))
        series = forch.run_forchheimer(str(tmp_path / "series"), forch.HIGH_RE_CASES)
        parallel = forch.run_forchheimer(str(tmp_path / "parallel"), forch.HIGH_RE_CASES,
                                         extra_set=[PARALLEL])
    for s, p in zip(series, parallel):
        for key in ("u_numeric", "u_outside", "steady_change"):
            assert p[key] == s[key], (key, s, p)
        assert abs(p["rel_error"]) < 1e-3 and abs(p["flux_ratio"] - 1.0) < 1e-3, p
