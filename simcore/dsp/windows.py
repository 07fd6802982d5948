"""Windows and the one dtype policy of the processing chain.

Dtype policy: spectra are computed and returned as complex64 and maps as float32. The
float32 round-off of a 512-point FFT sits near −140 dB relative to the peak, far below
any window sidelobe (≥ 30 dB down) or ADC quantisation floor, so single precision costs
nothing measurable. Sums that feed a CFAR threshold (summed-area tables) and the
angle-search refinement are done in float64.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.signal import get_window
from scipy.signal.windows import chebwin

from simcore.jit import kernel
from simcore.scene.dsp_config import WindowName

#: Smallest power used before taking logarithms (keeps exact zeros finite in dB).
POWER_FLOOR = float(np.finfo(np.float32).tiny)


def as_complex64(x: ArrayLike) -> NDArray[np.complex64]:
    """Return ``x`` as a complex64 array (no copy when it already is one).

    Examples
    --------
    >>> as_complex64([1.0, 2.0]).dtype
    dtype('complex64')
    """
    return np.asarray(x, dtype=np.complex64)


def as_float32(x: ArrayLike) -> NDArray[np.float32]:
    """Return ``x`` as a float32 array (no copy when it already is one).

    Examples
    --------
    >>> as_float32([1, 2]).dtype
    dtype('float32')
    """
    return np.asarray(x, dtype=np.float32)


def power_to_db(power: ArrayLike) -> NDArray[np.float32]:
    """Convert a power (linear, ≥ 0) to dB, ``10 log10(max(p, POWER_FLOOR))``, as float32.

    Examples
    --------
    >>> np.round(power_to_db([1.0, 100.0, 0.5]), 2)
    array([ 0.  , 20.  , -3.01], dtype=float32)
    """
    p = np.asarray(power)
    if p.dtype == np.float32:
        # The maps: one compiled pass, no float64 temporaries (the same numbers).
        out = np.empty(p.shape, dtype=np.float32)
        _db_float32(np.ascontiguousarray(p).reshape(-1), out.reshape(-1))
        return out
    return as_float32(10.0 * np.log10(np.maximum(np.asarray(p, dtype=np.float64),
                                                 POWER_FLOOR)))


@kernel
def _db_float32(power: NDArray[np.float32], out: NDArray[np.float32]) -> None:
    """:func:`power_to_db` of a float32 array: float64 arithmetic, float32 result."""
    for i in range(power.size):
        p = np.float64(power[i])
        out[i] = np.float32(10.0 * math.log10(POWER_FLOOR if p < POWER_FLOOR else p))


def make_window(name: WindowName, length: int, *, sidelobe_db: float = 60.0) -> NDArray[
    np.float32
]:
    """Build an analysis window.

    Parameters
    ----------
    name : {"none", "hann", "hamming", "blackman", "blackmanharris", "chebyshev"}
        Window family. ``"none"`` is the rectangular window.
    length : int
        Number of samples.
    sidelobe_db : float, keyword-only
        Sidelobe attenuation of the Dolph–Chebyshev window (dB, positive); ignored by the
        other families.

    Returns
    -------
    window : ndarray, shape (length,), float32
        DFT-even (periodic) window for the cosine families, from
        :func:`scipy.signal.get_window`; the symmetric Dolph–Chebyshev window from
        :func:`scipy.signal.windows.chebwin` (its equiripple sidelobes are exact only in the
        symmetric form). Peak value 1.

    Examples
    --------
    The periodic Hann window of length 4, and a 60 dB Chebyshev window:

    >>> make_window("hann", 4)
    array([0. , 0.5, 1. , 0.5], dtype=float32)
    >>> round(peak_sidelobe_db(make_window("chebyshev", 32, sidelobe_db=60.0)), 1)
    -60.0
    """
    return _window(name, int(length), float(sidelobe_db)).copy()


@lru_cache(maxsize=32)
def _window(name: WindowName, length: int, sidelobe_db: float) -> NDArray[np.float32]:
    """:func:`make_window`, cached (read-only): the chain asks for the same few every frame."""
    if length < 1:
        raise ValueError(f"window length must be >= 1, got {length}")
    if length == 1:
        w = np.ones(1)
    elif name == "chebyshev":
        w = chebwin(length, at=sidelobe_db, sym=True)
    elif name == "none":
        w = np.ones(length)
    else:
        w = get_window(name, length, fftbins=True)
    w = np.asarray(w, dtype=np.float64)
    out = as_float32(w / np.max(w))
    out.setflags(write=False)
    return out


def next_pow2(n: int) -> int:
    """Smallest power of two ≥ ``n`` (``n`` ≥ 1).

    Examples
    --------
    >>> next_pow2(1), next_pow2(300), next_pow2(512)
    (1, 512, 512)
    """
    return 1 << max(0, int(n - 1).bit_length())


def peak_sidelobe_db(window: NDArray[np.floating]) -> float:
    """Peak sidelobe level of a window's spectrum relative to its mainlobe (dB, negative).

    Parameters
    ----------
    window : ndarray, shape (n,)
        Window samples.

    Returns
    -------
    float
        ``20 log10(max sidelobe / mainlobe peak)`` from a 256× zero-padded FFT; the
        sidelobe region starts at the first minimum beside the mainlobe. ``-inf`` for a
        window of length 1 (no sidelobes).

    Examples
    --------
    The rectangular window's first sidelobe is 13.26 dB down (the limit of long windows):

    >>> round(peak_sidelobe_db(np.ones(64)), 2), round(peak_sidelobe_db(np.ones(4096)), 2)
    (-13.25, -13.26)
    """
    w = np.asarray(window, dtype=np.float64)
    if w.size < 2:
        return float("-inf")
    n = 256 * next_pow2(w.size)
    spec = np.abs(np.fft.rfft(w, n))
    spec /= spec[0]
    rising = np.flatnonzero(np.diff(spec) > 0)
    if rising.size == 0:
        return float("-inf")
    return float(20.0 * np.log10(max(float(np.max(spec[rising[0]:])), 1e-300)))
