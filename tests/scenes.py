"""Small scenes built in code, shared by several test modules."""

from __future__ import annotations

from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.model import SensorRig


def wall_project(distance_m: float = 2.0, material: str = "concrete") -> Project:
    """A large wall whose front face is ``distance_m`` ahead of both sensors (rig at origin)."""
    return Project(
        objects=[SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 40.0, 30.0)),
                             pose=Pose(position_m=(distance_m + 0.1, 0.0, 0.0)),
                             material=material)],
        rig=SensorRig(),
    )
