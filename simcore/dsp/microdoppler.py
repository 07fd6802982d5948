"""Micro-Doppler spectrograms: Doppler power over time at a range gate, across frames.

A radar frame is a burst of ``chirps_per_frame`` chirps ``n_tx · T_r`` apart, and the
frames follow each other at the frame rate, usually with a gap: the frame period
``1 / frame_rate_hz`` is longer than the burst. The slow-time signal across frames is
therefore **not uniformly sampled**, and an FFT over the chirps of several frames
concatenated as if they were contiguous would put wrong, aliased Doppler lines in the
spectrogram. Two forms handle this:

* :func:`frame_spectrogram` (and the streaming :class:`SpectrogramBuffer`): one column per
  frame, the Doppler power spectrum of that frame's chirps, stamped with the mean time of
  the frame's chirps. Doppler resolution ``λ / (2 N_c n_tx T_r)``, time resolution one
  frame period. This is the default (``DspConfig.spectrogram_mode = "frame"``) and works
  with any gap.
* :func:`stft_spectrogram`: a short-time Fourier transform over the concatenated chirps,
  with a window of ``segment_length`` chirps hopping by ``segment_length · (1 − overlap)``;
  a segment is used only if its chirps are uniformly spaced (no inter-frame gap inside
  it). When the frames are contiguous (frame period = burst length) segments run across
  frame boundaries and give longer windows (finer Doppler) than one frame; with a gap
  only segments inside one frame remain, i.e. several overlapping columns per frame.

Power is summed non-coherently over the channels and the range bins of the gate, so a
moving scatterer counts wherever it is within the gate and the channels' different
phases never cancel. Spectra are amplitude-normalised by the window sum (a
constant-velocity target of amplitude ``A`` in the range spectrum reads ``A²`` at its
bin) and returned in dB, float32 (the dtype policy of :mod:`simcore.dsp.windows`). The
velocity axis is that of :func:`simcore.dsp.spectrum.velocity_axis_mps`: fft-shifted,
**positive = moving away**. Spectrogram images are ``(time, doppler)``: frame axis first,
as in the dataset.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.fft
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.spectrum import doppler_fft_size, velocity_axis_mps
from simcore.dsp.vitals import spectral_peak
from simcore.dsp.windows import as_complex64, make_window, power_to_db
from simcore.scene.dsp_config import WindowName

#: Relative tolerance on the chirp spacing inside an STFT segment.
SPACING_TOLERANCE = 1e-3
#: Half width of a range gate that follows an object's true range (m): a walking
#: person's limbs reach about this far from the torso along the line of sight.
OBJECT_GATE_HALF_WIDTH_M = 0.6


@dataclass(frozen=True)
class Spectrogram:
    """A micro-Doppler spectrogram.

    Attributes
    ----------
    time_s : ndarray, shape (columns,), float64
        Time of each column (s): the mean time of the chirps it was computed from.
    velocity_mps : ndarray, shape (doppler,), float64
        Radial velocity of each Doppler bin (m/s, increasing, positive = moving away).
    power_db : ndarray, shape (columns, doppler), float32
        Doppler power per column (dB re. FS², amplitude-normalised).
    """

    time_s: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    power_db: NDArray[np.float32]

    def peak_velocity_mps(self) -> NDArray[np.float64]:
        """Velocity of the strongest Doppler bin of each column, shape (columns,), m/s."""
        return np.asarray(self.velocity_mps[np.argmax(self.power_db, axis=1)],
                          dtype=np.float64)


def gate_bins(range_axis_m: ArrayLike, *, min_m: float, max_m: float) -> NDArray[np.intp]:
    """Indices of the range bins inside a range gate ``[min_m, max_m]``.

    Parameters
    ----------
    range_axis_m : array_like, shape (range,)
        Range of each bin (m), increasing.
    min_m, max_m : float, keyword-only
        Gate limits (m). When no bin centre falls inside, the bin nearest the gate's
        centre is returned, so a gate narrower than a bin still selects one.

    Returns
    -------
    ndarray, shape (bins,), intp

    Examples
    --------
    >>> gate_bins(np.arange(6) * 0.5, min_m=0.9, max_m=2.0)
    array([2, 3, 4])
    >>> gate_bins(np.arange(6) * 0.5, min_m=1.1, max_m=1.2)
    array([2])
    """
    r = np.asarray(range_axis_m, dtype=np.float64)
    if max_m < min_m:
        raise ValueError(f"range gate max_m ({max_m}) is below min_m ({min_m})")
    inside = np.flatnonzero((r >= min_m) & (r <= max_m))
    if inside.size:
        return inside
    return np.array([int(np.argmin(np.abs(r - 0.5 * (min_m + max_m))))], dtype=np.intp)


def gate_slow_time(range_cube: ArrayLike, *, range_bins: ArrayLike) -> NDArray[np.complex64]:
    """Slow-time signals of a range gate: every (channel, bin) pair as one column.

    Parameters
    ----------
    range_cube : array_like, shape (chirps, channels, range)
        Range spectra of one frame (:func:`simcore.dsp.spectrum.range_fft`).
    range_bins : array_like of int, shape (bins,), keyword-only
        Range bins of the gate (:func:`gate_bins`).

    Returns
    -------
    ndarray, shape (chirps, channels * bins), complex64
        Channel-major columns.

    Examples
    --------
    >>> gate_slow_time(np.zeros((16, 3, 256)), range_bins=[40, 41]).shape
    (16, 6)
    """
    x = as_complex64(range_cube)
    if x.ndim != 3:
        raise ValueError(f"range_cube must have shape (chirps, channels, range), got {x.shape}")
    bins = np.atleast_1d(np.asarray(range_bins, dtype=np.intp))
    return x[:, :, bins].reshape(x.shape[0], -1)


def doppler_power_spectrum(
    slow_time: ArrayLike,
    *,
    window: WindowName = "hann",
    sidelobe_db: float = 60.0,
    fft_size: int | None = None,
    clutter_removal: bool = True,
) -> NDArray[np.float32]:
    """Doppler power spectrum of uniformly sampled slow-time signals, summed over columns.

    Parameters
    ----------
    slow_time : array_like, shape (chirps,) or (chirps, k)
        Complex samples at one chirp interval; the ``k`` columns (channels × range bins)
        are summed non-coherently.
    window : str, keyword-only
        Slow-time window (:func:`simcore.dsp.windows.make_window`, via
        :func:`scipy.signal.get_window`).
    sidelobe_db : float, keyword-only
        Sidelobe level of a Chebyshev window (dB).
    fft_size : int or None, keyword-only
        FFT length (zero padding); ``None``: twice the next power of two ≥ chirps.
    clutter_removal : bool, keyword-only
        Subtract each column's mean first (removes what does not move during the chirps).

    Returns
    -------
    ndarray, shape (fft_size,), float32
        Linear power per fft-shifted Doppler bin (FS²), bin ``fft_size // 2`` = 0 m/s.

    Examples
    --------
    A phase ramp of 1/8 cycle per chirp over 16 chirps peaks 4 bins above zero (bin 20
    of 32) with power 1:

    >>> p = doppler_power_spectrum(np.exp(2j * np.pi * np.arange(16) / 8),
    ...                            clutter_removal=False)
    >>> int(np.argmax(p)), round(float(p.max()), 4)
    (20, 1.0)
    """
    x = as_complex64(slow_time)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] < 1:
        raise ValueError(f"slow_time must have shape (chirps,) or (chirps, k), got {x.shape}")
    n = x.shape[0]
    if clutter_removal:
        x = x - x.mean(axis=0, keepdims=True)
    n_fft = doppler_fft_size(n, fft_size)
    w = make_window(window, n, sidelobe_db=sidelobe_db)
    w = w / np.float32(np.sum(w, dtype=np.float64))
    spec = scipy.fft.fftshift(scipy.fft.fft(x * w[:, None], n=n_fft, axis=0), axes=0)
    return np.asarray(np.sum(np.abs(spec) ** 2, axis=1), dtype=np.float32)


def doppler_column_from_map(
    range_doppler_db: ArrayLike, *, range_bins: ArrayLike
) -> NDArray[np.float32]:
    """One spectrogram column from a frame's range–Doppler map: power summed over a gate.

    This is the per-frame spectrogram column built from what
    :func:`simcore.dsp.process_frame` already computed (its Doppler window, zero padding
    and clutter setting), for consumers that keep only the maps (the GUI).

    Parameters
    ----------
    range_doppler_db : array_like, shape (doppler, range)
        Range–Doppler power map (dB).
    range_bins : array_like of int, keyword-only
        Range bins of the gate.

    Returns
    -------
    ndarray, shape (doppler,), float32
        Power summed over the gate's bins (dB).

    Examples
    --------
    >>> rd = np.array([[0.0, 10.0], [3.0103, -300.0]])   # (doppler, range), dB
    >>> np.round(doppler_column_from_map(rd, range_bins=[0, 1]), 2)
    array([10.41,  3.01], dtype=float32)
    """
    rd = np.asarray(range_doppler_db, dtype=np.float64)
    if rd.ndim != 2:
        raise ValueError(f"range_doppler_db must have shape (doppler, range), got {rd.shape}")
    bins = np.atleast_1d(np.asarray(range_bins, dtype=np.intp))
    return power_to_db(np.sum(10.0 ** (rd[:, bins] / 10.0), axis=1))


def frame_spectrogram(
    range_cubes: Sequence[ArrayLike] | NDArray[np.complexfloating],
    frame_times_s: ArrayLike,
    *,
    range_bins: ArrayLike | Sequence[ArrayLike],
    chirp_interval_s: float,
    wavelength_m: float,
    window: WindowName = "hann",
    sidelobe_db: float = 60.0,
    fft_size: int | None = None,
    clutter_removal: bool = True,
) -> Spectrogram:
    """Per-frame spectrogram: the Doppler spectrum of each frame's chirps, one column each.

    Frames need not be contiguous: each column uses only its own frame's uniformly spaced
    chirps, so the inter-frame gap never enters a transform (module docstring).

    Parameters
    ----------
    range_cubes : sequence of array_like, each shape (chirps, channels, range)
        Range spectra of consecutive frames, or one array (frames, chirps, channels, range).
    frame_times_s : array_like, shape (frames,)
        Time of each frame (s), e.g. the mean start time of its chirps.
    range_bins : array_like of int, or a sequence of them (one per frame), keyword-only
        The range gate: fixed bins, or per-frame bins to follow an object's range.
    chirp_interval_s : float, keyword-only
        Time between two chirps of the same Tx, ``n_tx · T_r`` (s).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    window, sidelobe_db, fft_size, clutter_removal
        As in :func:`doppler_power_spectrum`.

    Returns
    -------
    Spectrogram
        ``power_db`` shape (frames, fft_size).

    Examples
    --------
    Two frames of 8 chirps 1 ms apart at λ = 4 mm; the range bin's phase turns by
    +π/2 per chirp, i.e. +0.5 m/s (half the unambiguous ±1 m/s):

    >>> ramp = np.exp(0.5j * np.pi * np.arange(8)).reshape(8, 1, 1)
    >>> sg = frame_spectrogram([ramp, ramp], [0.0, 0.1], range_bins=[0],
    ...                        chirp_interval_s=1e-3, wavelength_m=4e-3)
    >>> sg.power_db.shape, sg.peak_velocity_mps()
    ((2, 16), array([0.5, 0.5]))
    """
    cubes = list(range_cubes)
    times = np.asarray(frame_times_s, dtype=np.float64).reshape(-1)
    if len(cubes) != times.size:
        raise ValueError(f"{len(cubes)} frames but {times.size} frame times")
    per_frame = _per_frame_bins(range_bins, len(cubes))
    cols = [doppler_power_spectrum(gate_slow_time(c, range_bins=b), window=window,
                                   sidelobe_db=sidelobe_db, fft_size=fft_size,
                                   clutter_removal=clutter_removal)
            for c, b in zip(cubes, per_frame, strict=True)]
    if not cols:
        raise ValueError("no frames")
    n_fft = cols[0].size
    v = velocity_axis_mps(fft_size=n_fft, chirp_interval_s=chirp_interval_s,
                          wavelength_m=wavelength_m)
    return Spectrogram(times, v, power_to_db(np.stack(cols)))


def _per_frame_bins(range_bins: ArrayLike | Sequence[ArrayLike], n: int) -> list[NDArray[
        np.intp]]:
    """One array of range bins per frame (a fixed gate repeated, or the given list)."""
    if isinstance(range_bins, (list, tuple)) and range_bins and np.ndim(range_bins[0]) == 1:
        if len(range_bins) != n:
            raise ValueError(f"{len(range_bins)} range gates for {n} frames")
        return [np.asarray(b, dtype=np.intp) for b in range_bins]
    fixed = np.atleast_1d(np.asarray(range_bins, dtype=np.intp))
    return [fixed] * n


def uniform_segments(
    chirp_times_s: ArrayLike, *, chirp_interval_s: float, segment_length: int, hop: int
) -> NDArray[np.intp]:
    """Start indices of the STFT segments whose chirps are uniformly spaced.

    Parameters
    ----------
    chirp_times_s : array_like, shape (n,)
        Time of every chirp of the concatenated slow-time signal (s), increasing.
    chirp_interval_s : float, keyword-only
        The uniform chirp spacing (s).
    segment_length, hop : int, keyword-only
        Segment length and hop (chirps).

    Returns
    -------
    ndarray, shape (segments,), intp
        Starts ``s`` (multiples of ``hop``) such that chirps ``s … s + segment_length − 1``
        are ``chirp_interval_s`` apart (within :data:`SPACING_TOLERANCE`).

    Examples
    --------
    Two frames of 4 chirps 1 ms apart with a 6 ms gap between them: 3-chirp segments with
    hop 1 fit twice in each frame, never across the gap:

    >>> t = np.r_[0:4, 10:14] * 1e-3
    >>> uniform_segments(t, chirp_interval_s=1e-3, segment_length=3, hop=1)
    array([0, 1, 4, 5])
    """
    t = np.asarray(chirp_times_s, dtype=np.float64).reshape(-1)
    if segment_length < 1 or hop < 1:
        raise ValueError(f"segment_length ({segment_length}) and hop ({hop}) must be >= 1")
    if t.size < segment_length:
        return np.zeros(0, dtype=np.intp)
    bad = np.abs(np.diff(t) - chirp_interval_s) > SPACING_TOLERANCE * chirp_interval_s
    n_bad = np.concatenate([[0], np.cumsum(bad)])  # n_bad[i]: gaps before chirp i
    starts = np.arange(0, t.size - segment_length + 1, hop, dtype=np.intp)
    ok = n_bad[starts + segment_length - 1] == n_bad[starts]
    return starts[ok]


def stft_spectrogram(
    slow_time: ArrayLike,
    chirp_times_s: ArrayLike,
    *,
    chirp_interval_s: float,
    wavelength_m: float,
    segment_length: int,
    overlap: float = 0.5,
    window: WindowName = "hann",
    sidelobe_db: float = 60.0,
    fft_size: int | None = None,
    clutter_removal: bool = True,
) -> Spectrogram:
    """STFT spectrogram over concatenated chirps; segments never straddle a gap.

    Parameters
    ----------
    slow_time : array_like, shape (n,) or (n, k)
        Complex slow-time samples of a range gate over consecutive frames (chirps of all
        frames concatenated, e.g. :func:`gate_slow_time` of each frame stacked); the
        ``k`` columns are summed non-coherently.
    chirp_times_s : array_like, shape (n,)
        True time of every chirp (s) (the dataset's ``/radar/chirp_start_time`` of Tx 0).
    chirp_interval_s : float, keyword-only
        Time between two chirps of the same Tx, ``n_tx · T_r`` (s).
    wavelength_m : float, keyword-only
        Carrier wavelength (m).
    segment_length : int, keyword-only
        STFT window length (chirps).
    overlap : float, keyword-only
        Fraction of a segment shared with the next, in [0, 1); hop =
        ``max(1, round(segment_length · (1 − overlap)))``.
    window, sidelobe_db, fft_size, clutter_removal
        As in :func:`doppler_power_spectrum` (clutter removal per segment).

    Returns
    -------
    Spectrogram
        One column per uniformly spaced segment, stamped with its mean chirp time; no
        columns (shape (0, fft_size)) when no segment fits.

    Examples
    --------
    Twelve contiguous chirps, 4-chirp segments overlapping by half: starts 0, 2, … 8:

    >>> x = np.exp(0.5j * np.pi * np.arange(12))
    >>> sg = stft_spectrogram(x, np.arange(12) * 1e-3, chirp_interval_s=1e-3,
    ...                       wavelength_m=4e-3, segment_length=4, overlap=0.5)
    >>> sg.time_s * 1e3, sg.peak_velocity_mps()
    (array([1.5, 3.5, 5.5, 7.5, 9.5]), array([0.5, 0.5, 0.5, 0.5, 0.5]))
    """
    x = as_complex64(slow_time)
    if x.ndim == 1:
        x = x[:, None]
    t = np.asarray(chirp_times_s, dtype=np.float64).reshape(-1)
    if x.ndim != 2 or x.shape[0] != t.size:
        raise ValueError(f"slow_time {x.shape} does not match {t.size} chirp times")
    if not 0.0 <= overlap < 1.0:
        raise ValueError(f"overlap must be in [0, 1), got {overlap}")
    hop = max(1, int(round(segment_length * (1.0 - overlap))))
    starts = uniform_segments(t, chirp_interval_s=chirp_interval_s,
                              segment_length=segment_length, hop=hop)
    n_fft = doppler_fft_size(segment_length, fft_size)
    cols = [doppler_power_spectrum(x[s:s + segment_length], window=window,
                                   sidelobe_db=sidelobe_db, fft_size=n_fft,
                                   clutter_removal=clutter_removal) for s in starts]
    power = np.stack(cols) if cols else np.zeros((0, n_fft), dtype=np.float32)
    times = np.array([t[s:s + segment_length].mean() for s in starts], dtype=np.float64)
    v = velocity_axis_mps(fft_size=n_fft, chirp_interval_s=chirp_interval_s,
                          wavelength_m=wavelength_m)
    return Spectrogram(times, v, power_to_db(power))


def velocity_envelope(sg: Spectrogram, *, threshold_db: float = 20.0
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest and highest velocity of each column whose power is within ``threshold_db``.

    Parameters
    ----------
    sg : Spectrogram
    threshold_db : float, keyword-only
        Cells weaker than the column's maximum by more than this are ignored (dB).

    Returns
    -------
    lower, upper : ndarray, shape (columns,), float64
        Velocity envelope (m/s); NaN for an all-NaN column.

    Examples
    --------
    >>> sg = Spectrogram(np.zeros(1), np.array([-1.0, 0.0, 1.0, 2.0]),
    ...                  np.array([[-50.0, -5.0, 0.0, -30.0]], np.float32))
    >>> velocity_envelope(sg, threshold_db=10.0)
    (array([0.]), array([1.]))
    """
    p = np.asarray(sg.power_db, dtype=np.float64)
    lower = np.full(p.shape[0], np.nan)
    upper = np.full(p.shape[0], np.nan)
    for k, col in enumerate(p):
        if not np.isfinite(col).any():
            continue
        idx = np.flatnonzero(col >= np.nanmax(col) - threshold_db)
        lower[k], upper[k] = sg.velocity_mps[idx[0]], sg.velocity_mps[idx[-1]]
    return lower, upper


def step_frequency_hz(sg: Spectrogram, *, threshold_db: float = 20.0,
                      band_hz: tuple[float, float] = (0.5, 4.0)) -> float:
    """Step rate of a walker: the periodicity of its micro-Doppler spread.

    The spread ``upper − lower`` of :func:`velocity_envelope` widens each time a leg
    swings, i.e. twice per gait cycle (the legs alternate), so its strongest periodicity
    in ``band_hz`` is the step frequency; the gait cycle lasts ``2 / step_frequency``.
    Columns must be uniformly spaced in time (the per-frame spectrogram).

    Parameters
    ----------
    sg : Spectrogram
    threshold_db : float, keyword-only
        Envelope threshold (dB below each column's maximum).
    band_hz : (float, float), keyword-only
        Search band (Hz).

    Returns
    -------
    float
        Step frequency (Hz); NaN with fewer than 8 columns.

    Examples
    --------
    A spread that widens 1.7 times per second over 6 s at 25 columns/s:

    >>> t = np.arange(150) / 25.0
    >>> v = np.linspace(-4.0, 4.0, 64)
    >>> width = 1.0 + 0.8 * np.abs(np.sin(np.pi * 1.7 * t))
    >>> p = np.where(np.abs(v)[None, :] <= width[:, None], 0.0, -60.0).astype(np.float32)
    >>> round(step_frequency_hz(Spectrogram(t, v, p)), 1)
    1.7
    """
    t = np.asarray(sg.time_s, dtype=np.float64)
    if t.size < 8:
        return float("nan")
    lower, upper = velocity_envelope(sg, threshold_db=threshold_db)
    spread = upper - lower
    ok = np.isfinite(spread)
    spread = np.where(ok, spread, np.nanmean(spread) if ok.any() else 0.0)
    rate = 1.0 / float(np.median(np.diff(t)))
    f, _ = spectral_peak(spread, sample_rate_hz=rate, band_hz=band_hz)
    return f


class SpectrogramBuffer:
    """Streaming spectrogram: a ring buffer of the last ``capacity`` columns.

    Feed it frame by frame (:meth:`push` a column, or :meth:`push_frame` a range cube);
    :meth:`spectrogram` returns the columns in time order. Memory is bounded:
    ``capacity × n_doppler`` float32 values, whatever the run's length.

    Parameters
    ----------
    velocity_mps : array_like, shape (doppler,)
        Velocity axis of the columns (m/s).
    capacity : int, keyword-only
        Most columns kept (e.g. history seconds × frame rate).

    Examples
    --------
    >>> buf = SpectrogramBuffer([-1.0, 0.0, 1.0], capacity=2)
    >>> for k in range(3):
    ...     buf.push(np.array([k, 0.0, 0.0]), time_s=0.1 * k)
    >>> sg = buf.spectrogram()
    >>> sg.time_s, sg.power_db[:, 0]
    (array([0.1, 0.2]), array([1., 2.], dtype=float32))
    """

    def __init__(self, velocity_mps: ArrayLike, *, capacity: int) -> None:
        if capacity < 1:
            raise ValueError(f"capacity must be >= 1, got {capacity}")
        self.velocity_mps = np.asarray(velocity_mps, dtype=np.float64).copy()
        self.capacity = int(capacity)
        self._power = np.full((self.capacity, self.velocity_mps.size), np.nan,
                              dtype=np.float32)
        self._time = np.full(self.capacity, np.nan)
        self._next = 0
        self.count = 0

    def clear(self) -> None:
        """Forget every column (e.g. when playback jumps back in time)."""
        self._next = 0
        self.count = 0

    def push(self, column_db: ArrayLike, *, time_s: float) -> None:
        """Append one column (dB, shape (doppler,)) at ``time_s`` (s)."""
        col = np.asarray(column_db, dtype=np.float32).reshape(-1)
        if col.size != self.velocity_mps.size:
            raise ValueError(f"column has {col.size} Doppler bins, the buffer "
                             f"{self.velocity_mps.size}")
        self._power[self._next] = col
        self._time[self._next] = float(time_s)
        self._next = (self._next + 1) % self.capacity
        self.count = min(self.count + 1, self.capacity)

    def push_frame(
        self,
        range_cube: ArrayLike,
        *,
        time_s: float,
        range_bins: ArrayLike,
        window: WindowName = "hann",
        sidelobe_db: float = 60.0,
        clutter_removal: bool = True,
    ) -> None:
        """Append the Doppler spectrum of one frame's range gate.

        Parameters
        ----------
        range_cube : array_like, shape (chirps, channels, range)
            The frame's range spectra.
        time_s : float, keyword-only
            The frame's time (s).
        range_bins : array_like of int, keyword-only
            Range gate.
        window, sidelobe_db, clutter_removal
            As in :func:`doppler_power_spectrum`; the FFT length is the buffer's
            number of Doppler bins.
        """
        p = doppler_power_spectrum(gate_slow_time(range_cube, range_bins=range_bins),
                                   window=window, sidelobe_db=sidelobe_db,
                                   fft_size=self.velocity_mps.size,
                                   clutter_removal=clutter_removal)
        self.push(power_to_db(p), time_s=time_s)

    def spectrogram(self) -> Spectrogram:
        """The kept columns, oldest first (a copy)."""
        idx = (self._next - self.count + np.arange(self.count)) % self.capacity
        return Spectrogram(self._time[idx].copy(), self.velocity_mps.copy(),
                           self._power[idx].copy())


__all__ = [
    "OBJECT_GATE_HALF_WIDTH_M",
    "Spectrogram",
    "SpectrogramBuffer",
    "doppler_column_from_map",
    "doppler_power_spectrum",
    "frame_spectrogram",
    "gate_bins",
    "gate_slow_time",
    "step_frequency_hz",
    "stft_spectrogram",
    "uniform_segments",
    "velocity_envelope",
]
