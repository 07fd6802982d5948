"""Constant-false-alarm-rate detection (CA, GO, SO, OS; 1-D and 2-D) and peak grouping.

Model and thresholds
--------------------
Inputs are **powers** (square-law detector output, linear, not dB). A noise-only cell of a
map that averages ``L`` independent complex-Gaussian channels (``n_integrated = L``) has
power ~ Gamma(L, mean μ); ``L = 1`` is the exponential law of a single channel. For each
cell under test (CUT) a statistic ``S`` of the training cells around it (outside the guard
cells) estimates μ and the cell is a detection when ``P_CUT > alpha * S``:

* ``ca`` — mean of all N training cells;
* ``go`` / ``so`` — the greater / smaller of the means of the two halves (leading and
  lagging along the last axis; in 2-D the halves are the training cells left and right of
  the CUT's column, the column itself is not used);
* ``os`` — the k-th smallest training cell, ``k = round(rank * N)``.

``alpha`` is chosen so that ``P(P_CUT > alpha * S) = pfa`` exactly under that model (no
approximation for L > 1): ``pfa(alpha) = ∫ Q_L(alpha s) g_S(s) ds`` with ``Q_L`` the
Gamma(L) survival function and ``g_S`` the density of the statistic (a Gamma law for CA,
max/min of two Gamma laws for GO/SO, a Gamma order statistic for OS), integrated
numerically (composite Gauss–Legendre over the support of g_S) and solved for alpha with
Brent's method. For L = 1 this reproduces the
closed forms (CA: ``(1 + alpha/N)^-N``; OS: ``prod_{i<k} (N-i)/(N-i+alpha)``), which the tests
check. Correlated training cells (zero-padded or windowed FFTs) make the real rate differ
somewhat; the tests measure it.

Edges: an axis marked circular (the Doppler axis) wraps around; other axes are mirrored
(``reflect``) so that every cell has a full set of training cells.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np
import scipy.ndimage as ndi
from numpy.typing import ArrayLike, NDArray
from scipy import optimize, special

from simcore.jit import kernel
from simcore.scene.dsp_config import CfarMethod, PeakGrouping

_LogFn = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@dataclass(frozen=True)
class CfarResult:
    """Output of a CFAR detector; every array has the shape of the input power.

    Attributes
    ----------
    detections : ndarray, bool
        Cells whose power exceeds the threshold.
    threshold : ndarray, float32
        ``alpha * S`` (power, linear).
    noise : ndarray, float32
        Estimate of the mean noise power of each cell, ``S / E[S | μ = 1]``; the SNR of a
        cell is ``power / noise``.
    alpha : float
        Threshold factor applied to the statistic.
    n_training : int
        Number of training cells per CUT.
    """

    detections: NDArray[np.bool_]
    threshold: NDArray[np.float32]
    noise: NDArray[np.float32]
    alpha: float
    n_training: int


# --------------------------------------------------------------------------------------
# Threshold factors
# --------------------------------------------------------------------------------------


def os_rank(n_training: int, rank: float) -> int:
    """Order ``k`` (1-based) used by OS-CFAR: ``round(rank * N)`` clipped to [1, N].

    Examples
    --------
    >>> os_rank(16, 0.75), os_rank(16, 0.0), os_rank(16, 2.0)
    (12, 1, 16)
    """
    return int(np.clip(round(rank * n_training), 1, n_training))


@lru_cache(maxsize=256)
def cfar_threshold_factor(
    method: CfarMethod,
    *,
    n_training: int,
    pfa: float,
    k: int | None = None,
    n_integrated: int = 1,
) -> tuple[float, float]:
    """Threshold factor ``alpha`` giving the requested false-alarm probability.

    Parameters
    ----------
    method : {"ca", "go", "so", "os"}
        Statistic of the training cells.
    n_training : int, keyword-only
        Training cells N (for GO/SO: per half).
    pfa : float, keyword-only
        Requested false-alarm probability per cell.
    k : int, keyword-only
        OS order (1-based, 1 ≤ k ≤ N); required for ``"os"``.
    n_integrated : int, keyword-only
        Number L of independent channels averaged into each cell's power.

    Returns
    -------
    alpha : float
        Detection when ``power > alpha * S``.
    statistic_mean : float
        ``E[S]`` for unit mean noise power (1 for CA).

    Examples
    --------
    Cell averaging over N = 16 exponential cells has the closed form
    ``alpha = N (pfa**(-1/N) - 1)``:

    >>> alpha, mean = cfar_threshold_factor("ca", n_training=16, pfa=1e-4)
    >>> round(alpha, 4), round(16 * (1e-4 ** (-1 / 16) - 1), 4), round(mean, 6)
    (12.4525, 12.4525, 1.0)
    """
    if not 0.0 < pfa < 1.0:
        raise ValueError(f"pfa must be in (0, 1), got {pfa}")
    if n_training < 1:
        raise ValueError(f"need at least one training cell, got {n_training}")
    big_l = int(n_integrated)
    log_g, upper = _statistic_log_density(method, n_training, k, big_l)
    cut = _GammaLaw(big_l, big_l)
    # The statistic's density does not depend on alpha: tabulate it once.
    nodes, weights = _quadrature_nodes(log_g, upper)
    log_g_nodes = log_g(nodes)

    def log_pfa(log_alpha: float) -> float:
        return _log_sum(cut.logsf(np.exp(log_alpha) * nodes) + log_g_nodes, weights)

    target = np.log(pfa)
    lo, hi = np.log(1e-8), np.log(1e16)
    if log_pfa(hi) > target:
        raise ValueError(
            f"pfa = {pfa:g} is out of reach with {n_training} training cells "
            f"({method.upper()}-CFAR); use more training cells or a larger pfa"
        )
    log_alpha = optimize.brentq(lambda la: log_pfa(la) - target, lo, hi, xtol=1e-13,
                                rtol=1e-13)
    mean = float(np.exp(_log_sum(np.log(nodes) + log_g_nodes, weights)))
    return float(np.exp(log_alpha)), mean


class _GammaLaw:
    """Gamma law with integer shape ``a`` and rate ``b`` (mean ``a / b``), log functions."""

    def __init__(self, a: int, b: float) -> None:
        self.a, self.b = float(a), float(b)
        self.log_norm = self.a * np.log(self.b) - special.gammaln(self.a)

    def logpdf(self, s: NDArray[np.float64]) -> NDArray[np.float64]:
        with np.errstate(divide="ignore"):
            return np.asarray(self.log_norm + (self.a - 1.0) * np.log(s) - self.b * s)

    def logcdf(self, s: NDArray[np.float64]) -> NDArray[np.float64]:
        with np.errstate(divide="ignore"):
            return np.asarray(np.log(special.gammainc(self.a, self.b * s)))

    def logsf(self, s: NDArray[np.float64]) -> NDArray[np.float64]:
        x = self.b * np.asarray(s, dtype=np.float64)
        with np.errstate(divide="ignore"):
            out = np.log(special.gammaincc(self.a, x))
        # Far tail (gammaincc underflows): log of the leading terms of the series
        # e^-x sum_{i<a} x^i / i!, dominated by the last one.
        tail = ~np.isfinite(out)
        if np.any(tail):
            xt = x[tail]
            out[tail] = -xt + (self.a - 1.0) * np.log(xt) - special.gammaln(self.a)
        return np.asarray(out)

    def isf(self, p: float) -> float:
        return float(special.gammainccinv(self.a, p) / self.b)


def _statistic_log_density(method: str, n: int, k: int | None, big_l: int) -> tuple[
    _LogFn, float
]:
    """Log-density of the training statistic S (unit mean noise) and an upper bound of S."""
    if method == "ca":
        dist = _GammaLaw(n * big_l, n * big_l)
        return dist.logpdf, dist.isf(1e-40)
    if method in ("go", "so"):
        half = _GammaLaw(n * big_l, n * big_l)
        other = half.logcdf if method == "go" else half.logsf

        def log_g_half(s: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.asarray(np.log(2.0) + other(s) + half.logpdf(s))

        return log_g_half, half.isf(1e-40)
    if method == "os":
        if k is None or not 1 <= k <= n:
            raise ValueError(f"OS-CFAR needs 1 <= k <= N = {n}, got k = {k}")
        cell = _GammaLaw(big_l, big_l)
        log_c = special.gammaln(n + 1) - special.gammaln(k) - special.gammaln(n - k + 1)

        def log_g_os(s: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.asarray(log_c + (k - 1) * cell.logcdf(s) + (n - k) * cell.logsf(s)
                              + cell.logpdf(s))

        return log_g_os, cell.isf(1e-40 / n)
    raise ValueError(f"unknown CFAR method {method!r}")


def _quadrature_nodes(log_g: _LogFn, upper: float) -> tuple[
    NDArray[np.float64], NDArray[np.float64]
]:
    """Composite Gauss–Legendre nodes covering the support of the density ``exp(log_g)``.

    The support is located on a dense log/linear grid (where the density is within e^-80
    of its peak), then split into 64 panels of 24 nodes each; log-spaced panels are used
    when it spans more than a decade, so the left tail near 0 (where a large threshold
    factor puts the false alarms) is resolved.
    """
    grid = np.unique(np.concatenate([np.geomspace(upper * 1e-24, upper, 6000),
                                     np.linspace(0.0, upper, 4001)[1:]]))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        vals = np.nan_to_num(np.asarray(log_g(grid), dtype=np.float64), nan=-np.inf)
    inside = np.flatnonzero(vals > np.max(vals) - 80.0)
    lo = float(grid[max(inside[0] - 1, 0)])
    hi = float(grid[min(inside[-1] + 1, grid.size - 1)])
    edges = np.geomspace(lo, hi, 65) if lo > 0 and hi / lo > 10.0 else np.linspace(lo, hi, 65)
    x, w = np.polynomial.legendre.leggauss(24)
    a, b = edges[:-1, None], edges[1:, None]
    nodes = 0.5 * (b - a) * x[None, :] + 0.5 * (a + b)
    weights = 0.5 * (b - a) * w[None, :]
    return nodes.ravel(), weights.ravel()


def _log_sum(log_f: NDArray[np.float64], weights: NDArray[np.float64]) -> float:
    """``log sum(weights * exp(log_f))`` without underflow."""
    finite = np.isfinite(log_f)
    if not np.any(finite):
        return -1e4
    peak = float(np.max(log_f[finite]))
    total = float(np.sum(weights[finite] * np.exp(log_f[finite] - peak)))
    return float(np.log(max(total, 1e-300)) + peak)


# --------------------------------------------------------------------------------------
# Detectors
# --------------------------------------------------------------------------------------


def _pad(x: NDArray[np.float64], widths: tuple[int, int], circular: tuple[bool, bool]) -> NDArray[
    np.float64
]:
    w0, w1 = widths
    n0, n1 = x.shape
    if w0 <= n0 and w1 <= n1 - 1:
        # The usual case, by slicing (np.pad is the general path: 10x slower on a map).
        rows = (np.concatenate([x[n0 - w0:], x, x[:w0]]) if circular[0]
                else np.concatenate([x[1:w0 + 1][::-1], x, x[n0 - 1 - w0:n0 - 1][::-1]])
                if w0 <= n0 - 1 else None)
        if rows is not None:
            return (np.concatenate([rows[:, n1 - w1:], rows, rows[:, :w1]], axis=1)
                    if circular[1] else
                    np.concatenate([rows[:, 1:w1 + 1][:, ::-1], rows,
                                    rows[:, n1 - 1 - w1:n1 - 1][:, ::-1]], axis=1))
    out = x
    for axis in (0, 1):
        w = widths[axis]
        if w == 0:
            continue
        pad = [(0, 0), (0, 0)]
        pad[axis] = (w, w)
        mode: Literal["wrap", "reflect"] = "wrap" if circular[axis] else "reflect"
        if mode == "reflect" and out.shape[axis] < 2:
            out = np.pad(out, pad, mode="edge")
        else:
            out = np.pad(out, pad, mode=mode)
    return out


def _box_sums(sat: NDArray[np.float64], shape: tuple[int, int], r0: tuple[int, int],
              c0: tuple[int, int]) -> NDArray[np.float64]:
    """Sums over the box rows [i+r0[0], i+r0[1]] × cols [j+c0[0], j+c0[1]] (padded coords).

    ``sat`` is the summed-area table of the padded array with a leading zero row/column.
    """
    a, b = shape
    i = np.arange(a)[:, None]
    j = np.arange(b)[None, :]
    top, bot = i + r0[0], i + r0[1] + 1
    left, right = j + c0[0], j + c0[1] + 1
    return sat[bot, right] - sat[top, right] - sat[bot, left] + sat[top, left]


def _order_keys(x: NDArray[np.float32] | NDArray[np.int32]) -> NDArray[np.int32]:
    """Map float32 values to int32 keys that order like the floats, and back (an involution).

    Non-negative IEEE floats order like their bit patterns read as int32; negative ones in
    reverse, so their bits other than the sign are flipped. Integer comparison is faster
    than float comparison and needs no NaN handling (NaNs order last, as in
    :func:`numpy.partition`, or first when their sign bit is set).
    """
    bits = np.ascontiguousarray(x).view(np.int32)
    return np.where(bits < 0, bits ^ np.int32(0x7FFFFFFF), bits).astype(np.int32)


@kernel
def _select_kth(buf: NDArray[np.int32], k: int) -> np.int32:
    """The ``k``-th smallest (0-based) of ``buf``, which it reorders (Wirth's selection)."""
    lo, hi = 0, buf.size - 1
    while lo < hi:
        pivot = buf[k]
        i, j = lo, hi
        while i <= j:
            while buf[i] < pivot:
                i += 1
            while pivot < buf[j]:
                j -= 1
            if i <= j:
                buf[i], buf[j] = buf[j], buf[i]
                i += 1
                j -= 1
        if j < k:
            lo = i
        if k < i:
            hi = j
    return buf[k]


#: Largest rank distance from the neighbour's statistic that :func:`_select_near` walks.
_NEAR_STEPS = 16


@kernel
def _select_near(buf: NDArray[np.int32], k: int, guess: np.int32,
                 scratch: NDArray[np.int32]) -> np.int32:
    """The ``k``-th smallest (0-based) of ``buf``, starting from a nearby value ``guess``.

    Neighbouring CUTs share most training cells, so the statistic of one is a few ranks
    from that of the next (median 2 on a range–Doppler map): count the cells below and at
    ``guess``, then step through the next distinct values above (or below) it, one
    vectorisable pass each, until the rank is reached. Falls back to :func:`_select_kth`
    on a copy in ``scratch`` (same size) when the guess is far off; ``buf`` is not changed.
    """
    big = np.int32(2147483647)
    small = np.int32(-2147483648)
    below = 0
    equal = 0
    up = big        # smallest value above the guess
    down = small    # largest value below it
    for t in range(buf.size):
        v = buf[t]
        below += 1 if v < guess else 0
        equal += 1 if v == guess else 0
        up = min(up, v if v > guess else big)
        down = max(down, v if v < guess else small)
    if below <= k < below + equal:
        return guess
    if k >= below + equal:
        need = k - below - equal + 1      # rank among the values above the guess
        step = 1
        level = up
    else:
        need = below - k                  # rank from the top among the values below
        step = -1
        level = down
    if need > _NEAR_STEPS:
        scratch[:] = buf
        return _select_kth(scratch, k)
    while True:
        # Count ``level``, and find the next distinct value beyond it, in one pass.
        count = 0
        nxt_up = big
        nxt_down = small
        for t in range(buf.size):
            v = buf[t]
            count += 1 if v == level else 0
            nxt_up = min(nxt_up, v if v > level else big)
            nxt_down = max(nxt_down, v if v < level else small)
        if count >= need:
            return level
        need -= count
        level = nxt_up if step > 0 else nxt_down


@kernel
def _os_select(keys: NDArray[np.int32], half: tuple[int, int], guard: tuple[int, int], k: int,
               out: NDArray[np.int32]) -> None:
    """OS statistic of every CUT: the ``k``-th smallest (0-based) of its training cells.

    ``keys`` is the padded map (:func:`_order_keys`); the CUT at ``out[i, j]`` sits at
    padded ``(i + half[0], j + half[1])``. The window's columns live in a ring of slots
    that slides along each row: a step writes the entering column and swaps the guard
    cells in and out (guard cells hold the largest key, so they never reach rank ``k``,
    which is below the number of training cells), instead of gathering every training
    cell again. Each CUT starts from its left (or upper) neighbour's statistic
    (:func:`_select_near`).
    """
    h0, h1 = half
    g0, g1 = guard
    height, width = 2 * h0 + 1, 2 * h1 + 1
    big = np.int32(2147483647)
    buf = np.empty(height * width, dtype=np.int32)
    scratch = np.empty(height * width, dtype=np.int32)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            if j == 0:
                for c in range(width):
                    for r in range(height):
                        buf[c * height + r] = keys[i + r, c]
                for c in range(h1 - g1, h1 + g1 + 1):
                    for r in range(h0 - g0, h0 + g0 + 1):
                        buf[c * height + r] = big
            else:
                leaving = j - 1 + h1 - g1           # column leaving the guard band
                slot = (leaving % width) * height
                for r in range(h0 - g0, h0 + g0 + 1):
                    buf[slot + r] = keys[i + r, leaving]
                entering = j + 2 * h1               # column entering the window
                slot = (entering % width) * height
                for r in range(height):
                    buf[slot + r] = keys[i + r, entering]
                guarded = j + h1 + g1               # column entering the guard band
                slot = (guarded % width) * height
                for r in range(h0 - g0, h0 + g0 + 1):
                    buf[slot + r] = big
            if j > 0:
                out[i, j] = _select_near(buf, k, out[i, j - 1], scratch)
            elif i > 0:
                out[i, j] = _select_near(buf, k, out[i - 1, 0], scratch)
            else:
                scratch[:] = buf
                out[i, j] = _select_kth(scratch, k)


def _cfar_core(
    power: NDArray[np.float64],
    *,
    method: CfarMethod,
    train: tuple[int, int],
    guard: tuple[int, int],
    circular: tuple[bool, bool],
    pfa: float,
    rank: float,
    n_integrated: int,
) -> CfarResult:
    a, b = power.shape
    t0, t1 = train
    g0, g1 = guard
    h0, h1 = t0 + g0, t1 + g1
    n_train = (2 * h0 + 1) * (2 * h1 + 1) - (2 * g0 + 1) * (2 * g1 + 1)
    if n_train < 1:
        raise ValueError("CFAR window has no training cells")
    padded = _pad(power, (h0, h1), circular)
    if method in ("ca", "go", "so"):
        sat = np.zeros((padded.shape[0] + 1, padded.shape[1] + 1))
        sat[1:, 1:] = np.cumsum(np.cumsum(padded, axis=0), axis=1)
        # Box coordinates relative to the padded position of the CUT (i + h0, j + h1).
        rows_all = (0, 2 * h0)
        rows_g = (h0 - g0, h0 + g0)
        if method == "ca":
            total = _box_sums(sat, (a, b), rows_all, (0, 2 * h1)) - _box_sums(
                sat, (a, b), rows_g, (h1 - g1, h1 + g1))
            stat = total / n_train
            alpha, mean = cfar_threshold_factor("ca", n_training=n_train, pfa=pfa,
                                                n_integrated=n_integrated)
        else:
            if t1 < 1:
                raise ValueError("GO/SO-CFAR needs training cells along the last axis")
            n_half = (2 * h0 + 1) * h1 - (2 * g0 + 1) * g1
            lead = _box_sums(sat, (a, b), rows_all, (0, h1 - 1)) - (
                _box_sums(sat, (a, b), rows_g, (h1 - g1, h1 - 1)) if g1 else 0.0)
            lag = _box_sums(sat, (a, b), rows_all, (h1 + 1, 2 * h1)) - (
                _box_sums(sat, (a, b), rows_g, (h1 + 1, h1 + g1)) if g1 else 0.0)
            pick = np.maximum if method == "go" else np.minimum
            stat = pick(lead, lag) / n_half
            alpha, mean = cfar_threshold_factor(method, n_training=n_half, pfa=pfa,
                                                n_integrated=n_integrated)
    elif method == "os":
        k = os_rank(n_train, rank)
        alpha, mean = cfar_threshold_factor("os", n_training=n_train, pfa=pfa, k=k,
                                            n_integrated=n_integrated)
        keys = _order_keys(padded.astype(np.float32))
        stat_keys = np.empty((a, b), dtype=np.int32)
        _os_select(keys, (h0, h1), (g0, g1), k - 1, stat_keys)
        stat_bits = _order_keys(stat_keys)
        stat = stat_bits.view(np.float32).astype(np.float64)
    else:
        raise ValueError(f"unknown CFAR method {method!r}")
    threshold = alpha * stat
    return CfarResult(
        detections=power > threshold,
        threshold=threshold.astype(np.float32),
        noise=(stat / mean).astype(np.float32),
        alpha=alpha,
        n_training=int(n_train),
    )


def cfar_1d(
    power: ArrayLike,
    *,
    method: CfarMethod = "ca",
    train: int = 8,
    guard: int = 2,
    pfa: float = 1e-4,
    rank: float = 0.75,
    n_integrated: int = 1,
    axis: int = -1,
    circular: bool = False,
) -> CfarResult:
    """1-D CFAR along one axis of an array of powers.

    Parameters
    ----------
    power : array_like, shape (..., n, ...)
        Linear power (square-law), any number of dimensions; each 1-D line along
        ``axis`` is processed independently.
    method : {"ca", "go", "so", "os"}, keyword-only
        Detector (module docstring).
    train, guard : int, keyword-only
        Training and guard cells on each side of the CUT.
    pfa : float, keyword-only
        Requested false-alarm probability per cell.
    rank : float, keyword-only
        OS order as a fraction of the ``2 * train`` training cells.
    n_integrated : int, keyword-only
        Independent channels averaged into each power value (Gamma(L) noise law).
    axis : int, keyword-only
        Axis along which to slide the window.
    circular : bool, keyword-only
        Wrap around the ends of the axis (Doppler) instead of mirroring them.

    Returns
    -------
    CfarResult
        Arrays of the same shape as ``power``.

    Examples
    --------
    One target 30 dB above a flat noise floor of 1:

    >>> power = np.ones(40)
    >>> power[20] = 1000.0
    >>> res = cfar_1d(power, method="ca", train=8, guard=2, pfa=1e-4)
    >>> np.flatnonzero(res.detections), res.n_training, round(res.alpha, 3)
    (array([20]), 16, 12.452)
    >>> float(res.noise[20]), round(float(res.threshold[20]), 3)
    (1.0, 12.452)
    """
    p = np.moveaxis(np.asarray(power, dtype=np.float64), axis, -1)
    shape = p.shape
    res = _cfar_core(p.reshape(-1, shape[-1]), method=method, train=(0, train), guard=(0, guard),
                     circular=(False, circular), pfa=pfa, rank=rank, n_integrated=n_integrated)

    def back(x: NDArray[np.generic]) -> NDArray[np.generic]:
        return np.moveaxis(x.reshape(shape), -1, axis)

    return CfarResult(
        detections=back(res.detections).astype(bool),
        threshold=back(res.threshold).astype(np.float32),
        noise=back(res.noise).astype(np.float32),
        alpha=res.alpha,
        n_training=res.n_training,
    )


def cfar_2d(
    power: ArrayLike,
    *,
    method: CfarMethod = "os",
    train: tuple[int, int] = (4, 8),
    guard: tuple[int, int] = (1, 2),
    pfa: float = 1e-4,
    rank: float = 0.75,
    n_integrated: int = 1,
    circular: tuple[bool, bool] = (True, False),
) -> CfarResult:
    """2-D CFAR over a map, e.g. range–Doppler.

    Parameters
    ----------
    power : array_like, shape (n0, n1)
        Linear power, e.g. ``(doppler, range)``.
    method : {"ca", "go", "so", "os"}, keyword-only
        Detector (module docstring); GO/SO split the window left/right along axis 1.
    train, guard : tuple of int, keyword-only
        Training and guard cells on each side, per axis ``(axis 0, axis 1)``. The training
        region is the rectangular ring between the guard box and the outer box.
    pfa : float, keyword-only
        Requested false-alarm probability per cell.
    rank : float, keyword-only
        OS order as a fraction of the number of training cells.
    n_integrated : int, keyword-only
        Independent channels averaged into each power value.
    circular : tuple of bool, keyword-only
        Per axis: wrap around (Doppler) or mirror at the edges.

    Returns
    -------
    CfarResult
        Arrays of shape ``(n0, n1)``.

    Examples
    --------
    >>> power = np.ones((16, 32))
    >>> power[5, 10] = 1000.0
    >>> res = cfar_2d(power, method="ca", train=(2, 4), guard=(1, 1), pfa=1e-4)
    >>> np.argwhere(res.detections)
    array([[ 5, 10]])
    """
    p = np.asarray(power, dtype=np.float64)
    if p.ndim != 2:
        raise ValueError(f"cfar_2d needs a 2-D map, got shape {p.shape}")
    return _cfar_core(p, method=method, train=train, guard=guard, circular=circular, pfa=pfa,
                      rank=rank, n_integrated=n_integrated)


def ca_cfar_1d(power: ArrayLike, *, train: int = 8, guard: int = 2, pfa: float = 1e-4,
               n_integrated: int = 1, axis: int = -1, circular: bool = False) -> CfarResult:
    """Cell-averaging 1-D CFAR; see :func:`cfar_1d`.

    Examples
    --------
    >>> power = np.ones(40)
    >>> power[[10, 30]] = 500.0
    >>> np.flatnonzero(ca_cfar_1d(power, train=4, guard=1).detections)
    array([10, 30])
    """
    return cfar_1d(power, method="ca", train=train, guard=guard, pfa=pfa,
                   n_integrated=n_integrated, axis=axis, circular=circular)


def os_cfar_1d(power: ArrayLike, *, train: int = 8, guard: int = 2, pfa: float = 1e-4,
               rank: float = 0.75, n_integrated: int = 1, axis: int = -1,
               circular: bool = False) -> CfarResult:
    """Ordered-statistic 1-D CFAR; see :func:`cfar_1d`.

    Examples
    --------
    >>> power = np.ones(40)
    >>> power[[10, 12]] = 500.0     # two close targets: OS is not masked by the neighbour
    >>> np.flatnonzero(os_cfar_1d(power, train=8, guard=1).detections)
    array([10, 12])
    """
    return cfar_1d(power, method="os", train=train, guard=guard, pfa=pfa, rank=rank,
                   n_integrated=n_integrated, axis=axis, circular=circular)


def ca_cfar_2d(power: ArrayLike, *, train: tuple[int, int] = (4, 8),
               guard: tuple[int, int] = (1, 2), pfa: float = 1e-4, n_integrated: int = 1,
               circular: tuple[bool, bool] = (True, False)) -> CfarResult:
    """Cell-averaging 2-D CFAR; see :func:`cfar_2d`.

    Examples
    --------
    >>> power = np.ones((16, 32))
    >>> power[3, 20] = 1000.0
    >>> np.argwhere(ca_cfar_2d(power).detections)
    array([[ 3, 20]])
    """
    return cfar_2d(power, method="ca", train=train, guard=guard, pfa=pfa,
                   n_integrated=n_integrated, circular=circular)


def os_cfar_2d(power: ArrayLike, *, train: tuple[int, int] = (4, 8),
               guard: tuple[int, int] = (1, 2), pfa: float = 1e-4, rank: float = 0.75,
               n_integrated: int = 1, circular: tuple[bool, bool] = (True, False)
               ) -> CfarResult:
    """Ordered-statistic 2-D CFAR; see :func:`cfar_2d`.

    Examples
    --------
    >>> power = np.ones((16, 32))
    >>> power[0, 7] = 1000.0   # Doppler wraps around: row 0 has full training cells
    >>> np.argwhere(os_cfar_2d(power).detections)
    array([[0, 7]])
    """
    return cfar_2d(power, method="os", train=train, guard=guard, pfa=pfa, rank=rank,
                   n_integrated=n_integrated, circular=circular)


# --------------------------------------------------------------------------------------
# Peak grouping
# --------------------------------------------------------------------------------------


def group_peaks(
    power: ArrayLike,
    detections: ArrayLike,
    *,
    method: PeakGrouping = "local_max",
    neighbourhood: tuple[int, ...] = (3, 3),
    circular: tuple[bool, ...] = (True, False),
) -> NDArray[np.bool_]:
    """Reduce CFAR hits to one cell per target.

    Parameters
    ----------
    power : array_like, shape (n0, n1) (or any N-D)
        Linear power map the detector ran on.
    detections : array_like of bool, same shape
        CFAR hits.
    method : {"local_max", "cluster", "none"}, keyword-only
        ``local_max``: keep a hit only if it is the maximum of the map within the
        ``neighbourhood`` window centred on it. ``cluster``: keep the strongest cell of
        each 8-connected group of hits. ``none``: keep every hit.
    neighbourhood : tuple of int, keyword-only
        Odd window size per axis for ``local_max``.
    circular : tuple of bool, keyword-only
        Per axis: the window wraps around (Doppler) or stops at the edge.

    Returns
    -------
    peaks : ndarray of bool, same shape

    Examples
    --------
    >>> power = np.array([1.0, 5.0, 4.0, 1.0, 1.0, 3.0, 1.0])
    >>> hits = power > 2
    >>> np.flatnonzero(group_peaks(power, hits, neighbourhood=(3,), circular=(False,)))
    array([1, 5])
    >>> np.flatnonzero(group_peaks(power, hits, method="cluster"))
    array([1, 5])
    """
    p = np.asarray(power, dtype=np.float64)
    det = np.asarray(detections, dtype=bool)
    if method == "none":
        return det.copy()
    if method == "local_max":
        modes = ["wrap" if c else "nearest" for c in circular]
        local = ndi.maximum_filter(p, size=neighbourhood, mode=modes)
        return det & (p >= local)
    if method == "cluster":
        labels, n = ndi.label(det, structure=np.ones((3,) * det.ndim, dtype=bool))
        out = np.zeros_like(det)
        if n:
            positions = ndi.maximum_position(p, labels, index=np.arange(1, n + 1))
            for pos in positions:
                out[tuple(int(v) for v in pos)] = True
        return out
    raise ValueError(f"unknown peak grouping {method!r}")


def suppress_sidelobes(
    power: ArrayLike,
    peaks: ArrayLike,
    *,
    axis: int = 0,
    sidelobe_db: float,
    margin_db: float = 6.0,
    spread: int = 1,
) -> NDArray[np.bool_]:
    """Drop peaks that a window's sidelobes of a stronger cell nearby can explain.

    A very strong target spreads its window's sidelobes over the whole (short) Doppler
    axis; with a Chebyshev window they are equiripple, so at high SNR they form local
    maxima that pass the CFAR test. A peak is kept only if its power is at least
    ``strongest * 10^((sidelobe_db + margin_db) / 10)``, where ``strongest`` is the largest
    power along ``axis`` on the peak's own line and the ``spread`` lines on either side
    (the sidelobes of targets in neighbouring bins add up between them).

    Parameters
    ----------
    power : array_like, shape (n0, n1)
        Linear power map, e.g. ``(doppler, range)``.
    peaks : array_like of bool, same shape
        Candidate detections.
    axis : int, keyword-only
        Axis along which the sidelobes spread (0: Doppler).
    sidelobe_db : float, keyword-only
        Peak sidelobe level of the window along that axis (dB, negative;
        :func:`simcore.dsp.windows.peak_sidelobe_db`).
    margin_db : float, keyword-only
        How far above the sidelobe level a peak must be (dB).
    spread : int, keyword-only
        Neighbouring lines (across ``axis``) whose strongest cell also counts.

    Returns
    -------
    peaks : ndarray of bool, same shape

    Examples
    --------
    A 60 dB target and a 10 dB cell on its Doppler line, with -40 dB window sidelobes: the
    weak cell is within 6 dB of the sidelobe level and is dropped.

    >>> power = np.array([[1e6], [10.0], [1.0]])     # (doppler, range)
    >>> peaks = np.array([[True], [True], [False]])
    >>> suppress_sidelobes(power, peaks, sidelobe_db=-40.0)[:, 0]
    array([ True, False, False])
    """
    p = np.asarray(power, dtype=np.float64)
    keep = np.asarray(peaks, dtype=bool)
    if not np.isfinite(sidelobe_db):
        return keep.copy()
    line_max = np.max(p, axis=axis, keepdims=True)
    if spread > 0:
        other = 1 - (axis % 2)
        line_max = ndi.maximum_filter1d(line_max, size=2 * spread + 1, axis=other,
                                        mode="nearest")
    floor = line_max * 10.0 ** ((sidelobe_db + margin_db) / 10.0)
    return keep & (p >= floor)
