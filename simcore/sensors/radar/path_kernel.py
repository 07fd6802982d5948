"""Compiled path lengths of moving scatterers at a block's fit nodes (IF synthesis)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel


@kernel
def _node_paths(pos: NDArray[np.float64], vel: NDArray[np.float64], acc: NDArray[np.float64],
                accelerates: bool, lo: int, t: float, p_t: NDArray[np.float64],
                p_r: NDArray[np.float64], out_sum: NDArray[np.float64],
                out_t: NDArray[np.float64], out_r: NDArray[np.float64], split: bool) -> None:
    """Path lengths of rows ``lo … lo + len(out_sum) − 1`` at one time ``t`` (m).

    ``split``: also the distances to the Tx and the Rx (``out_t``, ``out_r``). One time per
    call: the loop over the rows has no branch that varies, so it vectorises.
    """
    h = 0.5 * (t * t)
    tx0, tx1, tx2 = p_t[0], p_t[1], p_t[2]
    rx0, rx1, rx2 = p_r[0], p_r[1], p_r[2]
    for j in range(out_sum.shape[0]):
        k = lo + j
        x = pos[0, k] + vel[0, k] * t
        y = pos[1, k] + vel[1, k] * t
        z = pos[2, k] + vel[2, k] * t
        if accelerates:
            x += h * acc[0, k]
            y += h * acc[1, k]
            z += h * acc[2, k]
        dx, dy, dz = x - tx0, y - tx1, z - tx2
        d_t = math.sqrt(dx * dx + dy * dy + dz * dz)
        dx, dy, dz = x - rx0, y - rx1, z - rx2
        d_r = math.sqrt(dx * dx + dy * dy + dz * dz)
        out_sum[j] = d_t + d_r
        if split:
            out_t[j] = d_t
            out_r[j] = d_r


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
    scratch = np.empty(hi - lo)
    _node_paths(pos, vel, acc, accelerates, lo, times[0], p_t, p_r, scratch, out_d0_t,
                out_d0_r, True)
    for n in range(1, times.shape[0]):
        _node_paths(pos, vel, acc, accelerates, lo, times[n], p_t, p_r, out_path[n - 1],
                    scratch, scratch, False)


@kernel
def _node_paths_rows(pos: NDArray[np.float64], vel: NDArray[np.float64],
                     acc: NDArray[np.float64], accelerates: bool, lo: int, t: float,
                     p_t: NDArray[np.float64], p_r: NDArray[np.float64],
                     out_sum: NDArray[np.float64], out_t: NDArray[np.float64],
                     out_r: NDArray[np.float64], split: bool) -> None:
    """:func:`_node_paths` with antennas of their own per row: ``p_t``, ``p_r`` (3, M)."""
    h = 0.5 * (t * t)
    for j in range(out_sum.shape[0]):
        k = lo + j
        x = pos[0, k] + vel[0, k] * t
        y = pos[1, k] + vel[1, k] * t
        z = pos[2, k] + vel[2, k] * t
        if accelerates:
            x += h * acc[0, k]
            y += h * acc[1, k]
            z += h * acc[2, k]
        dx, dy, dz = x - p_t[0, k], y - p_t[1, k], z - p_t[2, k]
        d_t = math.sqrt(dx * dx + dy * dy + dz * dz)
        dx, dy, dz = x - p_r[0, k], y - p_r[1, k], z - p_r[2, k]
        d_r = math.sqrt(dx * dx + dy * dy + dz * dz)
        out_sum[j] = d_t + d_r
        if split:
            out_t[j] = d_t
            out_r[j] = d_r


@kernel
def path_lengths_rows(pos: NDArray[np.float64], vel: NDArray[np.float64],
                      acc: NDArray[np.float64], accelerates: bool, lo: int, hi: int,
                      times: NDArray[np.float64], p_t: NDArray[np.float64],
                      p_r: NDArray[np.float64], out_path: NDArray[np.float64],
                      out_d0_t: NDArray[np.float64], out_d0_r: NDArray[np.float64]) -> None:
    """:func:`path_lengths` with a Tx and an Rx position per row, ``p_t``, ``p_r`` (3, M) (m).

    The same arithmetic per row as :func:`path_lengths` with that row's antennas, so a set
    of scatterers synthesised with its own antennas gets the same path lengths alone or
    among others (the image method's mirrored antennas, one set per reflector).
    """
    scratch = np.empty(hi - lo)
    _node_paths_rows(pos, vel, acc, accelerates, lo, times[0], p_t, p_r, scratch, out_d0_t,
                     out_d0_r, True)
    for n in range(1, times.shape[0]):
        _node_paths_rows(pos, vel, acc, accelerates, lo, times[n], p_t, p_r, out_path[n - 1],
                         scratch, scratch, False)
