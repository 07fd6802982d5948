"""The project model: scene objects, materials, the sensor rig and the timeline."""

from __future__ import annotations

from typing import Any

from pydantic import Field, PrivateAttr, model_validator

from simcore.scene.base import Model, Positive
from simcore.scene.dsp_config import DspConfig
from simcore.scene.geometry import Geometry
from simcore.scene.materials import DualBandMaterial
from simcore.scene.motion import Motion, Pose
from simcore.scene.radar_config import RadarConfig
from simcore.scene.rgb_config import RgbCameraConfig
from simcore.scene.tof_config import TofCameraConfig

#: Version 2: materials hold their parameters per band name (``bands``).
FORMAT_VERSION = 2


class SceneObject(Model):
    """One object of the scene: geometry, pose, dual-band material and motion."""

    id: int = Field(ge=0, le=2**31 - 1)
    name: str = Field(min_length=1)
    geometry: Geometry
    pose: Pose = Pose()
    material: str = Field("concrete", min_length=1)
    motion: Motion = Motion()


class SensorRig(Model):
    """The rig carrying the sensors; its body frame is x forward, y left, z up.

    Every field with a ``pose_on_rig`` is a sensor, named by the field; ``None`` leaves an
    optional sensor off (the RGB camera is off unless a project sets ``rgb``).
    """

    pose: Pose = Pose()
    motion: Motion = Motion()
    tof: TofCameraConfig = TofCameraConfig()
    radar: RadarConfig = RadarConfig()
    rgb: RgbCameraConfig | None = None

    def sensor_configs(self) -> dict[str, Model]:
        """The configurations of the sensors on the rig, by sensor name (field name)."""
        out: dict[str, Model] = {}
        for name in type(self).model_fields:
            value = getattr(self, name)
            if value is not None and hasattr(value, "pose_on_rig"):
                out[name] = value
        return out


class Timeline(Model):
    """Frame rate and duration of the simulated time span."""

    frame_rate_hz: Positive = 10.0
    duration_s: Positive = 1.0

    @property
    def n_frames(self) -> int:
        """Number of frames in the timeline (at least one)."""
        return max(1, int(round(self.duration_s * self.frame_rate_hz)))

    def frame_time(self, index: int) -> float:
        """Timestamp (s) of frame ``index``."""
        return index / self.frame_rate_hz


class Project(Model):
    """A complete tofradar project, as stored in a project JSON file."""

    format_version: int = FORMAT_VERSION
    name: str = "untitled"
    description: str = ""
    seed: int = Field(0, ge=0)
    timeline: Timeline = Timeline()
    materials: list[DualBandMaterial] = Field(
        default_factory=list, description="project materials; override the library by name"
    )
    objects: list[SceneObject] = Field(default_factory=list)
    materials_map: dict[str, str] = Field(
        default_factory=dict, max_length=4096,
        description="imported asset material name → library material it was mapped to")
    rig: SensorRig = SensorRig()
    dsp: DspConfig = DspConfig()
    #: Set on projects whose people were expanded into segments
    #: (:func:`simcore.scene.people.expand.expand_people`).
    _people: Any = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _check_unique(self) -> Project:
        for what, values in (
            ("object id", [o.id for o in self.objects]),
            ("object name", [o.name for o in self.objects]),
            ("material name", [m.name for m in self.materials]),
        ):
            seen: set[object] = set()
            for v in values:
                if v in seen:
                    raise ValueError(f"duplicate {what} {v!r}")
                seen.add(v)
        return self

    def object_by_name(self, name: str) -> SceneObject:
        """Return the object called ``name`` (KeyError if absent)."""
        for obj in self.objects:
            if obj.name == name:
                return obj
        raise KeyError(name)

    def next_object_id(self) -> int:
        """Smallest unused object id."""
        used = {o.id for o in self.objects}
        return next(i for i in range(len(used) + 1) if i not in used)
