"""BVH playback: a generated clip with known joint rotations reproduces the segment poses;
hostile files get one clear ``tofradar: error:`` line.

Known answers: a rotation θ about BVH's x axis (y up, x left, z forward) is a rotation θ
about the body's y axis (x forward, y left, z up), the frame change being a proper
rotation; a clip whose rest offsets are the skeleton's own (in cm) and whose rotations
are zero puts every segment where the standing rest pose has it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from simcore.cli import main
from simcore.resources import example_path
from simcore.scene.motion import Motion, Pose
from simcore.scene.people.body import PersonBody, rot_y, rot_z
from simcore.scene.people.bvh import BvhError, check_bvh_text, load_bvh
from simcore.scene.people.config import BvhClip, Person, PersonMotion
from simcore.scene.people.skeleton import PARENTS, SEGMENT_INDEX, SEGMENTS, build_skeleton

CMU = {"pelvis": "Hips", "abdomen": "LowerBack", "chest": "Spine1", "neck": "Neck",
       "head": "Head", "upper_arm_l": "LeftArm", "forearm_l": "LeftForeArm",
       "hand_l": "LeftHand", "upper_arm_r": "RightArm", "forearm_r": "RightForeArm",
       "hand_r": "RightHand", "thigh_l": "LeftUpLeg", "shin_l": "LeftLeg",
       "foot_l": "LeftFoot", "thigh_r": "RightUpLeg", "shin_r": "RightLeg",
       "foot_r": "RightFoot"}
# Body (x fwd, y left, z up) → BVH (x left, y up, z fwd): bvh = (y, z, x).


def _to_bvh(v: np.ndarray) -> np.ndarray:
    return np.array([v[1], v[2], v[0]])


def make_bvh(height: float, frames: list[dict[str, tuple[float, float, float]]],
             *, frame_time: float = 0.1) -> str:
    """A CMU-named BVH of the skeleton (cm); ``frames``: joint → (Z, X, Y) rotation deg."""
    skel = build_skeleton(height)
    lines = ["HIERARCHY"]

    def emit(i: int, depth: int) -> None:
        pad = "  " * depth
        off = 100 * (_to_bvh(skel.joints[i]) if i else np.zeros(3))
        head = "ROOT" if i == 0 else "JOINT"
        lines.append(f"{pad}{head} {CMU[SEGMENTS[i]]}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET {off[0]:.6f} {off[1]:.6f} {off[2]:.6f}")
        if i == 0:
            lines.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition "
                         "Zrotation Xrotation Yrotation")
        else:
            lines.append(f"{pad}  CHANNELS 3 Zrotation Xrotation Yrotation")
        children = [c for c, p in enumerate(PARENTS) if p == i]
        for c in children:
            emit(c, depth + 1)
        if not children:
            end = 100 * _to_bvh(2 * skel.centers[i])
            lines.extend([f"{pad}  End Site", f"{pad}  {{",
                          f"{pad}    OFFSET {end[0]:.6f} {end[1]:.6f} {end[2]:.6f}",
                          f"{pad}  }}"])
        lines.append(f"{pad}}}")

    emit(0, 0)
    order = []

    def walk(i: int) -> None:
        order.append(i)
        for c in [c for c, p in enumerate(PARENTS) if p == i]:
            walk(c)

    walk(0)
    lines += ["MOTION", f"Frames: {len(frames)}", f"Frame Time: {frame_time}"]
    hip = 100 * skel.joints[0, 2]
    for fr in frames:
        values = [0.0, hip, 0.0]
        for i in order:
            values += list(fr.get(CMU[SEGMENTS[i]], (0.0, 0.0, 0.0)))
        lines.append(" ".join(f"{v:.6f}" for v in values))
    return "\n".join(lines) + "\n"


def _body(tmp_path: Path, text: str, **clip: object) -> PersonBody:
    (tmp_path / "clip.bvh").write_text(text)
    person = Person(height_m=1.8, motion=PersonMotion(
        bvh=BvhClip(path="clip.bvh", **clip), sway_mm=0.0))  # type: ignore[arg-type]
    return PersonBody(person, Pose(), Motion(), base_dir=tmp_path)


def test_generated_bvh_reproduces_segment_poses(tmp_path: Path) -> None:
    frames = [{}, {"LeftUpLeg": (0.0, 30.0, 0.0), "RightForeArm": (-45.0, 0.0, 0.0),
                   "Hips": (0.0, 0.0, 90.0)}]
    body = _body(tmp_path, make_bvh(1.8, frames), loop=False)
    # Zero rotations: the skeleton's rest pose (all segment frames parallel to the body's,
    # joints at the summed offsets).
    skel = build_skeleton(1.8)
    joints = np.zeros_like(skel.joints)
    for i, p in enumerate(PARENTS):
        joints[i] = skel.joints[i] + (joints[p] if p >= 0 else 0.0)
    rest = body.segment_transforms(0.0)
    assert np.allclose(rest[:, :3, :3], np.eye(3), atol=1e-9)
    assert np.allclose(rest[:, :3, 3], joints + skel.centers, atol=1e-6)
    got = body.segment_transforms(0.1)
    hips = rot_z(np.pi / 2)  # BVH Y rotation (up) = body z rotation
    assert np.allclose(got[SEGMENT_INDEX["pelvis"], :3, :3], hips, atol=1e-6)
    assert np.allclose(got[SEGMENT_INDEX["thigh_l"], :3, :3], hips @ rot_y(np.radians(30)),
                       atol=1e-6)
    # BVH z (forward) rotation = body x rotation.
    from simcore.scene.people.body import rot_x

    assert np.allclose(got[SEGMENT_INDEX["forearm_r"], :3, :3],
                       hips @ rot_x(np.radians(-45)), atol=1e-6)


def test_play_rate_offset_and_loop(tmp_path: Path) -> None:
    frames = [{}, {"LeftUpLeg": (0.0, 30.0, 0.0)}, {}]
    text = make_bvh(1.8, frames)
    thigh = SEGMENT_INDEX["thigh_l"]
    fast = _body(tmp_path, text, play_rate=2.0)
    assert np.allclose(fast.segment_transforms(0.05)[thigh, :3, :3], rot_y(np.radians(30)))
    late = _body(tmp_path, text, start_offset_s=0.1)
    assert np.allclose(late.segment_transforms(0.0)[thigh, :3, :3], rot_y(np.radians(30)))
    looped = _body(tmp_path, text, loop=True)  # 3 frames of 0.1 s: frame 1 again at 0.4 s
    assert np.allclose(looped.segment_transforms(0.4)[thigh, :3, :3], rot_y(np.radians(30)))
    held = _body(tmp_path, text, loop=False)
    assert np.allclose(held.segment_transforms(5.0)[thigh, :3, :3], np.eye(3))


GOOD = make_bvh(1.8, [{}, {}])


def _hostile() -> dict[str, str]:
    head, motion = GOOD.split("MOTION")
    joints = "".join(f"JOINT J{i}\n{{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation "
                     f"Yrotation\n" for i in range(300)) + "}\n" * 300
    return {
        "truncated": GOOD[: len(GOOD) - 40],
        "nan": GOOD.replace("0.000000 0.000000 0.000000\n", "nan 0.000000 0.000000\n", 1),
        "huge_value": GOOD.replace("0.000000 0.000000 0.000000\n", "1e300 0 0\n", 1),
        "huge_offset": GOOD.replace("OFFSET 0.000000", "OFFSET 1e200", 1),
        "huge_channels": GOOD.replace("CHANNELS 3 Zrotation Xrotation Yrotation",
                                      "CHANNELS 1000000 Zrotation", 1),
        "huge_joints": head.replace("{\n", "{\n" + joints, 1) + "MOTION" + motion,
        "missing_motion": head,
        "cycle": GOOD.replace("JOINT LeftLeg", "JOINT LeftUpLeg", 1),
        "frame_count": GOOD.replace("Frames: 2", "Frames: 999999999", 1),
        "binary": "\0\1\2" * 100,
        "empty": "",
    }


@pytest.mark.parametrize("name", sorted(_hostile()))
def test_hostile_bvh_one_clear_error(name: str, tmp_path: Path, capsys) -> None:
    path = tmp_path / "clip.bvh"
    path.write_text(_hostile()[name])
    with pytest.raises(BvhError):
        check_bvh_text(path)
    project = json.loads(Path(example_path("wall")).read_text())
    project["objects"] = [{"id": 1, "name": "p", "geometry": {
        "kind": "person", "motion": {"bvh": {"path": "clip.bvh"}}}}]
    (tmp_path / "p.json").write_text(json.dumps(project))
    rc = main(["validate", str(tmp_path / "p.json")])
    err = capsys.readouterr().err
    assert rc != 0
    assert err.startswith("tofradar: error:") and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1  # one line
    assert "bvh" in err.lower()


def test_good_bvh_loads(tmp_path: Path) -> None:
    path = tmp_path / "clip.bvh"
    path.write_text(GOOD)
    clip = load_bvh(path)
    assert clip.n_frames == 2 and clip.frame_time_s == pytest.approx(0.1)
    assert clip.names[0] == "Hips" and len(clip.names) == len(SEGMENTS)

