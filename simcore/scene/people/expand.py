"""A project's people as rigid segment objects: what the engine and the sensors see.

:func:`expand_people` replaces each ``person`` object by its 17 segments (ellipsoid
objects named ``"<person>/<segment>"``, in :data:`~simcore.scene.people.skeleton.SEGMENTS`
order, with the person's id, so every id buffer and detection label names the person)
and records a :class:`PeopleExpansion` on the expanded project. The snapshot
(:func:`simcore.scene.snapshot.take_snapshot`) takes the segments' states from the body
model; the renderer, both sensors, the stage cache, the still-background accelerator,
multipath and the labels then see segments as moving rigid parts.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.geometry import Ellipsoid
from simcore.scene.model import Project, SceneObject
from simcore.scene.motion import RigidState
from simcore.scene.people.body import PersonBody
from simcore.scene.people.config import Person
from simcore.scene.people.skeleton import CLOTHED, SEGMENT_INDEX, SEGMENTS

#: Segment whose state is a person's object truth (``/objects/...``): the torso.
TORSO = "chest"


@dataclass(frozen=True)
class PersonSlot:
    """One person of an expanded project."""

    source_index: int      # index of the person in the source project's objects
    first: int             # index of its first segment in the expanded objects
    object_id: int
    name: str
    body: PersonBody


@dataclass(frozen=True)
class PeopleExpansion:
    """How an expanded project's objects map back to the source project's.

    Attributes
    ----------
    people : tuple of PersonSlot
        The people, in source order.
    source_of : ndarray, shape (expanded objects,), int64
        Index of each expanded object's source object.
    body_part : ndarray, shape (expanded objects,), int32
        Segment index (body-part id) of each expanded object; −1 for other objects.
    representative : ndarray, shape (source objects,), int64
        Expanded index whose state is each source object's truth (a person's torso).
    """

    people: tuple[PersonSlot, ...]
    source_of: NDArray[np.int64]
    body_part: NDArray[np.int32]
    representative: NDArray[np.int64]

    def apply(self, states: list[RigidState], t: float) -> None:
        """Put every segment's state at ``t`` (s) into ``states`` (expanded order)."""
        for slot in self.people:
            states[slot.first: slot.first + len(SEGMENTS)] = slot.body.states(t)


def segment_objects(obj: SceneObject, person: Person) -> list[SceneObject]:
    """The segment objects of person ``obj`` (rest geometry; states come per frame)."""
    from simcore.scene.people.skeleton import build_skeleton

    skel = build_skeleton(person.height_m, person.build)
    out = []
    for name in SEGMENTS:
        radii = tuple(float(r) for r in skel.radii[SEGMENT_INDEX[name]])
        out.append(SceneObject.model_construct(
            id=obj.id, name=f"{obj.name}/{name}",
            geometry=Ellipsoid(radii_m=radii),
            pose=obj.pose, motion=obj.motion,
            material=person.clothing if name in CLOTHED else person.skin))
    return out


def expand_people(project: Project, *, base_dir: Path | None = None) -> Project:
    """The project with every person replaced by its segments (itself if it has none)."""
    if not any(isinstance(o.geometry, Person) for o in project.objects):
        return project
    objects: list[SceneObject] = []
    slots: list[PersonSlot] = []
    source_of: list[int] = []
    parts: list[int] = []
    representative: list[int] = []
    for i, obj in enumerate(project.objects):
        geom = obj.geometry
        if isinstance(geom, Person):
            body = PersonBody(geom, obj.pose, obj.motion, object_id=obj.id, seed=project.seed,
                              base_dir=base_dir)
            slots.append(PersonSlot(i, len(objects), obj.id, obj.name, body))
            representative.append(len(objects) + SEGMENT_INDEX[TORSO])
            segs = segment_objects(obj, geom)
            parts += list(range(len(segs)))
        else:
            representative.append(len(objects))
            segs = [obj]
            parts.append(-1)
        objects += segs
        source_of += [i] * len(segs)
    fields = {name: getattr(project, name) for name in type(project).model_fields}
    fields["objects"] = objects
    expanded = Project.model_construct(**fields)
    expanded._people = PeopleExpansion(  # noqa: SLF001 - the model's own private slot
        tuple(slots), np.array(source_of, np.int64), np.array(parts, np.int32),
        np.array(representative, np.int64))
    return expanded


def people_of(project: Project) -> PeopleExpansion | None:
    """The expansion recorded on an expanded project (None for a plain project)."""
    return getattr(project, "_people", None)


def body_part_table(project: Project) -> NDArray[np.int32]:
    """Body-part id of each object of a project, shape (objects,) (−1: not a segment)."""
    people = people_of(project)
    if people is None:
        return np.full(len(project.objects), -1, dtype=np.int32)
    return people.body_part


__all__ = ["PeopleExpansion", "PersonSlot", "TORSO", "body_part_table", "expand_people",
           "people_of", "segment_objects"]
