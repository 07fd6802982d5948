"""Compiled per-scatterer passes of the moving-scatterer IF synthesis.

:func:`fit_delays` fits the delay model of a block and chooses each scatterer's series
length; :func:`transform_points` gives the type-3 transform's points and the phases of its
weights. Both do, in one loop without temporaries, the arithmetic that
:mod:`~simcore.sensors.radar.synthesis` documents (``_fit``, ``_transform``), in the same
order, so the model and its error bound are unchanged.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel

_TWO_PI = 2.0 * math.pi


@kernel
def fit_delays(path: NDArray[np.float64], nodes: NDArray[np.float64], big_u: float,
               c: float, k: float, f_r: float, f_max: float, rel_df: float, eps: float,
               eps_model: float, b_max: float, b2_max: float, max_order: int,
               tau: NDArray[np.float64], beta: NDArray[np.float64],
               alpha: NDArray[np.float64], gamma: NDArray[np.float64],
               cross: NDArray[np.bool_], order: NDArray[np.int8],
               ok: NDArray[np.bool_]) -> None:
    """Delay model of every scatterer of a block from its path lengths at ``nodes``.

    ``path`` has shape (nodes, B) (m); the outputs have shape (B,). The parabola goes
    through nodes 0, 2, 4; the others measure its error (see ``synthesis._fit``).
    """
    inv_u2 = 1.0 / big_u**2
    half_u = 0.5 / big_u
    geo = _TWO_PI * f_max / c * 1.5
    lin = math.pi * k * big_u**2 * rel_df
    curv = _TWO_PI * k * big_u**2
    k2f = k / (2.0 * f_r)
    kf = k / f_r
    inv_c = 1.0 / c
    half_c = 0.5 / c
    n_nodes = path.shape[0]
    for b in range(path.shape[1]):
        p0, l0, p4 = path[0, b], path[2, b], path[4, b]
        l1 = (p4 - p0) * half_u
        l2 = (p4 - 2.0 * l0 + p0) * inv_u2
        res = 0.0
        for j in range(1, n_nodes):
            if j == 2 or j == 4:
                continue
            u = big_u * nodes[j]
            res = max(res, abs(path[j, b] - (l0 + u * l1 + (0.5 * u * u) * l2)))
        t0, b1, a2 = l0 * inv_c, l1 * inv_c, l2 * half_c
        al = a2 - k2f * b1 * b1
        ga = kf * t0 * b1
        err = res * geo
        err += lin * b1 * b1
        err += curv * abs(t0 * a2)
        a = abs(al) * b_max
        g = abs(ga) * b2_max
        cr = g > 0.1 * eps_model
        err += 0.5 * g * g + a * g if cr else g
        # Series length: terms a^p/p! above what the model leaves of the budget.
        budget = eps - min(err, eps_model)
        n = 0
        term = a
        for p in range(1, max_order + 2):
            if term > budget:
                n += 1
            term *= a
            term /= p + 1
        tau[b], beta[b], alpha[b], gamma[b] = t0, b1, al, ga
        cross[b] = cr
        order[b] = n
        ok[b] = err <= eps_model and n <= max_order


@kernel
def transform_points(tau: NDArray[np.float64], alpha: NDArray[np.float64],
                     beta: NDArray[np.float64], sel: NDArray[np.int64], q_mean: float,
                     k: float, f_r: float, x: NDArray[np.float64], y: NDArray[np.float64],
                     phase: NDArray[np.float64]) -> None:
    """Points ``x = τ + α q̄``, ``y = β (1 − Kτ/f_r)`` of scatterers ``sel`` and their phases.

    ``phase = 2π f_r x − πKτ²`` reduced modulo 2π (to [−π, π]): the weights are
    ``w0 e^{j phase}``, their cosine and sine taken by the caller.
    """
    kf = k / f_r
    two_pi_fr = _TWO_PI * f_r
    pi_k = math.pi * k
    for j in range(sel.shape[0]):
        i = sel[j]
        t = tau[i]
        xj = t + alpha[i] * q_mean
        x[j] = xj
        y[j] = beta[i] * (1.0 - kf * t)
        arg = xj * two_pi_fr
        arg -= pi_k * t * t
        arg -= _TWO_PI * round(arg / _TWO_PI)
        phase[j] = arg
