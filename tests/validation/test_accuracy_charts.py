"""Speed-against-accuracy charts and stability maps (bench/accuracy_charts.py,
bench/stability_maps.py, docs/accuracy.md).

The Pareto-front logic is tested on synthetic points; the --quick path of one scene (Sod, ~5 s)
checks that the CSV and PNG are written, that the front is the set of non-dominated runs and that
--replot reproduces it from the CSV; two bar runs check the failure classification of the MPM map
(a stable CFL and one past the explicit limit).
"""
from __future__ import annotations

import math

import numpy as np

from bench import accuracy_charts as ac
from bench import accuracy_runs as runs
from bench import stability_maps as maps


# --------------------------------------------------------------------------- Pareto front

def test_pareto_front_synthetic_points():
    """Minimise both time and error: dominated points drop out, the corners stay."""
    times = [1.0, 2.0, 3.0, 2.5, 4.0, 0.5]
    errors = [0.5, 0.2, 0.1, 0.3, 0.1, 0.9]
    # (2.5, 0.3) is dominated by (2.0, 0.2); (4.0, 0.1) by (3.0, 0.1)
    assert ac.pareto_front(times, errors).tolist() == [True, True, True, False, False, True]


def test_pareto_front_ties_nan_and_single():
    """Exact duplicates both stay; NaN / inf never on the front; one point is its own front."""
    front = ac.pareto_front([1.0, 1.0, 2.0, math.nan, 0.1], [0.1, 0.1, 0.1, 0.01, math.inf])
    assert front.tolist() == [True, True, False, False, False]
    assert ac.pareto_front([3.0], [0.2]).tolist() == [True]
    assert ac.pareto_front([], []).tolist() == []


def test_pareto_front_tolerance():
    """With rtol, an equal-error but slower run (the same scheme on 2 ranks) is dominated;
    without it, a round-off smaller error keeps the slow run on the front."""
    times, errors = [1.0, 8.0], [1.0e-2, 1.0e-2 * (1.0 - 1e-9)]
    assert ac.pareto_front(times, errors).tolist() == [True, True]
    assert ac.pareto_front(times, errors, rtol=1e-4).tolist() == [True, False]
    # a genuinely smaller error still counts
    assert ac.pareto_front([1.0, 8.0], [1e-2, 5e-3], rtol=1e-4).tolist() == [True, True]


def test_pareto_front_matches_brute_force():
    """Random clouds: a point is on the front iff no other point is <= in both and < in one."""
    rng = np.random.default_rng(8)
    for _ in range(20):
        t, e = rng.random(30), rng.random(30)
        t[:3] = t[3]          # some ties in time
        front = ac.pareto_front(t, e)
        for i in range(30):
            dominated = any(t[j] <= t[i] and e[j] <= e[i] and (t[j] < t[i] or e[j] < e[i])
                            for j in range(30))
            assert front[i] == (not dominated)


# --------------------------------------------------------------------------- quick chart

def test_quick_sod_chart(mpmice_exe, tmp_path, monkeypatch):
    """--quick --only sod writes accuracy_sod.csv/.png; the marked front is the non-dominated
    set; the second-order scheme is more accurate than the first at every resolution."""
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))
    assert ac.main(["--quick", "--only", "sod", "--out", str(tmp_path)]) == 0
    csv_path, png_path = tmp_path / "accuracy_sod.csv", tmp_path / "accuracy_sod.png"
    assert csv_path.stat().st_size > 0 and png_path.stat().st_size > 10_000
    rows = ac.read_csv(str(csv_path))
    assert {r["method"] for r in rows} == {"order 1, 1 rank", "order 2, 1 rank"}
    assert all(r["state"] == "finished" and r["run_s"] > 0 for r in rows)
    assert all(0 < r["error"] < 0.05 for r in rows)
    expected = ac.pareto_front([r["run_s"] for r in rows], [r["error"] for r in rows],
                               rtol=ac.PARETO_RTOL)
    assert [bool(r["pareto"]) for r in rows] == expected.tolist()
    assert any(r["pareto"] for r in rows)
    by = {(r["method"], r["cells"]): r["error"] for r in rows}
    for n in (100, 200, 400):
        assert by[("order 2, 1 rank", n)] < by[("order 1, 1 rank", n)]
    # re-plotting from the CSV gives the same front
    assert ac.main(["--replot", "--only", "sod", "--out", str(tmp_path)]) == 0
    again = ac.read_csv(str(csv_path))
    assert [r["pareto"] for r in again] == [r["pareto"] for r in rows]


def test_bar_failure_classification(mpmice_exe, tmp_path, monkeypatch):
    """The elastic bar at cfl 0.5 is stable (energy within 5 %, history error < 10 %); at
    cfl 1.0 (linear shape functions, 2 particles per cell) it blows up: the energy grows by
    orders of magnitude or the run stops with status 3; with the map's stops the energy stop
    ends it early, and the stable run is the same with and without them."""
    monkeypatch.setenv("MPMICE_EXE", str(mpmice_exe))
    ok = runs.run_bar(str(tmp_path), 40, "linear", cfl=0.5)
    assert ok["run"]["state"] == "finished" and not runs.run_failed(ok["run"])
    assert ok["energy_growth"] < runs.ENERGY_LIMIT and ok["history_error"] < maps.BAR_ERROR_LIMIT
    bad = runs.run_bar(str(tmp_path), 40, "linear", cfl=1.0)
    assert runs.run_failed(bad["run"], bad.get("particles_lost", 0)) \
        or not (bad.get("energy_growth", math.inf) < runs.ENERGY_LIMIT)
    # the map's run-loop stops: the energy stop ends the unstable run within 100 steps (the
    # full run takes ~2,100), the stable one is untouched
    (tmp_path / "stops").mkdir()
    stopped = runs.run_bar(str(tmp_path / "stops"), 40, "linear", cfl=1.0, stops=True)
    assert runs.stop_kind(stopped["run"]) == "energy growth" and stopped["run"]["steps"] < 100
    assert runs.ENERGY_LIMIT < stopped["energy_growth"] < 1.0
    watched = runs.run_bar(str(tmp_path / "stops"), 40, "linear", cfl=0.5, stops=True)
    assert watched["run"]["exit_code"] == 0 and runs.stop_kind(watched["run"]) == ""
    assert watched["history_error"] == ok["history_error"]
