"""Sub-bin peak interpolation shared by the range, Doppler and angle estimates."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def parabolic_peak_offset(left: ArrayLike, mid: ArrayLike, right: ArrayLike) -> NDArray[
        np.float64]:
    """Offset of the vertex of the parabola through three equally spaced samples.

    For a peak at sample ``i`` with neighbours ``i - 1`` and ``i + 1`` (values usually in
    dB), the vertex lies at ``i + offset``. Where the three points do not bend down (no
    maximum) the offset is 0; it is clipped to ±0.5 samples.

    Parameters
    ----------
    left, mid, right : array_like, broadcastable to one shape
        Values at ``i - 1``, ``i`` and ``i + 1``.

    Returns
    -------
    ndarray of float64
        The offset in samples, in [-0.5, 0.5].

    Examples
    --------
    The samples of ``-(x - 0.25)**2`` at x = -1, 0, 1 put the vertex at +0.25:

    >>> float(parabolic_peak_offset(-1.5625, -0.0625, -0.5625))
    0.25
    >>> parabolic_peak_offset([1.0, 0.0, 3.0], [2.0, 0.0, 2.0], [0.0, 0.0, 2.5])
    array([-0.16666667,  0.        ,  0.        ])
    """
    left_, mid_, right_ = (np.asarray(v, dtype=np.float64) for v in (left, mid, right))
    denom = left_ - 2.0 * mid_ + right_
    with np.errstate(divide="ignore", invalid="ignore"):
        off = 0.5 * (left_ - right_) / denom
    off = np.where(denom < 0, off, 0.0)
    return np.clip(np.nan_to_num(off), -0.5, 0.5)
