"""Radar interference mitigation in the time domain: burst detection, zeroing, interpolation.

An aggressor with another chirp slope leaves short bursts in the victim's IF (see
:mod:`simcore.sensors.radar.interference`). In each chirp and channel the samples of a
burst stand out of the high-passed IF: the first difference along fast time removes the
strong low beat frequencies of near targets and the leakage, and a sample is flagged when
its difference deviates from the chirp's median by more than ``threshold`` robust standard
deviations (``1.4826 × median absolute deviation``). Flagged samples, widened by
``guard`` samples on each side (the IF filters' ringing), are set to zero or replaced by
linear interpolation between their unflagged neighbours (real and imaginary parts
separately). A steady sum of tones never reaches the threshold: a sinusoid's peak is
``√2`` times its median absolute value, far below the default 6 × 1.4826.

Reference: the zeroing/interpolation methods as compared in Toth et al., "Performance
comparison of mutual automotive radar interference mitigation algorithms", IEEE RadarConf
2019.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

MitigationMethod = Literal["off", "zero", "interpolate"]
MAD_TO_SIGMA = 1.4826


def burst_mask(cube: ArrayLike, *, threshold: float = 6.0, guard: int = 2) -> NDArray[np.bool_]:
    """Samples hit by interference bursts.

    Parameters
    ----------
    cube : array_like, shape (chirps, channels, samples)
        ADC samples, real or complex (FS).
    threshold : float, keyword-only
        Robust standard deviations of the first difference above which a sample is hit.
    guard : int, keyword-only
        Samples added on each side of every hit.

    Returns
    -------
    ndarray of bool, same shape as ``cube``

    Examples
    --------
    A tone with a short spike in its middle: only the spike (and the guard) is hit.

    >>> x = np.cos(0.3 * np.arange(64))[None, None, :]
    >>> x[..., 30] += 5.0
    >>> np.flatnonzero(burst_mask(x, guard=1)[0, 0]).tolist()
    [29, 30, 31, 32]
    """
    x = np.asarray(cube)
    d = np.diff(x, axis=-1, prepend=x[..., :1])
    dev = np.abs(d - np.median(d.real, axis=-1, keepdims=True)
                 - (1j * np.median(d.imag, axis=-1, keepdims=True) if np.iscomplexobj(d)
                    else 0.0))
    sigma = MAD_TO_SIGMA * np.median(dev, axis=-1, keepdims=True)
    hit = dev > threshold * np.maximum(sigma, np.finfo(np.float64).tiny)
    hit[..., 0] = False  # the prepended difference is zero by construction
    if guard > 0:
        grown = hit.copy()
        for s in range(1, guard + 1):
            grown[..., s:] |= hit[..., :-s]
            grown[..., :-s] |= hit[..., s:]
        hit = grown
    return hit


def _interpolate_rows(x: NDArray[np.generic], hit: NDArray[np.bool_]) -> NDArray[np.generic]:
    out = x.copy()
    n = x.shape[-1]
    idx = np.arange(n)
    rows = x.reshape(-1, n)
    flags = hit.reshape(-1, n)
    res = out.reshape(-1, n)
    for i in np.flatnonzero(flags.any(axis=1)):
        good = ~flags[i]
        if not good.any():
            res[i] = 0
            continue
        re = np.interp(idx[~good], idx[good], rows[i, good].real)
        if np.iscomplexobj(x):
            re = re + 1j * np.interp(idx[~good], idx[good], rows[i, good].imag)
        res[i, ~good] = re
    return out


def mitigate_interference(cube: ArrayLike, *, method: MitigationMethod = "zero",
                          threshold: float = 6.0, guard: int = 2) -> NDArray[np.generic]:
    """Remove interference bursts from an ADC cube before the range FFT.

    Parameters
    ----------
    cube : array_like, shape (chirps, channels, samples)
        ADC samples, real or complex (FS).
    method : {"off", "zero", "interpolate"}, keyword-only
        ``zero`` sets the hit samples to 0; ``interpolate`` replaces them linearly from
        their neighbours; ``off`` returns the cube unchanged.
    threshold, guard : keyword-only
        See :func:`burst_mask`.

    Returns
    -------
    ndarray, same shape and dtype as ``cube``

    Examples
    --------
    >>> x = np.cos(0.05 * np.arange(64))[None, None, :]
    >>> hit = x.copy(); hit[..., 30] += 5.0
    >>> fixed = mitigate_interference(hit, method="interpolate")
    >>> bool(np.max(np.abs(fixed - x)) < 0.02)
    True
    """
    x = np.asarray(cube)
    if method == "off":
        return x
    hit = burst_mask(x, threshold=threshold, guard=guard)
    if method == "zero":
        return np.where(hit, np.zeros((), x.dtype), x)
    if method == "interpolate":
        return _interpolate_rows(x, hit)
    raise ValueError(f"unknown interference mitigation {method!r}; use 'off', 'zero' or "
                     "'interpolate'")


__all__ = ["MitigationMethod", "burst_mask", "mitigate_interference"]
