"""Configuration of the RGB (colour) camera: a pinhole camera on the rig.

The camera sees the visible band of the materials (:data:`simcore.scene.materials.BANDS`),
tinted by each material's ``color_rgb``, lit by the scene's ambient light and a lamp at
the camera (``docs/physics.md``).
"""

from __future__ import annotations

from pydantic import Field

from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.motion import Pose
from simcore.scene.sensor_timing import SensorTiming


class RgbCameraConfig(SensorTiming):
    """A colour camera: resolution, field of view, mounting pose and exposure.

    ``pose_on_rig`` uses the rig's body convention (x forward, y left, z up); the camera's
    optical frame (x right, y down, z forward) is derived from it, as for the other sensors.
    """

    width: int = Field(640, ge=8, le=4096)
    height: int = Field(480, ge=8, le=4096)
    fov_h_deg: float = Field(69.0, gt=1, lt=170, description="horizontal field of view (deg)")
    fov_v_deg: float = Field(42.0, gt=1, lt=170, description="vertical field of view (deg)")
    pose_on_rig: Pose = Pose()
    ambient: float = Field(0.3, ge=0, le=1,
                           description="ambient light, as a fraction of a white surface's "
                                       "full exposure")
    lamp: float = Field(0.5, ge=0, le=10,
                        description="light of a lamp at the camera on a white surface "
                                    "facing it at 1 m, fraction of full exposure")
    lamp_falloff: bool = Field(False, description="lamp light falls off as 1/R² (else constant)")
    background_rgb: tuple[float, float, float] = Field(
        (0.78, 0.82, 0.88), description="colour where no surface is seen (linear RGB, 0–1)")

    def intrinsics(self) -> PinholeIntrinsics:
        """Pinhole intrinsics of the image (``width`` × ``height``)."""
        return PinholeIntrinsics.from_fov(self.width, self.height, self.fov_h_deg,
                                          self.fov_v_deg)

    def render_intrinsics(self) -> PinholeIntrinsics:
        """Render grid: one render pixel per image pixel."""
        return self.intrinsics()
