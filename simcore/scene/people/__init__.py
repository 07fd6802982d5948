"""People: an articulated body model (skeleton, gait, gestures, vital signs, BVH).

Used by the model layer only: :mod:`simcore.scene.people.expand` turns each person of a
project into rigid segment objects whose states the snapshot takes from
:class:`~simcore.scene.people.body.PersonBody`.
"""

from simcore.scene.people.config import (
    BvhClip,
    Gesture,
    Person,
    PersonMotion,
    VitalSigns,
    Walk,
)
from simcore.scene.people.skeleton import SEGMENTS, build_skeleton

__all__ = ["SEGMENTS", "BvhClip", "Gesture", "Person", "PersonMotion", "VitalSigns", "Walk",
           "build_skeleton"]
