"""Named radar configurations: ``bgt60tr13c``, a 2-Tx × 4-Rx TDM-MIMO radar, and the devices.

The device library's radars (TI IWR6843ISK, AWR1843BOOST, Infineon BGT60UTR11AIP) live in
:mod:`simcore.scene.device_radars`, with their sources and limits.

The BGT60TR13C's levels (transmit power, IF gain chain, noise, leakage) come from its vendor
settings through :func:`bgt60tr13c_levels`, calibrated against a real recording
(``docs/physics_radar.md``, "Calibration against a real BGT60TR13C").
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from simcore.scene.device_radars import (
    infineon_bgt60utr11aip,
    ti_awr1843boost,
    ti_iwr6843isk,
)
from simcore.scene.radar_arrays import l_shape, ula
from simcore.scene.radar_config import (
    SPEED_OF_LIGHT,
    Antenna,
    LeakageEcho,
    RadarConfig,
    default_l_rx,
)

# ----------------------------------------------------------------- BGT60TR13C calibration
#: Vendor settings range (Infineon Radar SDK, ``DeviceConfig.h``): IF gain 18…60 dB, Tx
#: power level 0…31.
IF_GAIN_DB_RANGE = (18, 60)
TX_POWER_LEVEL_RANGE = (0, 31)
#: Baseband gain steps (Radar SDK ``DeviceConfig.h``): the high-pass stage gives 18 or
#: 30 dB, the VGA 0…30 dB in 5 dB steps.
HP_GAIN_STEPS_DB = (18, 30)
VGA_GAIN_STEPS_DB = (0, 5, 10, 15, 20, 25, 30)
#: Transmit power at the antenna port at level 31 (dBm) and antenna gains (dBi):
#: representative values (not separable from the recording, see the calibration notes).
TX_POWER_MAX_DBM = 5.0
ANTENNA_GAIN_DBI = 6.0
#: Receiver noise figure (dB): representative value; the recording bounds it only together
#: with the RF conversion gain.
NOISE_FIGURE_DB = 12.0
#: Calibrated against the recording (docs/physics_radar.md): voltage conversion gain from
#: the Rx antenna port to the baseband input (LNA + mixer, dB), white noise after the IF
#: filters (FS rms), the direct Tx→Rx coupling (dBc, electrical length mm) and the
#: module/mount reflection (mm, dBc).
RF_CONVERSION_GAIN_DB = 22.8
ADC_NOISE_FS = 4.5e-4
LEAKAGE_DBC = -44.2
LEAKAGE_PATH_MM = 38.0
LEAKAGE_ECHOES: tuple[tuple[float, float], ...] = ((327.0, -102.0),)
#: Vendor settings the ``bgt60tr13c`` preset stands for (Radar SDK presence-sensing
#: defaults).
DEFAULT_DEVICE_SETTINGS: dict[str, Any] = {
    "tx_power_level": 31, "if_gain_dB": 33, "hp_cutoff_Hz": 80_000}


def baseband_gain_db(if_gain_db: float) -> int:
    """The IF gain the BGT60TR13C sets for a requested ``if_gain_dB`` (dB).

    As the Radar SDK documents it: the high-pass stage gain is 18 dB below 30 dB, else
    30 dB; the VGA step (0…30 dB by 5) brings the sum closest to the request.

    Examples
    --------
    >>> baseband_gain_db(23), baseband_gain_db(33), baseband_gain_db(60)
    (23, 35, 60)
    """
    hp = HP_GAIN_STEPS_DB[0] if if_gain_db < 30 else HP_GAIN_STEPS_DB[1]
    vga = min(VGA_GAIN_STEPS_DB, key=lambda g: (abs(hp + g - if_gain_db), g))
    return hp + vga


def tx_power_dbm(level: int) -> float:
    """Transmit power (dBm) of a ``tx_power_level``: ``P_max + 20 log10((level + 1) / 32)``.

    The level is taken to set the power amplifier's drive amplitude in 32 equal steps
    (assumption: no public table; level 31 = :data:`TX_POWER_MAX_DBM`).
    """
    return TX_POWER_MAX_DBM + 20.0 * math.log10((level + 1) / 32.0)


def bgt60tr13c_levels(*, tx_power_level: int = 31, if_gain_db: float = 33.0,
                      hp_cutoff_hz: float = 80e3, aaf_cutoff_hz: float = 0.0
                      ) -> dict[str, Any]:
    """The front-end fields of a BGT60TR13C at the given vendor settings.

    Parameters
    ----------
    tx_power_level : int
        0…31.
    if_gain_db : float
        Requested IF gain, 18…60 dB (:func:`baseband_gain_db` gives the gain set).
    hp_cutoff_hz, aaf_cutoff_hz : float
        High-pass and anti-aliasing cutoffs (Hz); ``aaf_cutoff_hz = 0``: no filter.

    Returns
    -------
    dict
        :class:`RadarConfig` fields: ``tx_power_dbm``, antenna gains, ``if_gain_db`` (RF
        conversion + baseband), noise figure, ``adc_noise_fs``, leakage, filters.
    """
    lo, hi = TX_POWER_LEVEL_RANGE
    if isinstance(tx_power_level, bool) or int(tx_power_level) != tx_power_level \
            or not lo <= tx_power_level <= hi:
        raise ValueError(f"tx_power_level = {tx_power_level!r}; the BGT60TR13C takes {lo}…{hi}")
    lo, hi = IF_GAIN_DB_RANGE
    if not lo <= if_gain_db <= hi:
        raise ValueError(f"if_gain_dB = {if_gain_db!r}; the BGT60TR13C takes {lo}…{hi} dB")
    if not 0 < hp_cutoff_hz or not 0 <= aaf_cutoff_hz:
        raise ValueError(f"hp_cutoff_Hz = {hp_cutoff_hz!r}, aaf_cutoff_Hz = {aaf_cutoff_hz!r}: "
                         "cutoffs must be positive")
    return {
        "tx_power_dbm": tx_power_dbm(int(tx_power_level)),
        "tx_gain_dbi": ANTENNA_GAIN_DBI, "rx_gain_dbi": ANTENNA_GAIN_DBI,
        "if_gain_db": RF_CONVERSION_GAIN_DB + baseband_gain_db(if_gain_db),
        "noise_figure_db": NOISE_FIGURE_DB, "adc_noise_fs": ADC_NOISE_FS,
        "leakage_dbc": LEAKAGE_DBC, "leakage_path_mm": LEAKAGE_PATH_MM,
        "leakage_echoes": [LeakageEcho(path_mm=p, level_dbc=d) for p, d in LEAKAGE_ECHOES],
        "if_highpass_hz": float(hp_cutoff_hz), "if_highpass_order": 1,
        "if_lowpass_hz": float(aaf_cutoff_hz), "if_lowpass_order": 4,
    }


def bgt60tr13c_from_device(settings: Mapping[str, Any], *, adc_bits: int = 12) -> RadarConfig:
    """A BGT60TR13C radar reproducing a vendor ``fmcw_single_shape`` configuration.

    Frequencies, timing (chirp time = samples / sample rate, as the Radar SDK defines it),
    antennas (Tx 1; Rx 1–3 of the L, :func:`default_l_rx`), filters, gain and Tx power
    level; the levels come from :func:`bgt60tr13c_levels`.

    Parameters
    ----------
    settings : mapping
        The keys of :data:`simcore.io.recordings.SINGLE_SHAPE_KEYS`, checked.
    adc_bits : int
        ADC resolution.

    Raises
    ------
    ValueError
        A setting the model cannot reproduce (down-chirp, antenna numbers the device lacks,
        values out of range).
    """
    f0, f1 = float(settings["start_frequency_Hz"]), float(settings["end_frequency_Hz"])
    if f1 <= f0:
        raise ValueError(f"end_frequency_Hz ({f1:.6g}) must be above start_frequency_Hz "
                         f"({f0:.6g}); down-chirps are not modelled")
    rx_layout = default_l_rx(0.5 * SPEED_OF_LIGHT / 60e9 * 1e3)
    bad_rx = [a for a in settings["rx_antennas"] if not 1 <= a <= len(rx_layout)]
    if bad_rx or list(settings["tx_antennas"]) != [1]:
        raise ValueError(f"tx_antennas {settings['tx_antennas']}, rx_antennas "
                         f"{settings['rx_antennas']}: the BGT60TR13C has Tx 1 and Rx 1–3")
    fs, n = float(settings["sample_rate_Hz"]), int(settings["num_samples_per_chirp"])
    levels = bgt60tr13c_levels(
        tx_power_level=settings["tx_power_level"], if_gain_db=float(settings["if_gain_dB"]),
        hp_cutoff_hz=float(settings["hp_cutoff_Hz"]),
        aaf_cutoff_hz=float(settings["aaf_cutoff_Hz"]))
    return RadarConfig(
        preset="bgt60tr13c", start_frequency_hz=f0, bandwidth_hz=f1 - f0,
        chirp_time_s=n / fs, sample_rate_hz=fs, samples_per_chirp=n,
        chirps_per_frame=int(settings["num_chirps_per_frame"]),
        chirp_repetition_time_s=float(settings["chirp_repetition_time_s"]),
        complex_iq=False, tx=[Antenna(name="tx1")],
        rx=[rx_layout[a - 1] for a in settings["rx_antennas"]], adc_bits=adc_bits,
        device_settings=dict(settings), **levels)


def bgt60tr13c(**overrides: Any) -> RadarConfig:
    """Infineon BGT60TR13C-like radar.

    60–66 GHz chirp in 256 µs, 512 real IF samples at 2 MHz (unambiguous range 6.4 m,
    range bin 2.5 cm), 16 chirps every 300 µs, 1 Tx and 3 Rx in an L with 2.5 mm (λ/2 at
    60 GHz) spacing, 12-bit ADC, the IF filters as Infineon's Radar SDK configures the
    chip by default: 80 kHz first-order high-pass and 500 kHz anti-aliasing low-pass
    (fourth-order Butterworth here; beat frequencies above it, i.e. ranges beyond
    ``500 kHz · c / (2 K) = 3.2 m``, are attenuated); levels of the device at
    :data:`DEFAULT_DEVICE_SETTINGS` (:func:`bgt60tr13c_levels`). ``overrides`` replace
    fields.
    """
    values: dict[str, Any] = {
        **bgt60tr13c_levels(
            tx_power_level=DEFAULT_DEVICE_SETTINGS["tx_power_level"],
            if_gain_db=DEFAULT_DEVICE_SETTINGS["if_gain_dB"],
            hp_cutoff_hz=DEFAULT_DEVICE_SETTINGS["hp_cutoff_Hz"]),
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
    # The device library's radars (simcore.scene.devices, docs/devices.md).
    "ti_iwr6843isk": ti_iwr6843isk,
    "ti_awr1843boost": ti_awr1843boost,
    "infineon_bgt60utr11aip": infineon_bgt60utr11aip,
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
