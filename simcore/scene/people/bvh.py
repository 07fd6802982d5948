"""BVH motion capture: checked text, read with ``bvhio``, retargeted onto the skeleton.

A BVH file is read in two steps. First its text is checked here, with limits, before any
parser sees it: size, one ``HIERARCHY`` with one ``ROOT``, balanced braces, joint count,
nesting depth, channel counts and names, unique joint names, finite offsets, a ``MOTION``
section whose frame count, frame time and every frame line (value count, finite, bounded
values) agree. Every problem is one :class:`BvhError` naming the file and the line. Then
the maintained ``bvhio`` package reads the checked file.

Retargeting (documented in docs/people.md): joints are found by name through
:data:`JOINT_MAP` (CMU-style names first, then common alternatives, case-insensitive);
each mapped segment takes the BVH joint's world rotation, corrected once by the rotation
that turns the skeleton's rest bone direction into the BVH's rest bone direction; segment
lengths stay the person's; the root's translation is scaled by the ratio of leg lengths
(person / BVH) and its horizontal start is put on the object's origin. BVH space is
y up with the character facing +z (CMU); it is turned to z up, facing +x.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.base import MAX_COORDINATE_M
from simcore.scene.files import InputFileError, read_regular_file
from simcore.scene.limits import (
    BVH_BYTES_PER_JOINT_FRAME,
    MAX_BVH_BYTES,
    MAX_BVH_DEPTH,
    MAX_BVH_FRAME_TIME_S,
    MAX_BVH_FRAMES,
    MAX_BVH_JOINTS,
    MAX_BVH_READER_BYTES,
    MAX_BVH_ROOT_SPEED_MPS,
    MAX_BVH_VALUE,
    MIN_BVH_FRAME_TIME_S,
    MIN_BVH_LEG_FRACTION,
)
from simcore.scene.people.skeleton import SEGMENT_INDEX

CHANNEL_NAMES = frozenset({"Xposition", "Yposition", "Zposition",
                           "Xrotation", "Yrotation", "Zrotation"})

#: Segment → BVH joint names tried in order (CMU names first).
JOINT_MAP: dict[str, tuple[str, ...]] = {
    "pelvis": ("Hips", "Hip", "Pelvis", "Root"),
    "abdomen": ("LowerBack", "Spine", "Abdomen"),
    "chest": ("Spine1", "Chest", "Spine2", "Thorax"),
    "neck": ("Neck", "Neck1"),
    "head": ("Head",),
    "upper_arm_l": ("LeftArm", "LeftUpArm", "LeftUpperArm", "lShldr"),
    "forearm_l": ("LeftForeArm", "LeftLowArm", "LeftLowerArm", "lForeArm"),
    "hand_l": ("LeftHand", "lHand"),
    "upper_arm_r": ("RightArm", "RightUpArm", "RightUpperArm", "rShldr"),
    "forearm_r": ("RightForeArm", "RightLowArm", "RightLowerArm", "rForeArm"),
    "hand_r": ("RightHand", "rHand"),
    "thigh_l": ("LeftUpLeg", "LeftHip", "LeftThigh", "lThigh"),
    "shin_l": ("LeftLeg", "LeftKnee", "LeftShin", "lShin"),
    "foot_l": ("LeftFoot", "LeftAnkle", "lFoot"),
    "thigh_r": ("RightUpLeg", "RightHip", "RightThigh", "rThigh"),
    "shin_r": ("RightLeg", "RightKnee", "RightShin", "rShin"),
    "foot_r": ("RightFoot", "RightAnkle", "rFoot"),
}
#: BVH (x left, y up, z forward) → body (x forward, y left, z up); columns are BVH axes.
BODY_FROM_BVH = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


class BvhError(ValueError):
    """A BVH file could not be read or breaks a limit."""


@dataclass(frozen=True)
class BvhMotion:
    """A BVH clip's joints and per-frame world rotations and root positions.

    Attributes
    ----------
    names : tuple of str
        Joint names (file order).
    parents : tuple of int
        Parent index of each joint (−1 for the root).
    offsets : ndarray, shape (J, 3)
        Rest offset of each joint from its parent (BVH units, BVH axes).
    end_sites : ndarray, shape (J, 3)
        End-site offset of each joint (zeros where there is none).
    rotations : ndarray, shape (F, J, 3, 3)
        World rotation of each joint per frame (BVH axes).
    root_positions : ndarray, shape (F, 3)
        Root position per frame (BVH units, BVH axes).
    frame_time_s : float
        Time between frames (s).
    """

    names: tuple[str, ...]
    parents: tuple[int, ...]
    offsets: NDArray[np.float64]
    end_sites: NDArray[np.float64]
    rotations: NDArray[np.float64]
    root_positions: NDArray[np.float64]
    frame_time_s: float

    @property
    def n_frames(self) -> int:
        """Number of frames."""
        return int(self.rotations.shape[0])

    @property
    def duration_s(self) -> float:
        """Duration of the clip (s)."""
        return self.n_frames * self.frame_time_s


def _fail(path: Path, line: int | None, message: str) -> BvhError:
    where = f"{path.name}" + (f" line {line}" if line is not None else "")
    return BvhError(f"BVH file {where}: {message}")


def _number(path: Path, line: int, token: str) -> float:
    try:
        value = float(token)
    except ValueError:
        raise _fail(path, line, f"{token[:20]!r} is not a number") from None
    if not math.isfinite(value) or abs(value) > MAX_BVH_VALUE:
        raise _fail(path, line, f"value {token[:20]} is not finite or beyond ±{MAX_BVH_VALUE:g}")
    return value


def _check_hierarchy(path: Path, lines: list[str]) -> tuple[int, int, int]:
    """Check the HIERARCHY part; return (line index of MOTION, channel count, joint count)."""
    if not lines or lines[0].strip() != "HIERARCHY":
        raise _fail(path, 1, "does not start with HIERARCHY")
    depth, joints, channels, roots = 0, 0, 0, 0
    names: set[str] = set()
    for i, raw in enumerate(lines[1:], start=2):
        tokens = raw.split()
        if not tokens:
            continue
        head = tokens[0]
        if head == "MOTION":
            if depth != 0:
                raise _fail(path, i, "MOTION inside an open joint (unbalanced braces)")
            if joints == 0:
                raise _fail(path, i, "no joints before MOTION")
            return i - 1, channels, joints
        if head in ("ROOT", "JOINT"):
            roots += head == "ROOT"
            joints += 1
            if roots > 1 or (head == "ROOT" and depth != 0) or (head == "JOINT" and depth == 0):
                raise _fail(path, i, f"{head} out of place (one ROOT at the top, JOINTs in it)")
            if joints > MAX_BVH_JOINTS:
                raise _fail(path, i, f"more than {MAX_BVH_JOINTS} joints")
            name = " ".join(tokens[1:])
            if not name or name in names:
                raise _fail(path, i, f"joint name {name!r} missing or used twice")
            names.add(name)
        elif head == "{":
            depth += 1
            if depth > MAX_BVH_DEPTH:
                raise _fail(path, i, f"joints nested deeper than {MAX_BVH_DEPTH}")
        elif head == "}":
            depth -= 1
            if depth < 0:
                raise _fail(path, i, "unbalanced '}'")
        elif head == "OFFSET":
            if len(tokens) != 4:
                raise _fail(path, i, "OFFSET needs 3 numbers")
            for tok in tokens[1:]:
                _number(path, i, tok)
        elif head == "CHANNELS":
            n = int(_number(path, i, tokens[1])) if len(tokens) > 1 else -1
            if n not in (0, 3, 6) or len(tokens) != n + 2 or not set(tokens[2:]) <= CHANNEL_NAMES:
                raise _fail(path, i, "CHANNELS needs 0, 3 or 6 channel names "
                                     "(X/Y/Z position or rotation)")
            channels += n
        elif head == "End":
            pass
        else:
            raise _fail(path, i, f"unexpected {head[:20]!r} in HIERARCHY")
    raise _fail(path, None, "no MOTION section (truncated file?)")


def _check_motion(path: Path, lines: list[str], start: int, channels: int,
                  joints: int) -> None:
    """Check the MOTION part from line index ``start``."""
    def text(index: int, key: str) -> str:
        line = lines[index].strip() if index < len(lines) else ""
        if not line.startswith(key):
            raise _fail(path, index + 1, f"expected {key!r} (truncated file?)")
        return line[len(key):].strip()

    count = text(start + 1, "Frames:")
    if not re.fullmatch(r"[0-9]{1,12}", count):
        raise _fail(path, start + 2, f"frame count {count[:20]!r} is not a whole number "
                                     f"1–{MAX_BVH_FRAMES}")
    frames = int(count)
    if not 1 <= frames <= MAX_BVH_FRAMES:
        raise _fail(path, start + 2, f"frame count {frames}; allowed 1–{MAX_BVH_FRAMES}")
    need = joints * frames * BVH_BYTES_PER_JOINT_FRAME
    if need > MAX_BVH_READER_BYTES:
        raise _fail(path, start + 2, f"{joints} joints × {frames} frames need about "
                                     f"{need / 2**30:.1f} GiB to read; the budget is "
                                     f"{MAX_BVH_READER_BYTES / 2**30:g} GiB "
                                     f"({MAX_BVH_READER_BYTES // BVH_BYTES_PER_JOINT_FRAME} "
                                     "joint-frames): cut the clip or its joints")
    dt_text = text(start + 2, "Frame Time:")
    try:
        dt = float(dt_text)
    except ValueError:
        raise _fail(path, start + 3, f"frame time {dt_text[:20]!r} is not a number") from None
    if not MIN_BVH_FRAME_TIME_S <= dt <= MAX_BVH_FRAME_TIME_S:
        raise _fail(path, start + 3, f"frame time {dt_text[:20]} s; allowed "
                                     f"{MIN_BVH_FRAME_TIME_S:g}–{MAX_BVH_FRAME_TIME_S:g} s")
    body = [ln for ln in lines[start + 3:] if ln.strip()]
    if len(body) < frames:
        raise _fail(path, None, f"declares {frames} frames but has {len(body)} "
                                f"(truncated file?)")
    for k, line in enumerate(body[:frames]):
        values = line.split()
        if len(values) != channels:
            raise _fail(path, start + 4 + k, f"frame {k} has {len(values)} values; the "
                                             f"hierarchy has {channels} channels")
        try:
            arr = np.array(values, dtype=np.float64)
        except ValueError:
            raise _fail(path, start + 4 + k, f"frame {k} has a value that is not a number"
                        ) from None
        if not np.all(np.isfinite(arr)) or np.any(np.abs(arr) > MAX_BVH_VALUE):
            raise _fail(path, start + 4 + k, f"frame {k} has a value that is not finite "
                                             f"or beyond ±{MAX_BVH_VALUE:g}")


def check_bvh_text(path: Path) -> None:
    """Check a BVH file's text against the limits (module docstring); BvhError if not."""
    try:
        data = read_regular_file(path, max_bytes=MAX_BVH_BYTES)
    except InputFileError as exc:
        raise BvhError(f"BVH file {exc}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise _fail(path, None, "is not UTF-8/ASCII text") from None
    if "\0" in text:
        raise _fail(path, None, "contains NUL bytes")
    lines = re.split(r"\r\n|\r|\n", text)
    start, channels, joints = _check_hierarchy(path, lines)
    _check_motion(path, lines, start, channels, joints)


def _quat_matrices(quats: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices of unit quaternions ``(w, x, y, z)``, shape (..., 3, 3)."""
    q = quats / np.linalg.norm(quats, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def _read_checked(path: Path) -> BvhMotion:
    """Read a checked BVH file with bvhio; world rotations by forward kinematics."""
    import bvhio

    try:
        container = bvhio.readAsBvh(str(path))
        joints = list(container.Root.layout())
        frame_time = float(container.FrameTime)
    except Exception as exc:  # noqa: BLE001 - bvhio raises many kinds; report one
        said = " ".join(str(exc).split())[:160] or "no reason given"
        raise _fail(path, None, f"the hierarchy does not parse: {said}") from None
    index = {id(j[0]): k for k, j in enumerate(joints)}
    parents = tuple(-1 if j[0] is container.Root else
                    index[id(_parent_of(joints, j[0]))] for j in joints)
    n_frames = len(container.Root.Keyframes)
    local = np.zeros((n_frames, len(joints), 4))
    for k, (joint, _, _) in enumerate(joints):
        for f, key in enumerate(joint.Keyframes):
            r = key.Rotation
            local[f, k] = (r.w, r.x, r.y, r.z)
    local_m = _quat_matrices(local)
    world = np.empty_like(local_m)
    for k, p in enumerate(parents):
        world[:, k] = local_m[:, k] if p < 0 else world[:, p] @ local_m[:, k]
    root = np.array([tuple(key.Position) for key in container.Root.Keyframes], np.float64)
    offsets = np.array([tuple(j[0].Offset) for j in joints], np.float64)
    ends = np.array([tuple(j[0].EndSite) if j[0].EndSite is not None else (0.0, 0.0, 0.0)
                     for j in joints], np.float64)
    return BvhMotion(names=tuple(j[0].Name for j in joints), parents=parents, offsets=offsets,
                     end_sites=ends, rotations=world, root_positions=root,
                     frame_time_s=frame_time)


def _parent_of(joints: list[tuple[object, int, int]], child: object) -> object:
    for joint, _, _ in joints:
        if any(c is child for c in joint.Children):  # type: ignore[attr-defined]
            return joint
    raise BvhError("joint without parent")


@functools.lru_cache(maxsize=16)
def _load_cached(path: str, mtime_ns: int, size: int) -> BvhMotion:
    p = Path(path)
    check_bvh_text(p)
    return _read_checked(p)


def load_bvh(path: Path) -> BvhMotion:
    """Check and read a BVH file (cached by path, size and modification time)."""
    try:
        st = path.stat()
    except OSError as exc:
        raise BvhError(f"BVH file {path.name}: cannot open: {exc.strerror}") from None
    return _load_cached(str(path), st.st_mtime_ns, st.st_size)


def map_joints(motion: BvhMotion, *, source: str | None = None) -> dict[str, int]:
    """Segment name → BVH joint index for the segments :data:`JOINT_MAP` finds.

    ``source`` (the file's name) is named in the error of a clip without legs.
    """
    lower = {n.lower(): k for k, n in enumerate(motion.names)}
    out: dict[str, int] = {}
    for segment, candidates in JOINT_MAP.items():
        for name in candidates:
            if name.lower() in lower:
                out[segment] = lower[name.lower()]
                break
    missing = [s for s in ("pelvis", "thigh_l", "shin_l", "thigh_r", "shin_r") if s not in out]
    if missing:
        raise BvhError(f"{f'BVH file {source}: ' if source else ''}BVH joints for "
                       f"{', '.join(missing)} not found (known names: "
                       f"{', '.join(JOINT_MAP[missing[0]])})")
    return out


def bone_offset(motion: BvhMotion, joint: int, towards: int | None) -> NDArray[np.float64]:
    """Rest offset from ``joint`` to its descendant ``towards`` (or its first child/end)."""
    if towards is not None:
        total = np.zeros(3)
        k = towards
        while k not in (joint, -1):
            total += motion.offsets[k]
            k = motion.parents[k]
        if k == joint:
            return total
    children = [c for c, p in enumerate(motion.parents) if p == joint]
    return motion.offsets[children[0]] if children else motion.end_sites[joint]


def leg_length(motion: BvhMotion, mapping: dict[str, int]) -> float:
    """The clip's left leg, thigh + shin (BVH units): what root motion is scaled by."""
    thigh = float(np.linalg.norm(bone_offset(motion, mapping["thigh_l"], mapping["shin_l"])))
    shin = float(np.linalg.norm(bone_offset(motion, mapping["shin_l"], mapping.get("foot_l"))))
    return thigh + shin


def root_motion_m(motion: BvhMotion, mapping: dict[str, int], leg_length_m: float
                  ) -> NDArray[np.float64]:
    """The root's displacement from its horizontal start, scaled to the person (m).

    Body axes (x forward, y left, z up), shape (F, 3): the translation the clip gives the
    person's pelvis, as :class:`~simcore.scene.people.body.PersonBody` plays it.
    """
    start = motion.root_positions[0]
    rel = motion.root_positions - np.array([start[0], 0.0, start[2]])
    scale = leg_length_m / leg_length(motion, mapping)
    return np.asarray(scale * rel @ BODY_FROM_BVH.T, dtype=np.float64)


def clip_motion_problems(motion: BvhMotion, *, source: str, leg_length_m: float,
                         play_rate: float = 1.0, origin_m: float = 0.0) -> list[str]:
    """What the clip would make of a person that no run accepts, one line each.

    The root's translation is scaled by the person's leg over the clip's: a clip whose
    legs have (almost) no length, or whose skeleton is far smaller than its root motion,
    throws the person out of the world or moves it faster than anyone runs.

    Parameters
    ----------
    motion : BvhMotion
        The clip.
    source : str
        The file's name, for messages.
    leg_length_m : float
        The person's leg length (m).
    play_rate : float
        Playback speed factor.
    origin_m : float
        Distance of the person's object from the world origin (m).

    Returns
    -------
    list of str
        Empty when the leg has a length, the root stays within ±``MAX_COORDINATE_M`` of
        the origin and moves at most ``MAX_BVH_ROOT_SPEED_MPS`` between frames.
    """
    mapping = map_joints(motion, source=source)
    leg = leg_length(motion, mapping)
    longest = float(max(np.linalg.norm(motion.offsets, axis=1).max(),
                        np.linalg.norm(motion.end_sites, axis=1).max()))
    legs = " → ".join(motion.names[mapping[s]] for s in ("thigh_l", "shin_l"))
    if not leg > MIN_BVH_LEG_FRACTION * longest:
        return [f"BVH file {source}: the leg {legs} is {leg:.3g} units long, under "
                f"{MIN_BVH_LEG_FRACTION:g} of the clip's longest bone ({longest:.3g}); its "
                "root motion cannot be scaled to the person (bones of zero length?)"]
    root = motion.names[0]
    disp = root_motion_m(motion, mapping, leg_length_m)
    reach = np.linalg.norm(disp, axis=1) + origin_m
    far = int(np.argmax(reach))
    out = []
    if reach[far] > MAX_COORDINATE_M:
        out.append(f"BVH file {source}: joint {root!r} at frame {far} puts the person "
                   f"{reach[far]:.3g} m from the origin (its leg {legs} is {leg:.3g} units, "
                   f"scaled to {leg_length_m:.3g} m); allowed at most {MAX_COORDINATE_M:g} m")
    if len(disp) > 1:
        speed = np.linalg.norm(np.diff(disp, axis=0), axis=1) / motion.frame_time_s * play_rate
        fast = int(np.argmax(speed))
        if speed[fast] > MAX_BVH_ROOT_SPEED_MPS:
            out.append(f"BVH file {source}: joint {root!r} moves {speed[fast]:.3g} m/s between "
                       f"frames {fast} and {fast + 1} (play_rate {play_rate:g}, leg {legs} "
                       f"{leg:.3g} units scaled to {leg_length_m:.3g} m); allowed at most "
                       f"{MAX_BVH_ROOT_SPEED_MPS:g} m/s")
    return out


def segment_index(name: str) -> int:
    """Index of a segment name (KeyError if unknown)."""
    return SEGMENT_INDEX[name]


__all__ = ["BODY_FROM_BVH", "MAX_BVH_BYTES", "MAX_BVH_DEPTH", "MAX_BVH_FRAMES",
           "MAX_BVH_JOINTS", "MAX_BVH_VALUE", "BvhError", "BvhMotion", "JOINT_MAP",
           "bone_offset", "check_bvh_text", "clip_motion_problems", "leg_length",
           "load_bvh", "map_joints", "root_motion_m"]
