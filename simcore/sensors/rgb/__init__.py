"""RGB camera: colour images of the visible band, a self-contained sensor plug-in."""

from simcore.sensors.rgb.camera import RgbOutput, simulate_rgb, srgb_encode
from simcore.sensors.rgb.sensor import RgbSensor

__all__ = ["RgbOutput", "RgbSensor", "simulate_rgb", "srgb_encode"]
