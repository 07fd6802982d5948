"""Angle of arrival: array geometry, steering vectors, monopulse, FFT, Bartlett and Capon.

Geometry and sign conventions
-----------------------------
* Element positions are in the radar's optical frame in metres: board x right, y down,
  boresight z (antennas lie in the z = 0 plane). ``RadarConfig`` stores them in mm.
* A far target at azimuth ``az`` (positive towards +x, right) and elevation ``el``
  (positive up, i.e. towards −y) lies in direction
  ``u = (sin az cos el, -sin el, cos az cos el)``.
* The two-way path through Tx at ``p_tx`` and Rx at ``p_rx`` is shorter by
  ``(p_tx + p_rx) . u`` than through the origin, so virtual channel (tx, rx) sees the phase
  ``-2 pi (p_v . u) / lambda`` with the virtual element ``p_v = p_tx + p_rx``.
  Steering vectors are ``a(u) = exp(-j 2 pi P u / lambda)`` (no normalisation).
* Virtual channels are ordered tx-major: ``channel = tx_index * n_rx + rx_index``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.peaks import parabolic_peak_offset
from simcore.dsp.windows import as_complex64
from simcore.jit import kernel
from simcore.scene.dsp_config import AngleMethod
from simcore.scene.radar_config import Antenna, RadarConfig

#: Positions closer than this are treated as equal when grouping rows/columns (m).
POSITION_TOLERANCE_M = 1e-6


def antenna_positions_m(antennas: Sequence[Antenna]) -> NDArray[np.float64]:
    """Positions of antennas in the optical frame.

    Parameters
    ----------
    antennas : sequence of Antenna
        Elements with ``position_mm = (x, y)`` on the board.

    Returns
    -------
    positions : ndarray, shape (n, 3), float64
        ``(x, y, 0)`` in metres.

    Examples
    --------
    >>> from simcore.scene.radar_config import Antenna
    >>> antenna_positions_m([Antenna(position_mm=(2.5, 0.0)), Antenna(position_mm=(0.0, -2.5))])
    array([[ 0.0025,  0.    ,  0.    ],
           [ 0.    , -0.0025,  0.    ]])
    """
    p = np.zeros((len(antennas), 3))
    for i, a in enumerate(antennas):
        p[i, :2] = np.asarray(a.position_mm, dtype=np.float64) * 1e-3
    return p


def virtual_array_positions_m(radar_config: RadarConfig) -> NDArray[np.float64]:
    """Virtual-array element positions ``p_tx + p_rx``, tx-major.

    Parameters
    ----------
    radar_config : RadarConfig
        Uses its ``tx`` and ``rx`` lists.

    Returns
    -------
    positions : ndarray, shape (n_tx * n_rx, 3), float64
        Row ``tx_index * n_rx + rx_index`` (m, optical frame).

    Examples
    --------
    Two Tx 5 mm apart and two Rx 2.5 mm apart make a 4-element virtual row:

    >>> from simcore.scene.radar_arrays import ula
    >>> from simcore.scene.radar_config import RadarConfig
    >>> cfg = RadarConfig(tx=ula(2, 5.0, prefix="tx"), rx=ula(2, 2.5))
    >>> virtual_array_positions_m(cfg)[:, 0] * 1e3
    array([0. , 2.5, 5. , 7.5])
    """
    tx = antenna_positions_m(radar_config.tx)
    rx = antenna_positions_m(radar_config.rx)
    return (tx[:, None, :] + rx[None, :, :]).reshape(-1, 3)


def direction_vectors(azimuth_rad: ArrayLike, elevation_rad: ArrayLike = 0.0) -> NDArray[
    np.float64
]:
    """Unit direction vectors in the optical frame.

    Parameters
    ----------
    azimuth_rad, elevation_rad : array_like, broadcastable
        Angles (rad): azimuth positive right (+x), elevation positive up (−y).

    Returns
    -------
    u : ndarray, shape (*broadcast_shape, 3), float64
        ``(sin az cos el, -sin el, cos az cos el)``.

    Examples
    --------
    >>> np.round(direction_vectors(np.radians([0.0, 30.0])), 3) + 0.0
    array([[0.   , 0.   , 1.   ],
           [0.5  , 0.   , 0.866]])
    >>> np.round(direction_vectors(0.0, np.radians(90.0)), 3) + 0.0   # straight up is -y
    array([ 0., -1.,  0.])
    """
    az, el = np.broadcast_arrays(np.asarray(azimuth_rad, float), np.asarray(elevation_rad, float))
    return np.stack([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)], axis=-1)


def steering_vectors(
    positions_m: ArrayLike,
    *,
    wavelength_m: float,
    azimuth_rad: ArrayLike,
    elevation_rad: ArrayLike = 0.0,
) -> NDArray[np.complex128]:
    """Array response to far targets in the given directions.

    Parameters
    ----------
    positions_m : array_like, shape (channels, 3)
        Virtual-element positions (m, optical frame).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    azimuth_rad, elevation_rad : array_like, keyword-only, broadcastable
        Directions (rad).

    Returns
    -------
    a : ndarray, shape (*broadcast_shape, channels), complex128
        ``exp(-j 2 pi (p . u) / lambda)``.

    Examples
    --------
    A λ/2 uniform linear array and a source at +30°: the phase falls by π/2 per element.

    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> a = steering_vectors(ula, wavelength_m=5e-3, azimuth_rad=np.radians(30.0))
    >>> a.shape, bool(np.allclose(a, [1, -1j, -1, 1j]))
    ((4,), True)
    """
    p = np.asarray(positions_m, dtype=np.float64)
    u = direction_vectors(azimuth_rad, elevation_rad)
    return np.exp(-2j * np.pi * (u @ p.T) / wavelength_m)


@dataclass(frozen=True)
class _GridSteering:
    """Steering vectors of a search grid, in the layouts the estimators use (read-only).

    ``steer`` (n_el * n_az, M), elevation-major; ``steer_h`` = ``steer^H``, (M, n_el * n_az)
    contiguous, for one BLAS product with the snapshots; ``steer_h_re``, ``steer_h_im`` its
    real and imaginary parts (float64), for the compiled Bartlett search.
    """

    steer: NDArray[np.complex128]
    steer_h: NDArray[np.complex128]
    steer_h_re: NDArray[np.float64]
    steer_h_im: NDArray[np.float64]


_GRID_STEERING: dict[tuple[bytes, float, bytes, bytes], _GridSteering] = {}


def _grid_steering(positions_m: NDArray[np.float64], wavelength_m: float,
                   az_grid: NDArray[np.float64], el_grid: NDArray[np.float64]
                   ) -> _GridSteering:
    """Steering vectors of an (elevation × azimuth) search grid.

    Cached, read-only: the grid, the array and the wavelength rarely change between frames.
    """
    key = (np.ascontiguousarray(positions_m).tobytes(), float(wavelength_m),
           az_grid.tobytes(), el_grid.tobytes())
    grid = _GRID_STEERING.get(key)
    if grid is None:
        steer = steering_vectors(positions_m, wavelength_m=wavelength_m,
                                 azimuth_rad=az_grid[None, :], elevation_rad=el_grid[:, None])
        steer = steer.reshape(-1, steer.shape[-1])
        steer_h = np.ascontiguousarray(np.conj(steer).T)
        grid = _GridSteering(steer, steer_h, np.ascontiguousarray(steer_h.real),
                             np.ascontiguousarray(steer_h.imag))
        for a in (grid.steer, grid.steer_h, grid.steer_h_re, grid.steer_h_im):
            a.setflags(write=False)
        if len(_GRID_STEERING) > 8:
            _GRID_STEERING.clear()
        _GRID_STEERING[key] = grid
    return grid


#: Grid directions per block of the compiled Bartlett search (its steering: 48 kB for 3
#: channels, kept in cache while every detection is scanned over it).
_GRID_BLOCK = 1024


@kernel
def _bartlett_grid_peaks(x: NDArray[np.complex128], steer_h_re: NDArray[np.float64],
                         steer_h_im: NDArray[np.float64], n_az: int,
                         out_index: NDArray[np.int64], out_power: NDArray[np.float64]) -> None:
    """Maximum of ``|a^H x|^2`` over a search grid, and the power at its four neighbours.

    Parameters
    ----------
    x : ndarray, shape (n, M), complex128
        Snapshots.
    steer_h_re, steer_h_im : ndarray, shape (M, n_el * n_az), float64
        Real and imaginary parts of ``a^H`` on the grid, elevation-major.
    n_az : int
        Azimuths per elevation row.
    out_index : ndarray, shape (n,), int64
        Flat grid index of the first maximum (as :func:`numpy.argmax`; the first NaN if
        any).
    out_power : ndarray, shape (n, 5), float64
        Power at the maximum, at azimuth −1 and +1, and at elevation −1 and +1 (indices
        clipped to the grid).
    """
    n, m = x.shape
    d = steer_h_re.shape[1]
    n_el = d // n_az
    inf_bits = 0x7FF0000000000000        # +inf; larger int64 patterns are NaNs
    best = np.full(n, -1, dtype=np.int64)
    out_index[:] = 0
    re = np.empty(_GRID_BLOCK)
    im = np.empty(_GRID_BLOCK)
    # A power is ≥ 0 (or NaN), and non-negative doubles order like their bits as int64:
    # the maximum is an integer reduction, which vectorises (a float one does not).
    bits = re.view(np.int64)
    # Blocks of directions in the outer loop: the grid's steering is read once, not once
    # per detection.
    for q0 in range(0, d, _GRID_BLOCK):
        q1 = min(q0 + _GRID_BLOCK, d)
        size = q1 - q0
        for i in range(n):
            if best[i] > inf_bits:
                continue                 # a NaN: the first one is the answer
            re[:size] = 0.0
            im[:size] = 0.0
            for c in range(m):
                xr = x[i, c].real
                xi = x[i, c].imag
                for q in range(q0, q1):
                    re[q - q0] += xr * steer_h_re[c, q] - xi * steer_h_im[c, q]
                    im[q - q0] += xr * steer_h_im[c, q] + xi * steer_h_re[c, q]
            for q in range(size):
                re[q] = re[q] * re[q] + im[q] * im[q]
            top = bits[0]
            for q in range(1, size):
                top = max(top, bits[q])
            if top > inf_bits:
                for q in range(size):
                    if re[q] != re[q]:
                        out_index[i] = q0 + q
                        best[i] = top
                        break
            elif top > best[i]:          # strictly: the first maximum wins
                for q in range(size):
                    if bits[q] == top:
                        out_index[i] = q0 + q
                        best[i] = top
                        break
    for i in range(n):
        i_el, i_az = divmod(out_index[i], n_az)
        cells = (out_index[i], i_el * n_az + max(i_az - 1, 0),
                 i_el * n_az + min(i_az + 1, n_az - 1), max(i_el - 1, 0) * n_az + i_az,
                 min(i_el + 1, n_el - 1) * n_az + i_az)
        for t in range(5):
            out_power[i, t] = _grid_power(x, i, steer_h_re, steer_h_im, cells[t])


@kernel
def _grid_power(x: NDArray[np.complex128], i: int, steer_h_re: NDArray[np.float64],
                steer_h_im: NDArray[np.float64], q: int) -> float:
    """``|a_q^H x_i|^2`` with the operations of :func:`_bartlett_grid_peaks` (same bits)."""
    re = 0.0
    im = 0.0
    for c in range(x.shape[1]):
        xr = x[i, c].real
        xi = x[i, c].imag
        re += xr * steer_h_re[c, q] - xi * steer_h_im[c, q]
        im += xr * steer_h_im[c, q] + xi * steer_h_re[c, q]
    return re * re + im * im


def spatial_covariance(snapshots: ArrayLike) -> NDArray[np.complex128]:
    """Sample covariance over snapshots.

    Parameters
    ----------
    snapshots : array_like, shape (n_snapshots, channels, ...)
        E.g. a range–Doppler cube ``(doppler, channels, range)`` (snapshots = Doppler bins)
        or a range cube ``(chirps, channels, range)``.

    Returns
    -------
    covariance : ndarray, shape (..., channels, channels), complex128
        ``R = (1/N) sum_n x_n x_n^H`` for every trailing index.

    Examples
    --------
    >>> a = np.array([1, -1j, -1, 1j])
    >>> r = spatial_covariance(np.tile(a, (8, 1)))    # 8 snapshots of 4 channels
    >>> r.shape, bool(np.allclose(r, np.outer(a, a.conj())))
    ((4, 4), True)
    """
    x = np.asarray(snapshots).astype(np.complex128, copy=False)
    n = x.shape[0]
    x = np.moveaxis(x, (0, 1), (-1, -2))  # (..., channels, snapshots)
    return (x @ np.conj(np.swapaxes(x, -1, -2))) / n


def bartlett_spectrum(covariance: ArrayLike, steering: ArrayLike) -> NDArray[np.float64]:
    """Bartlett (delay-and-sum) spatial spectrum ``a^H R a / M^2``.

    Parameters
    ----------
    covariance : array_like, shape (..., channels, channels)
        Spatial covariance (:func:`spatial_covariance`).
    steering : array_like, shape (directions, channels)
        Steering vectors (:func:`steering_vectors`), unit-modulus entries.

    Returns
    -------
    power : ndarray, shape (..., directions), float64
        Power of a unit-amplitude source in its own direction reads 1 (plus noise / M).

    Examples
    --------
    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> a = steering_vectors(ula, wavelength_m=5e-3, azimuth_rad=np.radians([-30.0, 0.0, 30.0]))
    >>> r = spatial_covariance(a[2][None, :])          # one unit source at +30°
    >>> np.round(bartlett_spectrum(r, a), 3) + 0.0
    array([0., 0., 1.])
    """
    r = np.asarray(covariance)
    a = np.asarray(steering)
    m = a.shape[-1]
    lead = r.shape[:-2]
    # a^H R a = Re sum_ij R_ij conj(a_i) a_j, a compiled (..., M²) × (M², D) product (no
    # BLAS threads: the map is small, and other chains run beside this one).
    pairs = (np.conj(a)[:, :, None] * a[:, None, :]).reshape(a.shape[0], m * m)
    out = np.empty((int(np.prod(lead)), a.shape[0]))
    _real_product(np.ascontiguousarray(r.reshape(-1, m * m), dtype=np.complex128),
                  np.ascontiguousarray(pairs.T), out)
    return out.reshape(*lead, a.shape[0]) / (m * m)


@kernel
def _real_product(x: NDArray[np.complex128], y: NDArray[np.complex128],
                  out: NDArray[np.float64]) -> None:
    """``out = Re(x @ y)`` for x (n, k) and y (k, d), complex128."""
    n, k = x.shape
    d = y.shape[1]
    for i in range(n):
        for j in range(d):
            out[i, j] = 0.0
        for q in range(k):
            xr = x[i, q].real
            xi = x[i, q].imag
            for j in range(d):
                out[i, j] += xr * y[q, j].real - xi * y[q, j].imag


def capon_spectrum(
    covariance: ArrayLike, steering: ArrayLike, *, diagonal_loading: float = 1e-3
) -> NDArray[np.float64]:
    """Capon / MVDR spatial spectrum ``1 / (a^H (R + d I)^-1 a)``.

    Parameters
    ----------
    covariance : array_like, shape (..., channels, channels)
        Spatial covariance.
    steering : array_like, shape (directions, channels)
        Steering vectors.
    diagonal_loading : float, keyword-only
        ``d`` relative to the mean element power ``trace(R) / M``.

    Returns
    -------
    power : ndarray, shape (..., directions), float64
        Same scale as :func:`bartlett_spectrum` (a unit source reads ≈ 1).

    Examples
    --------
    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> a = steering_vectors(ula, wavelength_m=5e-3, azimuth_rad=np.radians([-30.0, 0.0, 30.0]))
    >>> r = spatial_covariance(a[2][None, :])          # one unit source at +30°
    >>> np.round(capon_spectrum(r, a), 3) + 0.0
    array([0., 0., 1.])
    """
    r_inv = _loaded_inverse(np.asarray(covariance), diagonal_loading)
    a = np.asarray(steering)
    ria = np.einsum("...ij,dj->...di", r_inv, a)
    denom = np.real(np.einsum("di,...di->...d", np.conj(a), ria))
    return 1.0 / np.maximum(denom, np.finfo(np.float64).tiny)


def _loaded_inverse(r: NDArray[np.generic], loading: float) -> NDArray[np.complex128]:
    """Inverse of ``R + loading * trace(R)/M * I`` (batched over leading axes)."""
    r = r.astype(np.complex128, copy=False)
    m = r.shape[-1]
    level = np.real(np.trace(r, axis1=-2, axis2=-1)) / m
    level = np.maximum(level, np.finfo(np.float64).tiny)
    eye = np.eye(m)
    loaded = r + (loading * level)[..., None, None] * eye + 1e-12 * level[..., None, None] * eye
    return np.linalg.inv(loaded)


def monopulse_direction_cosine(
    x_a: ArrayLike, x_b: ArrayLike, *, baseline_m: float, wavelength_m: float
) -> NDArray[np.float64]:
    """Phase-difference (phase-comparison monopulse) direction cosine of a 2-element pair.

    Parameters
    ----------
    x_a, x_b : array_like, same shape
        Complex responses of elements a and b (e.g. one range–Doppler cell each).
    baseline_m : float, keyword-only
        Signed length of ``p_a - p_b`` along the axis of interest (m).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).

    Returns
    -------
    cosine : ndarray, float64
        ``(p_a - p_b) . u / |p_a - p_b|``, from the phase of ``x_a conj(x_b)``, clipped to
        [-1, 1]; unambiguous when ``|baseline| ≤ lambda / 2``. For a horizontal pair this is
        ``sin(az) cos(el)``; for a vertical pair (baseline along +y) it is ``-sin(el)``.

    Examples
    --------
    Element a, 2.5 mm right of element b (λ = 5 mm), lags by π/2: ``sin(az) = 0.5``.

    >>> round(float(monopulse_direction_cosine(-1j, 1.0, baseline_m=2.5e-3,
    ...                                        wavelength_m=5e-3)), 6)
    0.5
    """
    phase = np.angle(np.asarray(x_a) * np.conj(np.asarray(x_b)))
    cos = -phase * wavelength_m / (2.0 * np.pi * baseline_m)
    return np.clip(cos, -1.0, 1.0)


def monopulse_azimuth_rad(
    x_a: ArrayLike, x_b: ArrayLike, *, baseline_m: float, wavelength_m: float
) -> NDArray[np.float64]:
    """Azimuth from a horizontal 2-Rx pair, assuming zero elevation.

    Parameters
    ----------
    x_a, x_b : array_like, same shape
        Complex responses of elements a and b.
    baseline_m : float, keyword-only
        ``x_a - x_b`` element x-positions (m), signed.
    wavelength_m : float, keyword-only
        Carrier wavelength (m).

    Returns
    -------
    azimuth : ndarray, float64
        ``arcsin(-angle(x_a conj x_b) lambda / (2 pi d))`` (rad, positive right).

    Examples
    --------
    >>> az = monopulse_azimuth_rad(-1j, 1.0, baseline_m=2.5e-3, wavelength_m=5e-3)
    >>> round(float(np.degrees(az)), 6)
    30.0
    """
    return np.arcsin(
        monopulse_direction_cosine(x_a, x_b, baseline_m=baseline_m, wavelength_m=wavelength_m)
    )


@dataclass(frozen=True)
class ArrayLayout:
    """What the angle estimators need to know about a virtual array.

    Attributes
    ----------
    positions_m : ndarray, shape (channels, 3)
        Virtual-element positions (m, optical frame).
    horizontal_pairs : ndarray, shape (n, 2), int
        Channel index pairs (a, b) with equal y and the smallest non-zero x spacing, with
        ``x_a > x_b``.
    horizontal_spacing_m : float
        That spacing (0 when there is no horizontal pair).
    vertical_pairs : ndarray, shape (n, 2), int
        Pairs with equal x and the smallest non-zero y spacing, ``y_a > y_b`` (a below b).
    vertical_spacing_m : float
        That spacing (0 when there is no vertical pair).
    row_channels : ndarray, shape (k,), int
        Channels of the uniform horizontal row used by FFT beamforming.
    row_slots : ndarray, shape (k,), int
        Slot of each such channel on the uniform grid ``x0 + slot * row_spacing_m``
        (duplicated positions share a slot).
    row_spacing_m : float
        Grid spacing of that row (0 when there is no row of ≥ 2 distinct elements).
    """

    positions_m: NDArray[np.float64]
    horizontal_pairs: NDArray[np.int64]
    horizontal_spacing_m: float
    vertical_pairs: NDArray[np.int64]
    vertical_spacing_m: float
    row_channels: NDArray[np.int64]
    row_slots: NDArray[np.int64]
    row_spacing_m: float

    @property
    def has_horizontal_extent(self) -> bool:
        """Elements differ in x: azimuth is observable."""
        return bool(np.ptp(self.positions_m[:, 0]) > POSITION_TOLERANCE_M)

    @property
    def has_vertical_extent(self) -> bool:
        """Elements differ in y: elevation is observable."""
        return bool(np.ptp(self.positions_m[:, 1]) > POSITION_TOLERANCE_M)


def array_layout(positions_m: ArrayLike) -> ArrayLayout:
    """Analyse a virtual array: closest horizontal/vertical pairs and the uniform row.

    Parameters
    ----------
    positions_m : array_like, shape (channels, 3)
        Virtual-element positions (m, optical frame).

    Returns
    -------
    ArrayLayout

    Examples
    --------
    The BGT60TR13C-like L of three Rx (λ/2 = 2.5 mm):

    >>> p = np.array([[2.5e-3, 0, 0], [0.0, 0, 0], [0.0, -2.5e-3, 0]])
    >>> layout = array_layout(p)
    >>> layout.horizontal_pairs, layout.horizontal_spacing_m
    (array([[0, 1]]), 0.0025)
    >>> layout.vertical_pairs, layout.vertical_spacing_m
    (array([[1, 2]]), 0.0025)
    >>> layout.row_channels, layout.row_slots
    (array([1, 0]), array([0, 1]))
    """
    p = np.asarray(positions_m, dtype=np.float64)
    tol = POSITION_TOLERANCE_M
    h_pairs, h_d = _closest_pairs(p, along=0, across=1, tol=tol)
    v_pairs, v_d = _closest_pairs(p, along=1, across=0, tol=tol)

    # Uniform row: the y-row with the most distinct x positions, on a grid of its min spacing.
    rows: dict[int, list[int]] = {}
    for i, y in enumerate(p[:, 1]):
        rows.setdefault(int(np.round(y / tol)), []).append(i)
    best: list[int] = []
    best_distinct = 0
    for members in rows.values():
        distinct = len(np.unique(np.round(p[members, 0] / tol)))
        if distinct > best_distinct:
            best, best_distinct = members, distinct
    row_ch = np.asarray(sorted(best, key=lambda i: p[i, 0]), dtype=np.int64)
    row_slots = np.zeros(0, dtype=np.int64)
    row_d = 0.0
    if row_ch.size:
        xs = p[row_ch, 0]
        diffs = np.diff(xs)
        diffs = diffs[diffs > tol]
        if diffs.size:
            d = float(np.min(diffs))
            slots = np.round((xs - xs[0]) / d)
            if np.allclose(slots * d, xs - xs[0], atol=1e-3 * d + tol):
                row_d = d
                row_slots = slots.astype(np.int64)
    if row_d == 0.0:
        row_ch = np.zeros(0, dtype=np.int64)
    return ArrayLayout(p, h_pairs, h_d, v_pairs, v_d, row_ch, row_slots, row_d)


def _closest_pairs(p: NDArray[np.float64], *, along: int, across: int, tol: float) -> tuple[
    NDArray[np.int64], float
]:
    """Pairs with equal ``across`` coordinate and the smallest non-zero ``along`` spacing."""
    n = p.shape[0]
    best = np.inf
    pairs: list[tuple[int, int]] = []
    for i in range(n):
        for j in range(n):
            if abs(p[i, across] - p[j, across]) > tol:
                continue
            d = p[i, along] - p[j, along]
            if d <= tol:
                continue
            if d < best - tol:
                best, pairs = d, [(i, j)]
            elif abs(d - best) <= tol:
                pairs.append((i, j))
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64), 0.0
    return np.asarray(pairs, dtype=np.int64), float(best)


def fft_beamform(
    snapshots: ArrayLike, layout: ArrayLayout, *, fft_size: int = 64
) -> tuple[NDArray[np.complex64], NDArray[np.float64]]:
    """FFT beamforming over the uniform horizontal row of the virtual array.

    Parameters
    ----------
    snapshots : array_like, shape (..., channels)
        Complex channel responses (channel axis last).
    layout : ArrayLayout
        From :func:`array_layout`; needs a uniform row (``row_spacing_m > 0``).
    fft_size : int, keyword-only
        Zero-padded FFT length over the row.

    Returns
    -------
    spectrum : ndarray, shape (..., fft_size), complex64
        Fft-shifted spatial spectrum, normalised by the number of row elements.
    spatial_frequency : ndarray, shape (fft_size,), float64
        Cycles per element ``f`` of each bin, in [-0.5, 0.5); the direction cosine is
        ``sin(az) cos(el) = -f * lambda / row_spacing_m``.

    Examples
    --------
    A source at +30° on a λ/2 row sits at -0.25 cycles per element, with amplitude 1:

    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> spec, f = fft_beamform(np.array([1, -1j, -1, 1j]), array_layout(ula), fft_size=8)
    >>> float(f[np.argmax(np.abs(spec))]), round(float(np.abs(spec).max()), 6)
    (-0.25, 1.0)
    """
    if layout.row_spacing_m <= 0.0:
        raise ValueError(
            "FFT beamforming needs a uniform horizontal row of at least 2 distinct virtual "
            "elements; use angle_method='bartlett' or 'capon' for this array"
        )
    x = np.asarray(snapshots)
    n_slots = int(layout.row_slots.max()) + 1
    if fft_size < n_slots:
        raise ValueError(f"angle fft_size {fft_size} < {n_slots} row slots")
    grid = np.zeros((*x.shape[:-1], n_slots), dtype=np.complex128)
    count = np.zeros(n_slots)
    for ch, slot in zip(layout.row_channels, layout.row_slots, strict=True):
        grid[..., slot] += x[..., ch]
        count[slot] += 1
    grid /= np.maximum(count, 1)
    n_used = int(np.count_nonzero(count))
    spec = np.fft.fftshift(np.fft.fft(grid, n=fft_size, axis=-1), axes=-1) / n_used
    freq = np.fft.fftshift(np.fft.fftfreq(fft_size))
    return as_complex64(spec), freq


def fft_azimuth_power(
    snapshots: ArrayLike,
    layout: ArrayLayout,
    *,
    wavelength_m: float,
    azimuth_rad: ArrayLike,
    fft_size: int = 64,
) -> NDArray[np.float64]:
    """Power of the FFT beamformer at given azimuths (zero elevation), by interpolation.

    Parameters
    ----------
    snapshots : array_like, shape (..., channels)
        Complex channel responses (channel axis last).
    layout : ArrayLayout
        Array description with a uniform row.
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    azimuth_rad : array_like, shape (n_az,)
        Output grid (rad).
    fft_size : int, keyword-only
        Zero-padded FFT length.

    Returns
    -------
    power : ndarray, shape (..., n_az), float64
        ``|spectrum|^2`` linearly interpolated (circularly) at
        ``f = -sin(az) * row_spacing / lambda``; directions outside the row's
        unambiguous interval alias, as they physically do.

    Examples
    --------
    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> x = np.array([1, -1j, -1, 1j])                 # unit source at +30°
    >>> p = fft_azimuth_power(x, array_layout(ula), wavelength_m=5e-3,
    ...                       azimuth_rad=np.radians([0.0, 30.0]), fft_size=8)
    >>> np.round(p, 3) + 0.0
    array([0., 1.])
    """
    spec, _ = fft_beamform(snapshots, layout, fft_size=fft_size)
    power = np.abs(spec.astype(np.complex128)) ** 2
    return interpolate_fft_power(power, layout, wavelength_m=wavelength_m,
                                 azimuth_rad=azimuth_rad)


def interpolate_fft_power(
    power: ArrayLike, layout: ArrayLayout, *, wavelength_m: float, azimuth_rad: ArrayLike
) -> NDArray[np.float64]:
    """Sample an fft-shifted spatial power spectrum at given azimuths (zero elevation).

    Parameters
    ----------
    power : array_like, shape (..., fft_size)
        ``|spectrum|^2`` from :func:`fft_beamform` (possibly averaged over snapshots).
    layout : ArrayLayout
        Array description with a uniform row.
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    azimuth_rad : array_like, shape (n_az,)
        Output grid (rad).

    Returns
    -------
    ndarray, shape (..., n_az), float64
        Circular linear interpolation at ``f = -sin(az) * row_spacing / lambda``.

    Examples
    --------
    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> layout = array_layout(ula)
    >>> spec, _ = fft_beamform(np.array([1, -1j, -1, 1j]), layout, fft_size=8)
    >>> p = interpolate_fft_power(np.abs(spec) ** 2, layout, wavelength_m=5e-3,
    ...                           azimuth_rad=np.radians([0.0, 30.0]))
    >>> np.round(p, 3) + 0.0
    array([0., 1.])
    """
    p = np.asarray(power, dtype=np.float64)
    n = p.shape[-1]
    f = -np.sin(np.asarray(azimuth_rad, dtype=np.float64)) * layout.row_spacing_m / wavelength_m
    pos = (f * n + n // 2) % n  # fractional index into the shifted spectrum
    i0 = np.floor(pos).astype(np.int64)
    frac = pos - i0
    i1 = (i0 + 1) % n
    return p[..., i0] * (1.0 - frac) + p[..., i1] * frac


def _refine_grid_peak(power_db: NDArray[np.float64], idx: NDArray[np.int64], axis_vals:
                      NDArray[np.float64]) -> NDArray[np.float64]:
    """Parabolic refinement of 1-D peaks ``idx`` along the last axis of ``power_db``."""
    n = power_db.shape[-1]
    rows = np.arange(power_db.shape[0])
    if n < 3:
        return axis_vals[idx]
    i_l = np.clip(idx - 1, 0, n - 1)
    i_r = np.clip(idx + 1, 0, n - 1)
    return _refine_peak_3(power_db[rows, i_l], power_db[rows, idx], power_db[rows, i_r], idx,
                          axis_vals)


def _refine_peak_3(left_db: NDArray[np.float64], mid_db: NDArray[np.float64],
                   right_db: NDArray[np.float64], idx: NDArray[np.int64],
                   axis_vals: NDArray[np.float64]) -> NDArray[np.float64]:
    """Parabolic refinement of peaks ``idx`` on a uniform axis from three values (dB).

    The values are those at the peak and at its (clipped) neighbours; no offset at the
    ends of the axis.
    """
    n = axis_vals.size
    if n < 3:
        return axis_vals[idx]
    inner = (idx > 0) & (idx < n - 1)
    off = np.where(inner, parabolic_peak_offset(left_db, mid_db, right_db), 0.0)
    step = axis_vals[1] - axis_vals[0]
    return axis_vals[idx] + off * step


def estimate_angles(
    snapshots: ArrayLike,
    layout: ArrayLayout,
    *,
    wavelength_m: float,
    method: AngleMethod = "bartlett",
    azimuth_grid_rad: ArrayLike,
    elevation_grid_rad: ArrayLike,
    covariances: ArrayLike | None = None,
    diagonal_loading: float = 1e-3,
    fft_size: int = 64,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Azimuth and elevation of single targets from their channel responses.

    Parameters
    ----------
    snapshots : array_like, shape (n, channels)
        Complex response of each target (e.g. its range–Doppler cell on every channel,
        TDM phase already compensated).
    layout : ArrayLayout
        Virtual array (:func:`array_layout`).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    method : {"monopulse", "fft", "bartlett", "capon"}, keyword-only
        ``monopulse``: phase of the closest horizontal pair(s) gives ``sin az cos el``, of
        the closest vertical pair(s) ``sin el``. ``fft``: peak of the zero-padded FFT over
        the uniform row, elevation by vertical monopulse. ``bartlett``: maximum of
        ``|a^H x|^2`` over the (azimuth × elevation) grid. ``capon``: maximum of
        ``|w^H x|^2`` with the MVDR weights ``w = R^-1 a / (a^H R^-1 a)`` from
        ``covariances``. Grid maxima are refined by parabolic interpolation.
    azimuth_grid_rad, elevation_grid_rad : array_like, keyword-only, shape (n_az,), (n_el,)
        Uniform search grids (rad). Elevation is searched only when the array has
        vertical extent, otherwise it is reported as 0.
    covariances : array_like, shape (n, channels, channels), keyword-only
        Spatial covariance for each target (Capon only), e.g. over the Doppler bins of
        its range bin.
    diagonal_loading : float, keyword-only
        Capon diagonal loading relative to the mean element power.
    fft_size : int, keyword-only
        FFT length for ``method="fft"``.

    Returns
    -------
    azimuth_rad, elevation_rad : ndarray, shape (n,), float64
    """
    x = np.asarray(snapshots).astype(np.complex128, copy=False)
    n = x.shape[0]
    if n == 0:
        return np.zeros(n), np.zeros(n)
    if method in ("monopulse", "fft"):
        return _phase_angles(x, layout, wavelength_m=wavelength_m, method=method,
                             fft_size=fft_size)
    az_grid = np.asarray(azimuth_grid_rad, dtype=np.float64)
    el_grid = np.asarray(elevation_grid_rad, dtype=np.float64)
    if not layout.has_horizontal_extent:
        az_grid = np.zeros(1)
    if not layout.has_vertical_extent:
        el_grid = np.zeros(1)
    grid = _grid_steering(np.asarray(layout.positions_m, dtype=np.float64), wavelength_m,
                          az_grid, el_grid)
    if method == "bartlett":
        return _bartlett_angles(x, grid, az_grid, el_grid)
    if method != "capon":
        raise ValueError(f"unknown angle method {method!r}")
    if covariances is None:
        raise ValueError("Capon angle estimation needs the covariances")
    return _capon_angles(x, np.asarray(covariances), grid, az_grid, el_grid,
                         diagonal_loading=diagonal_loading)


def _db(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Power in dB, floored at 1e-300 before the logarithm."""
    return 10.0 * np.log10(np.maximum(p, 1e-300))


def _pair_phase(x: NDArray[np.complex128], pairs: NDArray[np.int64]) -> NDArray[np.complex128]:
    """Sum over element ``pairs`` (k, 2) of ``x[:, a] * conj(x[:, b])``, per snapshot."""
    a, b = pairs[:, 0], pairs[:, 1]
    return np.sum(x[:, a] * np.conj(x[:, b]), axis=1)


def _phase_angles(x: NDArray[np.complex128], layout: ArrayLayout, *, wavelength_m: float,
                  method: AngleMethod, fft_size: int) -> tuple[NDArray[np.float64],
                                                              NDArray[np.float64]]:
    """Monopulse or FFT angles: elevation by vertical monopulse, then azimuth."""
    n = x.shape[0]
    el = np.zeros(n)
    if layout.vertical_pairs.size:
        z = _pair_phase(x, layout.vertical_pairs)
        u_y = monopulse_direction_cosine(z, np.ones_like(z),
                                         baseline_m=layout.vertical_spacing_m,
                                         wavelength_m=wavelength_m)
        el = np.arcsin(-u_y)
    if method == "monopulse":
        if not layout.horizontal_pairs.size:
            return np.zeros(n), el
        z = _pair_phase(x, layout.horizontal_pairs)
        u_x = monopulse_direction_cosine(z, np.ones_like(z),
                                         baseline_m=layout.horizontal_spacing_m,
                                         wavelength_m=wavelength_m)
    else:
        u_x = _fft_direction_cosine(x, layout, wavelength_m=wavelength_m, fft_size=fft_size)
    cos_el = np.maximum(np.cos(el), 1e-9)
    az = np.arcsin(np.clip(u_x / cos_el, -1.0, 1.0))
    return az, el


def _fft_direction_cosine(x: NDArray[np.complex128], layout: ArrayLayout, *,
                          wavelength_m: float, fft_size: int) -> NDArray[np.float64]:
    """``sin az cos el`` from the refined peak of the zero-padded FFT over the row."""
    spec, freq = fft_beamform(x, layout, fft_size=fft_size)
    p_db = 10.0 * np.log10(np.maximum(np.abs(spec.astype(np.complex128)) ** 2, 1e-300))
    k = np.argmax(p_db, axis=1)
    f = _refine_grid_peak(p_db, k, freq)
    u_x: NDArray[np.float64] = -f * wavelength_m / layout.row_spacing_m
    return u_x


def _bartlett_angles(x: NDArray[np.complex128], grid: _GridSteering,
                     az_grid: NDArray[np.float64], el_grid: NDArray[np.float64]) -> tuple[
        NDArray[np.float64], NDArray[np.float64]]:
    """Maximum of the Bartlett spectrum over the grid, refined along both cuts."""
    n = x.shape[0]
    # Compiled search: the maximum and its four neighbours, no (n, grid) temporaries.
    flat = np.empty(n, dtype=np.int64)
    cut = np.empty((n, 5))
    _bartlett_grid_peaks(np.ascontiguousarray(x), grid.steer_h_re, grid.steer_h_im,
                         az_grid.size, flat, cut)
    i_el, i_az = np.divmod(flat, az_grid.size)
    cut_db = _db(cut)
    az = _refine_peak_3(cut_db[:, 1], cut_db[:, 0], cut_db[:, 2], i_az, az_grid)
    el = _refine_peak_3(cut_db[:, 3], cut_db[:, 0], cut_db[:, 4], i_el, el_grid)
    return az, el


def _capon_angles(x: NDArray[np.complex128], covariances: NDArray[np.generic],
                  grid: _GridSteering, az_grid: NDArray[np.float64],
                  el_grid: NDArray[np.float64], *, diagonal_loading: float) -> tuple[
        NDArray[np.float64], NDArray[np.float64]]:
    """Maximum of the Capon (MVDR) spectrum over the grid, refined along both cuts."""
    n = x.shape[0]
    steer = grid.steer  # (n_el * n_az, channels), elevation-major
    r_inv = _loaded_inverse(covariances, diagonal_loading)  # (n, M, M)
    ria = np.einsum("nij,dj->ndi", r_inv, steer)
    denom = np.real(np.einsum("di,ndi->nd", np.conj(steer), ria))
    w = ria / np.maximum(denom, 1e-300)[..., None]  # (n, dirs, M)
    resp = np.einsum("ndi,ni->nd", np.conj(w), x)
    power = (resp.real * resp.real + resp.imag * resp.imag).reshape(
        n, el_grid.size, az_grid.size)
    # The maximum of the power is that of its dB; dB only on the two cuts refined.
    flat = np.argmax(power.reshape(n, -1), axis=1)
    i_el, i_az = np.unravel_index(flat, (el_grid.size, az_grid.size))
    rows = np.arange(n)
    az = _refine_grid_peak(_db(power[rows, i_el, :]), i_az.astype(np.int64), az_grid)
    el = _refine_grid_peak(_db(power[rows, :, i_az]), i_el.astype(np.int64), el_grid)
    return az, el


def secondary_azimuth_peaks(
    snapshots: ArrayLike,
    positions_m: ArrayLike,
    *,
    wavelength_m: float,
    azimuth_grid_rad: ArrayLike,
    elevation_rad: ArrayLike,
    within_db: float,
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """Further targets in the same range–Doppler cell: other peaks of the azimuth spectrum.

    Two targets at one range and velocity share a range–Doppler cell; the array still
    separates them when they are farther apart in ``sin az`` than about ``2 / N`` (λ/2
    row of ``N`` elements). Each snapshot's Bartlett spectrum ``|a^H x|^2`` along azimuth
    (at that snapshot's elevation) is searched for local maxima other than its largest
    one, within ``within_db`` of it. A lone target's sidelobes (−13 dB for a uniform
    row) stay below any ``within_db`` < 13 dB.

    Parameters
    ----------
    snapshots : array_like, shape (n, channels)
        Complex response of each detected cell (TDM phase compensated).
    positions_m : array_like, shape (channels, 3)
        Virtual-element positions (m, optical frame).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    azimuth_grid_rad : array_like, shape (n_az,), keyword-only
        Uniform azimuth search grid (rad).
    elevation_rad : array_like, shape (n,), keyword-only
        Elevation of each snapshot's main target (rad).
    within_db : float, keyword-only
        How far below the largest peak a further peak may be (dB).

    Returns
    -------
    index : ndarray, shape (m,), int64
        Snapshot each further peak belongs to.
    azimuth_rad : ndarray, shape (m,), float64
        Its azimuth, refined by parabolic interpolation (rad).
    relative_db : ndarray, shape (m,), float64
        Its spectrum level relative to the snapshot's largest peak (dB, ≤ 0).

    Examples
    --------
    Two equal sources at ±20° on an 8-element λ/2 ULA: the largest peak is one of them,
    the further peak the other.

    >>> p = np.zeros((8, 3)); p[:, 0] = np.arange(8) * 2.5e-3
    >>> grid = np.radians(np.arange(-80.0, 80.5, 0.5))
    >>> x = sum(steering_vectors(p, wavelength_m=5e-3, azimuth_rad=np.radians(a))
    ...         for a in (-20.0, 20.0))[None, :]
    >>> idx, az, rel = secondary_azimuth_peaks(x, p, wavelength_m=5e-3,
    ...                                        azimuth_grid_rad=grid, elevation_rad=0.0,
    ...                                        within_db=6.0)
    >>> idx.tolist(), bool(abs(abs(np.degrees(az[0])) - 20.0) < 1.0)
    ([0], True)
    """
    x = np.asarray(snapshots).astype(np.complex128, copy=False)
    grid = np.asarray(azimuth_grid_rad, dtype=np.float64)
    el = np.broadcast_to(np.asarray(elevation_rad, dtype=np.float64), (x.shape[0],))
    if x.shape[0] == 0 or grid.size < 3:
        return np.zeros(0, np.int64), np.zeros(0), np.zeros(0)
    p_db = _azimuth_spectrum_db(x, positions_m, wavelength_m=wavelength_m, grid=grid,
                                elevation_rad=el)
    top = np.max(p_db, axis=1, keepdims=True)
    rows, cols = _further_peaks(p_db, top, within_db=within_db)
    az = _refine_grid_peak(p_db[rows], cols.astype(np.int64), grid)
    return rows.astype(np.int64), az, (p_db[rows, cols] - top[rows, 0])


def _azimuth_spectrum_db(x: NDArray[np.complex128], positions_m: ArrayLike, *,
                         wavelength_m: float, grid: NDArray[np.float64],
                         elevation_rad: NDArray[np.float64]) -> NDArray[np.float64]:
    """Bartlett spectrum ``|a^H x|^2`` (dB), shape (n, n_az), at each snapshot's elevation."""
    # In chunks of snapshots: the steering block is (chunk, n_az, channels).
    chunk = max(1, 2_000_000 // max(1, grid.size * x.shape[1]))
    resp = np.empty((x.shape[0], grid.size), dtype=np.complex128)
    for lo in range(0, x.shape[0], chunk):
        steer = steering_vectors(positions_m, wavelength_m=wavelength_m,
                                 azimuth_rad=grid[None, :],
                                 elevation_rad=elevation_rad[lo:lo + chunk, None])
        resp[lo:lo + chunk] = np.einsum("nai,ni->na", np.conj(steer), x[lo:lo + chunk])
    p_db: NDArray[np.float64] = 10.0 * np.log10(np.maximum(np.abs(resp) ** 2, 1e-300))
    return p_db


def _further_peaks(p_db: NDArray[np.float64], top: NDArray[np.float64], *,
                   within_db: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(row, column) of interior local maxima within ``within_db`` of ``top``, not the top."""
    mid = p_db[:, 1:-1]
    is_max = (mid > p_db[:, :-2]) & (mid >= p_db[:, 2:])
    rel = mid - top
    is_max &= rel >= -within_db
    best = np.argmax(p_db, axis=1) - 1  # the largest peak, as an index of ``mid``
    inner = (best >= 0) & (best < mid.shape[1])
    is_max[np.flatnonzero(inner), best[inner]] = False
    rows, cols = np.nonzero(is_max)
    return rows, cols + 1
