"""The state of a settling bank of critical-state sand, per dump (docs/earthquake_liquefaction.md,
"Elastic gravity loading"): the sediment's kinetic energy and largest particle speed (is it at
rest?), the share of its particles with p' <= 10 Pa, the share beyond the yield surface and the
mobilised strength tau / (mu p') of those with p' > 10 Pa, and the share that has yielded
(plastic strain > 0).

tau = sqrt(s:s / 2); mu = mu_1 + K (phi - phi_m) is the quasi-static strength of the packing
phi = phi0 V0 / V (`&solid fluid_viscosity = 0`; phi0 = 1 - porosity, V the particle volume,
V0 the first dump's); beyond yield: tau > 1.0001 mu p'.

    python -m postproc.mpmice_settle_state --dir RUN_DIR --phi0 0.57 --times 2.0 2.05 --until 2.0

With ``--moved T0`` it prints, for every dump from T0 on, how far the sediment has moved since T0
relative to the base (the base's mean x displacement taken off, periodic x unwrapped): the largest
displacement, the shares of the particles that moved more than 2 cm and 0.2 m, and the crest's
mean vertical displacement (particles starting above y = 2.3 m).

With ``--by-depth T`` it also prints, for the dump at time T, the particles grouped by their
initial p'_0 (bins in kPa: < 0.5, 0.5-2, 2-5, 5-10, > 10): count, share beyond yield, median
tau / (mu p') and median p' / p'_0.
"""
from __future__ import annotations

import argparse

import numpy as np

from postproc.measures import by_id, mean_stress
from postproc.mpmice_earthquake_slope import BASE, CREST_Y0, domain_length, unwrapped
from postproc.mpmice_io import list_dumps, read_dump

SEDIMENT = "sediment"
LOW_PRESSURE = 10.0   # Pa
P0_BINS = [0.0, 500.0, 2000.0, 5000.0, 10000.0, np.inf]   # Pa: bins of the initial p'


def state(parts: dict, volume0: np.ndarray, phi0: float, mu1: float, k_dil: float,
          phi_m: float) -> dict:
    """Kinetic energy [J], largest speed [m/s] and the shares [-] of one dump's sediment; also
    each particle's p' and mobilised strength tau / (mu p') (NaN where p' <= 10 Pa)."""
    v2 = parts["velocity_x"] ** 2 + parts["velocity_y"] ** 2 + parts["velocity_z"] ** 2
    sxx, syy, szz, sxy = (parts[k] for k in ("stress_xx", "stress_yy", "stress_zz", "stress_xy"))
    syz, sxz = parts["stress_yz"], parts["stress_xz"]
    p = mean_stress(parts)
    tau = np.sqrt(0.5 * ((sxx + p) ** 2 + (syy + p) ** 2 + (szz + p) ** 2)
                  + sxy ** 2 + syz ** 2 + sxz ** 2)
    mu = mu1 + k_dil * (phi0 * volume0 / parts["volume"] - phi_m)
    loaded = p > LOW_PRESSURE
    mobilised = tau[loaded] / (mu[loaded] * p[loaded])
    ratio = np.full(len(p), np.nan)
    ratio[loaded] = mobilised
    return {"kinetic": float(0.5 * np.sum(parts["mass"] * v2)), "speed": float(np.sqrt(v2.max())),
            "p": p, "ratio": ratio,
            "low": float(np.mean(~loaded)), "beyond": float(np.sum(mobilised > 1.0001) / len(p)),
            "mobilised": np.percentile(mobilised, [10, 50, 90]),
            "yielded": float(np.mean(parts["plastic_strain"] > 0.0))}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="kinetic energy, p' <= 10 Pa and yield state "
                                     "of a settling critical-state sand bank, per dump")
    parser.add_argument("--dir", required=True, help="run output folder")
    parser.add_argument("--name", default="quake", help="&run name")
    parser.add_argument("--phi0", type=float, required=True, help="1 - porosity")
    parser.add_argument("--mu1", type=float, default=0.577)
    parser.add_argument("--k-dil", type=float, default=4.09)
    parser.add_argument("--phi-m", type=float, default=0.585)
    parser.add_argument("--times", type=float, nargs="*", help="only these dump times [s]")
    parser.add_argument("--until", type=float, default=float("inf"),
                        help="the largest kinetic energy over the dumps up to this time [s]")
    parser.add_argument("--moved", type=float, metavar="T0",
                        help="the displacement relative to the base since the dump at T0 [s]")
    parser.add_argument("--by-depth", type=float, metavar="T",
                        help="group the particles by their initial p' at the dump of time T [s]")
    args = parser.parse_args(argv)
    paths = list_dumps(args.dir, args.name)
    first = by_id(read_dump(paths[0])["particles"][SEDIMENT])
    volume0, p0 = first["volume"], mean_stress(first)
    depth = None
    print("  t [s]  kinetic [J]  v max [mm/s]  p'<=10 Pa  beyond yield  tau/(mu p') p10/p50/p90"
          "  yielded")
    peak = (0.0, 0.0)
    for path in paths:
        dump = read_dump(path)
        t = float(dump["time"])
        s = state(by_id(dump["particles"][SEDIMENT]), volume0, args.phi0, args.mu1, args.k_dil,
                  args.phi_m)
        if t <= args.until + 1e-9:
            peak = max(peak, (s["kinetic"], t))
        if args.by_depth is not None and abs(t - args.by_depth) < 1e-6:
            depth = s
        if args.times and not any(abs(t - x) < 1e-6 for x in args.times):
            continue
        mob = "/".join(f"{m:.2f}" for m in s["mobilised"])
        print(f"{t:7.3f} {s['kinetic']:12.3e} {s['speed'] * 1e3:13.2f} {s['low'] * 100:9.1f} %"
              f" {s['beyond'] * 100:11.1f} %  {mob:>24s} {s['yielded'] * 100:7.1f} %")
    print(f"largest kinetic energy up to {min(args.until, t):.3f} s: {peak[0]:.3e} J at {peak[1]:.3f} s")
    if depth is not None:
        print(f"at {args.by_depth:.3f} s, by initial p'_0 [kPa]: particles, beyond yield, "
              "median tau/(mu p'), median p'/p'_0")
        for lo, hi in zip(P0_BINS[:-1], P0_BINS[1:]):
            sel = (p0 >= lo) & (p0 < hi)
            ratio = depth["ratio"][sel]
            beyond = float(np.mean(np.nan_to_num(ratio, nan=0.0) > 1.0001))
            print(f"  {lo / 1e3:5.1f}-{hi / 1e3:<5.1f} {int(sel.sum()):6d} {beyond * 100:6.1f} %"
                  f" {np.nanmedian(ratio):6.2f} {np.median(depth['p'][sel] / p0[sel]):6.2f}")
    if args.moved is not None:
        print_moved(paths, args.moved)
    return 0


def moved(ref: dict, dump: dict, crest: np.ndarray) -> dict:
    """Displacement of the sediment from dump `ref` to `dump` relative to the base [m]."""
    length = domain_length(ref)
    s0, b0 = by_id(ref["particles"][SEDIMENT]), by_id(ref["particles"][BASE])
    s, b = by_id(dump["particles"][SEDIMENT]), by_id(dump["particles"][BASE])
    base_dx = float(np.mean(unwrapped(b["x"] - b0["x"], length)))
    rel = np.hypot(unwrapped(s["x"] - s0["x"], length) - base_dx, s["y"] - s0["y"])
    return {"largest": float(rel.max()), "over_2cm": float(np.mean(rel > 0.02)),
            "over_20cm": float(np.mean(rel > 0.2)),
            "crest_uy": float(np.mean((s["y"] - s0["y"])[crest]))}


def print_moved(paths: list[str], t0: float) -> None:
    """The table of ``--moved T0``."""
    crest = by_id(read_dump(paths[0])["particles"][SEDIMENT])["y"] > CREST_Y0
    ref = None
    print(f"  t [s]  moved since {t0:.3f} s relative to the base: largest [m], > 2 cm, > 0.2 m,"
          " crest u_y [cm]")
    for path in paths:
        dump = read_dump(path)
        if float(dump["time"]) < t0 - 1e-9:
            continue
        ref = ref or dump
        m = moved(ref, dump, crest)
        print(f"{float(dump['time']):7.3f} {m['largest']:10.3f} {m['over_2cm'] * 100:8.1f} %"
              f" {m['over_20cm'] * 100:8.1f} % {m['crest_uy'] * 100:8.1f}")


if __name__ == "__main__":
    raise SystemExit(main())
