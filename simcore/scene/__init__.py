"""The project model: objects, geometry, dual-band materials, motion, sensor configurations.

This is the lowest layer of the core: everything a project file holds, validated, with
no rendering or physics.
"""

from __future__ import annotations

# The device library installs its preset hooks (simcore.scene.device_hooks) on import.
from simcore.scene import devices as _devices  # noqa: F401
from simcore.scene.geometry import (
    Box,
    CornerReflector,
    Cylinder,
    Mesh,
    Plane,
    PointTarget,
    Sphere,
)
from simcore.scene.materials import BandMaterial, DualBandMaterial, load_material_library
from simcore.scene.model import FORMAT_VERSION, Project, SceneObject, SensorRig, Timeline
from simcore.scene.motion import Keyframe, Motion, Pose
from simcore.scene.project_io import ProjectError, load_project, save_project

__all__ = [
    "BandMaterial",
    "Box",
    "CornerReflector",
    "Cylinder",
    "DualBandMaterial",
    "FORMAT_VERSION",
    "Keyframe",
    "Mesh",
    "Motion",
    "Plane",
    "PointTarget",
    "Pose",
    "Project",
    "ProjectError",
    "SceneObject",
    "SensorRig",
    "Sphere",
    "Timeline",
    "load_material_library",
    "load_project",
    "save_project",
]
