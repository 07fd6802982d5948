"""Rigid motion: constant linear and angular velocity, or keyframed paths.

Conventions: positions in metres (world frame), Euler angles ``rotation_deg`` are extrinsic
rotations about the world x, y, z axes applied in that order (``R = Rz @ Ry @ Rx``); angular
velocities are in degrees per second about world axes through the object's origin.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, model_validator
from scipy.spatial.transform import Rotation

from simcore.scene.base import (
    MAX_SPEED_MPS,
    MIN_KEYFRAME_SPACING_S,
    AngularVelocity3,
    Finite,
    Model,
    Position3,
    Rotation3,
    Time,
    Velocity3,
)


class Pose(Model):
    """Position (m) and extrinsic x-y-z Euler rotation (degrees)."""

    position_m: Position3 = (0.0, 0.0, 0.0)
    rotation_deg: Rotation3 = (0.0, 0.0, 0.0)

    def rotation(self) -> Rotation:
        """Return the rotation as a scipy :class:`Rotation`."""
        return Rotation.from_euler("xyz", self.rotation_deg, degrees=True)

    def rotation_matrix(self) -> NDArray[np.float64]:
        """The rotation as a 3×3 matrix (read-only; the same values as :meth:`rotation`'s)."""
        return _euler_matrix(tuple(float(a) for a in self.rotation_deg))

    def matrix(self) -> NDArray[np.float64]:
        """Return the 4×4 homogeneous transform (local → parent).

        Examples
        --------
        >>> np.round(Pose(position_m=(1, 2, 3), rotation_deg=(0, 0, 90)).matrix(), 6) + 0.0
        array([[ 0., -1.,  0.,  1.],
               [ 1.,  0.,  0.,  2.],
               [ 0.,  0.,  1.,  3.],
               [ 0.,  0.,  0.,  1.]])
        """
        return make_transform(self.rotation_matrix(), np.asarray(self.position_m))


@functools.lru_cache(maxsize=4096)
def _euler_matrix(rotation_deg: tuple[float, ...]) -> NDArray[np.float64]:
    """Matrix of extrinsic x-y-z Euler angles (degrees), cached.

    scipy's ``Rotation`` costs ≈ 0.1 ms per call, and a snapshot evaluates every object's
    pose.
    """
    out = Rotation.from_euler("xyz", rotation_deg, degrees=True).as_matrix()
    out.setflags(write=False)
    return out


def _rotvec_matrix(rotvec: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrix of a rotation vector (rad), Rodrigues' formula."""
    angle = float(np.sqrt(rotvec @ rotvec))
    if angle == 0.0:
        return np.eye(3)
    k = rotvec / angle
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * (cross @ cross)


class Keyframe(Model):
    """An offset from the base pose at a time: position added, rotation applied after."""

    time_s: Time
    position_m: Position3 = (0.0, 0.0, 0.0)
    rotation_deg: Rotation3 = (0.0, 0.0, 0.0)


class Motion(Model):
    """Rigid motion of an object or of the sensor rig.

    Either constant velocities (``velocity_mps``, ``angular_velocity_dps``) or a list of
    keyframes with linear interpolation of position and spherical interpolation of
    rotation; ``repeat`` says what happens after the last keyframe.
    """

    velocity_mps: Velocity3 = (0.0, 0.0, 0.0)
    angular_velocity_dps: AngularVelocity3 = (0.0, 0.0, 0.0)
    keyframes: list[Keyframe] = Field(default_factory=list, max_length=10_000)
    repeat: Literal["hold", "loop", "back_and_forth"] = "hold"

    @model_validator(mode="after")
    def _check(self) -> Motion:
        if self.keyframes:
            times = [k.time_s for k in self.keyframes]
            for i, (a, b) in enumerate(zip(times, times[1:], strict=False)):
                if b <= a:
                    raise ValueError(f"keyframe times must be strictly increasing, got "
                                     f"keyframes[{i}].time_s = {a} and keyframes[{i + 1}]"
                                     f".time_s = {b}")
                if b - a < MIN_KEYFRAME_SPACING_S:
                    raise ValueError(
                        f"keyframes[{i}] and [{i + 1}] are {b - a:.3g} s apart; at least "
                        f"{MIN_KEYFRAME_SPACING_S:g} s")
                step = np.subtract(self.keyframes[i + 1].position_m, self.keyframes[i].position_m)
                speed = float(np.linalg.norm(step)) / (b - a)
                if speed > MAX_SPEED_MPS:
                    raise ValueError(
                        f"keyframes[{i}] → [{i + 1}] move at {speed:.3g} m/s; at most "
                        f"{MAX_SPEED_MPS:g} m/s")
            if any(self.velocity_mps) or any(self.angular_velocity_dps):
                raise ValueError(
                    "use either keyframes or constant velocities, not both "
                    "(set velocity_mps and angular_velocity_dps to 0 or remove the keyframes)"
                )
        return self

    @property
    def is_static(self) -> bool:
        """True when the motion never changes the pose."""
        return not self.keyframes and not any(self.velocity_mps) and not any(
            self.angular_velocity_dps
        )


@dataclass(frozen=True)
class RigidState:
    """World transform and velocities of a rigid body at one instant.

    Attributes
    ----------
    transform : ndarray, shape (4, 4)
        Local → world homogeneous transform.
    velocity_mps : ndarray, shape (3,)
        Linear velocity of the body's origin (world frame, m/s).
    angular_velocity_rps : ndarray, shape (3,)
        Angular velocity (world frame, rad/s) about the body's origin.
    """

    transform: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    angular_velocity_rps: NDArray[np.float64]

    @property
    def origin(self) -> NDArray[np.float64]:
        """Position of the body's origin in the world (m)."""
        return self.transform[:3, 3]

    def point_velocity(self, points: NDArray[np.floating]) -> NDArray[np.float64]:
        """Velocity (m/s) of world points rigidly attached to the body, shape (..., 3).

        Examples
        --------
        A body spinning at 90°/s about z: a point 1 m along +x moves at π/2 m/s along +y.

        >>> state = rigid_state(Pose(), Motion(angular_velocity_dps=(0, 0, 90)), 0.0)
        >>> np.round(state.point_velocity(np.array([1.0, 0.0, 0.0])), 4) + 0.0
        array([0.    , 1.5708, 0.    ])
        """
        return self.velocity_mps + np.cross(self.angular_velocity_rps, points - self.origin)


def make_transform(rotation: NDArray[np.floating], translation: NDArray[np.floating]) -> NDArray[
    np.float64
]:
    """Build a 4×4 homogeneous transform from a 3×3 rotation and a translation.

    Examples
    --------
    >>> make_transform(np.eye(3), np.array([1.0, 2.0, 3.0]))[:3, 3]
    array([1., 2., 3.])
    """
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def _keyframe_time(times: NDArray[np.float64], t: float, repeat: str) -> tuple[float, float]:
    """Map time ``t`` into the keyframe span; return (local time, direction sign)."""
    t0, t1 = float(times[0]), float(times[-1])
    span = t1 - t0
    if t <= t0 or span == 0.0:
        return t0, 0.0 if t < t0 else 1.0
    if repeat == "hold":
        return (t, 1.0) if t < t1 else (t1, 0.0)
    if repeat == "loop":
        return t0 + (t - t0) % span, 1.0
    phase = (t - t0) % (2.0 * span)
    return (t0 + phase, 1.0) if phase < span else (t1 - (phase - span), -1.0)


def rigid_state(pose: Pose, motion: Motion, t: float) -> RigidState:
    """Evaluate the pose and exact velocities of a body at time ``t`` (s).

    Examples
    --------
    Constant velocity: 0.5 m/s along x for 2 s.

    >>> s = rigid_state(Pose(position_m=(1, 0, 0)), Motion(velocity_mps=(0.5, 0, 0)), 2.0)
    >>> s.origin, s.velocity_mps
    (array([2., 0., 0.]), array([0.5, 0. , 0. ]))

    Keyframes moving 1 m along y in 2 s and back (``back_and_forth``): at 3 s the body is
    half-way back, moving at -0.5 m/s.

    >>> m = Motion(keyframes=[Keyframe(time_s=0), Keyframe(time_s=2, position_m=(0, 1, 0))],
    ...            repeat="back_and_forth")
    >>> s = rigid_state(Pose(), m, 3.0)
    >>> s.origin + 0.0, s.velocity_mps + 0.0
    (array([0. , 0.5, 0. ]), array([ 0. , -0.5,  0. ]))
    """
    base_p = np.asarray(pose.position_m, dtype=np.float64)
    if not motion.keyframes:
        v = np.asarray(motion.velocity_mps, dtype=np.float64)
        w = np.deg2rad(np.asarray(motion.angular_velocity_dps, dtype=np.float64))
        if not (v.any() or w.any()):     # a still body (most of an imported asset's nodes)
            return RigidState(make_transform(pose.rotation_matrix(), base_p), v, w)
        rot = _rotvec_matrix(w * t) @ pose.rotation_matrix()
        return RigidState(make_transform(rot, base_p + v * t), v, w)
    path = _keyframe_path(tuple((float(k.time_s), tuple(map(float, k.position_m)),
                                 tuple(map(float, k.rotation_deg))) for k in motion.keyframes))
    times, offsets, rots = path.times, path.offsets, path.rotations
    if len(times) == 1:
        return RigidState(make_transform(rots[0] @ pose.rotation_matrix(), base_p + offsets[0]),
                          np.zeros(3), np.zeros(3))
    tl, sign = _keyframe_time(times, t, motion.repeat)
    i = int(np.clip(np.searchsorted(times, tl, side="right") - 1, 0, len(times) - 2))
    dt = times[i + 1] - times[i]
    s = (tl - times[i]) / dt
    position = offsets[i] + s * (offsets[i + 1] - offsets[i])
    # Slerp as scipy's: R_i · exp(s · log(R_i⁻¹ R_{i+1})).
    rot_offset = rots[i] @ _rotvec_matrix(s * path.steps[i])
    velocity = sign * (offsets[i + 1] - offsets[i]) / dt
    angular = sign * path.turns[i] / dt
    rot = rot_offset @ pose.rotation_matrix()
    return RigidState(make_transform(rot, base_p + position), velocity, angular)


@dataclass(frozen=True)
class _KeyframePath:
    """A keyframed path's arrays, built once per keyframe list (:func:`_keyframe_path`)."""

    times: NDArray[np.float64]        # (K,) s
    offsets: NDArray[np.float64]      # (K, 3) m
    rotations: NDArray[np.float64]    # (K, 3, 3)
    steps: NDArray[np.float64]        # (K − 1, 3) rotation vector of R_i⁻¹ R_{i+1} (body)
    turns: NDArray[np.float64]        # (K − 1, 3) rotation vector of R_{i+1} R_i⁻¹ (world)


@functools.lru_cache(maxsize=256)
def _keyframe_path(keyframes: tuple[tuple[float, tuple[float, ...], tuple[float, ...]], ...]
                   ) -> _KeyframePath:
    """The arrays of keyframes ``(time, position, rotation_deg)``, cached.

    scipy's Rotation and Slerp cost ≈ 0.3 ms per evaluation, and a snapshot evaluates
    every keyframed body.
    """
    rots = Rotation.from_euler("xyz", [k[2] for k in keyframes], degrees=True)
    if len(keyframes) > 1:
        steps = (rots[:-1].inv() * rots[1:]).as_rotvec()
        turns = (rots[1:] * rots[:-1].inv()).as_rotvec()
    else:
        steps = turns = np.zeros((0, 3))
    path = _KeyframePath(times=np.array([k[0] for k in keyframes]),
                         offsets=np.array([k[1] for k in keyframes], dtype=np.float64),
                         rotations=rots.as_matrix().reshape(-1, 3, 3),
                         steps=steps.reshape(-1, 3), turns=turns.reshape(-1, 3))
    for arr in (path.times, path.offsets, path.rotations, path.steps, path.turns):
        arr.setflags(write=False)
    return path


__all__ = ["Finite", "Keyframe", "Motion", "Pose", "RigidState", "make_transform", "rigid_state"]
