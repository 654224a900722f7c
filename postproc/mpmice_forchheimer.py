"""Steady water flow through a rigid porous column with the Forchheimer (Ergun / van Gent) drag:
pore velocity against the closed-form root of the quadratic law, from Darcy flow to Re_p ~ 2000.

Usage:  python -m postproc.mpmice_forchheimer [--out docs/validation] [--nranks 1]

The set-up is the Darcy scene's (namelists/mpmice_darcy_1d.nml run through
postproc/mpmice_darcy.py: a 2 m channel of water, a rigid column on 0.5 <= x <= 1.5 m, open ends
at p_ref + dp and p_ref) with `&solid drag_law = 'forchheimer'` and the case's grain size d and
coefficients a, b. In the steady state the whole dp falls across the column (L = 1 m), so the
Darcy flux q solves  G = dp / L = A q + B q^2,  A = a mu (1-n)^2 / (n^3 d^2),
B = b rho (1-n) / (n^3 d):  q = 2 G / (A + sqrt(A^2 + 4 B G)), the pore velocity U_f = q / n.
Each case reports the numeric U_f (mean water velocity over the column's cells in the final
dump), its relative error, the flux outside the column against q, the particle Reynolds number
Re_p = rho q d / mu, the share of the quadratic term in G, and the Darcy (linear-law) pore
velocity for comparison. Writes mpmice_forchheimer.csv and mpmice_forchheimer.png (U_f against
dp: the quadratic law's and Darcy's lines, the numeric markers).
"""
from __future__ import annotations

import os

import numpy as np

from postproc import mpmice_darcy
from postproc.figures import pyplot, run_study, save_figure

MU = mpmice_darcy.MU                 # Pa s
RHO = 999.8                          # kg/m^3, the namelist's water at p_ref
ERGUN = (150.0, 1.75)                # a, b
#: (name, phi_s, dp [atm], d [m], a, b): gravel at Re_p ~ 1700 and 700 (quadratic term 96 %
#: and 91 % of the gradient), and the Darcy scene's sand with a = 180 (Kozeny-Carman's constant)
#: at Re_p = 0.1, where the law is Darcy's to 0.2 %.
HIGH_RE_CASES = (("gravel_dp0.5", 0.6, 0.5, 0.01) + ERGUN,
                 ("gravel_dp0.1", 0.6, 0.1, 0.01) + ERGUN)
LOW_RE_CASES = (("sand_low_re", 0.6, 0.001, 1.0e-3, 180.0, 1.75),)
CASES = HIGH_RE_CASES + LOW_RE_CASES
#: Run time [s]: the slowest case (dp = 0.1 atm, relaxation time rho L_eff / (A + 2 B q) ~ 17 ms)
#: is steady to 1e-5 between the last two dumps.
END_TIME = 0.2


def law_coefficients(solid_fraction, grain_size, a, b, rho=RHO, mu=MU):
    """(A [Pa s/m^2], B [Pa s^2/m^3]) of -dp/dx = A q + B |q| q."""
    n = 1.0 - solid_fraction
    return (a * mu * solid_fraction**2 / (n**3 * grain_size**2),
            b * rho * solid_fraction / (n**3 * grain_size))


def exact_darcy_flux(solid_fraction, gradient, grain_size, a, b, rho=RHO, mu=MU):
    """Darcy flux q [m/s] of the law under -dp/dx = gradient [Pa/m] > 0: the positive root."""
    lin, quad = law_coefficients(solid_fraction, grain_size, a, b, rho, mu)
    return 2.0 * gradient / (lin + np.sqrt(lin**2 + 4.0 * quad * gradient))


def exact_pore_velocity(solid_fraction, dp_atm, grain_size, a, b):
    """Steady pore velocity U_f = q / n [m/s] across the scene's column (L = 1 m)."""
    gradient = dp_atm * mpmice_darcy.ATM / mpmice_darcy.LENGTH
    return exact_darcy_flux(solid_fraction, gradient, grain_size, a, b) / (1.0 - solid_fraction)


def linear_pore_velocity(solid_fraction, dp_atm, grain_size, a):
    """The pore velocity of the linear term alone (b = 0: Darcy with k = n^3 d^2 / (a phi_s^2))."""
    lin, _ = law_coefficients(solid_fraction, grain_size, a, 0.0)
    return dp_atm * mpmice_darcy.ATM / mpmice_darcy.LENGTH / lin / (1.0 - solid_fraction)


def analyse(result: dict, case) -> dict:
    """Add the Forchheimer comparison to a result of mpmice_darcy.run_case for `case`."""
    name, phi, dp_atm, d, a, b = case
    n = 1.0 - phi
    u_exact = float(exact_pore_velocity(phi, dp_atm, d, a, b))
    q = n * u_exact
    lin, quad = law_coefficients(phi, d, a, b)
    out = dict(result)
    out.update({
        "name": name, "grain_size": d, "a": a, "b": b, "u_exact": u_exact,
        "rel_error": result["u_numeric"] / u_exact - 1.0,
        "flux_ratio": result["u_outside"] / q,
        "re_p": RHO * q * d / MU,
        "quadratic_share": quad * q**2 / (lin * q + quad * q**2),
        "u_linear": float(linear_pore_velocity(phi, dp_atm, d, a)),
    })
    return out


def run_case(workdir: str, case, nranks: int = 1, extra_set=()) -> dict:
    """Run one case of CASES in its own folder under `workdir`; :func:`analyse` of it."""
    name, phi, dp_atm, d, a, b = case
    folder = os.path.join(workdir, name)
    os.makedirs(folder, exist_ok=True)
    solid = (f"&solid name='{mpmice_darcy.SOLID}', drag_law = 'forchheimer', "
             f"grain_size = {d:.12g}, forchheimer_a = {a:.12g}, forchheimer_b = {b:.12g} /")
    result = mpmice_darcy.run_case(folder, phi, dp_atm, nranks,
                                   [solid, f"&run end_time = {END_TIME} /", *extra_set])
    return analyse(result, case)


def run_forchheimer(workdir: str, cases=CASES, nranks: int = 1, extra_set=()) -> list[dict]:
    """Run `cases`; one dict per case."""
    return [run_case(workdir, case, nranks, extra_set) for case in cases]


def print_table(results: list[dict]) -> None:
    print(f"{'case':>14} {'d [m]':>7} {'dp [atm]':>8} {'Re_p':>8} {'quad %':>7} "
          f"{'U_f num':>12} {'U_f exact':>12} {'rel error':>10} {'q out/q':>9} "
          f"{'steady':>9} {'U_f Darcy':>10}")
    for r in results:
        print(f"{r['name']:>14} {r['grain_size']:7.3g} {r['dp_atm']:8.3g} {r['re_p']:8.3g} "
              f"{100 * r['quadratic_share']:7.2f} {r['u_numeric']:12.6e} {r['u_exact']:12.6e} "
              f"{r['rel_error']:10.2e} {r['flux_ratio']:9.6f} {r['steady_change']:9.2e} "
              f"{r['u_linear']:10.4g}")


def write_csv(results: list[dict], path: str) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write("case,phi_s,grain_size,a,b,dp_atm,re_p,quadratic_share,u_numeric,u_exact,"
                "rel_error,flux_ratio,steady_change,u_linear\n")
        for r in results:
            f.write(f"{r['name']},{r['phi_s']},{r['grain_size']},{r['a']},{r['b']},"
                    f"{r['dp_atm']},{r['re_p']:.6g},{r['quadratic_share']:.6f},"
                    f"{r['u_numeric']:.9e},{r['u_exact']:.9e},{r['rel_error']:.6e},"
                    f"{r['flux_ratio']:.9f},{r['steady_change']:.6e},{r['u_linear']:.9e}\n")


def plot(results: list[dict], path: str) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    gravel = [r for r in results if r["grain_size"] == HIGH_RE_CASES[0][3]]
    if gravel:
        _, phi, _, d, a, b = HIGH_RE_CASES[0]
        dp = np.linspace(1e-4, 1.1 * max(r["dp_atm"] for r in gravel), 200)
        ax.plot(dp, exact_pore_velocity(phi, dp, d, a, b), "-", color="C0",
                label=f"Forchheimer/Ergun, d = {d * 1e3:g} mm")
        ax.plot(dp, linear_pore_velocity(phi, dp, d, a), "--", color="C1",
                label="its linear (Darcy) term alone")
        ax.plot([r["dp_atm"] for r in gravel], [r["u_numeric"] for r in gravel], "o",
                color="C0", mfc="none", label="MPMICE")
        ax.set_ylim(0.0, 1.5 * max(r["u_exact"] for r in gravel))
    ax.set_xlabel("pressure drop dp across L = 1 m [atm]")
    ax.set_ylabel("pore velocity U_f [m/s]")
    ax.set_title("Flow through a rigid gravel column (phi_s = 0.6)", fontsize=10)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path, dpi=120)


def main(argv=None) -> int:
    return run_study(__doc__, run_forchheimer, print_table, plot, write_csv, "mpmice_forchheimer", argv)


if __name__ == "__main__":
    raise SystemExit(main())
