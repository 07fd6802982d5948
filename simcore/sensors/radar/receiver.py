"""Receiver chain: Tx→Rx leakage, receiver noise, IF high-pass on the noise, ADC.

See ``docs/physics_radar.md`` section 4. All values in FS (fractions of the ADC full scale).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.sensors.radar.equation import (
    adc_noise_std_fs,
    coupling_amplitude_fs,
    if_filter_response,
    leakage_amplitude_fs,
    noise_std_fs,
)

ComplexCube = NDArray[np.complex128]


def coupling_paths(config: RadarConfig) -> list[tuple[float, float | None]]:
    """The static Tx→Rx coupling paths: (peak amplitude at the ADC in FS, length in m).

    The direct leakage first (length ``leakage_path_mm``, or ``None`` for the distance
    between each pair's elements), then every ``leakage_echoes`` path; none when
    ``leakage_dbc`` is None.
    """
    if config.leakage_dbc is None:
        return []
    direct = None if config.leakage_path_mm is None else config.leakage_path_mm * 1e-3
    paths: list[tuple[float, float | None]] = [(leakage_amplitude_fs(config), direct)]
    paths += [(coupling_amplitude_fs(config, e.level_dbc), e.path_mm * 1e-3)
              for e in config.leakage_echoes]
    return paths


def leakage_if(config: RadarConfig) -> ComplexCube:
    """Tx→Rx leakage of every pair: one tone per coupling path, all chirps equal.

    A path of length ``ℓ`` is a tone of delay ``τ = ℓ / c`` (the signal model of a
    scatterer), through the IF filters (:func:`coupling_paths`).

    Returns
    -------
    ndarray, shape (1, tx*rx, samples), complex128
        Complex IF in FS (broadcasts over chirps), IF filters applied.
    """
    n_tx, n_rx = len(config.tx), len(config.rx)
    t_n = config.sample_times_s()
    out = np.zeros((1, n_tx * n_rx, len(t_n)), dtype=np.complex128)
    p_tx, p_rx = config.tx_positions_m(), config.rx_positions_m()
    f_c, slope = config.start_frequency_hz, config.slope_hz_per_s
    for amp, length_m in coupling_paths(config):
        if amp == 0.0:
            continue
        for t in range(n_tx):
            for r in range(n_rx):
                ell = float(np.linalg.norm(p_tx[t] - p_rx[r])) if length_m is None else length_m
                tau = ell / SPEED_OF_LIGHT
                h = if_filter_response(slope * tau, config)
                out[0, t * n_rx + r] += amp * h * np.exp(1j * (
                    2 * np.pi * f_c * tau + 2 * np.pi * slope * tau * t_n
                    - np.pi * slope * tau**2))
    return out


def receiver_noise(config: RadarConfig, shape: tuple[int, ...], rng: np.random.Generator
                   ) -> NDArray[np.float64] | NDArray[np.complex128]:
    """Receiver noise: thermal through the IF filters, plus white noise added after them.

    Real or complex per ``complex_iq``.

    Parameters
    ----------
    config : RadarConfig
        The radar (noise level, filters, IQ).
    shape : tuple
        Output shape; the last axis is fast time (samples).
    rng : numpy.random.Generator
        Source of randomness.

    Returns
    -------
    ndarray
        Noise in FS: white noise of variance ``noise_std_fs(config)**2`` per real channel
        through the IF high-pass and anti-aliasing filter, plus white noise of variance
        ``adc_noise_std_fs(config)**2`` (the baseband stages and ADC after the filters).
    """
    sigma = noise_std_fs(config)
    noise = _white(sigma, shape, rng, complex_iq=config.complex_iq)
    if (config.if_highpass_hz > 0 or config.if_lowpass_hz > 0) and sigma > 0:
        n = shape[-1]
        if config.complex_iq:
            f = np.fft.fftfreq(n, 1.0 / config.sample_rate_hz)
            h = if_filter_response(f, config)
            noise = np.fft.ifft(np.fft.fft(noise, axis=-1) * h, axis=-1)
        else:
            f = np.fft.rfftfreq(n, 1.0 / config.sample_rate_hz)
            h = if_filter_response(f, config)
            noise = np.fft.irfft(np.fft.rfft(noise, axis=-1) * h, n=n, axis=-1)
    sigma_adc = adc_noise_std_fs(config)
    if sigma_adc > 0:
        noise = noise + _white(sigma_adc, shape, rng, complex_iq=config.complex_iq)
    return noise


def _white(sigma: float, shape: tuple[int, ...], rng: np.random.Generator, *,
           complex_iq: bool) -> NDArray[np.float64] | NDArray[np.complex128]:
    """White Gaussian noise of standard deviation ``sigma`` per real channel."""
    if complex_iq:
        return sigma * (rng.standard_normal(shape) + 1j * rng.standard_normal(shape))
    return sigma * rng.standard_normal(shape)


def quantize(x: NDArray[np.float64], bits: int | None) -> tuple[NDArray[np.float64], int]:
    """Round to the ADC grid and clip at full scale (FS units).

    The LSB is ``2 / 2**bits``; codes run from ``-2**(bits-1)`` to ``2**(bits-1) - 1``.

    Returns
    -------
    quantized : ndarray, same shape as ``x``
        Quantized values (FS).
    clipped : int
        Number of values that exceeded full scale.
    """
    if bits is None:
        return x, 0
    half = 2 ** (bits - 1)
    codes = np.rint(x * half)
    clipped = int(np.count_nonzero((codes < -half) | (codes > half - 1)))
    return np.clip(codes, -half, half - 1) / half, clipped


def receiver_chain(ideal: ComplexCube, config: RadarConfig, rng: np.random.Generator
                   ) -> tuple[NDArray[np.float32] | NDArray[np.complex64], int]:
    """Leakage, noise, quantization: the ADC cube from the noise-free complex IF.

    With ``config.ideal`` the noise and the quantisation are left out (leakage stays).

    Parameters
    ----------
    ideal : ndarray, shape (chirps, tx*rx, samples), complex128
        Output of :func:`synthesize_if` (FS).
    config : RadarConfig
        Receiver settings.
    rng : numpy.random.Generator
        Source of the noise.

    Returns
    -------
    adc : ndarray, shape (chirps, tx*rx, samples)
        float32 (real IF) or complex64 (IQ), FS.
    clipped : int
        Number of real values (I and Q counted separately) clipped at full scale.
    """
    x = ideal + leakage_if(config)
    # The ideal sensor (config.ideal): no noise drawn, no ADC grid, no clipping.
    noise = (np.zeros_like(x) if config.ideal
             else receiver_noise(config, x.shape, rng))
    bits = None if config.ideal else config.adc_bits
    if config.complex_iq:
        z = x + noise
        i_q, c_i = quantize(z.real, bits)
        q_q, c_q = quantize(z.imag, bits)
        return (i_q + 1j * q_q).astype(np.complex64), c_i + c_q
    real, clipped = quantize(x.real + noise.real, bits)
    return real.astype(np.float32), clipped


__all__ = ["coupling_paths", "leakage_if", "quantize", "receiver_chain", "receiver_noise"]
