"""The project model: scene objects, materials, the sensor rig and the timeline."""

from __future__ import annotations

import re
from typing import Annotated, Any, Literal, TypeVar

from pydantic import AfterValidator, Field, PrivateAttr, model_validator

from simcore.scene.base import Model, Positive
from simcore.scene.dsp_config import DspConfig
from simcore.scene.geometry import Geometry
from simcore.scene.layout import reserved_names, reserved_reason
from simcore.scene.materials import DualBandMaterial
from simcore.scene.motion import Motion, Pose
from simcore.scene.radar_config import RadarConfig
from simcore.scene.rgb_config import RgbCameraConfig
from simcore.scene.tof_config import TofCameraConfig

M = TypeVar("M", bound=Model)

#: Version 2: materials hold their parameters per band name (``bands``).
#: Version 3: named sensors on several rigs (``rig.name``, ``rig.sensors``, ``rigs``) and
#: per-sensor ``frame_rate_hz`` / ``trigger_offset_s``; a version-2 file means the same.
FORMAT_VERSION = 3

#: Sensor and rig names: they name HDF5/Zarr groups, MCAP topics and TF frames.
NAME_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,63}")
#: Names a sensor or rig may not take: dataset groups and names of the layout.
RESERVED_SENSOR_NAMES = reserved_names()


def _check_identifier(name: str) -> str:
    if not NAME_PATTERN.fullmatch(name):
        raise ValueError(f"{name!r} is not a valid name: a letter, then up to 63 letters, "
                         "digits or underscores (it names dataset groups and MCAP topics)")
    return name


Identifier = Annotated[str, AfterValidator(_check_identifier)]


class NamedTof(TofCameraConfig):
    """A ToF camera in a rig's ``sensors`` table (``kind`` says which model)."""

    kind: Literal["tof"] = "tof"


class NamedRadar(RadarConfig):
    """A radar in a rig's ``sensors`` table."""

    kind: Literal["radar"] = "radar"


class NamedRgb(RgbCameraConfig):
    """An RGB camera in a rig's ``sensors`` table."""

    kind: Literal["rgb"] = "rgb"


SensorSpec = Annotated[NamedTof | NamedRadar | NamedRgb, Field(discriminator="kind")]
#: Configuration class of each sensor kind, and its named (``kind``-tagged) variant.
SENSOR_KINDS: dict[str, tuple[type[Model], type[Model]]] = {
    "tof": (TofCameraConfig, NamedTof),
    "radar": (RadarConfig, NamedRadar),
    "rgb": (RgbCameraConfig, NamedRgb),
}


def sensor_kind(config: Model) -> str:
    """``"tof"``, ``"radar"`` or ``"rgb"``: which sensor model a configuration is for."""
    for kind, (base, _) in SENSOR_KINDS.items():
        if isinstance(config, base):
            return kind
    raise TypeError(f"{type(config).__name__} is not a sensor configuration")


def named_sensor(config: Model) -> Model:
    """``config`` as an entry of a rig's ``sensors`` table (same values, ``kind`` set)."""
    named = SENSOR_KINDS[sensor_kind(config)][1]
    if isinstance(config, named):
        return config
    return named.model_validate(config.model_dump())


class SceneObject(Model):
    """One object of the scene: geometry, pose, dual-band material and motion."""

    id: int = Field(ge=0, le=2**31 - 1)
    name: str = Field(min_length=1)
    geometry: Geometry
    pose: Pose = Pose()
    material: str = Field("concrete", min_length=1)
    motion: Motion = Motion()


class Rig(Model):
    """A rig carrying named sensors; its body frame is x forward, y left, z up.

    Each sensor has a pose on the rig (``pose_on_rig``) and moves with the rig's motion.
    """

    name: Identifier = "rig"
    pose: Pose = Pose()
    motion: Motion = Motion()
    sensors: dict[Identifier, SensorSpec] = Field(
        default_factory=dict, max_length=64,
        description="named sensors on this rig; the name keys the sensor's outputs")

    def sensor_configs(self) -> dict[str, Model]:
        """The configurations of the sensors on the rig, by sensor name."""
        out: dict[str, Model] = {}
        for name in type(self).model_fields:
            value = getattr(self, name)
            if value is not None and hasattr(value, "pose_on_rig"):
                out[name] = value
        out.update(self.sensors)
        return out


class SensorRig(Rig):
    """The project's first rig, with its built-in sensor fields (all optional).

    Every field with a ``pose_on_rig`` is a sensor, named by the field (``tof``,
    ``radar``, ``rgb``); ``None`` leaves that sensor off. ``tof`` and ``radar`` default to
    the pico flexx and the BGT60TR13C (so a file that leaves them out means what it always
    did); ``"tof": null`` makes a radar-only rig, ``"radar": null`` a ToF-only one. More
    sensors of any kind go in ``sensors``, more rigs in :attr:`Project.rigs`.
    """

    tof: TofCameraConfig | None = TofCameraConfig()
    radar: RadarConfig | None = RadarConfig()
    rgb: RgbCameraConfig | None = None


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
    rigs: list[Rig] = Field(
        default_factory=list, max_length=64,
        description="further rigs, each with its own pose, motion and named sensors")
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
        self._check_sensors()
        return self

    def _check_sensors(self) -> None:
        """Names unique and free, timing consistent, at least one sensor.

        A failed check raises ``ValueError("@<field path>: message")``: the loader reports
        it against that field.
        """
        rigs: dict[str, str] = {}
        owner: dict[str, str] = {}
        for i, rig in enumerate(self.all_rigs()):
            where = "rig" if i == 0 else f"rigs[{i - 1}]"
            if rig.name in rigs:
                raise ValueError(f"@{where}.name: duplicate rig name {rig.name!r} (also "
                                 f"{rigs[rig.name]})")
            if rig.name in RESERVED_SENSOR_NAMES and rig.name != "rig":
                raise ValueError(f"@{where}.name: rig name {rig.name!r} collides with "
                                 f"{reserved_reason(rig.name)}; choose another name")
            rigs[rig.name] = f"{where}.name"
            for name in rig.sensors:
                if getattr(rig, name, None) is not None and name in type(rig).model_fields:
                    raise ValueError(f"@{where}.sensors.{name}: duplicate sensor name {name!r} "
                                     f"(also {where}.{name})")
            for name, cfg in rig.sensor_configs().items():
                path = f"{where}.sensors.{name}" if name in rig.sensors else f"{where}.{name}"
                self._check_sensor(name, cfg, path, owner)
                owner[name] = path
        if not owner:
            raise ValueError("@rig: the project has no sensor: set rig.tof, rig.radar or "
                             "rig.rgb, or add one to a rig's sensors table")
        # Rigs and sensors are both TF frames (MCAP, the live stream), beside "world".
        for name in sorted(set(rigs) & set(owner)):
            raise ValueError(f"@{owner[name]}: name {name!r} is both a rig's "
                             f"({rigs[name]}) and a sensor's; each names a TF frame, so they "
                             "must differ")
        for name, path in {**rigs, **owner}.items():
            if name == "world":
                raise ValueError(f"@{path}: 'world' names the world frame; choose another "
                                 "rig or sensor name")

    def _check_sensor(self, name: str, cfg: Model, path: str, owner: dict[str, str]) -> None:
        """One sensor's name and timing (``owner``: the sensors seen so far, by name)."""
        if name in owner:
            raise ValueError(f"@{path}: duplicate sensor name {name!r} (also {owner[name]})")
        if name in RESERVED_SENSOR_NAMES:
            raise ValueError(f"@{path}: sensor name {name!r} collides with "
                             f"{reserved_reason(name)}; choose another name")
        try:
            n = cfg.frame_divider(self.timeline.frame_rate_hz)  # type: ignore[attr-defined]
        except ValueError as exc:
            # The message starts with the field: "frame_rate_hz: 3 Hz is not ...".
            raise ValueError(f"@{path}.{exc}") from None
        period = n / self.timeline.frame_rate_hz
        offset = cfg.trigger_offset_s  # type: ignore[attr-defined]
        if offset >= period:
            raise ValueError(f"@{path}.trigger_offset_s: {offset:g} s is not shorter than "
                             f"the sensor's frame period {period:g} s")

    def all_rigs(self) -> list[Rig]:
        """Every rig: :attr:`rig` first, then :attr:`rigs`."""
        return [self.rig, *self.rigs]

    def sensor_configs(self) -> dict[str, Model]:
        """Every sensor's configuration, by name: the first rig's, then the others'."""
        out: dict[str, Model] = {}
        for rig in self.all_rigs():
            out.update(rig.sensor_configs())
        return out

    def sensor_config(self, name: str) -> Model:
        """The configuration of sensor ``name`` (KeyError naming the sensors there are)."""
        configs = self.sensor_configs()
        if name not in configs:
            raise KeyError(f"no sensor {name!r} (sensors: {', '.join(configs)})")
        return configs[name]

    def sensor_rig(self, name: str) -> Rig:
        """The rig that carries sensor ``name``."""
        for rig in self.all_rigs():
            if name in rig.sensor_configs():
                return rig
        raise KeyError(f"no sensor {name!r}")

    def sensor_path(self, name: str) -> str:
        """Field path of sensor ``name`` (``rig.radar``, ``rigs[0].sensors.side``, ...)."""
        for i, rig in enumerate(self.all_rigs()):
            where = "rig" if i == 0 else f"rigs[{i - 1}]"
            if name in rig.sensors:
                return f"{where}.sensors.{name}"
            if name in rig.sensor_configs():
                return f"{where}.{name}"
        raise KeyError(f"no sensor {name!r}")

    def radar(self, name: str | None = None) -> RadarConfig:
        """Radar ``name``'s configuration, or the first radar's (KeyError when none)."""
        return self._of_kind(RadarConfig, "radar", name)

    def tof(self, name: str | None = None) -> TofCameraConfig:
        """ToF camera ``name``'s configuration, or the first camera's (KeyError when none)."""
        return self._of_kind(TofCameraConfig, "tof", name)

    def _of_kind(self, cls: type[M], kind: str, name: str | None) -> M:
        configs = self.sensors_of_kind(kind)
        if name is None:
            if not configs:
                raise KeyError(f"the project has no sensor of kind {kind!r}")
            name = next(iter(configs))
        cfg = self.sensor_config(name)
        if not isinstance(cfg, cls):
            raise KeyError(f"sensor {name!r} is not of kind {kind!r}")
        return cfg

    def sensors_of_kind(self, kind: str) -> dict[str, Model]:
        """The configurations of the sensors of one kind (``"tof"``, ...), by name."""
        return {n: c for n, c in self.sensor_configs().items() if sensor_kind(c) == kind}

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
