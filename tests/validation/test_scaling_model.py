"""bench/scaling_model.py (docs/performance.md, "Scaling on paper"): the model's decomposition
and particle counts agree with the code's, its efficiencies are bounded and respond to the
network parameters, and one command writes the CSV and PNG. Uses the measured inputs in
bench/results/scaling_bench.csv; no mpmice run (~3 s).
"""
from __future__ import annotations

import csv
import math

import pytest

from bench import scaling_model as sm

BENCH = sm.os.path.join(sm.ROOT, "bench", "results", "scaling_bench.csv")


@pytest.fixture(scope="module")
def costs():
    return sm.single_core_costs(sm.read_bench(BENCH))


def test_decomposition_matches_the_code():
    """choose_dims gives the blocks the runs reported (MPI_Dims_create: balanced, largest
    first)."""
    for row in sm.read_bench(BENCH):
        ndim = 2
        assert "x".join(map(str, sm.choose_dims(int(row["ranks"]), ndim))) + "x1" == row["dims"]
    assert sm.choose_dims(4096, 2) == [64, 64]
    assert sm.choose_dims(12, 3) == [3, 2, 2]


def test_particle_counts_match_the_seeding():
    """The model's sand wedge and rigid bed at 5 mm hold the particles the code seeded in the
    800 x 400 run (the model's 3.5 m tank holds the whole of both bodies)."""
    row = [r for r in sm.read_bench(BENCH) if r["cells"] == 320000][0]
    scene = sm.Scene("5 mm", 0.005)
    assert scene.n == [700, 400]
    assert abs(scene.particles["sand"] / row["sand_particles"] - 1) < 2e-3
    assert abs(scene.particles["bed"] / row["bed_particles"] - 1) < 2e-3


def test_efficiency_bounded_and_network_sensitive(costs):
    """E <= 1 at every rank count; slower networks lower it; an ideal network and node
    (no latency, unlimited bandwidth) leave only the particle imbalance."""
    scene = sm.Scene("5 mm", 0.005)
    net = {"latency": 1.5e-6, "bandwidth": 12e9, "allreduce_stage": 1.5e-6,
           "a2av_peer": 0.1e-6, "cores_per_node": 64, "node_bw": 200e9, "core_bw": 20e9}
    slow = dict(net, latency=3e-6, allreduce_stage=3e-6)
    ideal = dict(net, latency=0.0, bandwidth=math.inf, allreduce_stage=0.0, a2av_peer=0.0,
                 node_bw=math.inf)
    t1 = sm.step_time(scene, 1, costs, net)["step"]
    for p in (2, 64, 1024):
        t = sm.step_time(scene, p, costs, net)
        assert t1 / (p * t["step"]) <= 1.0 + 1e-12
        assert sm.step_time(scene, p, costs, slow)["step"] > t["step"]
        best = sm.step_time(scene, p, costs, ideal)
        assert best["halo"] == best["pressure_comm"] == best["allreduce"] == 0.0
        assert t1 / (p * best["step"]) <= 1.0 + 1e-12
        assert best["particle_imbalance"] >= 1.0


def test_model_writes_csv_and_png(tmp_path):
    assert sm.main(["--out", str(tmp_path)]) == 0
    with open(tmp_path / "scaling_model.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert {int(r["ranks"]) for r in rows} == set(sm.RANKS)
    assert len({r["scene"] for r in rows}) == 3
    assert (tmp_path / "scaling_model.png").stat().st_size > 20_000
