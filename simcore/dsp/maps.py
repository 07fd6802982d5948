"""Maps of one frame: range profiles, range–Doppler, range–azimuth and its bird's-eye image.

Powers are linear ``|X|^2`` of the amplitude-normalised spectra of
:mod:`simcore.dsp.spectrum` (a unit-amplitude tone reads 1, i.e. 0 dB), averaged — not
summed — over channels and snapshots, so integrating more channels does not shift a
target's level. ``*_db`` functions return float32 ``10 log10(power)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.angle import (
    ArrayLayout,
    bartlett_spectrum,
    capon_spectrum,
    fft_beamform,
    interpolate_fft_power,
    spatial_covariance,
    steering_vectors,
)
from simcore.dsp.windows import as_float32, power_to_db
from simcore.jit import kernel
from simcore.scene.dsp_config import AngleMethod


def range_profile_power(range_cube: ArrayLike) -> NDArray[np.float32]:
    """Range profile of every channel, non-coherently averaged over chirps.

    Parameters
    ----------
    range_cube : array_like, shape (chirps, channels, range)
        Output of :func:`simcore.dsp.spectrum.range_fft`.

    Returns
    -------
    power : ndarray, shape (channels, range), float32
        Mean over chirps of ``|X|^2`` (linear).

    Examples
    --------
    >>> cube = np.array([[[1, 2j, 0]], [[1, 0, 0]]])   # 2 chirps, 1 channel, 3 bins
    >>> range_profile_power(cube)
    array([[1., 2., 0.]], dtype=float32)
    """
    x = np.asarray(range_cube)
    return as_float32(np.mean(np.abs(x) ** 2, axis=0))


def range_doppler_power(rd_cube: ArrayLike) -> NDArray[np.float32]:
    """Range–Doppler map, non-coherently averaged over channels.

    Parameters
    ----------
    rd_cube : array_like, shape (doppler, channels, range)
        Output of :func:`simcore.dsp.spectrum.doppler_fft`.

    Returns
    -------
    power : ndarray, shape (doppler, range), float32
        Mean over channels of ``|X|^2`` (linear). Its noise is Gamma(L) distributed with
        ``L = channels`` (the ``n_integrated`` of the CFAR functions).

    Examples
    --------
    >>> rd = np.zeros((4, 2, 3), dtype=complex)   # (doppler, channels, range)
    >>> rd[1, :, 2] = [2.0, 2j]
    >>> range_doppler_power(rd)[1]
    array([0., 0., 4.], dtype=float32)
    """
    x = np.asarray(rd_cube)
    return as_float32(np.mean(np.abs(x) ** 2, axis=1))


def range_azimuth_power(
    rd_cube: ArrayLike,
    layout: ArrayLayout,
    *,
    wavelength_m: float,
    azimuth_rad: ArrayLike,
    method: AngleMethod = "bartlett",
    diagonal_loading: float = 1e-3,
    fft_size: int = 64,
) -> NDArray[np.float32]:
    """Range–azimuth map at zero elevation, averaged over Doppler bins.

    Parameters
    ----------
    rd_cube : array_like, shape (doppler, channels, range)
        Range–Doppler cube, TDM phase already compensated. Its Doppler bins are the
        snapshots of the spatial covariance of each range bin.
    layout : ArrayLayout
        Virtual array (:func:`simcore.dsp.angle.array_layout`).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    azimuth_rad : array_like, shape (n_az,)
        Azimuth grid (rad, positive right).
    method : {"bartlett", "capon", "fft", "monopulse"}, keyword-only
        Spectrum estimator; ``"monopulse"`` gives no map and falls back to Bartlett.
    diagonal_loading : float, keyword-only
        Capon loading relative to the mean element power.
    fft_size : int, keyword-only
        FFT length of the ``"fft"`` method.

    Returns
    -------
    power : ndarray, shape (n_az, range), float32
        Linear power, the mean over snapshots: a unit-amplitude source present in every
        snapshot reads ≈ 1 in its own direction (Bartlett, FFT and Capon alike). With
        Doppler bins as snapshots, multiply by ``(sum w)^2 / sum w^2`` of the Doppler
        window to restore that scale (Parseval; :func:`simcore.dsp.process_frame` does).

    Examples
    --------
    A unit source at +30° azimuth in range bin 1, seen by a λ/2 uniform linear array:

    >>> from simcore.dsp.angle import array_layout, steering_vectors
    >>> ula = np.array([[0.0, 0, 0], [2.5e-3, 0, 0], [5e-3, 0, 0], [7.5e-3, 0, 0]])
    >>> az = np.radians([-30.0, 0.0, 30.0])
    >>> rd = np.zeros((1, 4, 2), dtype=complex)          # (doppler, channels, range)
    >>> rd[0, :, 1] = steering_vectors(ula, wavelength_m=5e-3, azimuth_rad=np.radians(30.0))
    >>> np.round(range_azimuth_power(rd, array_layout(ula), wavelength_m=5e-3, azimuth_rad=az), 3)
    array([[0., 0.],
           [0., 0.],
           [0., 1.]], dtype=float32)
    """
    az = np.asarray(azimuth_rad, dtype=np.float64)
    if method in ("bartlett", "monopulse"):
        # Covariance and spectrum of each range bin in one compiled pass.
        cube = np.asarray(rd_cube)
        if cube.ndim != 3:
            raise ValueError(f"rd_cube must be (doppler, channels, range), got {cube.shape}")
        pairs = _bartlett_pairs(np.asarray(layout.positions_m, dtype=np.float64),
                                float(wavelength_m), az)
        out = np.empty((cube.shape[2], az.size))
        _bartlett_map(np.ascontiguousarray(cube, dtype=np.complex128)
                      if cube.dtype != np.complex64 else np.ascontiguousarray(cube),
                      pairs, out)
        return as_float32(np.maximum(out, 0.0).T)
    x = np.asarray(rd_cube).astype(np.complex128, copy=False)
    if method == "fft":
        snap = np.moveaxis(x, 1, -1)  # (doppler, range, channels)
        spec, _ = fft_beamform(snap, layout, fft_size=fft_size)  # (doppler, range, fft)
        mean_power = np.mean(np.abs(spec) ** 2, axis=0, dtype=np.float64)  # (range, fft)
        p = interpolate_fft_power(mean_power, layout, wavelength_m=wavelength_m,
                                  azimuth_rad=az)
        return as_float32(p.T)
    a = steering_vectors(layout.positions_m, wavelength_m=wavelength_m, azimuth_rad=az)
    cov = spatial_covariance(x)  # (range, ch, ch)
    if method == "capon":
        p = capon_spectrum(cov, a, diagonal_loading=diagonal_loading)
    else:
        p = bartlett_spectrum(cov, a)
    return as_float32(np.maximum(p, 0.0).T)


_BARTLETT_PAIRS: dict[tuple[bytes, float, bytes], NDArray[np.float64]] = {}


def _bartlett_pairs(positions_m: NDArray[np.float64], wavelength_m: float,
                    az: NDArray[np.float64]) -> NDArray[np.float64]:
    """``conj(a_i) a_j`` of every azimuth, cached (read-only).

    Real and imaginary parts, shape (2, M², n_az), pair index ``i * M + j``.
    """
    key = (positions_m.tobytes(), wavelength_m, az.tobytes())
    pairs = _BARTLETT_PAIRS.get(key)
    if pairs is None:
        a = steering_vectors(positions_m, wavelength_m=wavelength_m, azimuth_rad=az)
        m = a.shape[-1]
        c = (np.conj(a)[:, :, None] * a[:, None, :]).reshape(a.shape[0], m * m).T
        pairs = np.ascontiguousarray(np.stack([c.real, c.imag]))
        pairs.setflags(write=False)
        if len(_BARTLETT_PAIRS) > 8:
            _BARTLETT_PAIRS.clear()
        _BARTLETT_PAIRS[key] = pairs
    return pairs


@kernel
def _bartlett_map(x: NDArray[np.complexfloating], pairs: NDArray[np.float64],
                  out: NDArray[np.float64]) -> None:
    """Bartlett power of each range bin and azimuth, Doppler bins as snapshots.

    ``x`` (doppler, M, range); ``pairs`` (2, M², n_az) from :func:`_bartlett_pairs`;
    ``out`` (range, n_az) ``= Re Σ_ij R_ij conj(a_i) a_j / M²`` with the covariance
    ``R = (1/N) Σ_n x_n x_n^H`` (complex128), as
    :func:`~simcore.dsp.angle.spatial_covariance` and
    :func:`~simcore.dsp.angle.bartlett_spectrum`.
    """
    n_snap, m, n_range = x.shape
    r_re = np.empty(m * m)
    r_im = np.empty(m * m)
    for r in range(n_range):
        for i in range(m):
            for j in range(m):
                acc = 0j
                for n in range(n_snap):
                    acc += complex(x[n, i, r]) * complex(x[n, j, r]).conjugate()
                acc = acc / n_snap
                r_re[i * m + j] = acc.real
                r_im[i * m + j] = acc.imag
        for d in range(out.shape[1]):
            out[r, d] = 0.0
        for q in range(m * m):
            for d in range(out.shape[1]):
                out[r, d] += r_re[q] * pairs[0, q, d] - r_im[q] * pairs[1, q, d]
        for d in range(out.shape[1]):
            out[r, d] /= m * m


def bird_eye_axes(
    *, max_range_m: float, max_azimuth_rad: float, resolution_m: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pixel-centre axes of the bird's-eye image.

    Parameters
    ----------
    max_range_m : float, keyword-only
        Largest range shown (m).
    max_azimuth_rad : float, keyword-only
        Largest |azimuth| of the range–azimuth map (rad); sets the lateral extent.
    resolution_m : float, keyword-only
        Pixel size (m).

    Returns
    -------
    x_m : ndarray, shape (nx,), float64
        Lateral axis (radar x, right), symmetric about 0.
    z_m : ndarray, shape (nz,), float64
        Forward axis (boresight z) from 0 to ``max_range_m``.

    Examples
    --------
    The lateral extent is ``max_range * sin(max_azimuth)``, here 2 m × sin 60° = 1.73 m:

    >>> x, z = bird_eye_axes(max_range_m=2.0, max_azimuth_rad=np.radians(60), resolution_m=0.5)
    >>> x
    array([-1.5, -1. , -0.5,  0. ,  0.5,  1. ,  1.5])
    >>> z
    array([0. , 0.5, 1. , 1.5, 2. ])
    """
    half = max_range_m * min(1.0, float(np.sin(min(abs(max_azimuth_rad), np.pi / 2))))
    nx = int(np.floor(half / resolution_m))
    nz = int(np.floor(max_range_m / resolution_m)) + 1
    x = np.arange(-nx, nx + 1, dtype=np.float64) * resolution_m
    z = np.arange(nz, dtype=np.float64) * resolution_m
    return x, z


def bird_eye_image(
    range_azimuth: ArrayLike,
    *,
    range_axis_m: ArrayLike,
    azimuth_axis_rad: ArrayLike,
    x_axis_m: ArrayLike,
    z_axis_m: ArrayLike,
) -> NDArray[np.float32]:
    """Resample a range–azimuth map onto a Cartesian (bird's-eye) grid.

    Parameters
    ----------
    range_azimuth : array_like, shape (n_az, n_range)
        Map on a uniform azimuth grid and a uniform range grid (dB or linear).
    range_axis_m : array_like, shape (n_range,)
        Uniform range axis (m).
    azimuth_axis_rad : array_like, shape (n_az,)
        Uniform azimuth axis (rad).
    x_axis_m, z_axis_m : array_like, shapes (nx,), (nz,)
        Output pixel centres: lateral x (right) and forward z (m).

    Returns
    -------
    image : ndarray, shape (nz, nx), float32
        Bilinear interpolation at ``range = hypot(x, z)``, ``azimuth = atan2(x, z)``; NaN
        outside the map's range or azimuth coverage. Row 0 is z = ``z_axis_m[0]``.

    Examples
    --------
    A map whose value is the range itself reads ``hypot(x, z)``: 4 m straight ahead and 5 m
    at (3 m right, 4 m ahead); beyond the map's 9 m it is NaN.

    >>> r = np.arange(10.0)
    >>> az = np.radians(np.arange(-60.0, 61.0, 10.0))
    >>> ra = np.tile(r, (az.size, 1))                      # (n_az, n_range)
    >>> bird_eye_image(ra, range_axis_m=r, azimuth_axis_rad=az, x_axis_m=[0.0, 3.0, 8.0],
    ...                z_axis_m=[4.0])
    array([[ 4.,  5., nan]], dtype=float32)
    """
    m = np.ascontiguousarray(range_azimuth, dtype=np.float64)
    plan = _bird_eye_plan(np.asarray(range_axis_m, dtype=np.float64),
                          np.asarray(azimuth_axis_rad, dtype=np.float64),
                          np.asarray(x_axis_m, dtype=np.float64),
                          np.asarray(z_axis_m, dtype=np.float64))
    out = np.empty(plan.start.shape[1], dtype=np.float32)
    _bilinear(m, plan.start, plan.weight, out)
    return out.reshape(plan.shape)


@dataclass(frozen=True)
class _BirdEyePlan:
    """Where each bird's-eye pixel samples the range–azimuth map (read-only arrays).

    ``start`` (2, pixels), int64: the map cell (azimuth, range) at or below the pixel's
    fractional index, −1 for pixels outside the coverage; ``weight`` (2, pixels), float64:
    the weight of the cell after it along each axis; ``shape`` (nz, nx).
    """

    start: NDArray[np.int64]
    weight: NDArray[np.float64]
    shape: tuple[int, int]


_BIRD_EYE_PLANS: dict[tuple[bytes, ...], _BirdEyePlan] = {}


def _bird_eye_plan(r_ax: NDArray[np.float64], a_ax: NDArray[np.float64],
                   x_ax: NDArray[np.float64], z_ax: NDArray[np.float64]) -> _BirdEyePlan:
    """The pixels' sampling positions: they depend only on the axes (cached)."""
    key = tuple(v.tobytes() for v in (r_ax, a_ax, x_ax, z_ax))
    plan = _BIRD_EYE_PLANS.get(key)
    if plan is not None:
        return plan
    xx, zz = np.meshgrid(x_ax, z_ax)
    rr = np.hypot(xx, zz)
    aa = np.arctan2(xx, zz)
    dr = r_ax[1] - r_ax[0] if r_ax.size > 1 else 1.0
    da = a_ax[1] - a_ax[0] if a_ax.size > 1 else 1.0
    ir = ((rr - r_ax[0]) / dr).ravel()
    ia = ((aa - a_ax[0]) / da).ravel()
    inside = (ir >= 0) & (ir <= r_ax.size - 1) & (ia >= 0) & (ia <= a_ax.size - 1)
    coords = np.stack([ia, ir])
    start = np.floor(coords)
    weight = coords - start
    start = np.where(inside, start, -1.0).astype(np.int64)
    plan = _BirdEyePlan(start, weight, (z_ax.size, x_ax.size))
    for a in (plan.start, plan.weight):
        a.setflags(write=False)
    if len(_BIRD_EYE_PLANS) > 8:
        _BIRD_EYE_PLANS.clear()
    _BIRD_EYE_PLANS[key] = plan
    return plan


@kernel
def _bilinear(m: NDArray[np.float64], start: NDArray[np.int64], weight: NDArray[np.float64],
              out: NDArray[np.float32]) -> None:
    """Bilinear samples of ``m`` (as :func:`scipy.ndimage.map_coordinates`, ``order=1``).

    The weights and the order of the sums are those of scipy's order-1 spline
    (``w0 = 1 − f``, ``w1 = 1 − w0``; indices clamped at the far edge), so the samples are
    the same numbers. Pixels with ``start`` −1 are NaN.
    """
    n0, n1 = m.shape
    for p in range(out.size):
        i0 = start[0, p]
        j0 = start[1, p]
        if i0 < 0:
            out[p] = np.nan
            continue
        i1 = min(i0 + 1, n0 - 1)
        j1 = min(j0 + 1, n1 - 1)
        wa0 = 1.0 - weight[0, p]
        wa1 = 1.0 - wa0
        wr0 = 1.0 - weight[1, p]
        wr1 = 1.0 - wr0
        t = 0.0
        t += m[i0, j0] * wa0 * wr0
        t += m[i0, j1] * wa0 * wr1
        t += m[i1, j0] * wa1 * wr0
        t += m[i1, j1] * wa1 * wr1
        out[p] = t


__all__ = [
    "bird_eye_axes",
    "bird_eye_image",
    "power_to_db",
    "range_azimuth_power",
    "range_doppler_power",
    "range_profile_power",
]
