"""Compiled path lengths of moving scatterers at a block's fit nodes (IF synthesis)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel


@kernel
def path_lengths(pos: NDArray[np.float64], vel: NDArray[np.float64],
                 acc: NDArray[np.float64], accelerates: bool, lo: int, hi: int,
                 times: NDArray[np.float64], p_t: NDArray[np.float64],
                 p_r: NDArray[np.float64], out_path: NDArray[np.float64],
                 out_d0_t: NDArray[np.float64], out_d0_r: NDArray[np.float64]) -> None:
    """Tx→scatterer→Rx path lengths of rows ``lo … hi−1`` at ``times`` (m).

    Positions follow ``x + v t + a t²/2`` (``pos``, ``vel``, ``acc`` of shape (3, M), one
    row per axis). ``times[0]`` is the frame start: its distances to the Tx and the Rx go
    to ``out_d0_t`` and ``out_d0_r``, shape (hi − lo,); the path lengths at ``times[1:]``
    to ``out_path``, shape (len(times) − 1, hi − lo). Same arithmetic as the numpy
    ``_distance`` of :mod:`~simcore.sensors.radar.synthesis` (squares summed x, y, z).
    """
    for j in range(hi - lo):
        k = lo + j
        for n in range(times.shape[0]):
            t = times[n]
            x = pos[0, k] + vel[0, k] * t
            y = pos[1, k] + vel[1, k] * t
            z = pos[2, k] + vel[2, k] * t
            if accelerates:
                h = 0.5 * (t * t)
                x += h * acc[0, k]
                y += h * acc[1, k]
                z += h * acc[2, k]
            dx, dy, dz = x - p_t[0], y - p_t[1], z - p_t[2]
            d_t = math.sqrt(dx * dx + dy * dy + dz * dz)
            dx, dy, dz = x - p_r[0], y - p_r[1], z - p_r[2]
            d_r = math.sqrt(dx * dx + dy * dy + dz * dz)
            if n == 0:
                out_d0_t[j] = d_t
                out_d0_r[j] = d_r
            else:
                out_path[n - 1, j] = d_t + d_r
