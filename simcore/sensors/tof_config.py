"""Configuration of the AMCW Time-of-Flight camera."""

from __future__ import annotations

from pydantic import Field

from simcore.scene.base import Model
from simcore.scene.motion import Pose


class TofCameraConfig(Model):
    """AMCW ToF camera: resolution, field of view, mounting pose and modulation.

    ``pose_on_rig`` uses the rig's body convention (x forward, y left, z up); the camera's
    optical frame (x right, y down, z forward) is derived from it.
    """

    preset: str = "pmd_pico_flexx"
    width: int = Field(224, ge=1, le=4096)
    height: int = Field(171, ge=1, le=4096)
    fov_h_deg: float = Field(62.0, gt=0, lt=170)
    fov_v_deg: float = Field(45.0, gt=0, lt=170)
    pose_on_rig: Pose = Pose()
    supersampling: int = Field(2, ge=1, le=8, description="sub-pixels per axis (2 → 2×2)")
    modulation_frequencies_hz: list[float] = Field(
        default_factory=lambda: [20e6], min_length=1, max_length=2
    )
    wavelength_nm: float = Field(850.0, gt=0)
