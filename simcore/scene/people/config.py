"""Project-file model of a person: body proportions, materials and the body's motions.

A person is the geometry kind ``"person"`` of a scene object. Its ``motion`` block (beside
the object's rigid ``motion``) says what the body does: ``walk``, ``gesture``,
``vital_signs`` and ``bvh``, combinable where a body can combine them (a walk with vital
signs and a gesture; a BVH clip alone).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator, model_validator

from simcore.scene.base import Model, check_name

#: Highest relative walking speed v / leg length that Boulic et al. (1990) cover.
MAX_RELATIVE_SPEED = 2.3
#: Lowest relative speed accepted for a walk (slower is standing: speed 0).
MIN_RELATIVE_SPEED = 0.1


class Walk(Model):
    """A walk at constant speed along the heading, or along the object's keyframe path.

    ``path = "straight"``: from the object's position along its pose's heading (local +x
    projected on the floor), for ever. ``path = "keyframes"``: through the positions of the
    object's ``motion.keyframes`` (offsets from its position; their times are not used:
    the walk's speed rules), repeated as ``motion.repeat`` says.
    """

    speed_mps: float = Field(1.2, ge=0.0, le=10.0, allow_inf_nan=False,
                             description="walking speed (m/s); 0 stands still")
    path: Literal["straight", "keyframes"] = "straight"


GestureKind = Literal["wave", "swipe_left", "swipe_right", "push", "pull", "circle"]


class Gesture(Model):
    """A hand gesture repeated ``repetitions`` times over ``duration_s`` from ``start_s``."""

    kind: GestureKind = "wave"
    hand: Literal["left", "right"] = "right"
    start_s: float = Field(0.0, ge=0.0, le=1e5, allow_inf_nan=False)
    duration_s: float = Field(2.0, gt=0.05, le=1e4, allow_inf_nan=False)
    repetitions: int = Field(2, ge=1, le=1000)


class VitalSigns(Model):
    """Breathing and heartbeat: chest-wall displacement along the chest's normal.

    Amplitudes are peak displacements from the mean (half the peak-to-peak swing).
    Defaults: an adult at rest (breathing 0.25 Hz = 15 /min, 5 mm; heart 1.2 Hz = 72 /min,
    0.3 mm).
    """

    breathing_rate_hz: float = Field(0.25, ge=0.0, le=2.0, allow_inf_nan=False)
    breathing_amplitude_mm: float = Field(5.0, ge=0.0, le=50.0, allow_inf_nan=False)
    heart_rate_hz: float = Field(1.2, ge=0.0, le=4.0, allow_inf_nan=False)
    heart_amplitude_mm: float = Field(0.3, ge=0.0, le=5.0, allow_inf_nan=False)


class BvhClip(Model):
    """A motion-capture clip (BVH file, path relative to the project file)."""

    path: str = Field(min_length=1, max_length=4096)
    play_rate: float = Field(1.0, gt=0.0, le=100.0, allow_inf_nan=False)
    start_offset_s: float = Field(0.0, ge=0.0, le=1e5, allow_inf_nan=False)
    loop: bool = True

    @field_validator("path")
    @classmethod
    def _printable(cls, path: str) -> str:
        return check_name(path, "path")


class PersonMotion(Model):
    """What a person's body does (every part optional)."""

    posture: Literal["standing", "sitting", "lying"] = "standing"
    walk: Walk | None = None
    gesture: Gesture | None = None
    vital_signs: VitalSigns | None = None
    bvh: BvhClip | None = None
    sway_mm: float = Field(2.0, ge=0.0, le=100.0, allow_inf_nan=False,
                           description="amplitude of slow random body sway (mm)")

    @model_validator(mode="after")
    def _combinable(self) -> PersonMotion:
        if self.bvh is not None and (self.walk is not None or self.gesture is not None):
            raise ValueError("a BVH clip drives the whole body: remove walk and gesture")
        if self.walk is not None and self.walk.speed_mps > 0 and self.posture != "standing":
            raise ValueError(f"a {self.posture} person cannot walk: set posture to "
                             f"'standing' or walk.speed_mps to 0")
        return self


class Person(Model):
    """An articulated person (17 ellipsoid segments) standing on its object's origin.

    The object's origin is on the floor between the feet; its local +x is the way the
    person faces (walks), +z up. ``skin`` and ``clothing`` name the materials of bare and
    clothed segments.
    """

    kind: Literal["person"] = "person"
    height_m: float = Field(1.75, ge=0.5, le=2.5, allow_inf_nan=False)
    build: float = Field(1.0, ge=0.6, le=1.6, allow_inf_nan=False,
                         description="girth scale: 1 average, 0.8 slim, 1.3 heavy")
    skin: str = Field("skin", min_length=1)
    clothing: str = Field("clothing", min_length=1)
    motion: PersonMotion = PersonMotion()

    @model_validator(mode="after")
    def _walk_speed(self) -> Person:
        walk = self.motion.walk
        if walk is not None and walk.speed_mps > 0:
            from simcore.scene.people.skeleton import build_skeleton

            leg = build_skeleton(self.height_m, self.build).leg_length_m
            check_walk_speed(walk.speed_mps, leg)
        return self


def check_walk_speed(speed_mps: float, leg_length_m: float) -> float:
    """Relative speed ``v / leg`` if Boulic's model covers it, else a ValueError."""
    rv = speed_mps / leg_length_m
    if rv > MAX_RELATIVE_SPEED or rv < MIN_RELATIVE_SPEED:
        lo, hi = MIN_RELATIVE_SPEED * leg_length_m, MAX_RELATIVE_SPEED * leg_length_m
        raise ValueError(
            f"walk.speed_mps {speed_mps:g} m/s is outside the walking model's range "
            f"{lo:.2f}–{hi:.2f} m/s for this person (relative speed v/leg length "
            f"{MIN_RELATIVE_SPEED:g}–{MAX_RELATIVE_SPEED:g}, Boulic et al. 1990); "
            f"running is not modelled")
    return rv


__all__ = ["BvhClip", "Gesture", "MAX_RELATIVE_SPEED", "Person", "PersonMotion", "VitalSigns",
           "Walk", "check_walk_speed"]
