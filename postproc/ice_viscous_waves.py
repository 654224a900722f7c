"""Viscous stress of the ICE scene against two exact decay rates (namelists/ice_taylor_green.nml).

Usage:  python -m postproc.ice_viscous_waves [--out docs/validation] [--cells 32 64]

1. Taylor-Green vortex (2D periodic, div u = 0, the cross terms of the stress present):
   u = U sin(kx) cos(ky), v = -U cos(kx) sin(ky), p = p0 + rho U^2/4 (cos 2kx + cos 2ky), an exact
   solution of the incompressible Navier-Stokes equations whose kinetic energy decays as
   exp(-4 nu k^2 t) (k = 2 pi, U = 0.1 m/s, nu = 0.01 m^2/s, Mach 3e-4).
2. Standing sound wave (1D periodic, div u != 0, no conduction): u = U sin(kx), p uniform at t = 0;
   its acoustic energy decays as exp(-2 G t) with Stokes' G = (2/3) nu k^2 (the (4/3) mu normal
   stress; the Laplacian form mu lap(u) gives nu k^2 / 2). The numerical damping of the scheme is
   measured by the same run with mu = 0 (same fixed dt) and subtracted.
3. Smagorinsky: the extra initial decay of the vortex (U = 1 m/s, C_s = 0.5) against the exact
   initial dissipation of the eddy viscosity of the Taylor-Green strain (`smagorinsky_rate`).
Neither initial field can be set by &region boxes: each case runs one step of dt = 1e-6 s to get a
checkpoint, overwrites its fields with the exact ones and restarts from it. Decay rates are
least-squares fits of ln(energy) against time over the dumps. Prints the measured rates against
the exact ones; writes ice_viscous_waves.png and ice_viscous_waves.csv into --out.
"""
from __future__ import annotations

import glob
import math
import os
import tempfile

import h5py
import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.mpmice_io import cell_centres, list_dumps, read_dump
from postproc.run_case import ROOT, run_mpmice

NAMELIST = os.path.join(ROOT, "namelists", "ice_taylor_green.nml")
GAMMA, CV, P0, T0 = 1.4, 717.5, 1.0e5, 300.0
RHO = P0 / ((GAMMA - 1.0) * CV * T0)      # [kg/m^3]
MU = 0.011612                             # [Pa s] of the namelist: nu = 0.01 m^2/s
K = 2.0 * math.pi                         # wave number [1/m]
U_TG = 0.1                                # Taylor-Green amplitude [m/s]
# sound wave: nu = 1 m^2/s so that the viscous damping dominates the numerical one
MU_SOUND = 100.0 * MU
U_SOUND = 0.01                            # [m/s]
C_SOUND = math.sqrt(GAMMA * (GAMMA - 1.0) * CV * T0)
DT_SOUND = 2.0e-5                         # fixed step of both sound runs at 64 cells [s]
END_SOUND = 0.04                          # [s]


def _restart_with(workdir: str, tag: str, sets: list[str], fields, end_time: float,
                  interval: float, extra: list[str] | None = None) -> list[dict]:
    """One step, overwrite the checkpoint's fields by `fields(x, y)` -> (u, v, p), restart."""
    first = os.path.join(workdir, f"{tag}_first")
    args = [NAMELIST] + sets + ["--set", f"&run output_dir = '{first}', max_steps = 1, "
                                "output_interval = 0.0 /"]
    run_mpmice(args, cwd=workdir)
    checkpoint = sorted(glob.glob(os.path.join(first, "tgv_checkpoint_*.h5")))[-1]
    with h5py.File(checkpoint, "r+") as f:
        n = f.attrs["ncells"]
        dx = f.attrs["dx"]
        x = (np.arange(n[0]) + 0.5) * dx[0]
        y = (np.arange(n[1]) + 0.5) * dx[1]
        xx, yy = np.meshgrid(x, y, indexing="ij")
        u, v, p = fields(xx, yy)
        rho = p / ((GAMMA - 1.0) * CV * T0)
        g = "checkpoint/cell/"
        for name, value in (("pressure", p), ("air/velocity_x", u), ("air/velocity_y", v),
                            ("air/velocity_z", 0.0 * u), ("air/density", rho),
                            ("air/specific_volume", 1.0 / rho), ("air/temperature", 0.0 * u + T0)):
            f[g + name][...] = value.T.reshape(f[g + name].shape)
        f.attrs["time"] = 0.0
    out = os.path.join(workdir, tag)
    run_mpmice(["--restart", checkpoint, "--set", f"&run output_dir = '{out}', max_steps = 0, "
                f"end_time = {end_time}, output_interval = {interval} /"] + (extra or []),
               cwd=workdir)
    return [read_dump(p) for p in list_dumps(out, "tgv")]


def _fit_rate(times, energies) -> float:
    """Decay rate [1/s] of energy ~ exp(-rate t), least squares on ln(energy)."""
    return -float(np.polyfit(np.asarray(times), np.log(np.asarray(energies)), 1)[0])


def taylor_green(workdir: str, n: int, amplitude: float = U_TG, smagorinsky: float = 0.0,
                 end_time: float = 0.5, interval: float = 0.05) -> dict:
    """Measured and exact kinetic-energy decay rate of the vortex on n x n cells (`smagorinsky`:
    C_s of the eddy viscosity, 0: none)."""
    def fields(x, y):
        u = amplitude * np.sin(K * x) * np.cos(K * y)
        v = -amplitude * np.cos(K * x) * np.sin(K * y)
        p = P0 + RHO * amplitude**2 / 4.0 * (np.cos(2 * K * x) + np.cos(2 * K * y))
        return u, v, p
    sets = ["--set", f"&grid ncells = {n}, {n}, 1, upper = 1.0, 1.0, {1.0 / n} /"]
    if smagorinsky > 0.0:
        sets += ["--set", f"&ice smagorinsky = .true., smagorinsky_constant = {smagorinsky} /"]
    dumps = _restart_with(workdir, f"tg{n}_{amplitude:g}_{smagorinsky:g}", sets, fields,
                          end_time, interval)
    times, energies = [], []
    for d in dumps:
        c = d["cell"]
        times.append(d["time"])
        energies.append(float(np.sum(0.5 * c["air/density"] * (c["air/velocity_x"] ** 2
                                                               + c["air/velocity_y"] ** 2))))
    nu = MU / RHO
    return {"case": f"taylor_green_{n}", "rate": _fit_rate(times, energies),
            "exact": 4.0 * nu * K**2, "times": times, "energies": energies}


def smagorinsky_rate(workdir: str, n: int, cs: float = 0.5, amplitude: float = 1.0) -> dict:
    """Extra decay rate of the vortex from the Smagorinsky eddy viscosity over the first 0.04 s,
    rate(C_s) - rate(0), against the initial one: -dE/dt = int rho (C_s Delta)^2 |S|^3 dV with
    |S| = 2 U k |cos kx cos ky| gives 32 (C_s Delta)^2 U k^3 (4 / (3 pi))^2."""
    on = taylor_green(workdir, n, amplitude, cs, 0.04, 0.01)
    off = taylor_green(workdir, n, amplitude, 0.0, 0.04, 0.01)
    delta = 1.0 / n
    exact = 32.0 * (cs * delta) ** 2 * amplitude * K**3 * (4.0 / (3.0 * math.pi)) ** 2
    return {"case": f"smagorinsky_{n}", "rate": on["rate"] - off["rate"], "exact": exact}


def sound_wave(workdir: str, n: int, viscosity: float) -> dict:
    """Measured energy decay rate of the standing sound wave on n cells (1D) for `viscosity`."""
    # below the explicit viscous limit (4.6e-5 s at 64 cells), the same with and without mu
    dt = DT_SOUND * (64.0 / n) ** 2

    def fields(x, y):
        u = U_SOUND * np.sin(K * x)
        return u, 0.0 * u, 0.0 * u + P0
    sets = ["--set", f"&grid ncells = {n}, 1, 1, periodic = .true., .false., .false., "
            "upper = 1.0, 1.0, 1.0 /",
            "--set", f"&fluid name = 'air', viscosity = {viscosity} /",
            "--set", "&numerics time_theta = 0.5 /"]
    dumps = _restart_with(workdir, f"sound{n}_{viscosity:g}", sets, fields, END_SOUND,
                          END_SOUND / 40,
                          ["--set", f"&time dt_init = {dt}, dt_max = {dt} /"])
    times, energies = [], []
    for d in dumps:
        x = cell_centres(d)[0]
        u = d["cell"]["air/velocity_x"][:, 0, 0]
        p = d["cell"]["pressure"][:, 0, 0]
        a = 2.0 * np.mean(u * np.sin(K * x))
        b = 2.0 * np.mean((p - np.mean(p)) / (RHO * C_SOUND) * np.cos(K * x))
        times.append(d["time"])
        energies.append(a * a + b * b)
    return {"case": f"sound_{n}_mu{viscosity:g}", "rate": _fit_rate(times, energies),
            "exact": 2.0 * (2.0 / 3.0) * viscosity / RHO * K**2, "times": times,
            "energies": energies}


def sound_viscous_rate(workdir: str, n: int) -> dict:
    """Viscous part of the sound-wave decay: rate(mu) - rate(0) against 2 (2/3) nu k^2."""
    viscous = sound_wave(workdir, n, MU_SOUND)
    inviscid = sound_wave(workdir, n, 0.0)
    return {"case": f"sound_{n}", "rate": viscous["rate"] - inviscid["rate"],
            "numerical": inviscid["rate"], "exact": viscous["exact"],
            "laplacian_form": 0.75 * viscous["exact"], "runs": (viscous, inviscid)}


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    parser.add_argument("--cells", type=int, nargs="+", default=[32, 64])
    args = parse_study_args(parser, argv)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for n in args.cells:
            rows.append(taylor_green(work, n))
            rows.append(sound_viscous_rate(work, 2 * n))
        rows.append(smagorinsky_rate(work, args.cells[0]))
    print("case               measured rate [1/s]   exact [1/s]   relative error")
    for r in rows:
        extra = ""
        if "numerical" in r:
            extra = (f"   (numerical damping {r['numerical']:.4g} 1/s subtracted; Laplacian form "
                     f"would give {r['laplacian_form']:.4g})")
        print(f"{r['case']:18s} {r['rate']:18.5g} {r['exact']:13.5g} "
              f"{r['rate'] / r['exact'] - 1.0:14.2e}{extra}")
    with open(os.path.join(args.out, "ice_viscous_waves.csv"), "w") as f:
        f.write("case,measured_rate,exact_rate,relative_error\n")
        for r in rows:
            f.write(f"{r['case']},{r['rate']:.6g},{r['exact']:.6g},"
                    f"{r['rate'] / r['exact'] - 1.0:.3e}\n")
    try:
        plt = pyplot()
    except ImportError:
        return 0
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for r in rows:
        if r["case"].startswith("taylor"):
            t = np.asarray(r["times"])
            axes[0].semilogy(t, np.asarray(r["energies"]) / r["energies"][0], "o",
                             label=r["case"])
            axes[0].semilogy(t, np.exp(-r["exact"] * (t - t[0])), "k-")
        elif "runs" in r:
            for run in r["runs"]:
                t = np.asarray(run["times"])
                axes[1].semilogy(t, np.asarray(run["energies"]) / run["energies"][0], ".",
                                 label=run["case"])
            axes[1].semilogy(t, np.exp(-(r["exact"] + r["numerical"]) * (t - t[0])), "k-")
    axes[0].set(xlabel="t [s]", ylabel="E / E0", title="Taylor-Green vortex (line: exact)")
    axes[1].set(xlabel="t [s]", ylabel="E / E0",
                title="standing sound wave (line: Stokes + numerical)")
    for ax in axes:
        ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "ice_viscous_waves.png"), dpi=120)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
