"""Body model against its published sources: Winter's proportions, Boulic's gait timing.

Known answers: segment lengths are the Drillis–Contini fractions of height (Winter 2009,
Fig. 4.1); Boulic et al. (1990) give the cycle duration 1.346/√RV (1.18 s at 1.15 m/s for
a 1.8 m person) and the support duration 0.752 Dc − 0.143; a foot in support does not move
and in swing travels one cycle length, peaking at π/(2(1 − Ds/Dc)) v on its raised cosine.
"""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError

from simcore.scene.motion import Keyframe, Motion, Pose
from simcore.scene.people.body import PersonBody
from simcore.scene.people.config import Gesture, Person, PersonMotion, VitalSigns, Walk
from simcore.scene.people.skeleton import PARENTS, SEGMENT_INDEX, SEGMENTS, build_skeleton

#: Winter (2009) Fig. 4.1 fractions, typed in again from the table (not from the code).
TABLE = {"thigh": 0.245, "shank": 0.246, "upper_arm": 0.186, "forearm": 0.146,
         "hand": 0.108, "foot": 0.152}


def _joint_world(body: PersonBody, t: float, name: str) -> np.ndarray:
    """World position of a segment's proximal joint (undo its ellipsoid-centre offset)."""
    i = SEGMENT_INDEX[name]
    tr = body.segment_transforms(t)[i]
    return tr[:3, :3] @ (-body.skeleton.centers[i]) + tr[:3, 3]


def _walker(height: float, speed: float, **kw: object) -> PersonBody:
    person = Person(height_m=height, motion=PersonMotion(walk=Walk(speed_mps=speed),
                                                         sway_mm=0.0, **kw))
    return PersonBody(person, Pose(), Motion())


@pytest.mark.parametrize("height", [1.55, 1.8, 2.0])
def test_segment_lengths_follow_winter_table(height: float) -> None:
    body = PersonBody(Person(height_m=height, motion=PersonMotion(sway_mm=0.0)), Pose(),
                      Motion())
    pairs = {"thigh": ("thigh_l", "shin_l"), "shank": ("shin_l", "foot_l"),
             "upper_arm": ("upper_arm_r", "forearm_r"), "forearm": ("forearm_r", "hand_r")}
    for key, (a, b) in pairs.items():
        length = np.linalg.norm(_joint_world(body, 0.0, a) - _joint_world(body, 0.0, b))
        assert length == pytest.approx(TABLE[key] * height, rel=1e-9)
    skel = build_skeleton(height)
    for key in ("hand", "foot"):
        assert skel.lengths[key] == pytest.approx(TABLE[key] * height)
    # Standing: ankles at 0.039 H, hips at 0.530 H, the head's top at H.
    assert _joint_world(body, 0.0, "foot_l")[2] == pytest.approx(0.039 * height)
    assert _joint_world(body, 0.0, "thigh_l")[2] == pytest.approx(0.530 * height)
    head = body.segment_transforms(0.0)[SEGMENT_INDEX["head"]]
    assert head[2, 3] + skel.radii[SEGMENT_INDEX["head"], 2] == pytest.approx(height, abs=0.02)
    assert len(SEGMENTS) >= 15 and len(PARENTS) == len(SEGMENTS)


@pytest.mark.parametrize(("height", "speed"), [(1.8, 1.15), (1.7, 0.6), (1.9, 1.7)])
def test_gait_cycle_and_speeds(height: float, speed: float) -> None:
    body = _walker(height, speed)
    leg = (TABLE["thigh"] + TABLE["shank"]) * height
    rv = speed / leg
    dc = 1.346 / np.sqrt(rv)
    if (height, speed) == (1.8, 1.15):
        assert dc == pytest.approx(1.18, abs=0.005)
    dt = 0.002
    t = np.arange(0.0, 3 * dc, dt)
    pelvis = np.array([_joint_world(body, ti, "pelvis") for ti in t])
    ankle = np.array([_joint_world(body, ti, "foot_l") for ti in t])
    # The gait repeats after one Boulic cycle (and not after half of one, for one foot).
    k = int(round(dc / dt))
    assert np.allclose(ankle[k:2 * k, 2], ankle[:k, 2], atol=2e-3)
    # The pelvis moves at v on average over whole cycles, with a small ripple.
    v_pelvis = np.gradient(pelvis[:, 0], dt)[: 2 * k]
    assert v_pelvis.mean() == pytest.approx(speed, rel=0.01)
    assert 0.0 < v_pelvis.std() < 0.2 * speed
    # Boulic's translations about the mean motion (van Dorp & Groen 2003, Table 1, in
    # leg lengths): forward 0.021 and vertical 0.015 RV twice a cycle, lateral 0.032 once
    # (RV > 0.5; below, 0.084 and 0.128 times RV (1 − RV)).
    low = rv * (1 - rv) if rv < 0.5 else 0.25
    phase = t[: 2 * k] / dc
    for axis, cycles, amplitude in ((0, 2, 0.084 * low), (1, 1, 0.128 * low),
                                    (2, 2, 0.015 * rv)):
        x = pelvis[: 2 * k, axis] - (speed * t[: 2 * k] if axis == 0 else 0.0)
        basis = np.column_stack([np.sin(2 * np.pi * cycles * phase),
                                 np.cos(2 * np.pi * cycles * phase), np.ones_like(phase)])
        coef = np.linalg.lstsq(basis, x, rcond=None)[0]
        assert np.hypot(*coef[:2]) == pytest.approx(amplitude * leg, rel=0.05), axis
    # The foot: nearly still in support for 0.752 Dc − 0.143 s, peak in swing.
    speed_ankle = np.linalg.norm(np.gradient(ankle, dt, axis=0), axis=1)
    still = speed_ankle < 0.05 * speed
    support = 0.752 * dc - 0.143
    assert still[:k].mean() == pytest.approx(support / dc, abs=0.03)
    peak = speed_ankle.max() / speed
    assert peak == pytest.approx(np.pi / (2 * (1 - support / dc)), rel=0.02)
    if rv < 2.0:
        assert 3.5 <= peak <= 5.0


def test_foot_peak_at_normal_speed_in_boulic_range() -> None:
    """Ankle and toe: about 3.5–4.5 v at the peak of swing in Boulic's curves."""
    body = _walker(1.8, 1.15)
    t = np.arange(0, 1.2, 0.001)
    i = SEGMENT_INDEX["foot_r"]
    ankle = np.array([_joint_world(body, ti, "foot_r") for ti in t])
    # The toe: the foot ellipsoid's front tip (its semi-axis along the foot, local +x).
    tip = np.array([body.skeleton.radii[i, 0], 0.0, 0.0, 1.0])
    toe = np.array([(body.segment_transforms(ti)[i] @ tip)[:3] for ti in t])
    for point in (ankle, toe):
        speed = np.linalg.norm(np.gradient(point, 0.001, axis=0), axis=1) / 1.15
        assert 3.5 <= speed.max() <= 4.5
        assert np.mean(speed < 0.05) > 0.5  # still through most of the support phase


def test_snapshot_velocities_are_the_derivative_of_poses() -> None:
    body = _walker(1.75, 1.3, gesture=Gesture(kind="wave"), vital_signs=VitalSigns())
    t, h = 0.73, 1e-3
    states = body.states(t)
    before, after = body.segment_transforms(t - h), body.segment_transforms(t + h)
    for i, s in enumerate(states):
        v = (after[i, :3, 3] - before[i, :3, 3]) / (2 * h)
        assert np.allclose(s.velocity_mps, v, atol=2e-3)
        # ω × r reproduces the motion of a point on the segment (its ellipsoid's tip).
        tip = np.array([0.0, 0.0, body.skeleton.radii[i, 2]])
        p = [tr[:3, :3] @ tip + tr[:3, 3] for tr in (before[i], after[i])]
        v_tip = (p[1] - p[0]) / (2 * h)
        assert np.allclose(s.point_velocity(s.transform[:3, :3] @ tip + s.transform[:3, 3]),
                           v_tip, atol=5e-3)


@pytest.mark.parametrize("speed", [3.0, 0.05])
def test_speed_outside_model_refused(speed: float) -> None:
    with pytest.raises(ValidationError, match="outside the walking model's range"):
        Person(height_m=1.8, motion=PersonMotion(walk=Walk(speed_mps=speed)))


def test_walk_along_keyframe_path_turns_back() -> None:
    person = Person(height_m=1.8, motion=PersonMotion(walk=Walk(speed_mps=1.0, path="keyframes"),
                                                      sway_mm=0.0))
    rigid = Motion(keyframes=[Keyframe(time_s=0.0), Keyframe(time_s=1.0, position_m=(3, 0, 0))],
                   repeat="back_and_forth")
    body = PersonBody(person, Pose(), rigid)
    assert body.states(1.0)[0].velocity_mps[0] > 0.8
    assert body.states(4.5)[0].velocity_mps[0] < -0.8  # on the way back
    assert body.body_frame(4.5).placement[0, 3] == pytest.approx(1.5)


def test_vital_signs_move_the_chest_along_its_normal() -> None:
    vs = VitalSigns(breathing_rate_hz=0.25, breathing_amplitude_mm=5.0, heart_rate_hz=1.0,
                    heart_amplitude_mm=0.0)
    body = PersonBody(Person(motion=PersonMotion(vital_signs=vs, sway_mm=0.0,
                                                 posture="lying")), Pose(), Motion())
    chest = SEGMENT_INDEX["chest"]
    z = [body.segment_transforms(t)[chest, 2, 3] for t in (0.0, 1.0, 3.0)]
    # Lying on its back, the chest's normal is +z: quarter period = +5 mm, 3/4 = −5 mm.
    assert z[1] - z[0] == pytest.approx(0.005, abs=1e-9)
    assert z[2] - z[0] == pytest.approx(-0.005, abs=1e-9)
    assert body.segment_transforms(1.0)[chest, :3, 0] @ np.array([0, 0, 1.0]) == \
        pytest.approx(1.0)


@pytest.mark.parametrize("kind", ["wave", "swipe_left", "swipe_right", "push", "pull",
                                  "circle"])
def test_gestures_move_the_chosen_hand_only(kind: str) -> None:
    g = Gesture(kind=kind, hand="left", start_s=0.0, duration_s=2.0, repetitions=2)
    body = PersonBody(Person(motion=PersonMotion(gesture=g, sway_mm=0.0)), Pose(), Motion())
    t = np.linspace(0.4, 1.6, 25)
    left = np.array([_joint_world(body, ti, "hand_l") for ti in t])
    right = np.array([_joint_world(body, ti, "hand_r") for ti in t])
    assert np.ptp(left, axis=0).max() > 0.1
    assert np.ptp(right, axis=0).max() < 1e-9
    if kind == "push":  # the hand moves forward and back
        assert np.ptp(left[:, 0]) > 0.15
    if kind in ("swipe_left", "swipe_right"):
        assert np.ptp(left[:, 1]) > 0.3


def test_sitting_thighs_horizontal() -> None:
    body = PersonBody(Person(height_m=1.8, motion=PersonMotion(posture="sitting", sway_mm=0)),
                      Pose(), Motion())
    hip, knee = _joint_world(body, 0, "thigh_l"), _joint_world(body, 0, "shin_l")
    assert hip[2] == pytest.approx(knee[2])
    assert knee[0] - hip[0] == pytest.approx(0.245 * 1.8)
    assert _joint_world(body, 0, "foot_l")[2] == pytest.approx(0.039 * 1.8)


def test_cli_refuses_a_running_speed_in_one_line(tmp_path, capsys) -> None:
    import json

    from people_scenes import walker_project

    from simcore.cli import main

    path = tmp_path / "fast.json"
    path.write_text(json.dumps(walker_project(speed=3.5, heading_deg=0.0, distance_m=3.0)))
    assert main(["validate", str(path)]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error:")
    assert "speed_mps 3.5 m/s is outside the walking model's range" in err[0]
