"""FMCW radar: scatterers from the radar render, IF synthesis, receiver, sensor plug-in."""

from simcore.sensors.radar.frontend import (
    RadarOutput,
    radar_output,
    radar_scatterers,
    radar_warnings,
    simulate_radar,
)
from simcore.sensors.radar.sensor import RadarFrameOutput, RadarSensor

__all__ = [
    "RadarFrameOutput",
    "RadarOutput",
    "RadarSensor",
    "radar_output",
    "radar_scatterers",
    "radar_warnings",
    "simulate_radar",
]
