"""Where any sensor of a project is at any time: for sensors that see other sensors.

The engine's snapshot holds the sensors' states at a frame's time; interference needs
another sensor's pose at the time *it* transmits (its own trigger), on whichever rig.
"""

from __future__ import annotations

from simcore.scene.base import Model
from simcore.scene.model import Project, Rig
from simcore.scene.motion import rigid_state
from simcore.scene.snapshot import SensorState, _sensor_state


def sensor_state(rig: Rig, config: Model, time_s: float) -> SensorState:
    """World pose (optical frame) and velocity of a sensor on ``rig`` at ``time_s``."""
    return _sensor_state(rigid_state(rig.pose, rig.motion, time_s),
                         config.pose_on_rig.matrix())  # type: ignore[attr-defined]


def other_sensors(project: Project, name: str, kind: type[Model]
                  ) -> list[tuple[str, Rig, Model]]:
    """Every sensor of the project of class ``kind`` but ``name``: (name, rig, config)."""
    out = []
    for rig in project.all_rigs():
        for other, cfg in rig.sensor_configs().items():
            if other != name and isinstance(cfg, kind):
                out.append((other, rig, cfg))
    return out


__all__ = ["other_sensors", "sensor_state"]
