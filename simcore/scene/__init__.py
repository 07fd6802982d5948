"""Scene model: objects, geometry, dual-band materials, motion and project files.

Names are imported lazily, so that sensor configuration modules can import
``simcore.scene.base`` and ``simcore.scene.motion`` without an import cycle through the
project model (which itself holds the sensor configurations).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_EXPORTS = {
    "Box": "geometry", "CornerReflector": "geometry", "Cylinder": "geometry",
    "Mesh": "geometry", "Plane": "geometry", "PointTarget": "geometry", "Sphere": "geometry",
    "BandMaterial": "materials", "DualBandMaterial": "materials",
    "load_material_library": "materials",
    "FORMAT_VERSION": "model", "Project": "model", "SceneObject": "model",
    "SensorRig": "model", "Timeline": "model",
    "Keyframe": "motion", "Motion": "motion", "Pose": "motion",
    "ProjectError": "project_io", "load_project": "project_io", "save_project": "project_io",
}

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


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(f"simcore.scene.{_EXPORTS[name]}"), name)
    raise AttributeError(f"module 'simcore.scene' has no attribute {name!r}")


if TYPE_CHECKING:
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
