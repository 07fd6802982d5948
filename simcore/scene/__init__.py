"""Scene model: objects, geometry, dual-band materials, motion and project files."""

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
    "FORMAT_VERSION",
    "BandMaterial",
    "Box",
    "CornerReflector",
    "Cylinder",
    "DualBandMaterial",
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
