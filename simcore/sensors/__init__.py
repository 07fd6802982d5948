"""Sensor models as plug-ins: each package registers one :class:`~simcore.sensors.base.Sensor`.

The ToF camera, the radar and the optional RGB camera are registered here; a new sensor is
one package with a configuration on the rig (``simcore.scene.model.SensorRig``) and one
``register`` line.
"""

from simcore.sensors.base import (
    Sensor,
    SensorContext,
    SensorOutput,
    active_sensors,
    frame_rng,
    register,
    registered,
)
from simcore.sensors.radar import RadarSensor
from simcore.sensors.rgb import RgbSensor
from simcore.sensors.tof import TofSensor

register(TofSensor())
register(RadarSensor())
register(RgbSensor())

__all__ = [
    "Sensor",
    "SensorContext",
    "SensorOutput",
    "active_sensors",
    "frame_rng",
    "register",
    "registered",
]
