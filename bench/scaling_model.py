"""Scaling on paper: the parallel efficiency of the coupled MPMICE step of the debris-flow scene
at 64-4096 ranks, predicted from measured single-core costs (bench/scaling_bench.py) and a
communication model with the network given as parameters (docs/performance.md, "Scaling").

Usage:  python -m bench.scaling_model [--bench bench/results/scaling_bench.csv]
            [--latency-us 1.5] [--bandwidth-gbs 12] [--allreduce-stage-us 1.5]
            [--alltoallv-peer-us 0.1] [--cores-per-node 64] [--node-bw-gbs 200]
            [--core-bw-gbs 20] [--out docs]
Writes <out>/scaling_model.csv and <out>/scaling_model.png.

Time of one step on P ranks (the busiest rank; every term per step):
  compute    sum over stages of max(measured single-core time per cell (per particle) x the
             cells (particles) of the busiest block, the stage's bytes / the memory bandwidth
             per core: min(one core's, the node's / the busy cores of a node))
  halo       the scene's own exchanges: M messages and B bytes per face cell of the block
             boundary per step (counted by instrumenting parallel_halo on 2 and 4 ranks), per
             neighbour: M alpha + B n_face / beta, one sweep per active dimension
  pressure   hypre PCG + PFMG: per PCG iteration a V(1,1) cycle over L levels (PFMG
             semicoarsening: L = sum_d ceil(log2 n_d)), 4 halo rounds per level plus the matvec,
             each alpha + bytes / beta, and 3 allreduces
  allreduce  the scene's own reductions (counted: 12.8 per step) and hypre's, each
             allreduce_stage x ceil(log2 P)
  migration  MPI_Alltoall of counts + MPI_Alltoallv per solid per step (2 solids): P x the
             per-peer cost of Alltoallv (every peer is visited even with 0 particles), plus
             log2 P latency for the counts, plus the particles that cross block faces
  imbalance  particles per block from the scene's initial geometry (sand wedge and rigid bed,
             2 x 2 particles per cell, the Cartesian blocks of choose_dims), with the measured
             costs of a sand and of a rigid-bed particle: the busiest block's particle work, not
             the mean, enters the compute term
Efficiency E(P) = T(1) / (P T(P)); also against a full node (T(node) = the step on one node's
cores with their shared memory bandwidth), which isolates the network.

Assumptions (parameters above): a fat-tree InfiniBand-class network (1.5 us latency, 12 GB/s
per link), allreduce of a few doubles 1.5 us per tree stage, Alltoallv 0.1 us per peer, nodes of
64 cores sharing 200 GB/s of memory bandwidth (one core alone: 20 GB/s as measured with
bench/stream.py). Limits: no overlap of communication with computation is assumed (the code has
none); hypre's coarse levels are modelled as latency only; the flow's evolution (the slide moving
into other blocks, the pressure iterations over time) is not modelled; the measured inputs come
from a 2-core machine shared with other jobs (+-20-30 %).
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from postproc.run_case import ROOT  # noqa: E402

#: per-step stages that scale with the cells of a block, and with its particles
CELL_STAGES = ("equil", "face", "lagrange", "advect", "faces_to_nodes", "nodal")
PARTICLE_STAGES = ("p2g", "g2p", "solid_cells", "migrate")
#: bytes moved per cell-step (cell stages) or per particle-step (particle stages), estimated from
#: the code (docs/performance.md roofline: pressure 590 B per PCG iteration + 800 B per solve,
#: Lagrangian 1.1 kB, G2P ~480 B per particle); the others are rough counts of the arrays read
CELL_BYTES = {"equil": 200.0, "face": 500.0, "lagrange": 1100.0, "advect": 600.0,
              "faces_to_nodes": 150.0, "nodal": 100.0}
PARTICLE_BYTES = {"p2g": 300.0, "g2p": 480.0, "solid_cells": 200.0, "migrate": 50.0}
PCG_BYTES_PER_ITERATION = 590.0
PCG_BYTES_PER_SOLVE = 800.0

#: the scene's own communication per step (instrumented parallel_halo / parallel_reduce, debris
#: flow 400 x 200 on 2 ranks (2 x 1) and 4 ranks (2 x 2), 10 steps): 32.8 messages and 1,442 B
#: per block-boundary face cell per neighbour, 12.8 allreduces
HALO_MESSAGES = 32.8
HALO_BYTES_PER_FACE_CELL = 1442.0
SCENE_ALLREDUCES = 12.8
#: bytes per migrating particle (packed reals) and the share of a block's particles that cross
#: one of its faces per step (cfl 0.3: <= 0.3 cells per step; a moving slide ~ 0.1 cells)
MIGRATION_BYTES = 8.0 * 60
CROSSING_CELLS_PER_STEP = 0.1
SOLIDS = 2


def read_bench(path: str) -> list[dict]:
    with open(path, encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in r.items():
            try:
                r[k] = float(v)
            except ValueError:
                pass
    return rows


def single_core_costs(rows: list[dict]) -> dict:
    """Single-core costs [s] from the 1-rank runs: per cell and stage (the 5 mm run), per PCG
    iteration and cell, per rigid-bed particle and stage (the run with the sand shrunk: kind
    'bed'), per sand particle and stage (the 10 mm run minus the bed run, over its sand), and
    the fit its = a + b log2(cells) of the PCG iterations per solve."""
    one = [r for r in rows if r["ranks"] == 1 and r["kind"] != "bed"]
    ref = max(one, key=lambda r: r["cells"])
    costs = {"cell": {s: ref[f"{s}_s"] / ref["cells"] for s in CELL_STAGES}}
    its_total = ref["pcg_per_solve"] * ref["solves_per_step"]
    costs["pcg_per_cell_iteration"] = ref["p_pcg_s"] / (ref["cells"] * its_total)
    costs["pressure_other_per_cell"] = (ref["pressure_s"] - ref["p_pcg_s"]) / ref["cells"]
    costs["solves_per_step"] = ref["solves_per_step"]
    bed = [r for r in rows if r["kind"] == "bed"][0]
    full = [r for r in one if r["cells"] == bed["cells"]][0]
    costs["bed"] = {s: bed[f"{s}_s"] / bed["bed_particles"] for s in PARTICLE_STAGES}
    costs["sand"] = {s: max(full[f"{s}_s"] - bed[f"{s}_s"], 0.0) / full["sand_particles"]
                     for s in PARTICLE_STAGES}
    sizes = sorted({(r["cells"], r["pcg_per_solve"]) for r in one})
    x = np.log2([s[0] for s in sizes])
    y = np.array([s[1] for s in sizes])
    b, a = np.polyfit(x, y, 1) if len(sizes) > 1 else (0.0, y[0])
    costs["its_fit"] = (float(a), float(b))
    costs["ref"] = ref
    return costs


def choose_dims(nranks: int, ndim: int) -> list[int]:
    """Balanced factors, largest first (MPI_Dims_create, as parallel_domain's choose_dims)."""
    dims = [1] * ndim
    n = nranks
    primes = []
    p = 2
    while n > 1:
        while n % p == 0:
            primes.append(p)
            n //= p
        p += 1
    for f in sorted(primes, reverse=True):
        dims[int(np.argmin(dims))] *= f
    return sorted(dims, reverse=True)


def polygon_particles(xs, ys, h: float, lower, upper) -> np.ndarray:
    """2 x 2 particle positions per cell of size h inside the polygon (xs, ys) (x, y)."""
    from matplotlib.path import Path
    nx, ny = int(round((upper[0] - lower[0]) / h)), int(round((upper[1] - lower[1]) / h))
    ox = lower[0] + (np.arange(2 * nx) + 0.5) * h / 2
    oy = lower[1] + (np.arange(2 * ny) + 0.5) * h / 2
    X, Y = np.meshgrid(ox, oy, indexing="ij")
    pts = np.column_stack([X.ravel(), Y.ravel()])
    inside = Path(np.column_stack([xs, ys])).contains_points(pts)
    return pts[inside]


class Scene:
    """The debris-flow scene on an nx x ny (x nz) grid of cell size h: cells and the particle
    positions of the sand wedge and the rigid bed (2 x 2 per cell; a 3D extrusion repeats them
    2 per cell along z)."""

    def __init__(self, name: str, h: float, width: float = 3.5, nz: int = 1):
        self.name, self.h, self.nz = name, h, nz
        self.n = [int(round(width / h)), int(round(2.0 / h))] + ([nz] if nz > 1 else [])
        lower, upper = (0.0, 0.0), (width, 2.0)
        self.xy = {"sand": polygon_particles([1.0, 1.65, 1.65], [1.5, 1.5, 0.85], h, lower,
                                             upper),
                   "bed": polygon_particles([0.0, 0.0, 1.0, 2.5], [0.0, 1.5, 1.5, 0.0], h,
                                            lower, upper)}
        self.per_column = 2 if nz > 1 else 1       # particles per cell along z
        self.cells = int(np.prod(self.n))
        self.particles = {k: len(v) * self.per_column * max(nz, 1) for k, v in self.xy.items()}

    def blocks(self, nranks: int):
        """dims, cells of a (the largest) block, its face cells normal to each dimension, and
        the sand and bed particles of every block (arrays over the blocks)."""
        dims = choose_dims(nranks, len(self.n))
        size = [math.ceil(n / d) for n, d in zip(self.n, dims)]
        faces = [int(np.prod(size)) // s for s in size]    # face cells normal to each dim
        zshare = self.per_column * (size[2] if len(self.n) == 3 else 1)
        counts = {}
        for kind, xy in self.xy.items():
            ix = np.minimum((xy[:, 0] / self.h).astype(int) // size[0], dims[0] - 1)
            iy = np.minimum((xy[:, 1] / self.h).astype(int) // size[1], dims[1] - 1)
            counts[kind] = np.bincount(ix * dims[1] + iy, minlength=dims[0] * dims[1]) * zshare
        return dims, int(np.prod(size)), faces, counts


def step_time(scene: Scene, nranks: int, c: dict, net: dict) -> dict:
    """The terms of the busiest rank's step [s]; the ranks fill nodes, so up to a node's cores
    share its memory bandwidth."""
    dims, cells, faces, counts = scene.blocks(nranks)
    cell_factor = 1.4 if len(scene.n) == 3 else 1.0   # 3D / 2D cost per cell (consolidation)
    bw = min(net["core_bw"], net["node_bw"] / min(nranks, net["cores_per_node"]))
    a, b = c["its_fit"]
    its = a + b * math.log2(scene.cells)
    solves = c["solves_per_step"]
    # the busiest block: its particle work (sand and rigid bed) is the largest
    part_time = np.zeros_like(counts["sand"], dtype=float)
    for s in PARTICLE_STAGES:
        part_time += np.maximum(c["sand"][s] * counts["sand"] + c["bed"][s] * counts["bed"],
                                PARTICLE_BYTES[s] * (counts["sand"] + counts["bed"]) / bw)
    busiest = int(np.argmax(part_time))
    t = {"dims": "x".join(map(str, dims)), "cells_per_rank": cells,
         "sand_max": int(counts["sand"][busiest]), "bed_max": int(counts["bed"][busiest]),
         "particle_imbalance": float(part_time.max() / max(part_time.mean(), 1e-30)),
         "pcg_its": its}
    comp = float(part_time[busiest])
    for s in CELL_STAGES:
        comp += max(c["cell"][s] * cell_factor * cells, CELL_BYTES[s] * cells / bw)
    parts = int(counts["sand"][busiest] + counts["bed"][busiest])
    pcg = c["pcg_per_cell_iteration"] * cell_factor * cells * its * solves
    pcg_bw = (PCG_BYTES_PER_ITERATION * its + PCG_BYTES_PER_SOLVE) * solves * cells / bw
    comp += max(pcg, pcg_bw) + c["pressure_other_per_cell"] * cell_factor * cells
    t["compute"] = comp
    alpha, beta = net["latency"], net["bandwidth"]
    split = [d for d in dims if d > 1]
    neighbours = [2 if d > 2 else 1 for d in dims]          # neighbours per split dimension
    halo = 0.0
    for d, n_d in enumerate(dims):
        if n_d > 1:
            halo += neighbours[d] * (HALO_MESSAGES * alpha
                                     + HALO_BYTES_PER_FACE_CELL * faces[d] / beta)
    t["halo"] = halo
    levels = sum(math.ceil(math.log2(n)) for n in scene.n)
    rounds = 4 * levels + 1
    face_bytes = 8.0 * sum(faces[d] for d in range(len(dims)) if dims[d] > 1)
    t["pressure_comm"] = (its * solves * (rounds * alpha + 2 * face_bytes / beta)
                          if split else 0.0)
    log_p = math.ceil(math.log2(nranks)) if nranks > 1 else 0
    t["allreduce"] = (SCENE_ALLREDUCES + 3 * its * solves) * net["allreduce_stage"] * log_p
    crossing = parts * CROSSING_CELLS_PER_STEP / max(min(s for s in
                                                         [math.ceil(n / d) for n, d in
                                                          zip(scene.n, dims)]), 1)
    t["migration"] = (SOLIDS * (nranks * net["a2av_peer"] + log_p * alpha)
                      + crossing * MIGRATION_BYTES / beta) if nranks > 1 else 0.0
    t["step"] = t["compute"] + t["halo"] + t["pressure_comm"] + t["allreduce"] + t["migration"]
    return t


#: the development machine (2 cores, shared-memory MPI) for the check against the measured runs
DEV_MACHINE = {"latency": 0.5e-6, "bandwidth": 5.0e9, "allreduce_stage": 0.5e-6,
               "a2av_peer": 0.05e-6, "cores_per_node": 2, "node_bw": 25.0e9, "core_bw": 20.0e9}


def check_measured(bench: list[dict], c: dict) -> list[dict]:
    """The model on the development machine for every measured multi-rank run that is not
    oversubscribed: predicted against measured time per step and efficiency."""
    out = []
    for r in bench:
        if r["ranks"] < 2 or r["oversubscribed"] or r["kind"] not in ("strong", "weak"):
            continue
        scene = Scene("measured", 4.0 / r["nx"], width=4.0)
        base = [b for b in bench if b["ranks"] == 1 and b["kind"] == r["kind"]][0]
        t1 = step_time(Scene("measured", 4.0 / base["nx"], width=4.0), 1, c, DEV_MACHINE)
        tp = step_time(scene, int(r["ranks"]), c, DEV_MACHINE)
        scale = r["cells"] / base["cells"] if r["kind"] == "weak" else 1.0
        out.append({"kind": r["kind"], "ranks": int(r["ranks"]), "cells": int(r["cells"]),
                    "measured_step_s": r["step_s"], "model_step_s": tp["step"],
                    "measured_efficiency": base["step_s"] * scale / (r["ranks"] * r["step_s"]),
                    "model_efficiency": t1["step"] * scale / (r["ranks"] * tp["step"])})
    return out


SCENES = [("5 mm, 700 x 400 (paper)", 0.005, 1), ("2.5 mm, 1400 x 800", 0.0025, 1),
          ("5 mm, 3D extrusion 700 x 400 x 100 (0.5 m)", 0.005, 100)]
RANKS = [1, 2, 4, 16, 64, 256, 1024, 4096]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", default=os.path.join(ROOT, "bench", "results",
                                                        "scaling_bench.csv"))
    parser.add_argument("--latency-us", type=float, default=1.5)
    parser.add_argument("--bandwidth-gbs", type=float, default=12.0)
    parser.add_argument("--allreduce-stage-us", type=float, default=1.5)
    parser.add_argument("--alltoallv-peer-us", type=float, default=0.1)
    parser.add_argument("--cores-per-node", type=int, default=64)
    parser.add_argument("--node-bw-gbs", type=float, default=200.0)
    parser.add_argument("--core-bw-gbs", type=float, default=20.0)
    parser.add_argument("--out", default=os.path.join(ROOT, "docs"))
    args = parser.parse_args(argv)
    net = {"latency": args.latency_us * 1e-6, "bandwidth": args.bandwidth_gbs * 1e9,
           "allreduce_stage": args.allreduce_stage_us * 1e-6,
           "a2av_peer": args.alltoallv_peer_us * 1e-6, "cores_per_node": args.cores_per_node,
           "node_bw": args.node_bw_gbs * 1e9, "core_bw": args.core_bw_gbs * 1e9}
    bench = read_bench(args.bench)
    c = single_core_costs(bench)
    rows = []
    for name, h, nz in SCENES:
        scene = Scene(name, h, nz=nz)
        t1 = step_time(scene, 1, c, net)["step"]
        tnode = step_time(scene, args.cores_per_node, c, net)["step"]
        for p in RANKS:
            t = step_time(scene, p, c, net)
            row = {"scene": name, "cells": scene.cells, "sand": scene.particles["sand"],
                   "bed": scene.particles["bed"], "ranks": p}
            row.update(t)
            row["efficiency_vs_1_core"] = t1 / (p * t["step"])
            row["efficiency_vs_1_node"] = (tnode * args.cores_per_node / (p * t["step"])
                                           if p >= args.cores_per_node else math.nan)
            rows.append(row)
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, "scaling_model.csv")
    with open(csv_path, "w", encoding="utf-8", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for r in rows:
            writer.writerow({k: f"{v:.5g}" if isinstance(v, float) else v for k, v in r.items()})
    print(f"single core: {sum(c['cell'].values()) * 1e6:.3f} us per cell-step (cell stages), "
          f"PCG {c['pcg_per_cell_iteration'] * 1e9:.1f} ns per cell-iteration, "
          f"{sum(c['sand'].values()) * 1e6:.3f} us per sand particle-step, "
          f"{sum(c['bed'].values()) * 1e6:.3f} us per rigid-bed particle-step; PCG iterations "
          f"{c['its_fit'][0]:.2f} + {c['its_fit'][1]:.2f} log2(cells)")
    for r in rows:
        print(f"{r['scene']:44s} P={r['ranks']:5d} {r['dims']:>8s} cells/rank "
              f"{r['cells_per_rank']:9d} sand {r['sand_max']:8d} bed {r['bed_max']:8d} "
              f"imb {r['particle_imbalance']:5.2f} step "
              f"{r['step'] * 1e3:8.3f} ms  [comp {r['compute'] * 1e3:.3f} halo "
              f"{r['halo'] * 1e3:.3f} hypre {r['pressure_comm'] * 1e3:.3f} allred "
              f"{r['allreduce'] * 1e3:.3f} migr {r['migration'] * 1e3:.3f}]  E "
              f"{r['efficiency_vs_1_core']:.3f} / node {r['efficiency_vs_1_node']:.3f}")
    checks = check_measured(bench, c)
    for r in checks:
        print(f"check {r['kind']:6s} {r['ranks']} ranks, {r['cells']} cells: measured "
              f"{r['measured_step_s'] * 1e3:.1f} ms per step (efficiency "
              f"{r['measured_efficiency']:.2f}), model on the 2-core machine "
              f"{r['model_step_s'] * 1e3:.1f} ms ({r['model_efficiency']:.2f})")
    plot(rows, bench, checks, os.path.join(args.out, "scaling_model.png"), args)
    return 0


def plot(rows, bench, checks, path, args) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for name, _, _ in SCENES:
        rr = [r for r in rows if r["scene"] == name]
        line = axes[0].semilogx([r["ranks"] for r in rr],
                                [r["efficiency_vs_1_core"] for r in rr], "o-", label=name)
        big = [r for r in rr if r["ranks"] >= args.cores_per_node]
        axes[0].semilogx([r["ranks"] for r in big], [r["efficiency_vs_1_node"] for r in big],
                         "s--", color=line[0].get_color(), mfc="none")
        axes[1].loglog([r["ranks"] for r in rr], [r["step"] for r in rr], "o-", label=name)
    for kind, marker in (("strong", "k^"), ("weak", "kv")):
        meas = sorted((r for r in bench if r["kind"] == kind), key=lambda r: r["ranks"])
        if not meas:
            continue
        base = meas[0]
        eff = [base["step_s"] / (r["ranks"] * r["step_s"]) if kind == "strong"
               else base["step_s"] / r["step_s"] for r in meas]
        axes[0].semilogx([r["ranks"] for r in meas], eff, marker, ms=9,
                         label=f"measured {kind} (10 / 14-20 mm; shared 2-core machine under "
                               f"load; 4 ranks oversubscribed)")
    for r in checks:
        axes[0].semilogx([r["ranks"]], [r["model_efficiency"]], "rx", ms=9,
                         label=f"model of the measured {r['kind']} run on that machine")
    axes[0].set_xlabel("ranks")
    axes[0].set_ylabel("parallel efficiency")
    axes[0].set_ylim(0, 1.15)
    axes[0].grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[0].set_title("solid: vs 1 core; dashed: vs 1 full node", fontsize=9)
    axes[1].set_xlabel("ranks")
    axes[1].set_ylabel("modelled time per step [s]")
    axes[1].grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.suptitle(f"Debris-flow coupled step, model: latency {args.latency_us} us, "
                 f"{args.bandwidth_gbs} GB/s links, allreduce {args.allreduce_stage_us} us per "
                 f"stage, Alltoallv {args.alltoallv_peer_us} us per peer, "
                 f"{args.cores_per_node} cores / {args.node_bw_gbs} GB/s per node", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
