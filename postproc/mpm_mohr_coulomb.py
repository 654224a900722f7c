"""Mohr-Coulomb element tests (eq. 17, non-associated) of the MPM constitutive interface against
the analytic values: drained triaxial compression (p0 = 100 kPa, c' = 10 kPa, phi' = 30 deg,
psi' = 10 deg; peak axial stress (s1 (1 + sin phi) - 2 c cos phi) / (1 - sin phi) with
s1 = -p0, tension positive; plastic dilation d eps_v / d eps_a = -2 sin psi / (1 - sin psi)) and
plane-strain simple shear under constant vertical stress (c' = 0; steady tau / sigma_n =
sin phi cos psi / (1 - sin phi sin psi), Davis 1968; dilation d eps_yy / d gamma = tan psi,
strains extension positive).

Runs build/bin/mc_element (tools/mc_element.f90, next to the mpmice executable), prints the
errors and writes mpm_mohr_coulomb.png.

Usage:  python -m postproc.mpm_mohr_coulomb [--out docs/validation]
"""
from __future__ import annotations

import os
import subprocess
import tempfile

import numpy as np

from postproc.figures import parse_study_args, pyplot, save_figure, study_parser
from postproc.run_case import mpmice_executable

P0, C, PHI, PSI = 1.0e5, 1.0e4, np.radians(30.0), np.radians(10.0)


def element_executable() -> str:
    """Path of mc_element: next to the mpmice executable."""
    return os.path.join(os.path.dirname(mpmice_executable()), "mc_element")


def analytic() -> dict:
    """Analytic peak axial stress [Pa], dilation ratio and the Davis ratios (phi, psi) [-]."""
    sp, sq = np.sin(PHI), np.sin(PSI)
    davis = {}
    for phi, psi in ((30.0, 0.0), (35.0, 10.0)):
        a, b = np.radians(phi), np.radians(psi)
        davis[(phi, psi)] = (np.sin(a) * np.cos(b) / (1.0 - np.sin(a) * np.sin(b)), np.tan(b))
    return {"peak": (-P0 * (1.0 + sp) - 2.0 * C * np.cos(PHI)) / (1.0 - sp),
            "dilation": -2.0 * sq / (1.0 - sq), "davis": davis}


def run(workdir: str) -> dict:
    """Run the element tests; return the curves and the errors."""
    subprocess.run([element_executable(), workdir], check=True, capture_output=True, text=True)
    tri = np.genfromtxt(os.path.join(workdir, "mc_triaxial.csv"), delimiter=",", names=True)
    shear = np.genfromtxt(os.path.join(workdir, "mc_simple_shear.csv"), delimiter=",",
                          names=True)
    ref = analytic()
    ea, ev = tri["axial_strain"], tri["volumetric_strain"]
    dilation = (ev[-1] - ev[-2]) / (ea[-1] - ea[-2])
    errors = {"peak": abs(tri["axial_stress"][-1] / ref["peak"] - 1.0),
              "lateral": abs(np.max(np.abs(tri["lateral_stress"] + P0))) / P0,
              "dilation": abs(dilation - ref["dilation"])}
    for (phi, psi), (ratio, tanpsi) in ref["davis"].items():
        rows = (shear["phi"] == phi) & (shear["psi"] == psi)
        errors[f"davis_{phi:g}_{psi:g}"] = abs(shear["tau_over_sigma_n"][rows][-1] - ratio)
        errors[f"dilation_{phi:g}_{psi:g}"] = abs(shear["deps_yy_dgamma"][rows][-1] - tanpsi)
    return {"triaxial": tri, "shear": shear, "ref": ref, "errors": errors,
            "dilation": dilation}


def main(argv=None) -> int:
    parser = study_parser(__doc__)
    args = parse_study_args(parser, argv)
    plt = pyplot()

    with tempfile.TemporaryDirectory() as work:
        r = run(work)
    tri, shear, ref = r["triaxial"], r["shear"], r["ref"]
    print(f"triaxial: peak axial stress {tri['axial_stress'][-1]:.6e} Pa (analytic "
          f"{ref['peak']:.6e}, relative error {r['errors']['peak']:.1e}); lateral stress held to "
          f"{r['errors']['lateral']:.1e} p0; dilation d eps_v/d eps_a {r['dilation']:.8f} "
          f"(analytic {ref['dilation']:.8f}, error {r['errors']['dilation']:.1e})")
    for (phi, psi), (ratio, tanpsi) in ref["davis"].items():
        print(f"simple shear phi = {phi:g}, psi = {psi:g}: tau/sigma_n "
              f"{ratio + 0.0:.8f} analytic, error {r['errors'][f'davis_{phi:g}_{psi:g}']:.1e}; "
              f"d eps_yy/d gamma analytic {tanpsi:.8f}, error "
              f"{r['errors'][f'dilation_{phi:g}_{psi:g}']:.1e}")
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].plot(-tri["axial_strain"], -tri["axial_stress"] / 1e3, label="MPM element")
    axes[0].axhline(-ref["peak"] / 1e3, color="k", ls="--", lw=0.8, label="analytic peak")
    axes[0].set_xlabel("axial strain (compression) [-]")
    axes[0].set_ylabel("axial stress (compression) [kPa]")
    axes[0].set_title("drained triaxial, p0 = 100 kPa, c' = 10 kPa", fontsize=9)
    axes[0].legend(fontsize=7)
    ea = -tri["axial_strain"]
    axes[1].plot(ea, tri["volumetric_strain"], label="MPM element")
    end = tri["volumetric_strain"][-1]
    axes[1].plot(ea[-600:], end + ref["dilation"] * (tri["axial_strain"][-600:]
                                                     - tri["axial_strain"][-1]),
                 "k--", lw=0.8, label="slope -2 sin psi / (1 - sin psi)")
    axes[1].set_xlabel("axial strain (compression) [-]")
    axes[1].set_ylabel("volumetric strain [-]")
    axes[1].set_title("dilation, psi' = 10 deg", fontsize=9)
    axes[1].legend(fontsize=7)
    for (phi, psi), (ratio, _) in ref["davis"].items():
        rows = (shear["phi"] == phi) & (shear["psi"] == psi)
        line, = axes[2].plot(shear["gamma"][rows], shear["tau_over_sigma_n"][rows],
                             label=f"phi = {phi:g}, psi = {psi:g}")
        axes[2].axhline(ratio, color=line.get_color(), ls="--", lw=0.8)
    axes[2].set_xlabel("shear strain gamma [-]")
    axes[2].set_ylabel("tau / sigma_n [-]")
    axes[2].set_title("plane-strain simple shear (dashed: Davis 1968)", fontsize=9)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, "mpm_mohr_coulomb.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
