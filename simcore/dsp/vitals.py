"""Vital signs from the phase of the chest's range bin: displacement, breathing, heartbeat.

Chain (one sample per radar frame):

1. **Slow time per range bin** (:func:`frame_slow_time`): each frame's range spectra
   averaged over its chirps (coherent integration: the chest moves a few µm within a
   frame), one channel; shape (frames, range).
2. **Chest bin** (:func:`select_vital_bin`): the range bin whose complex slow-time signal
   varies most (largest variance ``mean |x − mean x|²``) inside a search interval; static
   clutter is constant, so it adds nothing to the variance. Or a given bin.
3. **Static clutter / DC offset** (:func:`remove_static_offset`): in the chest's bin the
   echo is ``C + a·exp(j 4π d(t)/λ)``: a static phasor ``C`` (clutter in the same bin, the
   range window's leakage of nearby statics, receiver offset) plus the chest's phasor,
   which traces an arc of a circle centred on ``C``. The phase of the raw sum is not
   ``4π d/λ``; the phase about the circle's centre is. The centre is estimated by the
   algebraic (Kåsa) least-squares circle fit — I. Kåsa, "A circle fitting procedure and
   its error analysis", IEEE Trans. Instrum. Meas. IM-25(1), 8–14, 1976 — the DC-offset
   compensation compared for heart and respiration radar by M. Zakrzewski, H. Raittinen
   and J. Vanhala, "Comparison of center estimation algorithms for heart and respiration
   monitoring with microwave Doppler radar", IEEE Sensors J. 12(3), 627–634, 2012, ahead
   of arctangent demodulation (B.-K. Park, O. Boric-Lubecke, V. M. Lubecke, "Arctangent
   demodulation with DC offset compensation in quadrature Doppler radar receiver
   systems", IEEE Trans. MTT 55(5), 2007). The Kåsa centre then seeds a geometric
   least-squares fit (:func:`geometric_circle_fit`), which removes the algebraic fit's
   radius bias on the short, noisy arc of a heartbeat. The mean (``"mean"``) is the
   cheap alternative: right only when the arc covers whole turns.
4. **Displacement** (:func:`phase_displacement_m`): unwrapped phase about the centre,
   ``d = λ / (4π) · (φ − mean φ)`` (m, positive = moving away from the radar, as the
   project's velocity). Unwrapping needs the phase step per frame below π, i.e. a frame
   rate above ``4 v_max / λ`` (≈ 8 Hz for a 10 mm/s chest at 60 GHz).
5. **Rates** (:func:`spectral_peak`): the displacement, linearly detrended and windowed,
   zero-padded ``zoom`` times (a dense DFT grid), and the largest peak inside the band is
   refined by a parabola through the three grid points around it. Bands default to
   breathing 0.1–0.6 Hz and heartbeat 0.8–2.5 Hz. The amplitude is that of the sinusoid
   (half the peak-to-peak displacement): the peak magnitude × 2 / Σw.

Arrays: complex64 IQ (the DSP dtype policy); phases, displacements and spectra in
float64, because the heartbeat (≈ 0.1 mm) rides on a breathing motion 50× larger.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft
import scipy.optimize
import scipy.signal
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.peaks import parabolic_peak_offset
from simcore.dsp.windows import as_complex64, make_window, next_pow2
from simcore.scene.dsp_config import StaticOffsetMethod, WindowName

#: Default frequency bands (Hz).
BREATHING_BAND_HZ = (0.1, 0.6)
HEART_BAND_HZ = (0.8, 2.5)


@dataclass(frozen=True)
class VitalSigns:
    """What :func:`estimate_vital_signs` measures.

    Attributes
    ----------
    breathing_rate_hz, heart_rate_hz : float
        Frequency of the strongest peak in each band (Hz); NaN when the band lies outside
        the sampled spectrum.
    breathing_amplitude_m, heart_amplitude_m : float
        Amplitude of that sinusoidal component of the displacement (m, half its
        peak-to-peak excursion).
    displacement_m : ndarray, shape (n,), float64
        Chest displacement over time, mean removed (m, positive = away from the radar).
    sample_rate_hz : float
        Sampling rate of ``displacement_m`` (Hz).
    range_bin : int
        Range bin the signal came from (−1 when the caller gave the signal directly).
    """

    breathing_rate_hz: float
    breathing_amplitude_m: float
    heart_rate_hz: float
    heart_amplitude_m: float
    displacement_m: NDArray[np.float64]
    sample_rate_hz: float
    range_bin: int = -1

    def as_row(self) -> NDArray[np.float64]:
        """The four scalars as float64 ``[breathing Hz, breathing m, heart Hz, heart m]``."""
        return np.array([self.breathing_rate_hz, self.breathing_amplitude_m,
                         self.heart_rate_hz, self.heart_amplitude_m], dtype=np.float64)


def frame_slow_time(range_cubes: ArrayLike, *, channel: int = 0) -> NDArray[np.complex64]:
    """One complex sample per frame and range bin: each frame's chirps averaged.

    Parameters
    ----------
    range_cubes : array_like, shape (frames, chirps, channels, range)
        Range spectra of consecutive frames (:func:`simcore.dsp.spectrum.range_fft`).
    channel : int, keyword-only
        Virtual channel to use.

    Returns
    -------
    ndarray, shape (frames, range), complex64

    Examples
    --------
    >>> cubes = np.ones((5, 2, 3, 64), np.complex64)   # (frames, chirps, channels, range)
    >>> frame_slow_time(cubes, channel=1).shape
    (5, 64)
    """
    x = np.asarray(range_cubes)
    if x.ndim != 4:
        raise ValueError(
            f"range_cubes must have shape (frames, chirps, channels, range), got {x.shape}")
    if not 0 <= channel < x.shape[2]:
        raise ValueError(f"channel {channel} out of range: the cubes have {x.shape[2]}")
    return as_complex64(x[:, :, channel, :].mean(axis=1))


def select_vital_bin(
    slow_time: ArrayLike,
    *,
    range_axis_m: ArrayLike | None = None,
    min_range_m: float = 0.0,
    max_range_m: float = float("inf"),
) -> int:
    """The range bin whose slow-time signal varies most: where the chest moves.

    Parameters
    ----------
    slow_time : array_like, shape (frames, range)
        Complex samples per frame and range bin (:func:`frame_slow_time`).
    range_axis_m : array_like, shape (range,), keyword-only, optional
        Range of each bin (m); needed for the search interval.
    min_range_m, max_range_m : float, keyword-only
        Search interval (m): excludes the Tx→Rx leakage near 0 m and far movers.

    Returns
    -------
    int
        Index of the bin with the largest variance ``mean |x − mean x|²`` over frames.

    Examples
    --------
    >>> x = np.ones((50, 4), complex)
    >>> x[:, 2] += 0.1 * np.exp(1j * np.linspace(0, 3, 50))   # the moving bin
    >>> x[:, 0] *= 100.0                                       # strong but static
    >>> select_vital_bin(x)
    2
    """
    x = np.asarray(slow_time)
    if x.ndim != 2 or x.shape[0] < 2:
        raise ValueError(f"slow_time must have shape (frames >= 2, range), got {x.shape}")
    var = np.mean(np.abs(x - x.mean(axis=0, keepdims=True)) ** 2, axis=0)
    if range_axis_m is not None:
        r = np.asarray(range_axis_m, dtype=np.float64)
        inside = (r >= min_range_m) & (r <= max_range_m)
        if not inside.any():
            raise ValueError(f"no range bin between {min_range_m} and {max_range_m} m")
        var = np.where(inside, var, -1.0)
    return int(np.argmax(var))


def kasa_circle_fit(iq: ArrayLike) -> tuple[complex, float]:
    """Algebraic (Kåsa) least-squares circle through complex samples.

    Minimises ``Σ (x² + y² + D x + E y + F)²`` (linear in D, E, F); the centre is
    ``−(D + jE) / 2``, the radius ``sqrt((D² + E²)/4 − F)`` (Kåsa 1976, module docstring).

    Parameters
    ----------
    iq : array_like, shape (n,)
        Complex samples (n ≥ 3, not all on one line).

    Returns
    -------
    centre : complex
    radius : float

    Examples
    --------
    An arc of 60° of the circle of radius 2 about 5 − 3j:

    >>> z = 5 - 3j + 2 * np.exp(1j * np.linspace(0.2, 0.2 + np.pi / 3, 40))
    >>> c, r = kasa_circle_fit(z)
    >>> round(c.real, 6), round(c.imag, 6), round(r, 6)
    (5.0, -3.0, 2.0)
    """
    z = np.asarray(iq, dtype=np.complex128).reshape(-1)
    if z.size < 3:
        raise ValueError(f"a circle fit needs at least 3 samples, got {z.size}")
    # Centre and scale for conditioning; fit in normalised coordinates.
    z0 = z.mean()
    s = float(np.sqrt(np.mean(np.abs(z - z0) ** 2))) or 1.0
    u = (z - z0) / s
    a = np.column_stack([u.real, u.imag, np.ones(u.size)])
    b = -(u.real ** 2 + u.imag ** 2)
    (d, e, f), *_ = np.linalg.lstsq(a, b, rcond=None)
    centre = complex(z0 + s * complex(-d / 2, -e / 2))
    radius = float(np.sqrt(max(d * d / 4 + e * e / 4 - f, 0.0)))
    return centre, s * radius


def geometric_circle_fit(iq: ArrayLike) -> tuple[complex, float]:
    """Geometric least-squares circle: minimises ``Σ (|z − c| − R)²``.

    Starts from :func:`kasa_circle_fit` and refines with Levenberg–Marquardt
    (:func:`scipy.optimize.least_squares`). The algebraic fit underestimates the radius
    of a short, noisy arc (N. Chernov, C. Lesort, "Least squares fitting of circles",
    J. Math. Imaging Vis. 23, 239–252, 2005); the heartbeat alone draws such an arc
    (0.3 mm at 60 GHz is ±0.76 rad), so the refinement matters for its amplitude.

    Parameters
    ----------
    iq : array_like, shape (n,)
        Complex samples (n ≥ 3).

    Returns
    -------
    centre : complex
    radius : float

    Examples
    --------
    >>> z = 1j + 3 * np.exp(1j * np.linspace(0.0, 1.0, 30))
    >>> c, r = geometric_circle_fit(z)
    >>> round(abs(c - 1j), 6), round(r, 6)
    (0.0, 3.0)
    """
    z = np.asarray(iq, dtype=np.complex128).reshape(-1)
    c0, r0 = kasa_circle_fit(z)
    s = r0 if r0 > 0 else 1.0
    u = (z - c0) / s   # unit scale: the fit in well-conditioned coordinates

    def residual(p: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(np.abs(u - complex(p[0], p[1])) - p[2], dtype=np.float64)

    sol = scipy.optimize.least_squares(residual, np.array([0.0, 0.0, 1.0]), method="lm")
    if not sol.success or not np.all(np.isfinite(sol.x)):
        return c0, r0
    return complex(c0 + s * complex(sol.x[0], sol.x[1])), float(s * abs(sol.x[2]))


def remove_static_offset(iq: ArrayLike, *, method: StaticOffsetMethod = "circle"
                         ) -> NDArray[np.complex128]:
    """Subtract the static phasor (clutter, DC offset) under the chest's arc.

    Parameters
    ----------
    iq : array_like, shape (n,)
        Complex slow-time samples of the chest's range bin.
    method : {"circle", "mean", "none"}, keyword-only
        ``"circle"``: the centre of the geometric circle fit started from the Kåsa fit
        (:func:`geometric_circle_fit`);
        ``"mean"``: the mean (exact only over whole turns of the phasor);
        ``"none"``: nothing.

    Returns
    -------
    ndarray, shape (n,), complex128

    Examples
    --------
    A quarter arc about the clutter phasor 2 + 1j comes back centred on 0:

    >>> z = 2 + 1j + 0.5 * np.exp(1j * np.linspace(0, np.pi / 2, 20))
    >>> np.round(np.abs(remove_static_offset(z))[:3], 6)
    array([0.5, 0.5, 0.5])
    """
    z = np.asarray(iq, dtype=np.complex128).reshape(-1)
    if method == "none":
        return z
    if method == "mean":
        return z - z.mean()
    if method == "circle":
        centre, _ = geometric_circle_fit(z)
        return z - centre
    raise ValueError(f"unknown static offset method {method!r}")


def phase_displacement_m(
    iq: ArrayLike, *, wavelength_m: float, static_offset: StaticOffsetMethod = "circle"
) -> NDArray[np.float64]:
    """Displacement from the unwrapped phase: ``d = λ / (4π) · (φ − mean φ)``.

    Parameters
    ----------
    iq : array_like, shape (n,)
        Complex slow-time samples of the chest's range bin.
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    static_offset : {"circle", "mean", "none"}, keyword-only
        How the static phasor is removed first (:func:`remove_static_offset`).

    Returns
    -------
    ndarray, shape (n,), float64
        Displacement (m, mean removed, positive = moving away: the echo's phase
        ``4π R / λ`` grows with range).

    Examples
    --------
    A phase ramp of π/2 per sample is λ/8 per sample:

    >>> z = np.exp(1j * np.pi / 2 * np.arange(5))
    >>> np.round(phase_displacement_m(z, wavelength_m=8.0, static_offset="none"), 6)
    array([-2., -1.,  0.,  1.,  2.])
    """
    z = remove_static_offset(iq, method=static_offset)
    phi = np.unwrap(np.angle(z))
    return np.asarray((phi - phi.mean()) * (wavelength_m / (4.0 * np.pi)), dtype=np.float64)


def spectral_peak(
    x: ArrayLike,
    *,
    sample_rate_hz: float,
    band_hz: tuple[float, float],
    window: WindowName = "hann",
    zoom: int = 16,
) -> tuple[float, float]:
    """Frequency and amplitude of the strongest sinusoid of ``x`` inside a band.

    Parameters
    ----------
    x : array_like, shape (n,)
        Real signal, uniformly sampled; it is linearly detrended first.
    sample_rate_hz : float, keyword-only
        Sampling rate (Hz).
    band_hz : (float, float), keyword-only
        Search band (Hz); clipped to the Nyquist frequency.
    window : str, keyword-only
        Analysis window (:func:`simcore.dsp.windows.make_window`).
    zoom : int, keyword-only
        Zero-padding factor: the DFT grid is ``sample_rate_hz / (n · zoom)`` apart (at
        least); the peak is then refined by a parabola through the log-magnitudes of the
        three grid points around it.

    Returns
    -------
    frequency_hz : float
        NaN when the band holds no grid frequency.
    amplitude : float
        Amplitude of the sinusoid (units of ``x``): peak magnitude × 2 / Σw.

    Examples
    --------
    >>> t = np.arange(600) / 20.0
    >>> f, a = spectral_peak(3.0 * np.sin(2 * np.pi * 0.237 * t), sample_rate_hz=20.0,
    ...                      band_hz=(0.1, 0.6))
    >>> round(f, 3), round(a, 2)
    (0.237, 3.0)
    """
    y = np.asarray(x, dtype=np.float64).reshape(-1)
    n = y.size
    if n < 4:
        raise ValueError(f"a spectral peak needs at least 4 samples, got {n}")
    lo, hi = band_hz
    if not 0 <= lo < hi:
        raise ValueError(f"band must satisfy 0 <= low < high, got {band_hz}")
    y = scipy.signal.detrend(y, type="linear")
    w = make_window(window, n).astype(np.float64)
    n_fft = next_pow2(n * max(1, int(zoom)))
    mag = np.abs(scipy.fft.rfft(y * w, n=n_fft))
    f = np.arange(mag.size) * (sample_rate_hz / n_fft)
    inside = np.flatnonzero((f >= lo) & (f <= min(hi, 0.5 * sample_rate_hz)))
    if inside.size == 0:
        return float("nan"), float("nan")
    k = int(inside[np.argmax(mag[inside])])
    offset, peak = 0.0, float(mag[k])
    if 0 < k < mag.size - 1 and min(mag[k - 1], mag[k + 1]) > 0:
        lm, mm, rm = np.log(mag[k - 1:k + 2])
        offset = float(parabolic_peak_offset(lm, mm, rm))
        peak = float(np.exp(mm - 0.25 * (lm - rm) * offset))
    return (k + offset) * sample_rate_hz / n_fft, 2.0 * peak / float(np.sum(w))


def estimate_vital_signs(
    iq: ArrayLike,
    *,
    sample_rate_hz: float,
    wavelength_m: float,
    breathing_band_hz: tuple[float, float] = BREATHING_BAND_HZ,
    heart_band_hz: tuple[float, float] = HEART_BAND_HZ,
    window: WindowName = "hann",
    static_offset: StaticOffsetMethod = "circle",
    zoom: int = 16,
    range_bin: int = -1,
) -> VitalSigns:
    """Breathing and heart rate and amplitude from the chest's slow-time IQ.

    Parameters
    ----------
    iq : array_like, shape (n,)
        Complex samples of the chest's range bin, one per frame (:func:`frame_slow_time`
        at :func:`select_vital_bin`), uniformly sampled.
    sample_rate_hz : float, keyword-only
        Their rate: the frame rate (Hz).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    breathing_band_hz, heart_band_hz : (float, float), keyword-only
        Search bands (Hz).
    window : str, keyword-only
        Analysis window of the rate spectra.
    static_offset : {"circle", "mean", "none"}, keyword-only
        Static clutter / DC offset removal before the phase (:func:`remove_static_offset`).
    zoom : int, keyword-only
        Zero-padding factor of the rate spectra (:func:`spectral_peak`).
    range_bin : int, keyword-only
        Recorded in the result (where ``iq`` came from).

    Returns
    -------
    VitalSigns

    Examples
    --------
    40 s at 20 Hz of a chest breathing 4 mm at 0.3 Hz (λ = 5 mm) behind static clutter:

    >>> t = np.arange(800) / 20.0
    >>> d = 4e-3 * np.sin(2 * np.pi * 0.3 * t)
    >>> iq = 0.7 - 0.2j + 0.1 * np.exp(4j * np.pi * d / 5e-3)
    >>> vs = estimate_vital_signs(iq, sample_rate_hz=20.0, wavelength_m=5e-3)
    >>> round(vs.breathing_rate_hz, 3), round(vs.breathing_amplitude_m * 1e3, 2)
    (0.3, 4.0)
    """
    d = phase_displacement_m(iq, wavelength_m=wavelength_m, static_offset=static_offset)
    fb, ab = spectral_peak(d, sample_rate_hz=sample_rate_hz, band_hz=breathing_band_hz,
                           window=window, zoom=zoom)
    fh, ah = spectral_peak(d, sample_rate_hz=sample_rate_hz, band_hz=heart_band_hz,
                           window=window, zoom=zoom)
    return VitalSigns(fb, ab, fh, ah, d, float(sample_rate_hz), int(range_bin))


class VitalSignsBuffer:
    """Streaming vital signs: a ring buffer of each frame's complex range spectrum.

    Feed it one frame at a time (:meth:`push_frame`); :meth:`estimate` runs
    :func:`select_vital_bin` and :func:`estimate_vital_signs` on the kept frames. Memory
    is bounded: ``capacity × range`` complex64 values.

    Parameters
    ----------
    n_range : int
        Range bins per frame.
    capacity : int, keyword-only
        Most frames kept (history seconds × frame rate).
    """

    def __init__(self, n_range: int, *, capacity: int) -> None:
        if capacity < 4:
            raise ValueError(f"capacity must be >= 4 frames, got {capacity}")
        self.capacity = int(capacity)
        self._data = np.zeros((self.capacity, int(n_range)), dtype=np.complex64)
        self._next = 0
        self.count = 0

    def clear(self) -> None:
        """Forget every frame (e.g. when playback jumps)."""
        self._next = 0
        self.count = 0

    def push_frame(self, range_cube: ArrayLike, *, channel: int = 0) -> None:
        """Append one frame: its range spectra (chirps, channels, range) averaged over chirps."""
        x = np.asarray(range_cube)
        row = frame_slow_time(x[None], channel=channel)[0]
        if row.size != self._data.shape[1]:
            raise ValueError(f"frame has {row.size} range bins, the buffer "
                             f"{self._data.shape[1]}")
        self._data[self._next] = row
        self._next = (self._next + 1) % self.capacity
        self.count = min(self.count + 1, self.capacity)

    def slow_time(self) -> NDArray[np.complex64]:
        """The kept frames, oldest first, shape (frames, range), complex64 (a copy)."""
        idx = (self._next - self.count + np.arange(self.count)) % self.capacity
        return self._data[idx].copy()

    def estimate(
        self,
        *,
        sample_rate_hz: float,
        wavelength_m: float,
        range_axis_m: ArrayLike | None = None,
        min_range_m: float = 0.0,
        max_range_m: float = float("inf"),
        range_bin: int | None = None,
        **options: object,
    ) -> VitalSigns:
        """Estimate from the kept frames (``options``: those of :func:`estimate_vital_signs`)."""
        x = self.slow_time()
        if x.shape[0] < 4:
            raise ValueError(f"{x.shape[0]} frames kept; at least 4 are needed")
        k = range_bin if range_bin is not None else select_vital_bin(
            x, range_axis_m=range_axis_m, min_range_m=min_range_m, max_range_m=max_range_m)
        return estimate_vital_signs(x[:, k], sample_rate_hz=sample_rate_hz,
                                    wavelength_m=wavelength_m, range_bin=k,
                                    **options)  # type: ignore[arg-type]


__all__ = [
    "BREATHING_BAND_HZ",
    "HEART_BAND_HZ",
    "VitalSigns",
    "VitalSignsBuffer",
    "estimate_vital_signs",
    "frame_slow_time",
    "geometric_circle_fit",
    "kasa_circle_fit",
    "phase_displacement_m",
    "remove_static_offset",
    "select_vital_bin",
    "spectral_peak",
]
