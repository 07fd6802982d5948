"""Range and Doppler FFTs of an FMCW ADC cube, with their physical axes.

Conventions
-----------
* ADC cube: shape ``(chirps, channels, samples)``; real IF (float) or complex IQ. For
  TDM-MIMO the channel axis holds the ``n_tx * n_rx`` virtual channels, tx-major.
* Beat frequency ``f_b = 2 K R / c``; complex IQ is ``exp(+j phase)``, so a target at range
  ``R`` lands in bin ``f_b * fft_size / f_s`` (IQ: all ``fft_size`` bins cover
  ``[0, f_s)``; real IF: the first ``fft_size // 2`` bins cover ``[0, f_s / 2)``).
* Amplitude scaling: spectra are divided by the window sum, and real-IF spectra are
  doubled, so a tone ``A cos(...)`` (real) or ``A exp(j ...)`` (IQ) reads ``|X| = A`` at
  its bin and the Doppler FFT keeps that scale (``|X| = A`` for a constant-velocity
  target).
* Velocity: the carrier phase ``4 pi R / lambda`` grows from chirp to chirp for a target
  moving away, so it lands at a positive Doppler frequency: **velocity > 0 = moving
  away**. The Doppler axis is fft-shifted: bin ``fft_size // 2`` is zero velocity.
"""

from __future__ import annotations

import numpy as np
import scipy.fft
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.windows import as_complex64, make_window, next_pow2
from simcore.scene.dsp_config import WindowName
from simcore.scene.radar_config import SPEED_OF_LIGHT


def range_fft_size(samples_per_chirp: int, fft_size: int | None = None) -> int:
    """FFT length of the range transform: ``fft_size`` or the next power of two ≥ samples.

    Examples
    --------
    >>> range_fft_size(300), range_fft_size(512), range_fft_size(300, 1024)
    (512, 512, 1024)
    """
    n = next_pow2(samples_per_chirp) if fft_size is None else int(fft_size)
    if n < samples_per_chirp:
        raise ValueError(f"range fft_size {n} is shorter than {samples_per_chirp} samples")
    return n


def doppler_fft_size(chirps: int, fft_size: int | None = None) -> int:
    """FFT length of the Doppler transform: ``fft_size`` or 2 × next power of two ≥ chirps.

    Examples
    --------
    >>> doppler_fft_size(16), doppler_fft_size(16, 64)
    (32, 64)
    """
    n = 2 * next_pow2(chirps) if fft_size is None else int(fft_size)
    if n < chirps:
        raise ValueError(f"doppler fft_size {n} is shorter than {chirps} chirps")
    return n


def range_bin_count(fft_size: int, *, complex_iq: bool) -> int:
    """Number of non-redundant range bins: ``fft_size`` (IQ) or ``fft_size // 2`` (real).

    Examples
    --------
    >>> range_bin_count(512, complex_iq=False), range_bin_count(512, complex_iq=True)
    (256, 512)
    """
    return fft_size if complex_iq else fft_size // 2


def range_axis_m(
    *, n_bins: int, fft_size: int, sample_rate_hz: float, slope_hz_per_s: float
) -> NDArray[np.float64]:
    """Range of each range bin.

    Parameters
    ----------
    n_bins : int
        Number of bins kept (from bin 0).
    fft_size : int
        Length of the range FFT.
    sample_rate_hz : float
        ADC sampling rate (Hz).
    slope_hz_per_s : float
        Chirp slope K (Hz/s).

    Returns
    -------
    range_m : ndarray, shape (n_bins,), float64
        ``k * f_s / fft_size * c / (2 K)`` (m).

    Examples
    --------
    Without zero padding the bins are ``c / (2 B)`` apart; here 512 samples at 2 MHz sweep
    B = 6 GHz, so 2.498 cm:

    >>> r = range_axis_m(n_bins=4, fft_size=512, sample_rate_hz=2e6, slope_hz_per_s=6e9 / 256e-6)
    >>> np.round(r * 100, 3)
    array([0.   , 2.498, 4.997, 7.495])
    """
    beat_hz = np.arange(n_bins, dtype=np.float64) * (sample_rate_hz / fft_size)
    return beat_hz * SPEED_OF_LIGHT / (2.0 * slope_hz_per_s)


def velocity_axis_mps(
    *, fft_size: int, chirp_interval_s: float, wavelength_m: float
) -> NDArray[np.float64]:
    """Radial velocity of each (fft-shifted) Doppler bin.

    Parameters
    ----------
    fft_size : int
        Length of the Doppler FFT.
    chirp_interval_s : float
        Time between two chirps of the same Tx (s): ``n_tx * chirp_repetition_time_s``.
    wavelength_m : float
        Carrier wavelength (m).

    Returns
    -------
    velocity_mps : ndarray, shape (fft_size,), float64
        ``f_d * lambda / 2`` for the fft-shifted Doppler frequencies ``f_d``; increasing,
        from ``-lambda / (4 T)`` to just below ``+lambda / (4 T)``. Positive = moving away.

    Examples
    --------
    >>> velocity_axis_mps(fft_size=4, chirp_interval_s=1e-4, wavelength_m=5e-3)
    array([-12.5 ,  -6.25,   0.  ,   6.25])
    """
    f_d = np.fft.fftshift(np.fft.fftfreq(fft_size, d=chirp_interval_s))
    return f_d * (wavelength_m / 2.0)


def range_fft(
    cube: ArrayLike,
    *,
    window: WindowName = "hann",
    sidelobe_db: float = 80.0,
    fft_size: int | None = None,
    remove_dc: bool = True,
    n_bins: int | None = None,
) -> NDArray[np.complex64]:
    """Range FFT along fast time.

    Parameters
    ----------
    cube : array_like, shape (chirps, channels, samples)
        ADC samples, real (IF) or complex (IQ).
    window : str, keyword-only
        Fast-time window (see :func:`simcore.dsp.windows.make_window`).
    sidelobe_db : float, keyword-only
        Sidelobe level of a Chebyshev window (dB).
    fft_size : int or None, keyword-only
        FFT length (zero padding); ``None``: next power of two ≥ samples.
    remove_dc : bool, keyword-only
        Subtract each chirp's mean over fast time before windowing (ADC offset).
    n_bins : int or None, keyword-only
        Keep only the first ``n_bins`` bins (e.g. up to a maximum range); ``None`` keeps the
        non-redundant bins (``fft_size // 2`` real, ``fft_size`` complex).

    Returns
    -------
    spectrum : ndarray, shape (chirps, channels, n_bins), complex64
        Axes (chirp, channel, range bin); amplitude-normalised (module docstring).

    Examples
    --------
    A unit-amplitude IQ tone at bin 8 of 64 reads amplitude 1 in bin 8:

    >>> n = np.arange(64)
    >>> cube = np.exp(2j * np.pi * 8 * n / 64).reshape(1, 1, 64)
    >>> spec = range_fft(cube)
    >>> spec.shape, int(np.argmax(np.abs(spec[0, 0])))
    ((1, 1, 64), 8)
    >>> round(float(np.abs(spec[0, 0, 8])), 4)
    1.0
    """
    x = np.asarray(cube)
    if x.ndim != 3:
        raise ValueError(f"cube must have shape (chirps, channels, samples), got {x.shape}")
    is_complex = np.iscomplexobj(x)
    x = x.astype(np.complex64 if is_complex else np.float32, copy=False)
    n_samples = x.shape[-1]
    n_fft = range_fft_size(n_samples, fft_size)
    if remove_dc:
        x = x - x.mean(axis=-1, keepdims=True)
    w = make_window(window, n_samples, sidelobe_db=sidelobe_db)
    scale = (1.0 if is_complex else 2.0) / float(np.sum(w, dtype=np.float64))
    xw = x * (w * np.float32(scale))
    keep = range_bin_count(n_fft, complex_iq=is_complex) if n_bins is None else int(n_bins)
    if is_complex:
        spec = scipy.fft.fft(xw, n=n_fft, axis=-1)
    else:
        spec = scipy.fft.rfft(xw, n=n_fft, axis=-1)
    if keep > spec.shape[-1]:
        raise ValueError(f"n_bins {keep} exceeds the {spec.shape[-1]} bins of the spectrum")
    return as_complex64(spec[..., :keep])


def remove_static_clutter(range_cube: ArrayLike) -> NDArray[np.complex64]:
    """Subtract the mean over chirps of every (channel, range bin): keeps only movers.

    Parameters
    ----------
    range_cube : array_like, shape (chirps, channels, range)
        Output of :func:`range_fft`.

    Returns
    -------
    ndarray, shape (chirps, channels, range), complex64

    Examples
    --------
    >>> rc = np.array([1.0, 3.0]).reshape(2, 1, 1)   # (chirps, channels, range)
    >>> remove_static_clutter(rc)[:, 0, 0].real
    array([-1.,  1.], dtype=float32)
    """
    x = as_complex64(range_cube)
    return as_complex64(x - x.mean(axis=0, keepdims=True))


def doppler_fft(
    range_cube: ArrayLike,
    *,
    window: WindowName = "chebyshev",
    sidelobe_db: float = 60.0,
    fft_size: int | None = None,
    static_clutter_removal: bool = False,
) -> NDArray[np.complex64]:
    """Doppler FFT along slow time, fft-shifted so that zero velocity is in the middle.

    Parameters
    ----------
    range_cube : array_like, shape (chirps, channels, range)
        Output of :func:`range_fft`.
    window : str, keyword-only
        Slow-time window; Chebyshev by default.
    sidelobe_db : float, keyword-only
        Sidelobe level of the Chebyshev window (dB).
    fft_size : int or None, keyword-only
        FFT length; ``None``: twice the next power of two ≥ chirps (2× zero padding).
    static_clutter_removal : bool, keyword-only
        Apply :func:`remove_static_clutter` first.

    Returns
    -------
    spectrum : ndarray, shape (doppler, channels, range), complex64
        Axes (Doppler bin, channel, range bin); the Doppler axis is that of
        :func:`velocity_axis_mps` (fft-shifted). Amplitude-normalised by the window sum.

    Examples
    --------
    A phase advancing by 1/8 cycle per chirp over 16 chirps lands 4 bins right of zero
    velocity (bin 16 of the 2x zero-padded, fft-shifted axis):

    >>> k = np.arange(16)
    >>> rc = np.exp(2j * np.pi * k / 8).reshape(16, 1, 1)
    >>> rd = doppler_fft(rc)
    >>> rd.shape, int(np.argmax(np.abs(rd[:, 0, 0])))
    ((32, 1, 1), 20)
    """
    x = as_complex64(range_cube)
    if x.ndim != 3:
        raise ValueError(f"range_cube must have shape (chirps, channels, range), got {x.shape}")
    if static_clutter_removal:
        x = remove_static_clutter(x)
    n_chirps = x.shape[0]
    n_fft = doppler_fft_size(n_chirps, fft_size)
    w = make_window(window, n_chirps, sidelobe_db=sidelobe_db)
    w = w / np.float32(np.sum(w, dtype=np.float64))
    spec = scipy.fft.fft(x * w[:, None, None], n=n_fft, axis=0)
    return as_complex64(scipy.fft.fftshift(spec, axes=0))


def compensate_tdm_doppler(
    rd_cube: ArrayLike,
    *,
    velocity_axis_mps: ArrayLike,
    n_tx: int,
    chirp_repetition_time_s: float,
    wavelength_m: float,
) -> NDArray[np.complex64]:
    """Remove the Doppler phase that accrues between the Tx slots of a TDM-MIMO frame.

    Chirp ``k`` of Tx ``j`` starts at ``(k * n_tx + j) * T_r``, so a target with radial
    velocity ``v`` gives virtual channel ``(j, i)`` an extra phase ``4 pi v j T_r / lambda``
    that is not an angle. Each Doppler bin is de-rotated with its own velocity; the result
    is exact for targets inside the unambiguous velocity interval.

    Parameters
    ----------
    rd_cube : array_like, shape (doppler, n_tx * n_rx, range)
        Output of :func:`doppler_fft`, channels tx-major.
    velocity_axis_mps : array_like, shape (doppler,)
        Velocity of each Doppler bin (m/s).
    n_tx : int
        Number of transmitters.
    chirp_repetition_time_s : float
        Time between consecutive chirps (any Tx), T_r (s).
    wavelength_m : float
        Carrier wavelength (m).

    Returns
    -------
    ndarray, shape (doppler, n_tx * n_rx, range), complex64

    Examples
    --------
    Two Tx slots, 1 m/s, ``T_r`` = 0.1 ms and λ = 0.8 mm: the second Tx's channel carries an
    extra π/2, which is removed:

    >>> rd = np.ones((1, 2, 1), dtype=np.complex64)
    >>> out = compensate_tdm_doppler(rd, velocity_axis_mps=[1.0], n_tx=2,
    ...                              chirp_repetition_time_s=1e-4, wavelength_m=8e-4)
    >>> np.round(np.angle(out[0, :, 0]) / np.pi, 3)
    array([ 0. , -0.5], dtype=float32)
    """
    x = as_complex64(rd_cube)
    n_ch = x.shape[1]
    if n_tx <= 1:
        return x
    if n_ch % n_tx:
        raise ValueError(f"{n_ch} channels are not a multiple of n_tx = {n_tx}")
    n_rx = n_ch // n_tx
    v = np.asarray(velocity_axis_mps, dtype=np.float64)
    tx_index = np.repeat(np.arange(n_tx), n_rx)  # tx-major channel order
    phase = 4.0 * np.pi * v[:, None] * tx_index[None, :] * chirp_repetition_time_s / wavelength_m
    return as_complex64(x * np.exp(-1j * phase)[:, :, None])
