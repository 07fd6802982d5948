"""Named radar configurations: ``bgt60tr13c`` and a 2-Tx × 4-Rx TDM-MIMO radar."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from simcore.scene.radar_arrays import l_shape, ula
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig


def bgt60tr13c(**overrides: Any) -> RadarConfig:
    """Infineon BGT60TR13C-like radar.

    60–66 GHz chirp in 256 µs, 512 real IF samples at 2 MHz (unambiguous range 6.4 m,
    range bin 2.5 cm), 16 chirps every 300 µs, 1 Tx and 3 Rx in an L with 2.5 mm (λ/2 at
    60 GHz) spacing, 12-bit ADC, the IF filters as Infineon's Radar SDK configures the
    chip by default: 80 kHz first-order high-pass and 500 kHz anti-aliasing low-pass
    (fourth-order Butterworth here; beat frequencies above it, i.e. ranges beyond
    ``500 kHz · c / (2 K) = 3.2 m``, are attenuated). ``overrides`` replace fields.
    """
    values: dict[str, Any] = {
        "preset": "bgt60tr13c",
        "start_frequency_hz": 60e9,
        "bandwidth_hz": 6e9,
        "chirp_time_s": 256e-6,
        "sample_rate_hz": 2e6,
        "samples_per_chirp": 512,
        "chirps_per_frame": 16,
        "chirp_repetition_time_s": 300e-6,
        "complex_iq": False,
        "tx": [Antenna(name="tx1", position_mm=(0.0, 0.0))],
        "rx": l_shape(2, 2, 0.5 * SPEED_OF_LIGHT / 60e9 * 1e3),
        "if_highpass_hz": 80e3,
        "if_lowpass_hz": 500e3,
    }
    values.update(overrides)
    return RadarConfig(**values)


def tdm_mimo_2tx4rx(**overrides: Any) -> RadarConfig:
    """2-Tx × 4-Rx TDM-MIMO radar with complex IQ sampling.

    60–64 GHz chirp in 64 µs, 256 complex samples at 4 MHz (range bin 3.75 cm,
    unambiguous range 9.6 m), 64 chirps per Tx with 100 µs between successive chirps
    (Tx1, Tx2, Tx1, …). Rx: 4-element ULA with λ/2 spacing at the centre frequency; Tx 2λ
    apart, so the 8 virtual channels form a λ/2 ULA (``virtual_positions_m``).
    """
    lam = SPEED_OF_LIGHT / 62e9 * 1e3  # mm, centre of the chirp
    values: dict[str, Any] = {
        "preset": "tdm_mimo_2tx4rx",
        "start_frequency_hz": 60e9,
        "bandwidth_hz": 4e9,
        "chirp_time_s": 64e-6,
        "sample_rate_hz": 4e6,
        "samples_per_chirp": 256,
        "chirps_per_frame": 64,
        "chirp_repetition_time_s": 100e-6,
        "complex_iq": True,
        "tx": ula(2, 2.0 * lam, prefix="tx", origin_mm=(-3.0 * lam, 0.0)),
        "rx": ula(4, 0.5 * lam, prefix="rx"),
        "if_highpass_hz": 150e3,
    }
    values.update(overrides)
    return RadarConfig(**values)


RADAR_PRESETS: dict[str, Callable[..., RadarConfig]] = {
    "bgt60tr13c": bgt60tr13c,
    "tdm_mimo_2tx4rx": tdm_mimo_2tx4rx,
}


def radar_preset(name: str, **overrides: Any) -> RadarConfig:
    """The preset called ``name`` (see :data:`RADAR_PRESETS`), with fields overridden."""
    try:
        factory = RADAR_PRESETS[name]
    except KeyError:
        raise ValueError(
            f"unknown radar preset {name!r}; known: {', '.join(sorted(RADAR_PRESETS))}"
        ) from None
    return factory(**overrides)
