"""Radar presets of the device library: TI IWR6843ISK, TI AWR1843BOOST, BGT60UTR11AIP.

Every number names its source in :data:`RADAR_SOURCES` (``docs/devices.md`` has the same
table); values that are not public are listed in :data:`RADAR_ASSUMPTIONS`. The TI
presets are the chirps of the mmWave SDK's own example configurations (``profile_2d.cfg``
of the xwr68xx and xwr18xx demos), mapped onto the model by
:func:`simcore.scene.ti_mmwave.radar_from_ti`.

Sources (cited by key below):

- ``[IWR6843-DS]`` TI, *IWR6843, IWR6443 Single-Chip 60- to 64-GHz mmWave Sensor*, data
  sheet SWRS219.
- ``[ISK-UG]`` TI, *IWR6843ISK(-ODS) Evaluation Module* user guide SWRU546 (antenna
  layout: 4 Rx λ/2 apart, Tx1 and Tx3 2λ apart, Tx2 between them raised by λ/2).
- ``[AWR1843-DS]`` TI, *AWR1843 Single-Chip 77- and 79-GHz FMCW Radar Sensor*, data sheet
  SWRS211.
- ``[AWR1843BOOST-UG]`` TI, *AWR1843BOOST Evaluation Module* user guide SPRUIM4 (same
  array topology as the ISK at 77 GHz).
- ``[SDK-CFG]`` TI mmWave SDK 3.x demo configurations ``xwr68xx/profile_2d.cfg`` and
  ``xwr18xx/profile_2d.cfg`` (text in ``tests/test_devices.py``).
- ``[SDK-UG]`` TI mmWave SDK user guide, CLI commands ``profileCfg``, ``frameCfg``,
  ``adcCfg`` (HPF codes, numADCBits, frame periodicity 0.1 ms … 1342 ms, numLoops 1 … 255,
  numAdcSamples up to 1024).
- ``[BGT60UTR11-DS]`` Infineon, *BGT60UTR11AIP* data sheet (58–63.5 GHz, 1 Tx, 1 Rx,
  antennas in package, 12-bit ADC).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from simcore.scene.radar_arrays import ula
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig
from simcore.scene.ti_mmwave import TiSettings, radar_from_ti


@dataclass(frozen=True)
class RadarLimits:
    """What a radar device can be configured to do.

    Attributes
    ----------
    band_hz : (float, float)
        Lowest start and highest stop frequency of a chirp (Hz).
    max_if_bandwidth_hz : float
        Widest IF (beat-frequency) band of the receiver (Hz).
    max_sample_rate_hz : float
        Fastest ADC sample rate in the radar's IF mode (complex for TI, real for Infineon).
    complex_iq : tuple of bool
        IF modes the device offers (``False`` real, ``True`` complex).
    max_samples_per_chirp, max_chirps_per_frame : int
        ADC samples per chirp; chirps (loops) per frame.
    max_tx, max_rx : int
        Transmitters and receivers on the chip.
    frame_rate_hz : (float, float)
        Slowest and fastest frame rate (Hz).
    adc_bits : tuple of int
        ADC resolutions the device offers.
    """

    band_hz: tuple[float, float]
    max_if_bandwidth_hz: float
    max_sample_rate_hz: float
    complex_iq: tuple[bool, ...]
    max_samples_per_chirp: int
    max_chirps_per_frame: int
    max_tx: int
    max_rx: int
    frame_rate_hz: tuple[float, float]
    adc_bits: tuple[int, ...]


# ----------------------------------------------------------------------------- TI
#: Board λ/2 of the ISK antennas: at 60.5 GHz (assumption: the design frequency is not in
#: the user guide), mm.
ISK_HALF_WAVELENGTH_MM = 0.5 * SPEED_OF_LIGHT / 60.5e9 * 1e3
#: AWR1843BOOST antennas: λ/2 at 77 GHz (assumption, as above), mm.
BOOST_HALF_WAVELENGTH_MM = 0.5 * SPEED_OF_LIGHT / 77e9 * 1e3


def ti_board_layout(half_wavelength_mm: float) -> tuple[list[Antenna], list[Antenna]]:
    """Tx1…Tx3 and Rx1…Rx4 of TI's ISK/BOOST boards ([ISK-UG], [AWR1843BOOST-UG]).

    Rx 1–4 along board x, λ/2 apart; Tx1 at the origin, Tx3 2λ to its right, Tx2 λ to the
    right of Tx1 and λ/2 up (board −y). The virtual array of Tx1+Tx3 is an 8-element λ/2
    ULA; Tx2 adds 4 elements one row up, shifted by 2 elements (azimuth and elevation).
    """
    d = half_wavelength_mm
    tx = [Antenna(name="tx1", position_mm=(0.0, 0.0)),
          Antenna(name="tx2", position_mm=(2 * d, -d)),
          Antenna(name="tx3", position_mm=(4 * d, 0.0))]
    return tx, ula(4, d, prefix="rx")


#: The xwr68xx demo's profile_2d.cfg chirp [SDK-CFG]: 60 GHz start, 359 µs idle, ADC at
#: 7 µs, ramp end 57.14 µs, 70 MHz/µs, 256 complex samples at 5209 ksps, Tx1, Tx2, Tx3,
#: 16 loops, 100 ms frames, 16-bit ADC (adcCfg 2 1), HPF codes 0 0, Rx gain 30 dB (158 =
#: 30 dB with bit 7 set).
IWR6843ISK_PROFILE_2D = TiSettings(
    start_freq_ghz=60.0, idle_time_us=359.0, adc_start_time_us=7.0, ramp_end_time_us=57.14,
    freq_slope_mhz_us=70.0, num_adc_samples=256, sample_rate_ksps=5209.0,
    tx_masks=(1, 2, 4), rx_mask=15, loops=16, frame_period_ms=100.0, complex_iq=True,
    adc_bits=16, hpf1=0, hpf2=0, rx_gain_db=158, tx_out_power=0, tx_start_time_us=1.0)
#: The xwr18xx demo's profile_2d.cfg chirp [SDK-CFG]: 77 GHz, 429 µs idle, otherwise as
#: above; Tx1 and Tx3 (channelCfg 15 5 0), 16 loops, 100 ms.
AWR1843_PROFILE_2D = TiSettings(
    start_freq_ghz=77.0, idle_time_us=429.0, adc_start_time_us=7.0, ramp_end_time_us=57.14,
    freq_slope_mhz_us=70.0, num_adc_samples=256, sample_rate_ksps=5209.0,
    tx_masks=(1, 4), rx_mask=15, loops=16, frame_period_ms=100.0, complex_iq=True,
    adc_bits=16, hpf1=0, hpf2=0, rx_gain_db=30, tx_out_power=0, tx_start_time_us=1.0)

IWR6843_LIMITS = RadarLimits(
    band_hz=(60e9, 64e9), max_if_bandwidth_hz=10e6, max_sample_rate_hz=12.5e6,
    complex_iq=(False, True), max_samples_per_chirp=1024, max_chirps_per_frame=255,
    max_tx=3, max_rx=4, frame_rate_hz=(1 / 1.342, 1e4), adc_bits=(12, 14, 16))
AWR1843_LIMITS = RadarLimits(
    band_hz=(76e9, 81e9), max_if_bandwidth_hz=10e6, max_sample_rate_hz=12.5e6,
    complex_iq=(False, True), max_samples_per_chirp=1024, max_chirps_per_frame=255,
    max_tx=3, max_rx=4, frame_rate_hz=(1 / 1.342, 1e4), adc_bits=(12, 14, 16))

#: Levels of the TI presets: datasheet Tx power and noise figure; antenna gain, IF gain
#: to full scale and leakage are assumptions (TI publishes the patterns only relatively).
IWR6843_LEVELS: dict[str, Any] = {
    "tx_power_dbm": 12.0, "noise_figure_db": 12.0, "tx_gain_dbi": 7.0, "rx_gain_dbi": 7.0,
    "if_gain_db": 30.0, "leakage_dbc": -40.0}
AWR1843_LEVELS: dict[str, Any] = {
    "tx_power_dbm": 12.0, "noise_figure_db": 14.0, "tx_gain_dbi": 10.5, "rx_gain_dbi": 10.5,
    "if_gain_db": 30.0, "leakage_dbc": -40.0}


def ti_iwr6843isk(**overrides: Any) -> RadarConfig:
    """TI IWR6843ISK: 60–64 GHz, 3 Tx × 4 Rx TDM-MIMO with a 2-D virtual array.

    The chirp and frame of the SDK's xwr68xx ``profile_2d.cfg`` [SDK-CFG]: 60 GHz + 70
    MHz/µs × 7 µs at the first sample (60.49 GHz), 256 complex samples at 5.209 Msps
    (49.1 µs, 3.44 GHz sampled: range resolution 4.4 cm, TI's maximum range 10.0 m),
    chirps every 416.14 µs in the order Tx1, Tx2, Tx3, 16 loops (velocity resolution
    0.125 m/s, ±1.0 m/s); 16-bit ADC; IF high-pass 175 kHz (HPF1 code 0, [SDK-UG]).
    Antennas: the ISK board [ISK-UG] (:func:`ti_board_layout`). Levels: Tx power 12 dBm
    and noise figure 12 dB [IWR6843-DS]; antenna gain 7 dBi, IF gain and leakage are
    assumptions. ``overrides`` replace fields.
    """
    tx, rx = ti_board_layout(ISK_HALF_WAVELENGTH_MM)
    cfg = radar_from_ti(IWR6843ISK_PROFILE_2D, tx_layout=tx, rx_layout=rx,
                        preset="ti_iwr6843isk", **IWR6843_LEVELS)
    return RadarConfig(**{**cfg.model_dump(), **overrides}) if overrides else cfg


def ti_awr1843boost(**overrides: Any) -> RadarConfig:
    """TI AWR1843BOOST: 76–81 GHz, Tx1 and Tx3 × 4 Rx TDM-MIMO (8-element λ/2 ULA).

    The chirp and frame of the SDK's xwr18xx ``profile_2d.cfg`` [SDK-CFG]: 77 GHz + 70
    MHz/µs × 7 µs (77.49 GHz at the first sample), 256 complex samples at 5.209 Msps
    (range resolution 4.4 cm), chirps every 486.14 µs, Tx1 then Tx3, 16 loops; 16-bit
    ADC. Antennas: the BOOST board [AWR1843BOOST-UG] (:func:`ti_board_layout` at 77 GHz).
    Levels: Tx power 12 dBm and noise figure 14 dB (76–77 GHz) [AWR1843-DS]; antenna gain
    10.5 dBi, IF gain and leakage are assumptions. ``overrides`` replace fields.
    """
    tx, rx = ti_board_layout(BOOST_HALF_WAVELENGTH_MM)
    cfg = radar_from_ti(AWR1843_PROFILE_2D, tx_layout=tx, rx_layout=rx,
                        preset="ti_awr1843boost", **AWR1843_LEVELS)
    return RadarConfig(**{**cfg.model_dump(), **overrides}) if overrides else cfg


# ------------------------------------------------------------------------ Infineon
BGT60UTR11_LIMITS = RadarLimits(
    band_hz=(58e9, 63.5e9), max_if_bandwidth_hz=1e6, max_sample_rate_hz=4e6,
    complex_iq=(False,), max_samples_per_chirp=1024, max_chirps_per_frame=4095,
    max_tx=1, max_rx=1, frame_rate_hz=(0.1, 1e3), adc_bits=(12,))
#: Infineon's BGT60TR13C (the ``bgt60tr13c`` preset), same family as the UTR11AIP.
BGT60TR13C_LIMITS = RadarLimits(
    band_hz=(58e9, 63.5e9), max_if_bandwidth_hz=1e6, max_sample_rate_hz=4e6,
    complex_iq=(False,), max_samples_per_chirp=1024, max_chirps_per_frame=4095,
    max_tx=1, max_rx=3, frame_rate_hz=(0.1, 1e3), adc_bits=(12,))


def infineon_bgt60utr11aip(**overrides: Any) -> RadarConfig:
    """Infineon BGT60UTR11AIP: 58–63.5 GHz, 1 Tx and 1 Rx in package, real IF.

    Band, antennas and 12-bit ADC from [BGT60UTR11-DS]. The chirp (58.5–62.5 GHz in
    64 µs, 128 real samples at 2 MHz: range resolution 3.75 cm, unambiguous range 2.4 m;
    32 chirps every 400 µs) is an assumption in the style of Infineon's Radar SDK
    examples (the SDK computes the chirp time as samples / sample rate); levels as the
    ``bgt60tr13c`` preset's (assumption). ``overrides`` replace fields.
    """
    values: dict[str, Any] = {
        "preset": "infineon_bgt60utr11aip", "start_frequency_hz": 58.5e9,
        "bandwidth_hz": 4e9, "chirp_time_s": 64e-6, "sample_rate_hz": 2e6,
        "samples_per_chirp": 128, "chirps_per_frame": 32, "chirp_repetition_time_s": 400e-6,
        "complex_iq": False, "tx": [Antenna(name="tx1", position_mm=(0.0, 0.0))],
        "rx": [Antenna(name="rx1", position_mm=(2.5, 0.0))], "adc_bits": 12,
        "tx_power_dbm": 5.0, "noise_figure_db": 12.0, "if_highpass_hz": 80e3,
        "if_lowpass_hz": 500e3}
    values.update(overrides)
    return RadarConfig(**values)


#: Device figures and where they come from: preset name → figure → source.
RADAR_SOURCES: dict[str, dict[str, str]] = {
    "ti_iwr6843isk": {
        "band 60–64 GHz, 3 Tx, 4 Rx": "[IWR6843-DS] features",
        "max IF bandwidth 10 MHz": "[IWR6843-DS] receiver specifications",
        "max complex sample rate 12.5 Msps": "[IWR6843-DS] receiver specifications",
        "Tx power 12 dBm, noise figure 12 dB": "[IWR6843-DS] RF specifications",
        "antenna layout": "[ISK-UG] antenna figure",
        "chirp and frame (profileCfg 0 60 359 7 57.14 0 0 70 1 256 5209 0 0 158, "
        "frameCfg 0 2 16 0 100 1 0)": "[SDK-CFG] xwr68xx profile_2d.cfg",
        "max 1024 samples, 255 loops, frame period 0.1–1342 ms, 12/14/16-bit ADC":
            "[SDK-UG] profileCfg, frameCfg, adcCfg",
    },
    "ti_awr1843boost": {
        "band 76–81 GHz, 3 Tx, 4 Rx": "[AWR1843-DS] features",
        "max IF bandwidth 10 MHz": "[AWR1843-DS] receiver specifications",
        "max complex sample rate 12.5 Msps": "[AWR1843-DS] receiver specifications",
        "Tx power 12 dBm, noise figure 14 dB": "[AWR1843-DS] RF specifications",
        "antenna layout": "[AWR1843BOOST-UG] antenna figure",
        "chirp and frame (profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30, "
        "frameCfg 0 1 16 0 100 1 0, channelCfg 15 5 0)": "[SDK-CFG] xwr18xx profile_2d.cfg",
        "max 1024 samples, 255 loops, frame period 0.1–1342 ms, 12/14/16-bit ADC":
            "[SDK-UG] profileCfg, frameCfg, adcCfg",
    },
    "infineon_bgt60utr11aip": {
        "band 58–63.5 GHz, 1 Tx, 1 Rx, 12-bit ADC": "[BGT60UTR11-DS] features",
    },
    "bgt60tr13c": {
        "band 58–63.5 GHz, 1 Tx, 3 Rx, 12-bit ADC": "Infineon BGT60TR13C data sheet",
        "levels": "calibrated against a recording (docs/physics_radar.md)",
    },
}
#: Values that are not public (assumptions), per preset.
RADAR_ASSUMPTIONS: dict[str, tuple[str, ...]] = {
    "ti_iwr6843isk": ("antenna design frequency 60.5 GHz (λ/2 = 2.48 mm)",
                      "antenna gain 7 dBi", "IF gain 30 dB to full scale", "leakage −40 dBc",
                      "HPF2 (350 kHz) not modelled"),
    "ti_awr1843boost": ("antenna design frequency 77 GHz (λ/2 = 1.95 mm)",
                        "antenna gain 10.5 dBi", "IF gain 30 dB to full scale",
                        "leakage −40 dBc", "HPF2 (350 kHz) not modelled"),
    "infineon_bgt60utr11aip": (
        "chirp 58.5–62.5 GHz, 128 samples at 2 MHz, 32 chirps every 400 µs",
        "max sample rate 4 MHz, max IF bandwidth 1 MHz (anti-aliasing filter), 1024 samples, "
        "4095 chirps, frame rate 0.1–1000 Hz", "levels as the BGT60TR13C's",
        "Rx 2.5 mm beside the Tx"),
    "bgt60tr13c": ("max sample rate 4 MHz, max IF bandwidth 1 MHz, 1024 samples, 4095 chirps, "
                   "frame rate 0.1–1000 Hz",
                   "the preset's 60–66 GHz chirp (the reference paper's) exceeds the "
                   "data sheet's 63.5 GHz: its limits are reported, not enforced"),
}
