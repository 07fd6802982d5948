"""Rigs and named sensors of a project, for the editors, panels and the 3D view (issue #30).

A project carries its first rig (``rig``: the built-in ``tof`` and ``radar`` fields, the
optional ``rgb`` field, more sensors in ``rig.sensors``) and further rigs (``rigs[i]``, each
with its ``sensors`` table). This module names where each sensor and rig sits in the project
document (its field path), checks new names, and applies the sensor editor's structural
edits (add, copy, rename, remove sensors and rigs) to a project document, each as one undo
step of :class:`~app.document.document.ProjectDocument`.

How a sensor is followed through an edit lives one level lower, in
:mod:`app.document.identity` (the document itself needs it); ``follow_sensor`` is
re-exported here for the editors and panels.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from app.document.document import RIG, RIG_KEY_PREFIX, EditError, ProjectDocument
from app.document.identity import follow_sensor
from simcore.scene import Project
from simcore.scene.model import (
    NAME_PATTERN,
    RESERVED_SENSOR_NAMES,
    SENSOR_KINDS,
    Rig,
    named_sensor,
    sensor_kind,
)
from simcore.scene.motion import RigidState, make_transform, rigid_state
from simcore.scene.radar_config import RadarConfig
from simcore.scene.snapshot import BODY_FROM_OPTICAL, SensorState

#: The sensor kinds, in the order the editor offers them, with their words.
KIND_WORDS: dict[str, str] = {"tof": "ToF camera", "radar": "radar", "rgb": "RGB camera"}
#: Sensor fields of the first rig (built in: named by the field, never renamed).
BUILT_IN = ("tof", "radar", "rgb")


# --- where things are --------------------------------------------------------------------
def rig_index(project: Project, rig_name: str) -> int:
    """Index of rig ``rig_name`` in :meth:`Project.all_rigs` (KeyError if absent)."""
    for i, rig in enumerate(project.all_rigs()):
        if rig.name == rig_name:
            return i
    raise KeyError(f"no rig {rig_name!r}")


def rig_path(index: int) -> str:
    """Field path of rig ``index`` of :meth:`Project.all_rigs`: ``rig`` or ``rigs[i]``."""
    return "rig" if index == 0 else f"rigs[{index - 1}]"


def is_built_in(project: Project, name: str) -> bool:
    """Whether sensor ``name`` is a field of the first rig (``tof``, ``radar``, ``rgb``)."""
    return name in BUILT_IN and getattr(project.rig, name, None) is not None


def sensor_path(project: Project, name: str) -> str:
    """Field path of sensor ``name``: ``rig.radar``, ``rig.sensors.radar_b``, ``rigs[0]…``."""
    if is_built_in(project, name):
        return f"rig.{name}"
    for i, rig in enumerate(project.all_rigs()):
        if name in rig.sensors:
            return f"{rig_path(i)}.sensors.{name}"
    raise KeyError(f"no sensor {name!r} (sensors: {', '.join(project.sensor_configs())})")


def sensor_names(project: Project, kind: str | None = None) -> list[str]:
    """Every sensor's name (of one kind), the first rig's first."""
    if kind is None:
        return list(project.sensor_configs())
    return list(project.sensors_of_kind(kind))


def rig_key(project: Project, index: int) -> str:
    """Selection key of rig ``index``: :data:`RIG` or ``"rig:<name>"``."""
    return RIG if index == 0 else RIG_KEY_PREFIX + project.all_rigs()[index].name


def is_rig_key(key: object) -> bool:
    """Whether a selection key names a rig."""
    return key == RIG or (isinstance(key, str) and key.startswith(RIG_KEY_PREFIX))


def rig_of_key(project: Project, key: object) -> int | None:
    """Index (in :meth:`Project.all_rigs`) of the rig a selection key names, or None."""
    if key == RIG:
        return 0
    if isinstance(key, str) and key.startswith(RIG_KEY_PREFIX):
        name = key[len(RIG_KEY_PREFIX):]
        for i, rig in enumerate(project.rigs, start=1):
            if rig.name == name:
                return i
    return None


def removal_refusal(project: Project, name: str) -> str | None:
    """Why sensor ``name`` cannot be removed, or None when it can.

    Any sensor can go, the first rig's built-in ToF camera and radar too (issue 40: a
    radar-only or ToF-only project is an ordinary one), except the project's last sensor.
    """
    configs = project.sensor_configs()
    if name in configs and len(configs) == 1:
        words = KIND_WORDS[sensor_kind(configs[name])]
        return (f"The {words} “{name}” is the project's only sensor and cannot be removed: "
                "a project needs at least one sensor; add another sensor first")
    return None


def rename_refusal(project: Project, name: str) -> str | None:
    """Why sensor ``name`` cannot be renamed, or None when it can."""
    if is_built_in(project, name):
        return (f"The first rig's built-in sensor “{name}” keeps its name (it is the field "
                "of that name in the project file); copy it to get a renamed sensor")
    return None


def name_problem(project: Project, name: str, *, what: str = "sensor",
                 old: str | None = None) -> str | None:
    """Why ``name`` cannot name a new (or renamed) sensor or rig, or None when it can."""
    if not NAME_PATTERN.fullmatch(name):
        return (f"{what.capitalize()} name “{name}” is not valid: a letter, then up to 63 "
                "letters, digits or underscores (it names dataset groups and MCAP topics)")
    if name == old:
        return None
    if what == "sensor":
        if name in RESERVED_SENSOR_NAMES:
            return f"Sensor name “{name}” is reserved for a dataset group"
        if name in project.sensor_configs() or name in BUILT_IN:
            return f"Sensor name “{name}” is taken: every sensor needs its own name"
    elif name in {r.name for r in project.all_rigs()}:
        return f"Rig name “{name}” is taken: every rig needs its own name"
    return None


def unique_name(project: Project, base: str, *, what: str = "sensor") -> str:
    """``base``, or ``base_2``, ``base_3`` … : the first that names no sensor (rig) yet."""
    base = base[:60]
    if name_problem(project, base, what=what) is None:
        return base
    n = 2
    while name_problem(project, f"{base}_{n}", what=what) is not None:
        n += 1
    return f"{base}_{n}"


def has_kind(project: Project, kind: str) -> bool:
    """Whether the project has a sensor of ``kind`` (``"tof"``, ``"radar"``, ``"rgb"``)."""
    return bool(project.sensors_of_kind(kind))


def _current(document: ProjectDocument, kind: str) -> str:
    name = document.current_sensor(kind)
    if name is None:
        raise KeyError(f"the project has no {KIND_WORDS[kind]}")
    return name


def current_radar_path(document: ProjectDocument) -> str:
    """Field path of the radar the editors edit (:meth:`ProjectDocument.current_sensor`).

    KeyError when the project has no radar (the radar editors are disabled then).
    """
    return sensor_path(document.project, _current(document, "radar"))


def current_radar(document: ProjectDocument) -> Any:
    """Configuration of the radar the editors edit (KeyError: the project has none)."""
    return document.project.sensor_config(_current(document, "radar"))


def radar_wavelength_m(project: Project) -> float:
    """Wavelength (m) of the first radar; the default radar's in a project without one.

    What the material editor, the corner reflector's RCS and the scene import quote
    radar-band values at.
    """
    radar = next(iter(project.sensors_of_kind("radar").values()), None) or RadarConfig()
    return float(radar.wavelength_m)  # type: ignore[attr-defined]


# --- where things are at a time ---------------------------------------------------------
def rig_states(project: Project, t: float) -> list[RigidState]:
    """Body-frame state of every rig at time ``t`` (s), in :meth:`Project.all_rigs` order."""
    return [rigid_state(r.pose, r.motion, t) for r in project.all_rigs()]


def sensor_states(project: Project, t: float) -> dict[str, SensorState]:
    """Optical-frame state of every sensor of every rig at time ``t``, by sensor name.

    The same transforms as :func:`simcore.scene.snapshot.take_snapshot` (rig × mount ×
    optical axes), for the sensors of every rig.
    """
    optical = make_transform(BODY_FROM_OPTICAL, np.zeros(3))
    out: dict[str, SensorState] = {}
    for rig, state in zip(project.all_rigs(), rig_states(project, t), strict=True):
        for name, cfg in rig.sensor_configs().items():
            transform = state.transform @ cfg.pose_on_rig.matrix() @ optical  # type: ignore[attr-defined]
            out[name] = SensorState(transform=transform,
                                    velocity_mps=state.point_velocity(transform[:3, 3]),
                                    angular_velocity_rps=state.angular_velocity_rps)
    return out


# --- structural edits (one undo step each) ----------------------------------------------
def _rig_doc(data: dict[str, Any], index: int) -> dict[str, Any]:
    return data["rig"] if index == 0 else data["rigs"][index - 1]


def _sensor_entry(data: dict[str, Any], project: Project, name: str) -> tuple[dict[str, Any],
                                                                              str]:
    """The dict holding sensor ``name`` and its key there."""
    if is_built_in(project, name):
        return data["rig"], name
    i = rig_index(project, project.sensor_rig(name).name)
    return _rig_doc(data, i)["sensors"], name


def new_sensor_config(kind: str) -> dict[str, Any]:
    """A new sensor's settings: the model's defaults for ``kind`` (the ``kind`` tag set)."""
    if kind not in SENSOR_KINDS:
        raise EditError(f"unknown sensor kind {kind!r}; known: {', '.join(SENSOR_KINDS)}")
    return dict(SENSOR_KINDS[kind][1]().model_dump())


def free_built_in(project: Project, rig: int, kind: str) -> bool:
    """Whether a new ``kind`` sensor on rig ``rig`` goes into the first rig's empty field.

    The first rig's ``tof``, ``radar`` or ``rgb`` field when it is empty (removed, or a
    radar-only / ToF-only project) and no other sensor is called so: the sensor added back
    gets its built-in name and dataset paths.
    """
    return (rig == 0 and kind in BUILT_IN and getattr(project.rig, kind, None) is None
            and kind not in project.sensor_configs())


def add_sensor(document: ProjectDocument, rig: int, kind: str, name: str | None = None) -> str:
    """Add a ``kind`` sensor with default settings to rig ``rig``; its name.

    On the first rig, a ToF camera, radar or RGB camera whose built-in field is empty
    fills that field (named ``tof``, ``radar``, ``rgb``) unless another ``name`` is asked.
    """
    project = document.project
    if kind not in SENSOR_KINDS:
        raise EditError(f"unknown sensor kind {kind!r}; known: {', '.join(SENSOR_KINDS)}")
    rig_name = project.all_rigs()[rig].name
    if name in (None, kind) and free_built_in(project, rig, kind):
        field = dict(SENSOR_KINDS[kind][0]().model_dump())
        document.edit(f"Add {KIND_WORDS[kind]} {kind} to {rig_name}",
                      lambda d: d["rig"].__setitem__(kind, field))
        return kind
    name = name or unique_name(project, kind if kind not in BUILT_IN else f"{kind}_2")
    problem = name_problem(project, name)
    if problem:
        raise EditError(problem)
    config = new_sensor_config(kind)
    document.edit(f"Add {KIND_WORDS[kind]} {name} to {rig_name}",
                  lambda d: _rig_doc(d, rig)["sensors"].__setitem__(name, config))
    return name


def copy_sensor(document: ProjectDocument, name: str, new_name: str | None = None) -> str:
    """Duplicate sensor ``name`` on its rig under a new name; the new name."""
    project = document.project
    cfg = project.sensor_config(name)
    new_name = new_name or unique_name(project, f"{name}_copy")
    problem = name_problem(project, new_name)
    if problem:
        raise EditError(problem)
    config = named_sensor(cfg).model_dump()
    rig = rig_index(project, project.sensor_rig(name).name)
    document.edit(f"Copy {KIND_WORDS[sensor_kind(cfg)]} {name} as {new_name}",
                  lambda d: _rig_doc(d, rig)["sensors"].__setitem__(new_name, config))
    return new_name


def remove_sensor(document: ProjectDocument, name: str) -> None:
    """Remove sensor ``name`` (one undo step; the project's last sensor is refused).

    A built-in sensor of the first rig (``tof``, ``radar``, ``rgb``) is set to null there.
    """
    project = document.project
    problem = removal_refusal(project, name)
    if problem:
        raise EditError(problem)
    kind = sensor_kind(project.sensor_config(name))

    def mutate(d: dict[str, Any]) -> None:
        holder, key = _sensor_entry(d, project, name)
        if holder is d["rig"] and key in BUILT_IN:
            holder[key] = None  # the first rig's built-in field: off
        else:
            del holder[key]

    document.edit(f"Remove {KIND_WORDS[kind]} {name}", mutate)


def rename_sensor(document: ProjectDocument, name: str, new_name: str) -> None:
    """Rename sensor ``name`` (its place in its rig's table is kept)."""
    project = document.project
    problem = rename_refusal(project, name) or name_problem(project, new_name, old=name)
    if problem:
        raise EditError(problem)
    if new_name == name:
        return

    def mutate(d: dict[str, Any]) -> None:
        holder, _ = _sensor_entry(d, project, name)
        items = list(holder.items())
        holder.clear()
        holder.update((new_name if k == name else k, v) for k, v in items)

    document.edit(f"Rename sensor {name} to {new_name}", mutate)


def add_rig(document: ProjectDocument, name: str | None = None) -> str:
    """Add an empty rig (1 m to the left of the last one); its name."""
    project = document.project
    name = name or unique_name(project, f"rig{len(project.all_rigs()) + 1}", what="rig")
    problem = name_problem(project, name, what="rig")
    if problem:
        raise EditError(problem)
    last = project.all_rigs()[-1]
    x, y, z = last.pose.position_m
    pose = last.pose.model_copy(update={"position_m": (x, y + 1.0, z)})
    new = Rig(name=name, pose=pose).model_dump()
    document.edit(f"Add rig {name}", lambda d: d["rigs"].append(new))
    return name


def remove_rig(document: ProjectDocument, index: int) -> None:
    """Remove rig ``index`` (≥ 1) with its sensors; the first rig stays."""
    project = document.project
    if index == 0:
        raise EditError("The first rig cannot be removed: it is the project's “rig” (its "
                        "sensors can be removed one by one)")
    rig = project.all_rigs()[index]
    document.edit(f"Remove rig {rig.name}", lambda d: d["rigs"].pop(index - 1))


def rename_rig(document: ProjectDocument, index: int, new_name: str) -> None:
    """Rename rig ``index``."""
    project = document.project
    old = project.all_rigs()[index].name
    problem = name_problem(project, new_name, what="rig", old=old)
    if problem:
        raise EditError(problem)
    if new_name != old:
        document.edit(f"Rename rig {old} to {new_name}",
                      lambda d: _rig_doc(d, index).__setitem__("name", new_name))


__all__ = ["BUILT_IN", "KIND_WORDS", "RIG_KEY_PREFIX", "add_rig", "add_sensor", "copy_sensor",
           "current_radar", "current_radar_path", "follow_sensor", "free_built_in", "has_kind",
           "is_built_in", "is_rig_key", "name_problem", "radar_wavelength_m", "remove_rig",
           "remove_sensor", "removal_refusal", "rename_refusal", "rename_rig", "rename_sensor",
           "rig_index", "rig_key", "rig_of_key", "rig_path", "rig_states", "sensor_names",
           "sensor_path", "sensor_states", "unique_name"]
