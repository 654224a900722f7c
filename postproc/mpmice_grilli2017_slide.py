"""Grilli et al. (2017) test 17: the slide's motion against time (front, mass centre, speed),
for the diagnostic runs that isolate why the model's slide is slower than the measured one.

Usage:  python -m postproc.mpmice_grilli2017_slide --dir RUN [--dir RUN2 ...] [--label L ...]
            [--reference DIR] [--shape-shift S] [--alt-shift S] [--mu MU ...] [--fit-end T]
            [--out DIR] [--name STEM]

Per run and dump: the front (the largest x of the bead particles + a quarter cell, as
postproc.mpmice_grilli2017.front), the beads' mass centre x, and their mass-weighted mean
velocity along the slope (down-slope positive; the slope's unit vector (cos 35, -sin 35)) and
height (the largest vertical height of a bead particle above the bed + a quarter cell; the
digitised shapes': the largest y - bed of their points).
Against them: the digitised front and centroid x of the six shapes (postproc.mpmice_grilli2017,
record time = model time + --shape-shift, default 0) and two sliding-block references that start
from rest at t = 0 and move along the slope with a constant acceleration:

* dry block, a = g (sin b - mu cos b), the bead packing sliding on the bed with Coulomb friction
  mu and no fluid;
* submerged block, a = g (1 - rho_w / rho_b) (sin b - mu cos b) with rho_b = (1 - n) rho_s +
  n rho_w the saturated packing's density (its pore water carried along, the ambient water's
  pressure giving the buoyancy, no drag on the block's outer faces, no added mass): an upper
  bound of a slide that keeps its pore water.

(b = 35 deg, the mass centre's x moves by cos b times the distance along the slope). Writes
<stem>.png (front, centroid x and height against time) and <stem>.csv (per run and dump: time,
front, centroid, speed, height) in --out and prints, per run, the values at the shapes' times and the
acceleration of a least-squares fit s = a t^2 / 2 of the centroid's path along the slope over
the dumps up to --fit-end (default 0.4 s model time: the slide still on the slope, before the
fastest runs' fronts reach the toe x = 1.08 m); the same fit of the digitised centroids whose
model time (record - --shape-shift) lies in that window; and, where the run wrote
<dir>/grilli_contact_force.csv, the bed's effective friction mu_eff (`bed_friction`: the time
averages over model t = 0.1 to 0.4 s of the contact force on the bed along the slope over the
one into it), and the beads' momentum budget along the slope over the same window
(`force_budget`: inertia = weight + the bed's force + the fluids' force, the last split into
buoyancy, the pore water the beads carry and the rest, the ambient water's resistance; each
printed over the beads' weight along the slope) and where the water moves with them
(`slip_by_layer`: the beads' and the water's velocity along the slope in the beads' cells next
to the bed and in the others).
"""
from __future__ import annotations

import argparse
import math
import os

import numpy as np

from postproc import mpmice_grilli2017 as grilli
from postproc.figures import pyplot, save_figure, write_table
from postproc.mpmice_io import read_run_dumps

SLOPE = math.atan(0.7)                  # rad: the scene's slope y = 0.756 - 0.7 x (35.0 deg)
ALONG = np.array([math.cos(SLOPE), -math.sin(SLOPE)])
G = 9.81                                # m/s^2
RHO_S, RHO_W, POROSITY = 2500.0, 999.8, 0.39
FIT_END = 0.4                           # s: model time, before the fastest fronts reach the toe
MU_WINDOW = (0.1, 0.4)                  # s: model time of the bed friction's averages


def block_acceleration(mu: float, submerged: bool) -> float:
    """Acceleration [m/s^2] along the slope of a sliding block (module notes)."""
    a = G * (math.sin(SLOPE) - mu * math.cos(SLOPE))
    if submerged:
        rho_b = (1.0 - POROSITY) * RHO_S + POROSITY * RHO_W
        a *= 1.0 - RHO_W / rho_b
    return max(a, 0.0)


def track(dumps: list[dict]) -> dict[str, np.ndarray]:
    """{time, front, centroid, speed, height} of the beads over the dumps (module notes; height:
    the largest vertical height of a bead particle above the bed plus half a particle
    spacing)."""
    rows = {"time": [], "front": [], "centroid": [], "speed": [], "height": []}
    for d in dumps:
        p = d["particles"][grilli.BEADS]
        w = p["mass"]
        dx = float(np.asarray(d["attrs"]["dx"]).reshape(3)[0])
        rows["height"].append(float(np.max(p["y"] - grilli.bed_height(p["x"]))) + 0.25 * dx)
        v = np.array([np.average(p["velocity_x"], weights=w),
                      np.average(p["velocity_y"], weights=w)])
        rows["time"].append(d["time"])
        rows["front"].append(grilli.front(d))
        rows["centroid"].append(grilli.model_centroid(d))
        rows["speed"].append(float(v @ ALONG))
    return {k: np.array(v) for k, v in rows.items()}


def fitted_acceleration(tr: dict[str, np.ndarray], t_end: float = FIT_END) -> float:
    """a of the least-squares fit s = a t^2 / 2 of the centroid's distance along the slope."""
    sel = tr["time"] <= t_end + 1e-9
    s = (tr["centroid"][sel] - tr["centroid"][0]) / math.cos(SLOPE)
    h = 0.5 * tr["time"][sel] ** 2
    return float(np.sum(h * s) / np.sum(h * h))


def bed_friction(folder: str, t0: float = MU_WINDOW[0], t1: float = MU_WINDOW[1]) -> float | None:
    """The bed's effective friction: the time averages over t0 <= t <= t1 of the contact force on
    the bed along the slope (down-slope) over the one into it, from
    <folder>/grilli_contact_force.csv (None without the file or samples in the window)."""
    path = os.path.join(folder, f"{grilli.NAME}_contact_force.csv")
    if not os.path.isfile(path):
        return None
    data = np.genfromtxt(path, delimiter=",", names=True)
    sel = (data["time"] >= t0) & (data["time"] <= t1)
    if np.count_nonzero(sel) < 2:
        return None
    t, fx, fy = data["time"][sel], data["bed_fx"][sel], data["bed_fy"][sel]
    into = -np.array([math.sin(SLOPE), math.cos(SLOPE)])   # into the bed
    tangential = np.trapezoid(ALONG[0] * fx + ALONG[1] * fy, t)
    normal = np.trapezoid(into[0] * fx + into[1] * fy, t)
    return float(tangential / normal) if normal > 0.0 else None


def force_budget(folder: str, tr: dict[str, np.ndarray], mass: float,
                 t0: float = MU_WINDOW[0], t1: float = MU_WINDOW[1]) -> dict[str, float] | None:
    """The beads' momentum budget along the slope, time-averaged over t0 <= t <= t1 [N, per the
    grid's depth in 2D; down-slope positive], from the dumps' mean speed (`track`) and
    <folder>/grilli_contact_force.csv (None without the file or the dumps at t0, t1):

    * inertia M dv/dt (M the beads' mass, dv/dt from their mean speed at t0 and t1);
    * weight M g sin b; the bed's force on the beads along the slope (minus the contact force on
      the bed) and into the bed (the normal load);
    * the fluids' force, the rest: inertia - weight - bed;
    * of which buoyancy -(M / rho_s) rho_w g sin b, the pore water carried along -m_pw dv/dt
      (m_pw = n / (1 - n) (M / rho_s) rho_w: what the beads must give the water they hold), and
      the rest, the ambient water's resistance;
    * the submerged normal weight M g cos b (1 - rho_w / rho_s) against the normal load.
    """
    path = os.path.join(folder, f"{grilli.NAME}_contact_force.csv")
    n0, n1 = at_time(tr, t0), at_time(tr, t1)
    if not os.path.isfile(path) or n0 is None or n1 is None:
        return None
    data = np.genfromtxt(path, delimiter=",", names=True)
    sel = (data["time"] >= t0) & (data["time"] <= t1)
    t, fx, fy = data["time"][sel], data["bed_fx"][sel], data["bed_fy"][sel]
    span = t[-1] - t[0]
    into = -np.array([math.sin(SLOPE), math.cos(SLOPE)])
    bed_along = -float(np.trapezoid(ALONG[0] * fx + ALONG[1] * fy, t)) / span
    normal = float(np.trapezoid(into[0] * fx + into[1] * fy, t)) / span
    accel = (tr["speed"][n1] - tr["speed"][n0]) / (tr["time"][n1] - tr["time"][n0])
    weight = mass * G * math.sin(SLOPE)
    fluid = mass * accel - weight - bed_along
    buoyancy = -mass / RHO_S * RHO_W * G * math.sin(SLOPE)
    pore = -POROSITY / (1.0 - POROSITY) * mass / RHO_S * RHO_W * accel
    return {"accel": accel, "inertia": mass * accel, "weight": weight, "bed": bed_along,
            "normal": normal, "fluid": fluid, "buoyancy": buoyancy, "pore_water": pore,
            "ambient": fluid - buoyancy - pore,
            "normal_submerged": mass * G * math.cos(SLOPE) * (1.0 - RHO_W / RHO_S)}


def slip_by_layer(dumps: list[dict], t0: float = MU_WINDOW[0],
                  t1: float = MU_WINDOW[1]) -> dict[str, float] | None:
    """Where the water moves with the beads: over the dumps with t0 <= t <= t1, the beads' and
    the water's cell velocities along the slope [m/s], averaged with the beads' volume in each
    cell, in the beads' cells next to the bed (the cell or a face neighbour holds bed) and in the
    others; and the share of the beads' volume next to the bed."""
    sel = [d for d in dumps if t0 - 1e-9 <= d["time"] <= t1 + 1e-9]
    if not sel:
        return None
    acc = {"u_s_bed": 0.0, "u_w_bed": 0.0, "u_s_other": 0.0, "u_w_other": 0.0, "share_bed": 0.0}
    for d in sel:
        c = d["cell"]
        phi_s = c[f"{grilli.BEADS}/volume_fraction"][:, :, 0]
        touch = c["bed/volume_fraction"][:, :, 0] > 0.0
        near = touch.copy()
        near[1:, :] |= touch[:-1, :]
        near[:-1, :] |= touch[1:, :]
        near[:, 1:] |= touch[:, :-1]
        near[:, :-1] |= touch[:, 1:]
        vel = {m: ALONG[0] * c[f"{m}/velocity_x"][:, :, 0] + ALONG[1] * c[f"{m}/velocity_y"][:, :, 0]
               for m in (grilli.BEADS, grilli.WATER)}
        beads = phi_s > 1e-6
        total = float(np.sum(phi_s[beads]))
        for key, mask in (("bed", beads & near), ("other", beads & ~near)):
            w = phi_s[mask]
            if np.sum(w) <= 0.0:
                continue
            acc["u_s_" + key] += float(np.average(vel[grilli.BEADS][mask], weights=w)) / len(sel)
            acc["u_w_" + key] += float(np.average(vel[grilli.WATER][mask], weights=w)) / len(sel)
        acc["share_bed"] += float(np.sum(phi_s[beads & near])) / total / len(sel)
    return acc


def record_track(shapes) -> dict[str, np.ndarray]:
    """{time, front, centroid, height (the largest vertical height above the bed)} of the
    digitised shapes."""
    t, fr, ce, he = [], [], [], []
    for time, (x, y) in shapes.items():
        env = grilli.upper_envelope(x, y)
        t.append(time)
        fr.append(float(np.max(x)))
        ce.append(grilli.record_centroid(x[env], y[env])[1])
        he.append(float(np.max(y - grilli.bed_height(x))))
    return {"time": np.array(t), "front": np.array(fr), "centroid": np.array(ce),
            "height": np.array(he)}


def at_time(tr, t):
    n = int(np.argmin(np.abs(tr["time"] - t)))
    return n if abs(tr["time"][n] - t) < 0.011 else None


def plot(tracks, rec, shape_shift, mus, path, alt_shift=None):
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), sharex=True)
    t = np.linspace(0.0, 0.8, 81)
    x0_front, x0_cent = rec["front"][0], rec["centroid"][0]
    for key, ax, x0 in (("front", axes[0], x0_front), ("centroid", axes[1], x0_cent)):
        ax.plot(rec["time"] - shape_shift, rec[key], "ks", mfc="none", ms=7,
                label="Grilli et al. (2017), digitised shapes")
        if alt_shift is not None:
            ax.plot(rec["time"] - alt_shift, rec[key], "k^", mfc="none", ms=7,
                    label=f"the same at model = record {-alt_shift:+g} s")
        for k, (label, tr) in enumerate(tracks.items()):
            ax.plot(tr["time"], tr[key], "-", color=f"C{k}", label=label)
        for j, mu in enumerate(mus):
            for sub, ls in ((False, ":"), (True, "--")):
                a = block_acceleration(mu, sub)
                ax.plot(t, x0 + 0.5 * a * t**2 * math.cos(SLOPE), ls, color=f"{0.2 + 0.4 * j:.1f}",
                        lw=0.9,
                        label=f"{'submerged' if sub else 'dry'} block, mu = {mu:g}")
        ax.set_xlabel(f"model time [s] (record = model + {shape_shift:g} s)")
        ax.set_ylabel(f"slide {key} x [m]")
        ax.set_ylim(0.74, 1.3)
        ax.grid(True, lw=0.3)
    ax = axes[2]
    ax.plot(rec["time"] - shape_shift, rec["height"], "ks", mfc="none", ms=7)
    if alt_shift is not None:
        ax.plot(rec["time"] - alt_shift, rec["height"], "k^", mfc="none", ms=7)
    for k, (label, tr) in enumerate(tracks.items()):
        ax.plot(tr["time"], tr["height"], "-", color=f"C{k}")
    ax.set_xlabel(f"model time [s] (record = model + {shape_shift:g} s)")
    ax.set_ylabel("slide height above the bed [m]")
    ax.set_ylim(0.0, 0.1)
    ax.set_xlim(0.0, 0.8)               # the shapes' window (longer runs are cut)
    ax.grid(True, lw=0.3)
    axes[0].legend(fontsize=6, loc="upper left")
    fig.suptitle("Grilli et al. (2017) test 17: slide front and mass centre (scene frame)",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", action="append", required=True, help="run folder (repeatable)")
    parser.add_argument("--label", action="append", default=None, help="label per --dir")
    parser.add_argument("--reference", default=grilli.DEFAULT_REFERENCE)
    parser.add_argument("--shape-shift", type=float, default=0.0)
    parser.add_argument("--mu", type=float, action="append", default=None,
                        help="bed friction of the block references (repeatable; default 0.41)")
    parser.add_argument("--alt-shift", type=float, default=None,
                        help="also plot the shapes at record = model + this [s]")
    parser.add_argument("--fit-end", type=float, default=FIT_END)
    parser.add_argument("--out", default=None)
    parser.add_argument("--name", default="grilli2017_slide")
    args = parser.parse_args(argv)
    if not os.path.isdir(args.reference):
        raise SystemExit(f"reference folder {args.reference} not found (--reference DIR)")
    labels = args.label or [os.path.basename(os.path.normpath(d)) for d in args.dir]
    if len(labels) != len(args.dir):
        raise SystemExit("give one --label per --dir")
    out = args.out or args.dir[0]
    os.makedirs(out, exist_ok=True)
    rec = record_track(grilli.reference_shapes(args.reference))
    mus = args.mu or [0.41]
    for mu in mus:
        print(f"block references, mu = {mu:g}: dry a = {block_acceleration(mu, False):.3f}, "
              f"submerged a = {block_acceleration(mu, True):.3f} m/s^2")
    print("record: " + "  ".join(f"t={t:.2f}: front {f:.3f} centroid {c:.3f} height {h:.3f}"
                                 for t, f, c, h in zip(rec["time"], rec["front"], rec["centroid"],
                                                       rec["height"])))
    t_rec = rec["time"] - args.shape_shift
    sel = t_rec <= args.fit_end + 1e-9
    rec_s = (rec["centroid"][sel] - rec["centroid"][0]) / math.cos(SLOPE)
    h = 0.5 * t_rec[sel] ** 2
    print(f"record centroid fit a = {np.sum(h * rec_s) / np.sum(h * h):.3f} m/s^2 "
          f"(s = a t^2/2 at model time t = record - {args.shape_shift:g} s <= {args.fit_end:g})")
    tracks, table = {}, []
    for label, folder in zip(labels, args.dir):
        try:
            dumps = read_run_dumps(folder, grilli.NAME)
        except RuntimeError as error:
            raise SystemExit(str(error)) from None
        tr = track(dumps)
        tracks[label] = tr
        cells = []
        for t in grilli.SHAPE_TIMES:
            n = at_time(tr, t - args.shape_shift)
            cells.append("      --      " if n is None else
                         f"{tr['front'][n]:.3f}/{tr['centroid'][n]:.3f}/{tr['speed'][n]:.2f}/"
                         f"{tr['height'][n]:.3f}")
        print(f"{label}: front/centroid [m]/speed [m/s]/height [m] at t = "
              + ", ".join(f"{t:g}" for t in grilli.SHAPE_TIMES) + ": " + "  ".join(cells)
              + f"; centroid fit a = {fitted_acceleration(tr, args.fit_end):.3f} m/s^2, peak speed "
              f"{np.max(tr['speed']):.3f} m/s at {tr['time'][int(np.argmax(tr['speed']))]:.2f} s"
              + ("" if (mu_eff := bed_friction(folder)) is None else
                 f"; bed mu_eff = {mu_eff:.3f} (t = {MU_WINDOW[0]:g} to {MU_WINDOW[1]:g} s)"))
        budget = force_budget(folder, tr, float(np.sum(dumps[0]["particles"][grilli.BEADS]
                                                      ["mass"])))
        if budget is not None:
            w = budget["weight"]
            print(f"  budget along the slope, t = {MU_WINDOW[0]:g} to {MU_WINDOW[1]:g} s, / the "
                  f"beads' weight along it ({w:.4g} N): inertia {budget['inertia'] / w:.3f} = "
                  f"weight 1 + bed {budget['bed'] / w:.3f} + fluids {budget['fluid'] / w:.3f} "
                  f"(buoyancy {budget['buoyancy'] / w:.3f}, pore water carried "
                  f"{budget['pore_water'] / w:.3f}, ambient water {budget['ambient'] / w:.3f}); "
                  f"dv/dt {budget['accel']:.3f} m/s^2; normal load / submerged normal weight "
                  f"{budget['normal'] / budget['normal_submerged']:.3f}")
        slip = slip_by_layer(dumps)
        if slip is not None:
            print(f"  along the slope, t = {MU_WINDOW[0]:g} to {MU_WINDOW[1]:g} s, in the beads' "
                  f"cells next to the bed ({slip['share_bed']:.0%} of the beads): beads "
                  f"{slip['u_s_bed']:.3f}, water {slip['u_w_bed']:.3f} m/s; elsewhere: beads "
                  f"{slip['u_s_other']:.3f}, water {slip['u_w_other']:.3f} m/s")
        for n in range(tr["time"].size):
            table.append({"run": label, **{k: float(v[n]) for k, v in tr.items()}})
    plot(tracks, rec, args.shape_shift, mus, os.path.join(out, f"{args.name}.png"),
         args.alt_shift)
    write_table(os.path.join(out, f"{args.name}.csv"), table,
                ["run", "time", "front", "centroid", "speed", "height"])
    print(f"written: {out}/{args.name}.png, {args.name}.csv")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
