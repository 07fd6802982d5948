"""Configuration of the FMCW radar front end: waveform, antennas, receiver, render sampling.

Units are SI unless a field name says otherwise (``_mm``, ``_deg``, ``_db``, ``_dbm``,
``_dbi``). Antenna positions are on the radar board, which is the x–y plane of the radar's
optical frame (x right, y down, boresight z). ADC values are expressed as fractions of the
ADC full scale ("FS": ±1 is the largest code); see ``docs/physics_radar.md``.

The defaults describe an Infineon BGT60TR13C-like sensor: 60–66 GHz chirp, 1 Tx, 3 Rx in an
L with λ/2 (at 60 GHz) spacing, real IF sampled at 2 MHz by a 12-bit ADC, a first-order
80 kHz IF high-pass, 12 dB receiver noise figure and strong Tx→Rx leakage. Transmit power,
antenna gains, conversion gain and leakage are representative values, not measured ones.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, Union

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, PrivateAttr, field_validator, model_validator

from simcore.scene import device_hooks
from simcore.scene.base import Finite, Model, check_name
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.motion import Pose
from simcore.scene.sensor_timing import SensorTiming

SPEED_OF_LIGHT = 299_792_458.0

#: Plausible carrier range of an FMCW radar (Hz): 1 GHz (L band) to 300 GHz (sub-THz).
MIN_START_FREQUENCY_HZ = 1e9
MAX_CARRIER_FREQUENCY_HZ = 300e9
#: Largest chirp bandwidth as a fraction of the start frequency.
MAX_FRACTIONAL_BANDWIDTH = 0.5
#: ADC sample rate limits (Hz) and the longest chirp or repetition time (s).
MIN_SAMPLE_RATE_HZ = 1e3
MAX_SAMPLE_RATE_HZ = 1e10
MAX_CHIRP_TIME_S = 1.0
#: Shortest unambiguous range (m): below it the ADC cannot sample any beat frequency of a
#: target in front of the board.
MIN_UNAMBIGUOUS_RANGE_M = 0.1
#: Lowest IF high-pass cutoff other than 0 (Hz): below it the filter's pole overflows.
MIN_HIGHPASS_HZ = 1.0
#: Antenna positions must lie on a board of this half-size (mm).
MAX_ANTENNA_OFFSET_MM = 1000.0
#: Most Tx and Rx elements, and virtual channels (Tx × Rx).
MAX_TX = 64
MAX_RX = 256
MAX_CHANNELS = 4096
#: Largest render grid per axis (pixels, supersampling included): the offscreen GL
#: framebuffer limit of Mesa llvmpipe and common GPUs.
MAX_RENDER_AXIS = 16384

AntennaOffsetMm = Annotated[float, Field(ge=-MAX_ANTENNA_OFFSET_MM, le=MAX_ANTENNA_OFFSET_MM,
                                         allow_inf_nan=False)]


#: Two-way pattern level down to which the radar render should cover the field of view (dB).
COVERAGE_LEVEL_DB = -25.0


class CosinePattern(Model):
    """Separable cosine-power element pattern (power gain relative to boresight).

    ``g(az, el) = max(cos az, 0) ** exponent_az * max(cos el, 0) ** exponent_el`` with
    azimuth measured from boresight towards board +x and elevation towards board −y (up).
    Exponent 0 gives an isotropic element; 2.6 gives −3 dB at ±40°.
    """

    kind: Literal["cosine"] = "cosine"
    exponent_az: float = Field(2.6, ge=0, le=100, allow_inf_nan=False)
    exponent_el: float = Field(2.6, ge=0, le=100, allow_inf_nan=False)


class TablePattern(Model):
    """Element power pattern tabulated in dB over an azimuth × elevation grid.

    ``gain_db[i][j]`` is the gain relative to the boresight peak gain at
    ``elevation_deg[i]``, ``azimuth_deg[j]``; values are interpolated bilinearly in dB and
    held constant beyond the table edges.
    """

    kind: Literal["table"] = "table"
    azimuth_deg: list[Finite] = Field(min_length=2, max_length=3601)
    elevation_deg: list[Finite] = Field(min_length=2, max_length=1801)
    gain_db: list[list[Annotated[float, Field(ge=-300, le=100, allow_inf_nan=False)]]] = Field(
        max_length=1801)

    @model_validator(mode="after")
    def _check(self) -> TablePattern:
        for name, axis in (("azimuth_deg", self.azimuth_deg),
                           ("elevation_deg", self.elevation_deg)):
            if any(b <= a for a, b in zip(axis, axis[1:], strict=False)):
                raise ValueError(f"{name} must be strictly increasing, got {axis}")
            if axis[0] < -180 or axis[-1] > 180:
                raise ValueError(f"{name} must lie within [-180, 180] degrees")
        shape = (len(self.elevation_deg), len(self.azimuth_deg))
        if len(self.gain_db) != shape[0] or any(len(row) != shape[1] for row in self.gain_db):
            raise ValueError(
                f"gain_db must have shape (len(elevation_deg), len(azimuth_deg)) = {shape}"
            )
        return self


ElementPattern = Annotated[Union[CosinePattern, TablePattern], Field(discriminator="kind")]


class Antenna(Model):
    """One Tx or Rx element at ``position_mm`` on the radar board (x right, y down).

    ``pattern`` overrides the configuration's ``element_pattern`` for this element.
    """

    name: str = Field("", max_length=256)
    position_mm: tuple[AntennaOffsetMm, AntennaOffsetMm] = (0.0, 0.0)
    pattern: ElementPattern | None = None

    @field_validator("name")
    @classmethod
    def _printable(cls, name: str) -> str:
        return check_name(name)


class LeakageEcho(Model):
    """A further static Tx→Rx coupling path beside the direct leakage.

    Reflections inside the module, on the board, the radome or the mount: a tone like the
    direct leakage, with the delay of its electrical length ``path_mm`` (Tx → Rx, total) and
    the power ``level_dbc`` at the Rx port relative to the Tx power
    (``docs/physics_radar.md``, "Calibration against a real BGT60TR13C").
    """

    path_mm: float = Field(ge=0, le=100_000, allow_inf_nan=False)
    level_dbc: float = Field(ge=-400, le=0, allow_inf_nan=False)


#: Values of a vendor device configuration kept with a radar made from it.
DeviceSettingValue = Union[int, float, str, list[int]]


def default_l_rx(spacing_mm: float = 2.5) -> list[Antenna]:
    """Three Rx in an L (BGT60TR13C-like): a horizontal pair and a vertical pair, λ/2 apart."""
    return [
        Antenna(name="rx1", position_mm=(spacing_mm, 0.0)),
        Antenna(name="rx2", position_mm=(0.0, 0.0)),
        Antenna(name="rx3", position_mm=(0.0, -spacing_mm)),
    ]


class RadarConfig(SensorTiming):
    """FMCW radar: chirp, antenna layout, transmitter, receiver chain and render sampling.

    ``pose_on_rig`` uses the rig's body convention (x forward, y left, z up); the radar's
    optical frame (board x right, y down, boresight z) is derived from it.

    Receiver chain (applied in this order): the IF signal of every scatterer, with the
    IF high-pass's steady-state response; Tx→Rx leakage; receiver noise; ADC quantization
    and clipping. Each stage can be switched off: ``leakage_dbc=None``,
    ``noise_variance_adc=0``, ``if_highpass_hz=0``, ``adc_bits=None``.
    """

    preset: str = "bgt60tr13c"
    pose_on_rig: Pose = Pose()
    start_frequency_hz: float = Field(60e9, ge=MIN_START_FREQUENCY_HZ,
                                      lt=MAX_CARRIER_FREQUENCY_HZ, allow_inf_nan=False)
    bandwidth_hz: float = Field(6e9, gt=0, le=MAX_FRACTIONAL_BANDWIDTH * MAX_CARRIER_FREQUENCY_HZ,
                                allow_inf_nan=False)
    chirp_time_s: float = Field(256e-6, gt=0, le=MAX_CHIRP_TIME_S, allow_inf_nan=False)
    sample_rate_hz: float = Field(2e6, gt=0, le=MAX_SAMPLE_RATE_HZ, allow_inf_nan=False)
    samples_per_chirp: int = Field(512, ge=8, le=8192)
    chirps_per_frame: int = Field(16, ge=1, le=1024)
    chirp_repetition_time_s: float = Field(300e-6, gt=0, le=MAX_CHIRP_TIME_S,
                                           allow_inf_nan=False)
    complex_iq: bool = False
    tx: list[Antenna] = Field(default_factory=lambda: [Antenna(name="tx1")], min_length=1,
                              max_length=MAX_TX)
    rx: list[Antenna] = Field(default_factory=lambda: default_l_rx(), min_length=1,
                              max_length=MAX_RX)
    render_width: int = Field(
        640, ge=8, le=8192,
        description="radar render pixels across; the render only decides which surface "
                    "facets are seen")
    render_height: int = Field(640, ge=8, le=8192)
    render_fov_h_deg: float = Field(
        142.0, ge=0.1, lt=170,
        description="horizontal field of view of the radar render (square pixels); the "
                    "default covers the two-way element pattern down to −25 dB")
    render_supersampling: int = Field(
        1, ge=1, le=8,
        description="render sub-pixels per facet and axis; each facet (render_width × "
                    "render_height grid) sums the RCS of its sub-pixels")
    # Transmitter and antennas.
    tx_power_dbm: float = Field(5.0, ge=-100, le=60, description="per Tx, at the antenna port")
    tx_gain_dbi: float = Field(6.0, ge=-30, le=60, description="boresight gain of a Tx element")
    rx_gain_dbi: float = Field(6.0, ge=-30, le=60, description="boresight gain of an Rx element")
    element_pattern: ElementPattern = Field(default_factory=CosinePattern)
    # Receiver.
    if_gain_db: float = Field(
        66.0, ge=-50, le=200,
        description="voltage gain from the Rx antenna port (50 Ω) to the ADC input")
    noise_figure_db: float = Field(12.0, ge=0, le=60)
    noise_variance_adc: float | None = Field(
        None, ge=0, le=1e12, allow_inf_nan=False,
        description="receiver noise variance per real channel in FS²; overrides the noise "
                    "figure when set (0 = no noise)")
    leakage_dbc: float | None = Field(
        -40.0, ge=-400, le=0, allow_inf_nan=False,
        description="Tx→Rx leakage power at the Rx port relative to the Tx power "
                    "(None = no leakage)")
    leakage_path_mm: float | None = Field(
        None, ge=0, le=100_000, allow_inf_nan=False,
        description="electrical length of the direct Tx→Rx coupling path (mm); None = the "
                    "distance between the two elements on the board")
    leakage_echoes: list[LeakageEcho] = Field(
        default_factory=list, max_length=64,
        description="further static coupling paths (module, board, radome, mount "
                    "reflections); off with the leakage (leakage_dbc = None)")
    adc_noise_fs: float = Field(
        0.0, ge=0, le=1, allow_inf_nan=False,
        description="rms noise per real channel added after the IF filters (baseband "
                    "amplifier output, ADC driver, ADC) in FS: white, independent of the IF "
                    "gain; noise_variance_adc, when set, replaces it too")
    device_settings: dict[str, DeviceSettingValue] | None = Field(
        None, description="the vendor device configuration this radar reproduces (e.g. a "
                          "recording's fmcw_single_shape), kept for reference")
    if_highpass_hz: float = Field(80e3, ge=0, le=MAX_SAMPLE_RATE_HZ, allow_inf_nan=False,
                                  description="IF high-pass cutoff (0 = none)")
    if_highpass_order: int = Field(1, ge=1, le=8)
    if_lowpass_hz: float = Field(
        0.0, ge=0, le=MAX_SAMPLE_RATE_HZ, allow_inf_nan=False,
        description="IF anti-aliasing low-pass cutoff (Butterworth, 0 = none): beat "
                    "frequencies above it, e.g. targets beyond the maximum range, are "
                    "attenuated instead of folding back at full level")
    if_lowpass_order: int = Field(4, ge=1, le=8)
    adc_bits: int | None = Field(12, ge=1, le=24, description="None = no quantization")
    adc_full_scale_v: float = Field(1.0, ge=1e-9, le=1e6, allow_inf_nan=False,
                                    description="peak ADC input voltage of the largest code")
    # Transmit-side interference mitigation (docs/interference.md); off by default.
    chirp_jitter_s: float = Field(
        0.0, ge=0, le=1e-3, allow_inf_nan=False,
        description="random extra delay of each chirp's start, uniform in [0, "
                    "chirp_jitter_s), drawn anew every frame from transmit_seed (s): "
                    "decorrelates an equal-slope aggressor's ghost over the chirps. "
                    "0 = off. The chirp must still end before the next one starts")
    hop_step_hz: float = Field(
        0.0, ge=0, le=50e9, allow_inf_nan=False,
        description="frequency hopping per frame: each frame's start frequency is "
                    "start_frequency_hz + c × hop_step_hz with a channel c drawn from "
                    "0 … hop_channels − 1 every frame (Hz)")
    hop_channels: int = Field(
        1, ge=1, le=1024,
        description="number of hopping channels (1 = no frequency hopping)")
    transmit_seed: int = Field(
        0, ge=0, le=2**31 - 1,
        description="seed of this radar's chirp jitter and hopping sequence; radars "
                    "with equal seeds and settings hop and jitter in step")
    # Scattering and synthesis.
    speckle: bool = Field(
        default=True,
        description="random phase of each surface facet's diffuse part, fixed to the "
                    "surface (rough-surface speckle); off: phase 0")
    nufft_tolerance: float = Field(1e-9, ge=1e-14, le=1e-2)
    multipath_order: Literal[0, 1, 2] = Field(
        0,
        description="specular multipath by the image method (simcore.sensors.radar."
                    "multipath): 0 = single bounce only; 1 = add radar → reflector → target "
                    "→ radar and its reverse (ghosts × Γ); 2 = also radar → reflector → "
                    "target → reflector → radar (× Γ²), paths over two different faces and "
                    "two bounces on one leg, the room's corners. Reflectors are the smooth "
                    "planar faces of any material (|Γ| ≥ 0.05: concrete, plaster, wood, "
                    "glass, metal), with the Fresnel coefficient at each bounce's angle; the "
                    "room's edges come with order 1. 0 for files that do not say (older "
                    "projects); the bundled examples with walls use 1 (docs/physics_radar.md)")
    ideal: bool = Field(
        False,
        description="ideal sensor for validation and ground truth: no receiver noise and "
                    "no ADC quantisation (nor clipping); the IF filters, leakage and every "
                    "path stay")
    polarization: Literal["V", "H"] = Field(
        "V",
        description="linear polarisation of the Tx and Rx antennas in the board frame: "
                    "V = E along board y (vertical with the board upright), H = along board "
                    "x, on boresight; off it θ̂ (V) and φ̂ (H) about board y (3GPP TR "
                    "38.901 §7.3.2, as Sionna RT's V/H: H stays across board y). Sets the "
                    "Fresnel TE/TM mix of every multipath reflection at its "
                    "incidence angle (a floor reflects V near Brewster's angle weakly); "
                    "no effect on single-bounce returns")
    # The rig's own front (evaluation board or radome) as a multipath reflector.
    rig_front_width_m: float = Field(
        0.025, ge=0, le=2.0, allow_inf_nan=False,
        description="width (board x) of the rig's front around the antennas, a flat "
                    "rectangle in the board plane centred on the board origin (the "
                    "evaluation board or radome); with multipath_order ≥ 1 it reflects "
                    "the echoes of the scene's planar reflectors back into them (radar → "
                    "reflector → rig front → reflector → radar, an echo at twice the "
                    "reflector's range). 0 = no rig front. Default 25 mm: the 60 GHz "
                    "radar board's front (an assumed size, docs/physics_radar.md)")
    rig_front_height_m: float = Field(
        0.025, ge=0, le=2.0, allow_inf_nan=False,
        description="height (board y) of the rig's front (0 = no rig front)")
    rig_front_material: str = Field(
        "aluminium", min_length=1,
        description="material of the rig's front (a name in the project's material "
                    "table): its normal-incidence radar Γ. Default aluminium: the board's "
                    "copper ground plane around the antennas reflects like metal")

    #: One frame's chirp start jitter, (chirps × tx,) in TDM order (s); set only on the
    #: per-frame copies of :func:`simcore.sensors.radar.transmit.frame_transmit_config`.
    _chirp_delays_s: NDArray[np.float64] | None = PrivateAttr(default=None)

    @model_validator(mode="before")
    @classmethod
    def _device_defaults(cls, data: Any) -> Any:
        """A device preset named in a project gives the fields the project leaves out."""
        if isinstance(data, dict) and isinstance(data.get("preset"), str):
            defaults = device_hooks.preset_defaults("radar", data["preset"])
            if defaults is not None:
                return {**defaults, **data}
        return data

    @model_validator(mode="after")
    def _device_limits(self) -> RadarConfig:
        """A device preset's limits (:mod:`simcore.scene.devices`) hold."""
        problems = device_hooks.limit_problems(self)
        if problems:
            raise ValueError(f"preset {self.preset!r}: " + "; ".join(problems))
        return self

    @model_validator(mode="after")
    def _check(self) -> RadarConfig:
        """The fields together: band, sizes, chirp timing, IF filters, antenna names."""
        self._check_band()
        self._check_sizes()
        self._check_chirp_timing()
        self._check_filters()
        self._check_antenna_names()
        return self

    def _check_band(self) -> None:
        """Sample rate, carrier band, fractional bandwidth, unambiguous range."""
        if self.sample_rate_hz < MIN_SAMPLE_RATE_HZ:
            raise ValueError(f"sample_rate_hz = {self.sample_rate_hz:.4g} Hz; allowed "
                             f"[{MIN_SAMPLE_RATE_HZ:g}, {MAX_SAMPLE_RATE_HZ:g}] Hz")
        top = self.start_frequency_hz + self.bandwidth_hz
        if top > MAX_CARRIER_FREQUENCY_HZ:
            raise ValueError(
                f"start_frequency_hz + bandwidth_hz = {top:.4g} Hz exceeds the radar band "
                f"limit {MAX_CARRIER_FREQUENCY_HZ:.4g} Hz")
        if self.bandwidth_hz > MAX_FRACTIONAL_BANDWIDTH * self.start_frequency_hz:
            raise ValueError(
                f"bandwidth_hz = {self.bandwidth_hz:.4g} Hz is more than "
                f"{MAX_FRACTIONAL_BANDWIDTH:g} × start_frequency_hz "
                f"({self.start_frequency_hz:.4g} Hz); allowed (0, "
                f"{MAX_FRACTIONAL_BANDWIDTH * self.start_frequency_hz:.4g}] Hz")
        if self.max_range_m < MIN_UNAMBIGUOUS_RANGE_M:
            f_max = self.sample_rate_hz if self.complex_iq else 0.5 * self.sample_rate_hz
            b_max = f_max * SPEED_OF_LIGHT * self.chirp_time_s / (2 * MIN_UNAMBIGUOUS_RANGE_M)
            raise ValueError(
                f"bandwidth_hz = {self.bandwidth_hz:.4g} Hz in chirp_time_s = "
                f"{self.chirp_time_s:.4g} s puts the ADC's largest beat frequency "
                f"({f_max:.4g} Hz) at {self.max_range_m:.3g} m; allowed bandwidth_hz <= "
                f"{b_max:.4g} Hz (unambiguous range >= {MIN_UNAMBIGUOUS_RANGE_M} m)")

    def _check_sizes(self) -> None:
        """Virtual channels and render size."""
        if len(self.tx) * len(self.rx) > MAX_CHANNELS:
            raise ValueError(
                f"{len(self.tx)} tx × {len(self.rx)} rx = {len(self.tx) * len(self.rx)} "
                f"virtual channels; at most {MAX_CHANNELS}")
        for axis, size in (("render_width", self.render_width),
                           ("render_height", self.render_height)):
            if size * self.render_supersampling > MAX_RENDER_AXIS:
                raise ValueError(
                    f"{axis} × render_supersampling = {size} × {self.render_supersampling} = "
                    f"{size * self.render_supersampling} render pixels; at most "
                    f"{MAX_RENDER_AXIS} per axis")

    def _check_chirp_timing(self) -> None:
        """Sampling within the chirp, jitter and repetition, hopping within the band."""
        sampling_time = self.samples_per_chirp / self.sample_rate_hz
        if sampling_time > self.chirp_time_s * (1 + 1e-9):
            raise ValueError(
                f"samples_per_chirp / sample_rate_hz = {sampling_time * 1e6:.1f} µs exceeds "
                f"chirp_time_s = {self.chirp_time_s * 1e6:.1f} µs"
            )
        if self.chirp_repetition_time_s < (self.chirp_time_s + self.chirp_jitter_s) * (1 - 1e-9):
            if self.chirp_jitter_s > 0:
                longest = (self.chirp_time_s + self.chirp_jitter_s) * 1e6
                raise ValueError(
                    f"chirp_time_s + chirp_jitter_s ({longest:.1f} µs) exceeds "
                    "chirp_repetition_time_s "
                    f"({self.chirp_repetition_time_s * 1e6:.1f} µs): a jittered chirp would "
                    "overlap the next")
        top = self.start_frequency_hz + self.bandwidth_hz
        hop_top = top + (self.hop_channels - 1) * self.hop_step_hz
        if hop_top > MAX_CARRIER_FREQUENCY_HZ:
            raise ValueError(
                f"the highest hopping channel ends at {hop_top:.4g} Hz, beyond the radar "
                f"band limit {MAX_CARRIER_FREQUENCY_HZ:.4g} Hz")
        if self.chirp_repetition_time_s < self.chirp_time_s * (1 - 1e-9):
            raise ValueError(
                f"chirp_repetition_time_s ({self.chirp_repetition_time_s * 1e6:.1f} µs) is "
                f"shorter than chirp_time_s ({self.chirp_time_s * 1e6:.1f} µs)"
            )

    def _check_filters(self) -> None:
        """IF high-pass and anti-aliasing low-pass cutoffs against the IF bandwidth."""
        nyquist = self.sample_rate_hz if self.complex_iq else 0.5 * self.sample_rate_hz
        if 0 < self.if_highpass_hz < MIN_HIGHPASS_HZ:
            raise ValueError(
                f"if_highpass_hz = {self.if_highpass_hz:.3g} Hz; allowed 0 (no high-pass) or "
                f"[{MIN_HIGHPASS_HZ:g}, {nyquist:g}) Hz")
        if self.if_highpass_hz >= nyquist:
            raise ValueError(
                f"if_highpass_hz ({self.if_highpass_hz:g} Hz) must be below the IF bandwidth "
                f"({nyquist:g} Hz), or 0 for no high-pass"
            )
        if 0 < self.if_lowpass_hz <= self.if_highpass_hz:
            raise ValueError(
                f"if_lowpass_hz ({self.if_lowpass_hz:g} Hz) must be above the high-pass "
                f"cutoff ({self.if_highpass_hz:g} Hz), or 0 for no anti-aliasing filter")

    def _check_antenna_names(self) -> None:
        """Antenna names unique among the Tx and among the Rx."""
        for role, antennas in (("tx", self.tx), ("rx", self.rx)):
            seen: set[str] = set()
            dup_set: set[str] = set()
            for a in antennas:
                if a.name and a.name in seen:
                    dup_set.add(a.name)
                seen.add(a.name)
            dup = sorted(dup_set)
            if dup:
                raise ValueError(f"{role}: duplicate antenna names {dup}")

    # ----------------------------------------------------------------- derived values
    @property
    def wavelength_m(self) -> float:
        """Wavelength at the chirp's centre frequency (m)."""
        return SPEED_OF_LIGHT / (self.start_frequency_hz + 0.5 * self.bandwidth_hz)

    @property
    def slope_hz_per_s(self) -> float:
        """Chirp slope K = B / T_c (Hz/s)."""
        return self.bandwidth_hz / self.chirp_time_s

    @property
    def range_resolution_m(self) -> float:
        """Range resolution c / (2 B_sampled) of the sampled part of the chirp (m)."""
        sampled_bw = self.slope_hz_per_s * self.samples_per_chirp / self.sample_rate_hz
        return SPEED_OF_LIGHT / (2.0 * sampled_bw)

    @property
    def max_range_m(self) -> float:
        """Unambiguous range: beat frequency at f_s/2 (real IF) or f_s (complex IQ) (m)."""
        f_max = self.sample_rate_hz if self.complex_iq else 0.5 * self.sample_rate_hz
        return f_max * SPEED_OF_LIGHT / (2.0 * self.slope_hz_per_s)

    @property
    def velocity_resolution_mps(self) -> float:
        """Doppler resolution λ / (2 N_c T_r) for one Tx (m/s)."""
        t_r = self.chirp_repetition_time_s * len(self.tx)
        return self.wavelength_m / (2.0 * self.chirps_per_frame * t_r)

    @property
    def max_velocity_mps(self) -> float:
        """Unambiguous radial velocity ±λ / (4 T_r), T_r per Tx in TDM (m/s)."""
        return self.wavelength_m / (4.0 * self.chirp_repetition_time_s * len(self.tx))

    @property
    def frame_duration_s(self) -> float:
        """Time from the first chirp's start to the last chirp's end (s)."""
        n_slots = self.chirps_per_frame * len(self.tx)
        return (n_slots - 1) * self.chirp_repetition_time_s + self.chirp_time_s

    @property
    def n_channels(self) -> int:
        """Number of virtual channels (Tx × Rx pairs)."""
        return len(self.tx) * len(self.rx)

    def tx_positions_m(self) -> NDArray[np.float64]:
        """Tx positions in the radar optical frame (board plane z = 0), shape (tx, 3), m."""
        return _positions_m(self.tx)

    def rx_positions_m(self) -> NDArray[np.float64]:
        """Rx positions in the radar optical frame (board plane z = 0), shape (rx, 3), m."""
        return _positions_m(self.rx)

    def virtual_positions_m(self) -> NDArray[np.float64]:
        """Virtual-array element positions ``p_tx + p_rx``, shape (tx*rx, 3), m.

        Channel ``t * n_rx + r`` pairs Tx ``t`` with Rx ``r``. In the far field its phase
        is ``-2π/λ · u·(p_tx + p_rx)`` plus a common term (u: unit direction to the
        target), i.e. that of a receive element at ``p_tx + p_rx`` with a transmitter at
        the origin; with a single Tx at the origin the virtual array is the Rx array.
        """
        tx, rx = self.tx_positions_m(), self.rx_positions_m()
        return (tx[:, None, :] + rx[None, :, :]).reshape(-1, 3)

    def sample_times_s(self) -> NDArray[np.float64]:
        """ADC sample times from the start of a chirp, shape (samples,), s."""
        return np.arange(self.samples_per_chirp) / self.sample_rate_hz

    def chirp_start_times_s(self) -> NDArray[np.float64]:
        """Chirp start times from the frame start, shape (chirps, tx), s (TDM order)."""
        n_tx = len(self.tx)
        slots = np.arange(self.chirps_per_frame)[:, None] * n_tx + np.arange(n_tx)[None, :]
        starts = np.asarray(slots * self.chirp_repetition_time_s, dtype=np.float64)
        if self._chirp_delays_s is not None:   # one frame's jitter (frame_transmit_config)
            starts = starts + self._chirp_delays_s.reshape(starts.shape)
        return starts

    def pattern_coverage_deg(self, level_db: float = COVERAGE_LEVEL_DB
                             ) -> tuple[float, float]:
        """Half-angles (azimuth, elevation) inside which the two-way pattern ≥ ``level_db``.

        The two-way pattern is the largest product of a Tx and an Rx element's power
        gains (relative to boresight); it is scanned along the azimuth axis (elevation
        0) and the elevation axis (azimuth 0), in 0.1° steps up to 89.9°.
        """
        angles = np.arange(0.0, 90.0, 0.1)
        floor = 10.0 ** (level_db / 10.0)
        out = []
        for axis in ("az", "el"):
            tx = np.max([_axis_gain(a.pattern or self.element_pattern, axis, angles)
                         for a in self.tx], axis=0)
            rx = np.max([_axis_gain(a.pattern or self.element_pattern, axis, angles)
                         for a in self.rx], axis=0)
            above = np.flatnonzero(tx * rx >= floor)
            out.append(float(angles[above[-1]]) if len(above) else 0.0)
        return out[0], out[1]

    def facet_intrinsics(self) -> PinholeIntrinsics:
        """Facet grid: one scatterer per grid cell and object (square cells over the FOV)."""
        return PinholeIntrinsics.from_fov(self.render_width, self.render_height,
                                          self.render_fov_h_deg)

    def render_intrinsics(self) -> PinholeIntrinsics:
        """Pixel grid of the radar render pass: the facet grid × ``render_supersampling``."""
        return self.facet_intrinsics().scaled(self.render_supersampling)


def _axis_gain(pattern: ElementPattern, axis: str, angles_deg: NDArray[np.float64]
               ) -> NDArray[np.float64]:
    """Power gain of a pattern along one axis (the other angle 0), both signs' maximum."""
    if isinstance(pattern, CosinePattern):
        exp = pattern.exponent_az if axis == "az" else pattern.exponent_el
        return np.asarray(np.maximum(np.cos(np.radians(angles_deg)), 0.0) ** exp)
    az = np.asarray(pattern.azimuth_deg)
    el = np.asarray(pattern.elevation_deg)
    table = np.asarray(pattern.gain_db)
    if axis == "az":
        row = table[int(np.argmin(np.abs(el)))]
        both = [np.interp(s * angles_deg, az, row, left=-300, right=-300) for s in (1, -1)]
    else:
        col = table[:, int(np.argmin(np.abs(az)))]
        both = [np.interp(s * angles_deg, el, col, left=-300, right=-300) for s in (1, -1)]
    return np.asarray(10.0 ** (np.maximum(both[0], both[1]) / 10.0))


def _positions_m(antennas: list[Antenna]) -> NDArray[np.float64]:
    pos = np.zeros((len(antennas), 3))
    pos[:, :2] = np.array([a.position_mm for a in antennas], dtype=np.float64) * 1e-3
    return pos


def aliasing_warnings(
    config: RadarConfig,
    *,
    ranges_m: NDArray[np.floating] | None = None,
    radial_velocities_mps: NDArray[np.floating] | None = None,
) -> list[str]:
    """Warnings about a configuration and the scene it observes (empty list if none).

    Parameters
    ----------
    config : RadarConfig
        The radar configuration.
    ranges_m : ndarray, optional
        Ranges present in the scene (m), e.g. the valid pixels of the radar render; NaN is
        ignored. Ranges beyond :attr:`RadarConfig.max_range_m` alias (fold back).
    radial_velocities_mps : ndarray, optional
        Radial velocities in the scene (m/s); beyond ±:attr:`max_velocity_mps` they alias.

    Returns
    -------
    list of str
        One human-readable sentence per problem.
    """
    out: list[str] = []
    if ranges_m is not None:
        r = np.asarray(ranges_m, dtype=np.float64)
        r = r[np.isfinite(r)]
        beyond = r > config.max_range_m
        if beyond.any():
            out.append(
                f"{int(beyond.sum())} scene points lie beyond the unambiguous range "
                f"{config.max_range_m:.2f} m (up to {r.max():.2f} m) and alias into the range "
                f"profile; raise sample_rate_hz or lower the chirp slope"
            )
    if radial_velocities_mps is not None:
        v = np.asarray(radial_velocities_mps, dtype=np.float64)
        v = v[np.isfinite(v)]
        beyond = np.abs(v) > config.max_velocity_mps
        if beyond.any():
            out.append(
                f"{int(beyond.sum())} scene points move faster than the unambiguous velocity "
                f"±{config.max_velocity_mps:.2f} m/s (up to {np.abs(v).max():.2f} m/s) and "
                f"alias in Doppler; shorten chirp_repetition_time_s"
            )
    half = 0.5 * config.wavelength_m
    for role, antennas in (("rx", config.rx), ("tx", config.tx)):
        pos = _positions_m(antennas)
        if len(pos) < 2:
            continue
        diff = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1)
        iu = np.triu_indices(len(pos), 1)
        if np.any(diff[iu] < 1e-9):
            out.append(f"{role}: two antennas share the same position")
    intr = config.render_intrinsics()
    az_need, el_need = config.pattern_coverage_deg()
    for name, need, fov in (("horizontal", az_need, intr.fov_h_deg),
                            ("vertical", el_need, intr.fov_v_deg)):
        if 0.5 * fov + 0.5 < need:
            out.append(
                f"the radar render covers ±{0.5 * fov:.0f}° {name}ly but the two-way antenna "
                f"pattern stays above {COVERAGE_LEVEL_DB:.0f} dB out to ±{need:.0f}°: returns "
                f"from outside the render are lost (raise render_fov_h_deg or the render's "
                f"{'width' if name == 'horizontal' else 'height'})")
    virt = config.virtual_positions_m()
    for axis, name, fov in ((0, "horizontal", intr.fov_h_deg), (1, "vertical", intr.fov_v_deg)):
        coords = np.unique(np.round(virt[:, axis], 9))
        if len(coords) >= 2:
            gap = float(np.min(np.diff(coords)))
            unambiguous_deg = float(np.degrees(np.arcsin(min(1.0, half / gap))))
            if unambiguous_deg < 0.5 * fov:
                out.append(
                    f"smallest {name} virtual-element spacing {gap * 1e3:.2f} mm exceeds λ/2 = "
                    f"{half * 1e3:.2f} mm: angles beyond ±{unambiguous_deg:.0f}° are ambiguous "
                    f"(grating lobes) inside the ±{0.5 * fov:.0f}° field of view"
                )
    return out
