"""The radar equation, element patterns and the IF high-pass: a scatterer's IF amplitude.

One function, :func:`if_amplitude_fs`, turns a scatterer's RCS, the element gains towards it
and its distances to the Tx and the Rx into the peak amplitude of its IF tone at the ADC
(in FS, fractions of the ADC full scale). The fast synthesis, the direct sum and the
calibration constant :func:`amplitude_scale_fs` all go through it (``docs/physics_radar.md``,
"Radar equation calibration").
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import RegularGridInterpolator

from simcore.scene.radar_config import CosinePattern, ElementPattern, RadarConfig, TablePattern

BOLTZMANN = 1.380649e-23
#: Reference noise temperature of the noise figure (K).
T0_K = 290.0
#: Reference impedance of the power → voltage conversion at the Rx port (Ω).
R_REF_OHM = 50.0

_Array = TypeVar("_Array", NDArray[np.float32], NDArray[np.float64], float)


def if_amplitude_fs(config: RadarConfig, rcs_m2: _Array, gain_tx: _Array, gain_rx: _Array,
                    range_tx_m: _Array, range_rx_m: _Array) -> _Array:
    """Peak IF amplitude at the ADC of a scatterer, from the radar equation (FS).

    The scatterer receives ``P_r = P_t G_t g_t G_r g_r λ² σ / ((4π)³ R_t² R_r²)`` at the Rx
    port; the receiver turns it into a tone of peak voltage ``√(2 R_ref P_r) · 10^(G_IF/20)``
    at the ADC input, i.e. ``√(2 R_ref P_r) · 10^(G_IF/20) / V_fs`` in FS. ``P_t`` =
    ``tx_power_dbm``, ``G_t``, ``G_r`` = ``tx_gain_dbi``, ``rx_gain_dbi`` (boresight), λ the
    centre wavelength, ``G_IF`` = ``if_gain_db``, ``V_fs`` = ``adc_full_scale_v``. The IF
    high-pass is not included.

    Parameters
    ----------
    config : RadarConfig
        Powers, gains, wavelength, receiver gain and full scale.
    rcs_m2 : float or ndarray, shape (M,)
        Radar cross-section σ (m²).
    gain_tx, gain_rx : float or ndarray, shape (M,)
        Element power patterns ``g_t``, ``g_r`` relative to boresight, towards the scatterer.
    range_tx_m, range_rx_m : float or ndarray, shape (M,)
        Distances scatterer–Tx and scatterer–Rx (m).

    Returns
    -------
    float or ndarray, shape (M,)
        Amplitude (FS), in the precision of the arrays given (float32 stays float32).
    """
    p_t = 1e-3 * 10.0 ** (config.tx_power_dbm / 10.0)
    g = 10.0 ** ((config.tx_gain_dbi + config.rx_gain_dbi) / 10.0)
    lam = config.wavelength_m
    volts = np.sqrt(2.0 * R_REF_OHM * p_t * g * lam**2 / (4.0 * np.pi) ** 3)
    scale = float(volts * 10.0 ** (config.if_gain_db / 20.0) / config.adc_full_scale_v)
    out: _Array = scale * np.sqrt(rcs_m2 * gain_tx * gain_rx) / (range_tx_m * range_rx_m)
    return out


def amplitude_scale_fs(config: RadarConfig) -> float:
    """Calibration constant ``C``: :func:`if_amplitude_fs` at σ = 1 m², g = 1, R = 1 m.

    ``C = √(2 R_ref P_t G_t G_r λ² / (4π)³) · 10^(if_gain_db/20) / V_fs`` (FS · m / √m²);
    a scatterer's amplitude is ``C √(σ g_t g_r) / (R_t R_r)``.
    """
    return float(if_amplitude_fs(config, 1.0, 1.0, 1.0, 1.0, 1.0))


def noise_std_fs(config: RadarConfig) -> float:
    """Receiver noise standard deviation per real channel (I or Q) at the ADC (FS).

    ``noise_variance_adc`` when set; otherwise thermal noise ``k T0 F B R_ref`` in the
    Nyquist band ``B = f_s / 2`` of each real channel, referred to the ADC input through
    the IF gain.
    """
    if config.noise_variance_adc is not None:
        return float(np.sqrt(config.noise_variance_adc))
    f = 10.0 ** (config.noise_figure_db / 10.0)
    power = BOLTZMANN * T0_K * f * 0.5 * config.sample_rate_hz
    volts = np.sqrt(power * R_REF_OHM) * 10.0 ** (config.if_gain_db / 20.0)
    return float(volts / config.adc_full_scale_v)


def adc_noise_std_fs(config: RadarConfig) -> float:
    """Standard deviation of the noise added after the IF filters, per real channel (FS).

    ``adc_noise_fs``, or 0 when ``noise_variance_adc`` replaces the noise model.
    """
    return 0.0 if config.noise_variance_adc is not None else float(config.adc_noise_fs)


def coupling_amplitude_fs(config: RadarConfig, level_dbc: float) -> float:
    """Peak amplitude at the ADC of a coupling path of power ``level_dbc`` re the Tx (FS).

    ``√(2 R_ref P_t 10^(level_dbc/10)) · 10^(G_IF/20) / V_fs``, before the IF filters.
    """
    p = 1e-3 * 10.0 ** ((config.tx_power_dbm + level_dbc) / 10.0)
    volts = np.sqrt(2.0 * R_REF_OHM * p) * 10.0 ** (config.if_gain_db / 20.0)
    return float(volts / config.adc_full_scale_v)


def leakage_amplitude_fs(config: RadarConfig) -> float:
    """Peak amplitude of the Tx→Rx leakage tone at the ADC, before the high-pass (FS)."""
    if config.leakage_dbc is None:
        return 0.0
    return coupling_amplitude_fs(config, config.leakage_dbc)


def butterworth_poles(order: int) -> NDArray[np.complex128]:
    """The ``order`` poles of a Butterworth filter normalised to a 1 rad/s cutoff.

    They lie on the unit circle in the left half plane, ``exp(jπ(2k + n − 1)/(2n))``.

    Examples
    --------
    >>> np.round(butterworth_poles(2), 6)
    array([-0.707107+0.707107j, -0.707107-0.707107j])
    """
    k = np.arange(1, order + 1)
    return np.exp(1j * np.pi * (2 * k + order - 1) / (2 * order))


def highpass_response(freq_hz: NDArray[np.floating] | float, cutoff_hz: float, order: int
                      ) -> NDArray[np.complex128]:
    """Frequency response of an analog Butterworth high-pass, ``H(j 2π f)``.

    ``H(s) = Π_k s / (s − p_k)`` with the ``order`` Butterworth poles ``p_k`` on the circle of
    radius ``2π cutoff_hz`` in the left half plane; ``|H|² = x^{2n} / (1 + x^{2n})`` with
    ``x = f / cutoff``. ``cutoff_hz = 0`` gives ``H = 1``. Negative frequencies (complex IQ)
    get ``H(−f) = conj H(f)``.
    """
    f = np.asarray(freq_hz, dtype=np.float64)
    if cutoff_hz <= 0:
        return np.ones(f.shape, dtype=np.complex128)
    s = 2j * np.pi * f
    h = np.ones(f.shape, dtype=np.complex128)
    for p in 2 * np.pi * cutoff_hz * butterworth_poles(order):
        h *= s / (s - p)
    return h


def lowpass_response(freq_hz: NDArray[np.floating] | float, cutoff_hz: float, order: int
                     ) -> NDArray[np.complex128]:
    """Frequency response of an analog Butterworth low-pass, ``H(j 2π f)``.

    ``H(s) = Π_k (−p_k) / (s − p_k)`` with the Butterworth poles ``p_k`` of
    :func:`highpass_response`; ``|H|² = 1 / (1 + x^{2n})``, ``x = f / cutoff``.
    ``cutoff_hz = 0`` gives ``H = 1``.

    Examples
    --------
    >>> round(float(abs(lowpass_response(2e6, 1e6, 4)) ** 2), 6)   # 1 / (1 + 2⁸)
    0.003891
    """
    f = np.asarray(freq_hz, dtype=np.float64)
    if cutoff_hz <= 0:
        return np.ones(f.shape, dtype=np.complex128)
    s = 2j * np.pi * f
    h = np.ones(f.shape, dtype=np.complex128)
    for p in 2 * np.pi * cutoff_hz * butterworth_poles(order):
        h *= -p / (s - p)
    return h


def if_filter_response(freq_hz: NDArray[np.floating] | float, config: RadarConfig
                       ) -> NDArray[np.complex128]:
    """The IF chain's filters at beat frequency ``freq_hz``: high-pass × anti-aliasing."""
    return (highpass_response(freq_hz, config.if_highpass_hz, config.if_highpass_order)
            * lowpass_response(freq_hz, config.if_lowpass_hz, config.if_lowpass_order))


def element_gain(pattern: ElementPattern, directions: NDArray[np.floating]
                 ) -> NDArray[np.float64]:
    """Power gain of an element pattern relative to its boresight peak.

    Parameters
    ----------
    pattern : CosinePattern or TablePattern
        The element pattern.
    directions : ndarray, shape (M, 3)
        Directions in the radar optical frame (need not be unit vectors).

    Returns
    -------
    ndarray, shape (M,)
        Linear power gain (1 on boresight for a cosine pattern).
    """
    d = np.asarray(directions, dtype=np.float64)
    horiz = np.hypot(d[:, 0], d[:, 2])
    if isinstance(pattern, CosinePattern):
        # cos az = z / √(x² + z²), cos el = √(x² + z²) / |d|: no trigonometric calls.
        norm = np.hypot(horiz, d[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_az = np.where(horiz > 0, d[:, 2] / horiz, 1.0)
            cos_el = np.where(norm > 0, horiz / norm, 1.0)
            g = (np.maximum(cos_az, 0.0) ** pattern.exponent_az
                 * np.maximum(cos_el, 0.0) ** pattern.exponent_el)
        return np.asarray(g, dtype=np.float64)
    az = np.arctan2(d[:, 0], d[:, 2])
    el = np.arctan2(-d[:, 1], horiz)
    if isinstance(pattern, TablePattern):
        az_t = np.asarray(pattern.azimuth_deg)
        el_t = np.asarray(pattern.elevation_deg)
        interp = RegularGridInterpolator((el_t, az_t), np.asarray(pattern.gain_db))
        pts = np.stack([np.clip(np.degrees(el), el_t[0], el_t[-1]),
                        np.clip(np.degrees(az), az_t[0], az_t[-1])], axis=-1)
        return np.asarray(10.0 ** (interp(pts) / 10.0), dtype=np.float64)
    raise TypeError(f"unknown element pattern {pattern!r}")


def pattern_gains(config: RadarConfig, directions: NDArray[np.float64]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Element power patterns of every Tx and Rx towards ``directions`` (M, 3): (tx, M), (rx, M).

    Elements that share a pattern share one evaluation.
    """
    cache: dict[str, NDArray[np.float64]] = {}

    def gain(pattern: ElementPattern) -> NDArray[np.float64]:
        key = pattern.model_dump_json()
        if key not in cache:
            cache[key] = element_gain(pattern, directions)
        return cache[key]

    g_tx = np.array([gain(a.pattern or config.element_pattern) for a in config.tx])
    g_rx = np.array([gain(a.pattern or config.element_pattern) for a in config.rx])
    return g_tx.reshape(len(config.tx), -1), g_rx.reshape(len(config.rx), -1)


__all__ = ["BOLTZMANN", "R_REF_OHM", "T0_K", "adc_noise_std_fs", "amplitude_scale_fs",
           "butterworth_poles", "coupling_amplitude_fs",
           "element_gain",
           "highpass_response", "if_amplitude_fs", "if_filter_response", "leakage_amplitude_fs",
           "lowpass_response", "noise_std_fs", "pattern_gains"]
