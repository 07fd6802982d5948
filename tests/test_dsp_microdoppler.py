"""Known-answer tests of the micro-Doppler spectrogram on raw FMCW cubes built with numpy.

Scatterers on the boresight with a known radial velocity — constant, or sinusoidal like
a swinging limb — are synthesised by :mod:`tests.fmcw_synth` at each chirp's true time;
the spectrogram's strongest Doppler bin must sit at that velocity (positive = moving
away) within one bin, frame after frame.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.dsp import DspConfig, process_frame, range_fft
from simcore.dsp.microdoppler import (
    SpectrogramBuffer,
    doppler_column_from_map,
    frame_spectrogram,
    gate_bins,
    gate_slow_time,
    step_frequency_hz,
    stft_spectrogram,
    uniform_segments,
    velocity_envelope,
)
from simcore.dsp.processing import radar_axes
from simcore.scene.radar_config import RadarConfig
from tests.fmcw_synth import chirp_times, synth_frames

FRAME_RATE_HZ = 20.0


def preset(*, complex_iq: bool = False) -> RadarConfig:
    """The BGT60TR13C-like preset (real IF, 3 Rx, 16 chirps 300 µs apart), or its IQ twin."""
    return RadarConfig(complex_iq=complex_iq)


def doppler_bin_mps(rc: RadarConfig, fft_size: int) -> float:
    return rc.wavelength_m / (2 * fft_size * len(rc.tx) * rc.chirp_repetition_time_s)


@pytest.mark.parametrize(("complex_iq", "velocity"), [(False, 1.3), (False, -0.8),
                                                      (True, 2.1)])
def test_constant_velocity_lands_in_its_bin_in_every_frame(complex_iq: bool,
                                                           velocity: float) -> None:
    rc = preset(complex_iq=complex_iq)
    frames = np.arange(20) / FRAME_RATE_HZ

    def target(t: np.ndarray) -> np.ndarray:
        return 2.0 + velocity * t

    adc = synth_frames(rc, [(target, 0.05), (lambda t: 1.2 + 0 * t, 0.2)], frames,
                       noise_std=0.01, seed=1)
    cubes = [range_fft(c) for c in adc]
    r = radar_axes(rc, DspConfig()).range_m
    t_frame = chirp_times(rc, frames).mean(axis=1)
    gates = [gate_bins(r, min_m=target(t) - 0.1, max_m=target(t) + 0.1) for t in t_frame]
    sg = frame_spectrogram(cubes, t_frame, range_bins=gates,
                           chirp_interval_s=rc.chirp_repetition_time_s,
                           wavelength_m=rc.wavelength_m)
    assert sg.power_db.shape == (20, 32)
    dv = doppler_bin_mps(rc, 32)
    assert_allclose(sg.velocity_mps[1] - sg.velocity_mps[0], dv, rtol=1e-12)
    assert np.all(np.abs(sg.peak_velocity_mps() - velocity) <= dv)
    assert_allclose(sg.time_s, t_frame)


@pytest.mark.parametrize("complex_iq", [False, True])
def test_swinging_point_traces_its_sinusoidal_velocity(complex_iq: bool) -> None:
    """A limb-like point, v(t) = V cos(2π f t), beside a static torso (clutter removed)."""
    rc = preset(complex_iq=complex_iq)
    v_max, f = 2.5, 0.8
    frames = np.arange(int(2.5 * FRAME_RATE_HZ)) / FRAME_RATE_HZ

    def limb(t: np.ndarray) -> np.ndarray:
        return 1.5 + v_max / (2 * np.pi * f) * np.sin(2 * np.pi * f * t)

    adc = synth_frames(rc, [(limb, 0.05), (lambda t: 1.5 + 0 * t, 0.5)], frames,
                       noise_std=0.01, seed=2)
    cubes = np.stack([range_fft(c) for c in adc])
    r = radar_axes(rc, DspConfig()).range_m
    t_frame = chirp_times(rc, frames).mean(axis=1)
    sg = frame_spectrogram(cubes, t_frame, range_bins=gate_bins(r, min_m=0.8, max_m=2.2),
                           chirp_interval_s=rc.chirp_repetition_time_s,
                           wavelength_m=rc.wavelength_m, window="hann")
    truth = v_max * np.cos(2 * np.pi * f * t_frame)
    dv = doppler_bin_mps(rc, sg.velocity_mps.size)
    peak = sg.peak_velocity_mps()
    # Clutter removal (each frame's mean) also removes a mover slower than one Doppler
    # resolution cell λ/(2 N T): those frames show the torso's residue, not the limb.
    resolution = rc.wavelength_m / (2 * rc.chirps_per_frame * rc.chirp_repetition_time_s)
    moving = np.abs(truth) > resolution
    assert moving.sum() > 0.6 * truth.size
    assert np.all(np.abs(peak - truth)[moving] <= dv + 1e-9)
    assert abs(peak.max() - v_max) <= dv and abs(peak.min() + v_max) <= dv


def test_stft_runs_across_contiguous_frames_with_finer_doppler() -> None:
    """Frames back to back (period = burst): 64-chirp segments span four frames."""
    rc = preset()
    period = rc.chirps_per_frame * rc.chirp_repetition_time_s
    frames = np.arange(120) * period
    v_max, f = 1.5, 0.5

    def mover(t: np.ndarray) -> np.ndarray:
        return 1.5 + v_max / (2 * np.pi * f) * np.sin(2 * np.pi * f * t + 0.3)

    adc = synth_frames(rc, [(mover, 0.05)], frames, noise_std=0.01, seed=4)
    r = radar_axes(rc, DspConfig()).range_m
    bins = gate_bins(r, min_m=1.0, max_m=2.0)
    slow = np.concatenate([gate_slow_time(range_fft(c), range_bins=bins) for c in adc])
    t = chirp_times(rc, frames).reshape(-1)
    sg = stft_spectrogram(slow, t, chirp_interval_s=rc.chirp_repetition_time_s,
                          wavelength_m=rc.wavelength_m, segment_length=64, overlap=0.75)
    n_chirps = t.size
    assert sg.power_db.shape == ((n_chirps - 64) // 16 + 1, 128)
    truth = v_max * np.cos(2 * np.pi * f * sg.time_s + 0.3)
    resolution = rc.wavelength_m / (2 * 64 * rc.chirp_repetition_time_s)
    moving = np.abs(truth) > resolution             # slower ones: removed as clutter
    assert moving.sum() > 0.8 * truth.size
    assert np.all(np.abs(sg.peak_velocity_mps() - truth)[moving] <= resolution / 2)


def test_stft_segments_never_straddle_the_inter_frame_gap() -> None:
    rc = preset()
    frames = np.arange(10) / FRAME_RATE_HZ        # 4.8 ms bursts every 50 ms
    adc = synth_frames(rc, [(lambda t: 1.0 + 0.9 * t, 0.05)], frames, noise_std=0.01)
    r = radar_axes(rc, DspConfig()).range_m
    bins = gate_bins(r, min_m=0.8, max_m=1.6)
    slow = np.concatenate([gate_slow_time(range_fft(c), range_bins=bins) for c in adc])
    t = chirp_times(rc, frames).reshape(-1)
    kw = {"chirp_interval_s": rc.chirp_repetition_time_s, "wavelength_m": rc.wavelength_m}
    sg = stft_spectrogram(slow, t, segment_length=8, overlap=0.5, **kw)
    assert sg.power_db.shape[0] == 10 * 3           # starts 0, 4, 8 inside each frame
    dv = doppler_bin_mps(rc, 16)
    assert np.all(np.abs(sg.peak_velocity_mps() - 0.9) <= dv)
    assert stft_spectrogram(slow, t, segment_length=32, **kw).power_db.shape == (0, 64)
    assert_array_equal(uniform_segments(t[:32], chirp_interval_s=rc.chirp_repetition_time_s,
                                        segment_length=16, hop=16), [0, 16])


def test_streaming_buffer_matches_the_batch_spectrogram_and_stays_bounded() -> None:
    rc = preset()
    frames = np.arange(12) / FRAME_RATE_HZ
    adc = synth_frames(rc, [(lambda t: 1.5 - 1.1 * t, 0.05)], frames, noise_std=0.01)
    cubes = [range_fft(c) for c in adc]
    r = radar_axes(rc, DspConfig()).range_m
    bins = gate_bins(r, min_m=0.5, max_m=2.0)
    kw = {"chirp_interval_s": rc.chirp_repetition_time_s, "wavelength_m": rc.wavelength_m}
    batch = frame_spectrogram(cubes, frames, range_bins=bins, **kw)
    buf = SpectrogramBuffer(batch.velocity_mps, capacity=5)
    for c, t in zip(cubes, frames, strict=True):
        buf.push_frame(c, time_s=float(t), range_bins=bins)
    sg = buf.spectrogram()
    assert sg.power_db.shape == (5, 32)
    assert_allclose(sg.time_s, frames[-5:])
    assert_allclose(sg.power_db, batch.power_db[-5:], atol=1e-4)
    assert np.all(np.abs(sg.peak_velocity_mps() + 1.1) <= doppler_bin_mps(rc, 32))


def test_column_from_the_range_doppler_map_peaks_at_the_target_velocity() -> None:
    """What the live panel draws: the processed frame's map summed over the gate."""
    rc = preset()
    adc = synth_frames(rc, [(lambda t: 1.7 + 1.6 * t, 0.05)], np.zeros(1), noise_std=0.01)
    prod = process_frame(adc[0], rc, DspConfig())
    bins = gate_bins(prod.axes.range_m, min_m=1.5, max_m=1.9)
    col = doppler_column_from_map(prod.range_doppler_db, range_bins=bins)
    v = prod.axes.velocity_mps
    assert abs(v[int(np.argmax(col))] - 1.6) <= v[1] - v[0]


def test_gate_and_config_validation() -> None:
    assert_array_equal(gate_bins([0.0, 1.0, 2.0], min_m=5.0, max_m=6.0), [2])
    with pytest.raises(ValueError, match="below"):
        gate_bins([0.0, 1.0], min_m=1.0, max_m=0.5)
    with pytest.raises(ValueError, match="overlap"):
        stft_spectrogram(np.zeros(8), np.arange(8.0), chirp_interval_s=1.0,
                         wavelength_m=1.0, segment_length=4, overlap=1.0)
    assert DspConfig().spectrogram_mode == "frame"
    with pytest.raises(ValueError, match="spectrogram_range_m"):
        DspConfig(spectrogram_range_m=(2.0, 1.0))
    with pytest.raises(ValueError, match="spectrogram_overlap"):
        DspConfig(spectrogram_overlap=1.5)


def test_walker_legs_set_the_envelope_and_the_step_frequency() -> None:
    """Torso at −v, two legs swinging ±1.4 v about it in antiphase, cycle T (Boulic)."""
    rc = preset()
    v, period = 1.15, 1.346 / np.sqrt(1.15 / 0.9)          # 1.18 s at 1.15 m/s
    w = 2 * np.pi / period
    frames = np.arange(100) / 25.0

    def part(swing: float, phase: float):
        return lambda t: 5.0 - v * t + v * swing / w * (np.cos(w * t + phase) - np.cos(phase))

    adc = synth_frames(rc, [(part(0.0, 0.0), 0.05), (part(1.4, 0.0), 0.02),
                            (part(1.4, np.pi), 0.02)], frames, noise_std=0.01, seed=6)
    r = radar_axes(rc, DspConfig()).range_m
    t_frame = chirp_times(rc, frames).mean(axis=1)
    gates = [gate_bins(r, min_m=5.0 - v * t - 0.6, max_m=5.0 - v * t + 0.6) for t in t_frame]
    sg = frame_spectrogram([range_fft(c) for c in adc], t_frame, range_bins=gates,
                           chirp_interval_s=rc.chirp_repetition_time_s,
                           wavelength_m=rc.wavelength_m)
    assert np.all(np.abs(sg.peak_velocity_mps() + v) <= doppler_bin_mps(rc, 32))  # torso
    lower, upper = velocity_envelope(sg, threshold_db=25.0)
    legs = -v * (1 + 1.4 * np.abs(np.sin(w * t_frame)))     # the faster leg, approaching
    resolution = rc.wavelength_m / (2 * rc.chirps_per_frame * rc.chirp_repetition_time_s)
    # The envelope is the leg's line widened by the Hann mainlobe down to the threshold
    # (the legs are 8 dB below the torso, so 17 dB down their own mainlobe: ≈ 1.4 cells);
    # a few columns where torso and legs interfere reach down to noise at the band edge.
    near = np.abs(lower - legs) <= 2 * resolution
    assert near.mean() >= 0.9
    assert np.corrcoef(lower[near], legs[near])[0, 1] > 0.9
    assert abs(step_frequency_hz(sg, threshold_db=25.0) - 2 / period) < 0.05
