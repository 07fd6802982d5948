"""AMCW Time-of-Flight camera: the camera model and its sensor plug-in."""

from simcore.sensors.tof.camera import (
    TofOutput,
    simulate_tof,
    unwrap_frequencies,
    unwrap_two_frequencies,
)
from simcore.sensors.tof.sensor import TofSensor

__all__ = ["TofOutput", "TofSensor", "simulate_tof", "unwrap_frequencies",
           "unwrap_two_frequencies"]
