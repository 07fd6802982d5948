"""A person's segments at any time: posture, walk, gesture, vital signs, sway or BVH.

:class:`PersonBody` evaluates the world transform of every segment (origin at the
segment's ellipsoid centre) and its exact rigid velocities: linear and angular velocities
are central differences of the transforms over ±``VELOCITY_STEP_S`` (the motions are
smooth, so the error is of order ``h²``; far below what a radar frame resolves).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.motion import Motion, Pose, RigidState, rigid_state
from simcore.scene.people import gait
from simcore.scene.people.bvh import BODY_FROM_BVH, BvhMotion, bone_offset, load_bvh, map_joints
from simcore.scene.people.config import Person, check_walk_speed
from simcore.scene.people.gestures import gesture_angles, gesture_weight_phase
from simcore.scene.people.skeleton import PARENTS, SEGMENT_INDEX, SEGMENTS, build_skeleton
from simcore.scene.people.vitals import breathing_m, heartbeat_m, sway_m, sway_phases

#: Half-step of the central differences that give segment velocities (s).
VELOCITY_STEP_S = 1e-4
_S = len(SEGMENTS)


def rot_x(a: float) -> NDArray[np.float64]:
    """Rotation about x by ``a`` (rad)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a: float) -> NDArray[np.float64]:
    """Rotation about y by ``a`` (rad)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def rot_z(a: float) -> NDArray[np.float64]:
    """Rotation about z by ``a`` (rad)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def frame_from_bone(bone: NDArray[np.float64], forward: NDArray[np.float64]
                    ) -> NDArray[np.float64]:
    """Rotation whose −z is along ``bone`` and whose x is ``forward`` made perpendicular."""
    z = -bone / np.linalg.norm(bone)
    x = forward - (forward @ z) * z
    x /= np.linalg.norm(x)
    # z × x written out: the products and differences of np.cross, without its axis
    # handling (a body frame has 24 of these, three times per frame).
    y = np.array([z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2],
                  z[0] * x[1] - z[1] * x[0]])
    return np.column_stack([x, y, z])


@dataclass(frozen=True)
class BodyFrame:
    """Segment joints and rotations in a body frame, and its place in the world."""

    joints: NDArray[np.float64]     # (S, 3) joint positions, body frame (m)
    rotations: NDArray[np.float64]  # (S, 3, 3) segment → body rotations
    placement: NDArray[np.float64]  # (4, 4) body frame → world


#: Half-length of path (m) over which a walker turns at a corner or an end of its path.
TURN_HALF_LENGTH_M = 0.25


class _Path:
    """Where a walker is after walking a distance: a polyline walked at constant speed.

    The path is unfolded into legs (forward, then backward for ``back_and_forth``) of
    constant heading; the heading turns smoothly over ±``TURN_HALF_LENGTH_M`` around each
    leg boundary (a reversal turns left), so the body's angular velocity stays finite.
    """

    def __init__(self, pose: Pose, rigid: Motion, path: str):
        base = np.asarray(pose.position_m, dtype=np.float64)
        heading = pose.rotation_matrix()[:, 0]
        self.yaw0 = float(np.arctan2(heading[1], heading[0]))
        self.base = base
        self.points: NDArray[np.float64] | None = None
        self.repeat = rigid.repeat
        if path == "keyframes" and len(rigid.keyframes) >= 2:
            pts = base + np.array([k.position_m for k in rigid.keyframes], dtype=np.float64)
            pts[:, 2] = base[2]
            steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
            keep = np.concatenate([[True], steps > 1e-6])
            if keep.sum() >= 2:
                self._legs(pts[keep])

    def _legs(self, pts: NDArray[np.float64]) -> None:
        if self.repeat == "back_and_forth":
            pts = np.concatenate([pts, pts[-2::-1]])
        elif self.repeat == "loop" and np.linalg.norm(pts[-1] - pts[0]) > 1e-6:
            pts = np.concatenate([pts, pts[:1]])  # the jump back is walked too
        self.points = pts
        d = np.diff(pts, axis=0)
        self.yaws = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        self.cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(d, axis=1))])

    def distance(self, walked: float) -> float:
        """Distance along the path for a walked distance (clamped at the end for ``hold``)."""
        if self.points is not None and self.repeat == "hold":
            return min(walked, float(self.cum[-1]))
        return walked

    def at(self, distance: float) -> tuple[NDArray[np.float64], float]:
        """(position on the floor (m), yaw (rad)) at ``distance`` (m) along the path."""
        if self.points is None:
            d = np.array([np.cos(self.yaw0), np.sin(self.yaw0), 0.0])
            return self.base + distance * d, self.yaw0
        total = float(self.cum[-1])
        if distance < 0.0:  # before the walk: on the first leg's line, not yet turning
            d0 = (self.points[1] - self.points[0]) / self.cum[1]
            return self.points[0] + distance * d0, float(self.yaws[0])
        s = distance % total if self.repeat != "hold" else min(distance, total)
        n = len(self.yaws)
        i = int(np.clip(np.searchsorted(self.cum, s, side="right") - 1, 0, n - 1))
        seg = self.points[i + 1] - self.points[i]
        frac = (s - self.cum[i]) / (self.cum[i + 1] - self.cum[i])
        position = self.points[i] + frac * seg  # before the start: extrapolated back
        return position, self._yaw(s, i, first=distance < total)

    def _yaw(self, s: float, i: int, *, first: bool) -> float:
        cyclic = self.repeat != "hold"
        n, w = len(self.yaws), TURN_HALF_LENGTH_M
        yaw = float(self.yaws[i])
        for j, edge in ((i, self.cum[i]), (i + 1, self.cum[i + 1])):
            if abs(s - edge) >= w or ((not cyclic or first) and j == 0) or (
                    not cyclic and j == n):
                continue
            before, after = self.yaws[(j - 1) % n], self.yaws[j % n]
            turn = (after - before + np.pi) % (2 * np.pi) - np.pi
            if abs(abs(turn) - np.pi) < 1e-9:
                turn = np.pi  # a reversal: turn left
            f = (s - edge + w) / (2 * w)
            f = f * f * (3 - 2 * f)
            return float(before + turn * f)
        return yaw


class PersonBody:
    """Evaluates one person's segments (:mod:`simcore.scene.people`).

    Parameters
    ----------
    person : Person
        The geometry (proportions and motion block).
    pose : Pose
        The object's pose (origin on the floor between the feet, +x facing).
    rigid : Motion
        The object's rigid motion: moves a person that does not walk; its keyframe
        positions are the path of a walk with ``path = "keyframes"``.
    object_id, seed : int
        Seed the body's sway.
    base_dir : Path, optional
        Folder a BVH path is relative to.
    """

    def __init__(self, person: Person, pose: Pose, rigid: Motion, *, object_id: int = 0,
                 seed: int = 0, base_dir: Path | None = None):
        self.person = person
        self.pose = pose
        self.rigid = rigid
        self.skeleton = build_skeleton(person.height_m, person.build)
        m = person.motion
        self.walk_speed = m.walk.speed_mps if m.walk is not None else 0.0
        self.rv = (check_walk_speed(self.walk_speed, self.skeleton.leg_length_m)
                   if self.walk_speed > 0 else 0.0)
        self.path = _Path(pose, rigid, m.walk.path) if m.walk is not None else None
        self.phases = sway_phases(seed, object_id)
        self.bvh: BvhMotion | None = None
        if m.bvh is not None:
            from simcore.scene.project_io import resolve_mesh_path

            self.bvh = load_bvh(resolve_mesh_path(base_dir or Path.cwd(), m.bvh.path))
            self._bvh_map = map_joints(self.bvh)
            self._bvh_fix = self._bvh_corrections()

    # ------------------------------------------------------------------ public
    def segment_transforms(self, t: float) -> NDArray[np.float64]:
        """World transform of each segment's ellipsoid-centred frame, shape (S, 4, 4)."""
        frame = self.body_frame(t)
        out = np.tile(np.eye(4), (_S, 1, 1))
        place_r, place_p = frame.placement[:3, :3], frame.placement[:3, 3]
        centers = np.einsum("sij,sj->si", frame.rotations, self.skeleton.centers)
        out[:, :3, :3] = place_r @ frame.rotations
        out[:, :3, 3] = (frame.joints + centers) @ place_r.T + place_p
        return out

    def states(self, t: float) -> list[RigidState]:
        """Each segment's rigid state at ``t`` (s): transform, velocity, angular velocity."""
        h = VELOCITY_STEP_S
        now = self.segment_transforms(t)
        before, after = self.segment_transforms(t - h), self.segment_transforms(t + h)
        v = (after[:, :3, 3] - before[:, :3, 3]) / (2 * h)
        delta = after[:, :3, :3] @ np.transpose(before[:, :3, :3], (0, 2, 1))
        w = _log_rotations(delta) / (2 * h)
        return [RigidState(now[i], v[i], w[i]) for i in range(_S)]

    def chest_displacement(self, t: float) -> tuple[float, float]:
        """(breathing, heartbeat) chest-wall displacement at ``t`` (m, + outwards)."""
        vs = self.person.motion.vital_signs
        return breathing_m(vs, t), heartbeat_m(vs, t)

    def walked(self, t: float) -> float:
        """Distance walked by ``t`` (m; stops at the end of a ``hold`` path)."""
        d = self.walk_speed * t
        return self.path.distance(d) if self.path is not None else d

    def gait_phase(self, t: float) -> float:
        """Gait cycles completed by ``t`` (left heel strike at integers; 0 if not walking)."""
        if self.rv <= 0:
            return 0.0
        stride = self.walk_speed * gait.cycle_duration_s(self.rv)
        return self.walked(t) / stride

    # ------------------------------------------------------------------ body frame
    def body_frame(self, t: float) -> BodyFrame:
        """Joints and rotations of every segment at ``t`` in the body frame, and its place."""
        if self.bvh is not None:
            return self._bvh_frame(t)
        skel = self.skeleton
        rot = np.tile(np.eye(3), (_S, 1, 1))
        root = np.array([0.0, 0.0, skel.joints[0, 2]])
        posture = self.person.motion.posture
        legs: dict[str, NDArray[np.float64]] = {}
        arm_base = {"l": (0.0, 0.0, 0.0, 5.0, 0.0), "r": (0.0, 0.0, 0.0, 5.0, 0.0)}
        if self.rv > 0:
            phase = self.gait_phase(t) % 1.0
            surge, lateral, bounce, turn = gait.pelvis_ripple(phase, self.rv,
                                                              skel.leg_length_m)
            ankle_h = skel.height_m * 0.039
            root = np.array([surge, lateral, gait.hip_height(self.walk_speed, self.rv,
                                                        skel.leg_length_m, ankle_h) + bounce])
            rot[0] = rot_z(turn)
            rot[1] = rot_z(-0.5 * turn)
            rot[2] = rot_z(-0.8 * turn)
            swing = np.degrees(gait.arm_swing_rad(phase, self.rv))
            arm_base = {"l": (swing, 3.0, 0.0, 10.0 + 0.6 * max(swing, 0), 0.0),
                        "r": (-swing, 3.0, 0.0, 10.0 + 0.6 * max(-swing, 0), 0.0)}
            for side, shift in (("l", 0.0), ("r", 0.5)):
                fx, lift = gait.foot_offset(phase - shift, self.walk_speed, self.rv,
                                            skel.leg_length_m)
                sy = skel.joints[SEGMENT_INDEX[f"thigh_{side}"], 1]
                legs[side] = np.array([fx, sy, ankle_h + lift])
        elif posture == "sitting":
            root = np.array([0.0, 0.0, skel.height_m * 0.285])
            for side in ("l", "r"):
                rot[SEGMENT_INDEX[f"thigh_{side}"]] = rot_y(-np.pi / 2)
            arm_base = {"l": (25.0, 3.0, 0.0, 60.0, 0.0), "r": (25.0, 3.0, 0.0, 60.0, 0.0)}
        self._arms(t, rot, arm_base)
        joints = self._chain(root, rot)
        if legs:
            self._legs(joints, rot, legs)
        self._vitals(t, joints, rot)
        return BodyFrame(joints, rot, self._placement(t, posture))

    def _arms(self, t: float, rot: NDArray[np.float64],
              base: dict[str, tuple[float, float, float, float, float]]) -> None:
        gesture = self.person.motion.gesture
        for side, sy in (("l", 1.0), ("r", -1.0)):
            angles = np.array(base[side], dtype=np.float64)
            if gesture is not None and gesture.hand[0] == side:
                w, u = gesture_weight_phase(gesture, t)
                if w > 0:
                    angles = (1 - w) * angles + w * np.array(gesture_angles(gesture.kind, u, sy))
            flex, abd, horiz, elbow, elbow_side = np.radians(angles)
            chest = rot[SEGMENT_INDEX["chest"]]
            upper = chest @ rot_z(horiz) @ rot_y(-flex) @ rot_x(sy * abd)
            fore = upper @ rot_y(-elbow) @ rot_x(sy * elbow_side)
            rot[SEGMENT_INDEX[f"upper_arm_{side}"]] = upper
            rot[SEGMENT_INDEX[f"forearm_{side}"]] = fore
            rot[SEGMENT_INDEX[f"hand_{side}"]] = fore

    def _chain(self, root: NDArray[np.float64], rot: NDArray[np.float64]) -> NDArray[np.float64]:
        joints = np.zeros((_S, 3))
        joints[0] = root
        for i in range(1, _S):
            p = PARENTS[i]
            joints[i] = joints[p] + rot[p] @ self.skeleton.joints[i]
        return joints

    def _legs(self, joints: NDArray[np.float64], rot: NDArray[np.float64],
              ankles: dict[str, NDArray[np.float64]]) -> None:
        lengths = self.skeleton.lengths
        fwd = np.array([1.0, 0.0, 0.0])
        for side, ankle in ankles.items():
            i_th, i_sh, i_ft = (SEGMENT_INDEX[f"{n}_{side}"] for n in ("thigh", "shin", "foot"))
            hip = joints[i_th]
            knee = gait.two_link(hip, ankle, lengths["thigh"], lengths["shank"], fwd)
            rot[i_th] = frame_from_bone(knee - hip, fwd)
            rot[i_sh] = frame_from_bone(ankle - knee, fwd)
            joints[i_sh] = knee
            joints[i_ft] = knee + rot[i_sh] @ np.array([0.0, 0.0, -lengths["shank"]])

    def _vitals(self, t: float, joints: NDArray[np.float64], rot: NDArray[np.float64]) -> None:
        breathing, heart = self.chest_displacement(t)
        for name, d in (("chest", breathing + heart), ("abdomen", breathing)):
            i = SEGMENT_INDEX[name]
            joints[i] = joints[i] + rot[i][:, 0] * d

    def _placement(self, t: float, posture: str) -> NDArray[np.float64]:
        place = np.eye(4)
        if self.path is not None:
            p, yaw = self.path.at(self.walked(t))
            place[:3, :3], place[:3, 3] = rot_z(yaw), p
        else:
            place = rigid_state(self.pose, self.rigid, t).transform.copy()
        if posture == "lying":
            h = self.skeleton.height_m
            lie = np.eye(4)
            lie[:3, :3] = rot_z(np.pi) @ rot_y(-np.pi / 2)
            lie[:3, 3] = lie[:3, :3] @ np.array([0.0, 0.0, -self.skeleton.joints[0, 2]]) \
                + np.array([0.0, 0.0, 0.062 * h * self.person.build])
            place = place @ lie
        place[:3, 3] += sway_m(self.person.motion.sway_mm, self.phases, t)
        return place

    # ------------------------------------------------------------------ BVH
    def _bvh_corrections(self) -> dict[int, NDArray[np.float64]]:
        """Per mapped segment, Q' (BVH axes): our rest bone direction → the BVH's."""
        assert self.bvh is not None
        fixes: dict[int, NDArray[np.float64]] = {}
        for seg, joint in self._bvh_map.items():
            i = SEGMENT_INDEX[seg]
            children = [c for c, p in enumerate(PARENTS) if p == i]
            if seg in ("pelvis", "chest") or not children and seg not in ("hand_l", "hand_r"):
                fixes[i] = np.eye(3)
                continue
            towards = self._bvh_map.get(SEGMENTS[children[0]]) if children else None
            ours = self.skeleton.joints[children[0]] if children else self.skeleton.centers[i]
            theirs = bone_offset(self.bvh, joint, towards)
            fixes[i] = _align(BODY_FROM_BVH.T @ ours, theirs)
        return fixes

    def _bvh_frame(self, t: float) -> BodyFrame:
        assert self.bvh is not None and self.person.motion.bvh is not None
        clip, bvh = self.person.motion.bvh, self.bvh
        f = (clip.start_offset_s + clip.play_rate * t) / bvh.frame_time_s
        last = bvh.n_frames - 1
        f = f % bvh.n_frames if clip.loop and last > 0 else min(max(f, 0.0), float(last))
        f0 = int(np.floor(f))
        f1, s = (f0 + 1) % bvh.n_frames, f - f0
        world = _interp_rotations(bvh.rotations[f0], bvh.rotations[f1], s)
        m = BODY_FROM_BVH
        rot = np.tile(np.eye(3), (_S, 1, 1))
        for i in range(_S):
            seg = SEGMENTS[i]
            if seg in self._bvh_map:
                rot[i] = m @ world[self._bvh_map[seg]] @ self._bvh_fix[i] @ m.T
            elif PARENTS[i] >= 0:
                rot[i] = rot[PARENTS[i]]
        scale = self.skeleton.leg_length_m / _bvh_leg_length(bvh, self._bvh_map)
        pos = (1 - s) * bvh.root_positions[f0] + s * bvh.root_positions[f1]
        start = bvh.root_positions[0]
        root = scale * (m @ (pos - np.array([start[0], 0.0, start[2]])))
        joints = self._chain(root, rot)
        self._vitals(t, joints, rot)
        return BodyFrame(joints, rot, self._placement(t, "standing"))


def _bvh_leg_length(bvh: BvhMotion, mapping: dict[str, int]) -> float:
    thigh = float(np.linalg.norm(bone_offset(bvh, mapping["thigh_l"], mapping["shin_l"])))
    shin = float(np.linalg.norm(bone_offset(bvh, mapping["shin_l"], mapping.get("foot_l"))))
    return max(thigh + shin, 1e-9)


def _align(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Smallest rotation turning direction ``a`` into direction ``b``."""
    a = a / np.linalg.norm(a)
    b = b / max(float(np.linalg.norm(b)), 1e-12)
    v, c = np.cross(a, b), float(a @ b)
    if c < -1 + 1e-9:  # opposite: half turn about any perpendicular axis
        axis = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        axis /= np.linalg.norm(axis)
        return 2 * np.outer(axis, axis) - np.eye(3)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + vx + vx @ vx / (1 + c)


def _log_rotations(r: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation vectors of rotation matrices, shape (..., 3) (angles below π)."""
    cos = np.clip((np.trace(r, axis1=-2, axis2=-1) - 1) / 2, -1.0, 1.0)
    angle = np.arccos(cos)
    axis = np.stack([r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0],
                     r[..., 1, 0] - r[..., 0, 1]], -1)
    sin = np.sin(angle)
    factor = np.where(sin > 1e-12, angle / (2 * np.where(sin > 1e-12, sin, 1.0)), 0.5)
    return axis * factor[..., None]


def _interp_rotations(a: NDArray[np.float64], b: NDArray[np.float64], s: float
                      ) -> NDArray[np.float64]:
    """Per-joint slerp from ``a`` to ``b`` (shape (J, 3, 3)) at fraction ``s``."""
    if s <= 0:
        return a
    rel = np.transpose(a, (0, 2, 1)) @ b
    vec = _log_rotations(rel) * s
    angle = np.linalg.norm(vec, axis=-1)
    out = np.empty_like(a)
    for j in range(len(a)):
        k = vec[j] / angle[j] if angle[j] > 0 else np.zeros(3)
        kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        out[j] = a[j] @ (np.eye(3) + np.sin(angle[j]) * kx
                         + (1 - np.cos(angle[j])) * kx @ kx)
    return out


__all__ = ["PersonBody", "VELOCITY_STEP_S", "frame_from_bone", "rot_x", "rot_y", "rot_z"]
