"""TI mmWave chirp settings (mmWave SDK ``profileCfg``/``chirpCfg``/``frameCfg``) ↔ radar model.

A TI chirp (mmWave SDK user guide, "profileCfg"; TI application note SWRA553, "Programming
Chirp Parameters in TI Radar Devices") starts at ``startFreq`` after ``idleTime``, ramps
with slope ``freqSlopeConst`` until ``rampEndTime``, and the ADC samples
``numAdcSamples`` at ``digOutSampleRate`` from ``adcStartTime`` after the ramp start. The
model's chirp starts where the ADC starts (``docs/physics_radar.md``), so::

    start_frequency_hz      = startFreq + S · adcStartTime
    chirp_time_s            = rampEndTime − adcStartTime
    bandwidth_hz            = S · chirp_time_s
    chirp_repetition_time_s = idleTime + rampEndTime

TDM-MIMO: ``chirpCfg`` entries ``chirpStartIdx … chirpEndIdx`` of ``frameCfg``, each with
one Tx enabled, are the chirp slots of a loop; a frame is ``numLoops`` loops. The
model's Tx list is in slot order, so its channel ``t · n_rx + r`` and TI's chirp
``loop · n_tx + t`` hold the same data (:mod:`simcore.io.ti_dca1000`).

The figures :func:`ti_figures` gives are the ones TI's tools print for a configuration
(mmWave Demo Visualizer's configuration header; SWRA553 eqs.): ``c = 3·10⁸ m/s``,
wavelength at ``startFreq``, usable IF bandwidth 90 % of the complex sample rate.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from simcore.scene.radar_config import Antenna, RadarConfig

#: Speed of light TI's tools use for their figures (m/s).
TI_SPEED_OF_LIGHT = 3e8
#: Fraction of the complex sample rate the digital IF filter passes (SWRA553; the
#: mmWave Demo Visualizer's maximum-range formula).
TI_IF_PASSBAND = 0.9
#: ``profileCfg`` high-pass corner codes (mmWave SDK user guide, profileCfg
#: ``hpfCornerFreq1``/``hpfCornerFreq2``), Hz.
HPF1_HZ = {0: 175e3, 1: 235e3, 2: 350e3, 3: 700e3}
HPF2_HZ = {0: 350e3, 1: 700e3, 2: 1.4e6, 3: 2.8e6}
#: ``adcCfg numADCBits`` codes → bits.
ADC_BITS = {0: 12, 1: 14, 2: 16}
#: Prefix of the TI settings kept in :attr:`RadarConfig.device_settings`.
KEY = "ti_"


@dataclass(frozen=True)
class TiSettings:
    """One TI mmWave configuration (one profile, its chirps, one frame), in TI's units.

    Attributes
    ----------
    start_freq_ghz, idle_time_us, adc_start_time_us, ramp_end_time_us : float
        ``profileCfg`` fields (GHz, µs).
    freq_slope_mhz_us : float
        Chirp slope (MHz/µs).
    num_adc_samples : int
        Samples per chirp.
    sample_rate_ksps : float
        ``digOutSampleRate`` (ksps).
    tx_masks : tuple of int
        ``chirpCfg txEnable`` of each chirp slot in frame order (bit k = Tx k+1).
    rx_mask : int
        ``channelCfg rxChannelEn``.
    loops : int
        ``frameCfg numLoops``.
    frame_period_ms : float
        ``frameCfg framePeriodicity`` (ms).
    num_frames : int
        ``frameCfg numFrames`` (0 = endless).
    complex_iq : bool
        ``adcCfg adcOutputFmt`` ≠ 0 (complex 1x/2x).
    adc_bits : int
        12, 14 or 16.
    hpf1, hpf2, rx_gain_db, tx_out_power, tx_start_time_us : int or float
        Remaining ``profileCfg`` fields, kept for writing the configuration back.
    """

    start_freq_ghz: float
    idle_time_us: float
    adc_start_time_us: float
    ramp_end_time_us: float
    freq_slope_mhz_us: float
    num_adc_samples: int
    sample_rate_ksps: float
    tx_masks: tuple[int, ...]
    rx_mask: int = 0b1111
    loops: int = 16
    frame_period_ms: float = 100.0
    num_frames: int = 0
    complex_iq: bool = True
    adc_bits: int = 16
    hpf1: int = 0
    hpf2: int = 0
    rx_gain_db: int = 30
    tx_out_power: int = 0
    tx_start_time_us: float = 1.0
    extra: dict[str, Any] = field(default_factory=dict, compare=False)

    # ----------------------------------------------------------------- derived
    @property
    def n_tx(self) -> int:
        """Chirp slots per loop (one Tx each)."""
        return len(self.tx_masks)

    @property
    def n_rx(self) -> int:
        """Enabled receivers."""
        return bin(self.rx_mask).count("1")

    @property
    def slope_hz_per_s(self) -> float:
        """Chirp slope (Hz/s)."""
        return self.freq_slope_mhz_us * 1e12

    @property
    def sample_rate_hz(self) -> float:
        """ADC sample rate (Hz)."""
        return self.sample_rate_ksps * 1e3

    @property
    def chirp_period_s(self) -> float:
        """``idleTime + rampEndTime`` (s)."""
        return (self.idle_time_us + self.ramp_end_time_us) * 1e-6


def ti_figures(s: TiSettings) -> dict[str, float]:
    """Range and velocity figures of a TI configuration, as TI's tools compute them.

    ``range_resolution_m = c f_s / (2 S N)`` (the bandwidth the ADC samples),
    ``max_range_m = 0.9 f_s c / (2 S)`` (complex; ``0.9 f_s / 2`` real),
    ``velocity_resolution_mps = λ / (2 N_loops N_tx T_c)``,
    ``max_velocity_mps = λ / (4 N_tx T_c)``, with ``c = 3·10⁸ m/s``,
    ``λ = c / startFreq`` and ``T_c = idleTime + rampEndTime`` (SWRA553; the mmWave Demo
    Visualizer's configuration header).

    Examples
    --------
    >>> s = TiSettings(60, 359, 7, 57.14, 70, 256, 5209, (1, 2, 4))
    >>> f = ti_figures(s)
    >>> round(f["range_resolution_m"], 3), round(f["max_velocity_mps"], 2)
    (0.044, 1.0)
    """
    c = TI_SPEED_OF_LIGHT
    lam = c / (s.start_freq_ghz * 1e9)
    if_max = TI_IF_PASSBAND * s.sample_rate_hz * (1.0 if s.complex_iq else 0.5)
    return {
        "range_resolution_m": c * s.sample_rate_hz / (2 * s.slope_hz_per_s * s.num_adc_samples),
        "max_range_m": if_max * c / (2 * s.slope_hz_per_s),
        "velocity_resolution_mps": lam / (2 * s.loops * s.n_tx * s.chirp_period_s),
        "max_velocity_mps": lam / (4 * s.n_tx * s.chirp_period_s),
    }


def _settings_dict(s: TiSettings) -> dict[str, int | float | str | list[int]]:
    """The TI settings as :attr:`RadarConfig.device_settings` entries (``ti_*``)."""
    return {
        f"{KEY}start_freq_ghz": s.start_freq_ghz, f"{KEY}idle_time_us": s.idle_time_us,
        f"{KEY}adc_start_time_us": s.adc_start_time_us,
        f"{KEY}ramp_end_time_us": s.ramp_end_time_us,
        f"{KEY}freq_slope_mhz_us": s.freq_slope_mhz_us,
        f"{KEY}num_adc_samples": s.num_adc_samples, f"{KEY}sample_rate_ksps": s.sample_rate_ksps,
        f"{KEY}tx_masks": list(s.tx_masks), f"{KEY}rx_mask": s.rx_mask, f"{KEY}loops": s.loops,
        f"{KEY}frame_period_ms": s.frame_period_ms, f"{KEY}num_frames": s.num_frames,
        f"{KEY}complex_iq": int(s.complex_iq), f"{KEY}adc_bits": s.adc_bits,
        f"{KEY}hpf1": s.hpf1, f"{KEY}hpf2": s.hpf2, f"{KEY}rx_gain_db": s.rx_gain_db,
        f"{KEY}tx_out_power": s.tx_out_power, f"{KEY}tx_start_time_us": s.tx_start_time_us,
    }


def radar_from_ti(s: TiSettings, *, tx_layout: list[Antenna], rx_layout: list[Antenna],
                  preset: str, **fields: Any) -> RadarConfig:
    """The model radar of a TI configuration.

    Parameters
    ----------
    s : TiSettings
        The configuration.
    tx_layout, rx_layout : list of Antenna
        The board's Tx 1, 2, 3 … and Rx 1, 2, 3 … (positions in mm); the configuration's
        chirp slots pick the Tx (in slot order), its ``rx_mask`` the Rx.
    preset : str
        Name of the device preset the radar belongs to.
    **fields
        Further :class:`RadarConfig` fields (levels, patterns).

    Raises
    ------
    ValueError
        A chirp slot enabling no Tx or several, a Tx or Rx the board lacks.
    """
    tx = []
    for slot, mask in enumerate(s.tx_masks):
        if mask <= 0 or mask & (mask - 1):
            raise ValueError(f"chirp slot {slot}: txEnable = {mask} must enable exactly one Tx "
                             "(TDM-MIMO; BPM-MIMO is not modelled)")
        k = mask.bit_length() - 1
        if k >= len(tx_layout):
            raise ValueError(f"chirp slot {slot}: txEnable = {mask} names Tx{k + 1}; the "
                             f"board has {len(tx_layout)} Tx")
        tx.append(tx_layout[k])
    rx = [rx_layout[k] for k in range(s.rx_mask.bit_length()) if s.rx_mask >> k & 1]
    if s.rx_mask >> len(rx_layout):
        raise ValueError(f"rxChannelEn = {s.rx_mask} names an Rx beyond the board's "
                         f"{len(rx_layout)}")
    if not rx:
        raise ValueError("rxChannelEn = 0 enables no receiver")
    slope = s.slope_hz_per_s
    chirp_time = (s.ramp_end_time_us - s.adc_start_time_us) * 1e-6
    return RadarConfig(
        preset=preset,
        start_frequency_hz=s.start_freq_ghz * 1e9 + slope * s.adc_start_time_us * 1e-6,
        bandwidth_hz=slope * chirp_time, chirp_time_s=chirp_time,
        sample_rate_hz=s.sample_rate_hz, samples_per_chirp=s.num_adc_samples,
        chirps_per_frame=s.loops, chirp_repetition_time_s=s.chirp_period_s,
        complex_iq=s.complex_iq, tx=tx, rx=rx, adc_bits=s.adc_bits,
        if_highpass_hz=HPF1_HZ.get(s.hpf1, HPF1_HZ[0]), if_highpass_order=1,
        device_settings=_settings_dict(s), **fields)


def _stored(config: RadarConfig) -> TiSettings | None:
    """The TI settings kept in ``config.device_settings``, if any."""
    d = config.device_settings or {}
    if f"{KEY}freq_slope_mhz_us" not in d:
        return None
    masks = d.get(f"{KEY}tx_masks", [1])
    return TiSettings(
        start_freq_ghz=float(d[f"{KEY}start_freq_ghz"]),  # type: ignore[arg-type]
        idle_time_us=float(d[f"{KEY}idle_time_us"]),  # type: ignore[arg-type]
        adc_start_time_us=float(d[f"{KEY}adc_start_time_us"]),  # type: ignore[arg-type]
        ramp_end_time_us=float(d[f"{KEY}ramp_end_time_us"]),  # type: ignore[arg-type]
        freq_slope_mhz_us=float(d[f"{KEY}freq_slope_mhz_us"]),  # type: ignore[arg-type]
        num_adc_samples=int(d[f"{KEY}num_adc_samples"]),  # type: ignore[arg-type]
        sample_rate_ksps=float(d[f"{KEY}sample_rate_ksps"]),  # type: ignore[arg-type]
        tx_masks=tuple(int(m) for m in masks),  # type: ignore[union-attr]
        rx_mask=int(d.get(f"{KEY}rx_mask", 15)),  # type: ignore[arg-type]
        loops=int(d.get(f"{KEY}loops", 16)),  # type: ignore[arg-type]
        frame_period_ms=float(d.get(f"{KEY}frame_period_ms", 100.0)),  # type: ignore[arg-type]
        num_frames=int(d.get(f"{KEY}num_frames", 0)),  # type: ignore[arg-type]
        complex_iq=bool(d.get(f"{KEY}complex_iq", 1)),
        adc_bits=int(d.get(f"{KEY}adc_bits", 16)),  # type: ignore[arg-type]
        hpf1=int(d.get(f"{KEY}hpf1", 0)), hpf2=int(d.get(f"{KEY}hpf2", 0)),  # type: ignore[arg-type]
        rx_gain_db=int(d.get(f"{KEY}rx_gain_db", 30)),  # type: ignore[arg-type]
        tx_out_power=int(d.get(f"{KEY}tx_out_power", 0)),  # type: ignore[arg-type]
        tx_start_time_us=float(d.get(f"{KEY}tx_start_time_us", 1.0)))  # type: ignore[arg-type]


def _slot_masks(config: RadarConfig, tx_layout: list[Antenna] | None) -> tuple[int, ...]:
    """``txEnable`` of each chirp slot: the board Tx each of ``config.tx`` is."""
    if tx_layout is None:
        return tuple(1 << t for t in range(len(config.tx)))
    masks = []
    for t, antenna in enumerate(config.tx):
        same = [k for k, a in enumerate(tx_layout) if a.position_mm == antenna.position_mm]
        masks.append(1 << (same[0] if same else t))
    return tuple(masks)


def ti_from_radar(config: RadarConfig, *, frame_period_s: float, num_frames: int = 0,
                  tx_layout: list[Antenna] | None = None) -> TiSettings:
    """The TI configuration that reproduces a model radar (inverse of :func:`radar_from_ti`).

    The ADC start time and the fields the model does not hold (gains, HPF2, Tx start) come
    from the radar's ``device_settings`` when it was made from a TI configuration, else
    ADC start 0 and TI's defaults. The Tx of each chirp slot and the Rx mask are the
    stored ones while the counts still match; otherwise Rx are numbered in list order
    (``rx_mask`` = the first ``n_rx`` bits) and Tx by their position on ``tx_layout``
    (else in list order).

    Raises
    ------
    ValueError
        More than 12 Tx or 4 Rx would not fit TI's masks (wider arrays are cascades).
    """
    if len(config.rx) > 4 or len(config.tx) > 12:
        raise ValueError(f"{len(config.tx)} Tx × {len(config.rx)} Rx: a TI mmWave "
                         "configuration has at most 4 Rx per device")
    stored = _stored(config)
    base = stored or TiSettings(0.0, 0.0, 0.0, 0.0, 0.0, 0, 0.0, (1,))
    adc_start = base.adc_start_time_us
    chirp_us = config.chirp_time_s * 1e6
    if config.chirp_repetition_time_s * 1e6 < adc_start + chirp_us:
        adc_start = 0.0
    slope = config.slope_hz_per_s
    ramp_end = adc_start + chirp_us
    masks = _slot_masks(config, tx_layout)
    if stored is not None and tx_layout is None and len(stored.tx_masks) == len(config.tx):
        masks = stored.tx_masks
    rx_mask = (1 << len(config.rx)) - 1
    if stored is not None and stored.n_rx == len(config.rx):
        rx_mask = stored.rx_mask
    return replace(
        base,
        start_freq_ghz=(config.start_frequency_hz - slope * adc_start * 1e-6) / 1e9,
        idle_time_us=max(0.0, config.chirp_repetition_time_s * 1e6 - ramp_end),
        adc_start_time_us=adc_start, ramp_end_time_us=ramp_end,
        freq_slope_mhz_us=slope / 1e12, num_adc_samples=config.samples_per_chirp,
        sample_rate_ksps=config.sample_rate_hz / 1e3,
        tx_masks=masks, rx_mask=rx_mask,
        loops=config.chirps_per_frame, frame_period_ms=frame_period_s * 1e3,
        num_frames=num_frames, complex_iq=config.complex_iq,
        adc_bits=config.adc_bits or 16)
