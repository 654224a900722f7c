"""Analytic solutions used by the validations."""
from __future__ import annotations

import numpy as np


def heat_mode_solution(centres, lower, upper, periodic, active, params, time):
    """Exact temperature [K] of the heat-conduction scene (see modules/heat/heat_conduction.f90).

    T = T_base + A exp(-rate t) prod_d s_d(x_d),  s_d = sin(m pi xi) on wall dimensions,
    cos(2 m pi xi) on periodic ones, xi = (x - lower)/L, rate = alpha sum_d k_d^2.

    centres: list of 3 1D arrays of cell-centre coordinates [m]; returns an [i, j, k] array.
    params: the ``&heat`` group as a dict.
    """
    k = params.get("conductivity", 1.0)
    rho = params.get("density", 1.0)
    cap = params.get("heat_capacity", 1.0)
    base = params.get("base_temperature", 300.0)
    amp = params.get("amplitude", 1.0)
    modes = params.get("modes", [1, 1, 1])
    alpha = k / (rho * cap)
    shape = np.ones([len(c) for c in centres])
    rate = 0.0
    for d in range(3):
        if not active[d]:
            continue
        length = upper[d] - lower[d]
        xi = (np.asarray(centres[d]) - lower[d]) / length
        if periodic[d]:
            wave = 2.0 * np.pi * modes[d] / length
            factor = np.cos(2.0 * np.pi * modes[d] * xi)
        else:
            wave = np.pi * modes[d] / length
            factor = np.sin(np.pi * modes[d] * xi)
        rate += alpha * wave**2
        expand = [None, None, None]
        expand[d] = slice(None)
        shape = shape * factor[tuple(expand)]
    return base + amp * np.exp(-rate * time) * shape


# --------------------------------------------------------------------------- porous media

def carman_kozeny_conductivity(solid_fraction, grain_size, viscosity):
    """Hydraulic conductivity k/mu [m^2/(Pa s)] of the Carman-Kozeny law,
    K = d^2 (1 - phi_s)^3 / (180 mu phi_s^2) (paper eq. 76-77)."""
    phi = np.asarray(solid_fraction, dtype=float)
    return grain_size**2 * (1.0 - phi) ** 3 / (180.0 * viscosity * phi**2)


def darcy_pore_velocity(solid_fraction, grain_size, viscosity, pressure_drop, length):
    """Steady intrinsic (pore) fluid velocity [m/s] through a porous column, paper eq. 77:
    U_f = (1/n) K dp/L with n = 1 - phi_s (errata E11: the Darcy flux is q = n U_f)."""
    porosity = 1.0 - np.asarray(solid_fraction, dtype=float)
    return carman_kozeny_conductivity(solid_fraction, grain_size, viscosity) \
        * pressure_drop / length / porosity


def oedometer_modulus(youngs_modulus, poisson_ratio):
    """E_v = E (1 - nu) / ((1 + nu)(1 - 2 nu)) [Pa]."""
    nu = poisson_ratio
    return youngs_modulus * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))


def consolidation_coefficient(youngs_modulus, poisson_ratio, porosity, grain_size, viscosity):
    """c_v = E_v n^3 d^2 / (180 (1 - n)^2 mu) [m^2/s] (paper, below eq. 78)."""
    n = porosity
    return oedometer_modulus(youngs_modulus, poisson_ratio) * n**3 * grain_size**2 \
        / (180.0 * (1.0 - n) ** 2 * viscosity)


def _terzaghi_modes(terms):
    return 0.5 * np.pi * (2.0 * np.arange(terms) + 1.0)


def terzaghi_excess_pressure(depth, time_factor, load, terms=200):
    """Excess pore pressure [Pa] of one-dimensional consolidation, paper eq. 78 summed from
    m = 0 (the printed sum starts at m = 1, which would drop the leading mode M = pi/2):
    p = sum_m (2 F / M) sin(M z / H) exp(-M^2 T_v), M = pi (2m + 1) / 2.

    depth: z / H, the distance from the drained boundary over the drainage length (array);
    time_factor: T_v = c_v t / H^2 (> 0); load: F_ext [Pa].
    """
    z = np.asarray(depth, dtype=float)[..., None]
    m = _terzaghi_modes(terms)
    return np.sum(2.0 * load / m * np.sin(m * z) * np.exp(-m**2 * time_factor), axis=-1)


def terzaghi_degree_of_consolidation(time_factor, terms=200):
    """Average degree of consolidation U(T_v) = 1 - sum_m (2 / M^2) exp(-M^2 T_v)."""
    tv = np.asarray(time_factor, dtype=float)[..., None]
    m = _terzaghi_modes(terms)
    return 1.0 - np.sum(2.0 / m**2 * np.exp(-m**2 * tv), axis=-1)
