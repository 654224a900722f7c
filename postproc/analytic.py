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
