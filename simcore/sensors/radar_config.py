"""Configuration of the FMCW radar front end: waveform, antennas, render sampling."""

from __future__ import annotations

from pydantic import Field, model_validator

from simcore.scene.base import Model, Vec2
from simcore.scene.motion import Pose

SPEED_OF_LIGHT = 299_792_458.0


class Antenna(Model):
    """One Tx or Rx element at ``position_mm`` on the radar board (x right, y down)."""

    name: str = ""
    position_mm: Vec2 = (0.0, 0.0)


def default_l_rx(spacing_mm: float = 2.5) -> list[Antenna]:
    """Three Rx in an L (BGT60TR13C-like): a horizontal pair and a vertical pair, λ/2 apart."""
    return [
        Antenna(name="rx1", position_mm=(spacing_mm, 0.0)),
        Antenna(name="rx2", position_mm=(0.0, 0.0)),
        Antenna(name="rx3", position_mm=(0.0, -spacing_mm)),
    ]


class RadarConfig(Model):
    """FMCW radar: chirp parameters, antenna layout and the radar render pass sampling.

    ``pose_on_rig`` uses the rig's body convention (x forward, y left, z up); the radar's
    optical frame (board x right, y down, boresight z) is derived from it.
    """

    preset: str = "bgt60tr13c"
    pose_on_rig: Pose = Pose()
    start_frequency_hz: float = Field(60e9, gt=0)
    bandwidth_hz: float = Field(6e9, gt=0)
    chirp_time_s: float = Field(256e-6, gt=0)
    sample_rate_hz: float = Field(2e6, gt=0)
    samples_per_chirp: int = Field(512, ge=8, le=8192)
    chirps_per_frame: int = Field(16, ge=1, le=1024)
    chirp_repetition_time_s: float = Field(300e-6, gt=0)
    complex_iq: bool = False
    tx: list[Antenna] = Field(default_factory=lambda: [Antenna(name="tx1")], min_length=1)
    rx: list[Antenna] = Field(default_factory=lambda: default_l_rx(), min_length=1)
    render_width: int = Field(1000, ge=8, le=8192)
    render_height: int = Field(342, ge=8, le=8192)
    render_fov_h_deg: float = Field(100.0, gt=0, lt=170)

    @model_validator(mode="after")
    def _check(self) -> RadarConfig:
        sampling_time = self.samples_per_chirp / self.sample_rate_hz
        if sampling_time > self.chirp_time_s * (1 + 1e-9):
            raise ValueError(
                f"samples_per_chirp / sample_rate_hz = {sampling_time * 1e6:.1f} µs exceeds "
                f"chirp_time_s = {self.chirp_time_s * 1e6:.1f} µs"
            )
        if self.chirp_repetition_time_s < self.chirp_time_s * (1 - 1e-9):
            raise ValueError(
                f"chirp_repetition_time_s ({self.chirp_repetition_time_s * 1e6:.1f} µs) is "
                f"shorter than chirp_time_s ({self.chirp_time_s * 1e6:.1f} µs)"
            )
        return self

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
