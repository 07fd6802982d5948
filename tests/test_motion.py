"""Rigid motion: constant velocities and keyframed paths against closed-form answers."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from simcore.scene import Keyframe, Motion, Pose
from simcore.scene.motion import rigid_state


def test_constant_velocity_and_rotation():
    pose = Pose(position_m=(1, 2, 3), rotation_deg=(0, 0, 30))
    motion = Motion(velocity_mps=(0.5, 0, -1), angular_velocity_dps=(0, 0, 90))
    s = rigid_state(pose, motion, 2.0)
    np.testing.assert_allclose(s.origin, [2, 2, 1])
    yaw = Rotation.from_matrix(s.transform[:3, :3]).as_euler("xyz", degrees=True)[2]
    assert yaw == pytest.approx(-150)  # 30° + 2 s × 90°/s = 210° ≡ −150°
    np.testing.assert_allclose(s.angular_velocity_rps, [0, 0, np.pi / 2])


def test_keyframes_interpolate_and_give_segment_velocity():
    motion = Motion(keyframes=[Keyframe(time_s=0.0), Keyframe(time_s=2.0, position_m=(4, 0, 0)),
                               Keyframe(time_s=3.0, position_m=(4, 1, 0))])
    pose = Pose(position_m=(10, 0, 0))
    s = rigid_state(pose, motion, 1.0)
    np.testing.assert_allclose(s.origin, [12, 0, 0])
    np.testing.assert_allclose(s.velocity_mps, [2, 0, 0])
    s = rigid_state(pose, motion, 2.5)
    np.testing.assert_allclose(s.origin, [14, 0.5, 0])
    np.testing.assert_allclose(s.velocity_mps, [0, 1, 0])
    s = rigid_state(pose, motion, 5.0)                      # hold after the end
    np.testing.assert_allclose(s.origin, [14, 1, 0])
    np.testing.assert_allclose(s.velocity_mps, [0, 0, 0])


def test_back_and_forth_reverses_velocity():
    motion = Motion(keyframes=[Keyframe(time_s=0.0), Keyframe(time_s=1.0, position_m=(1, 0, 0))],
                    repeat="back_and_forth")
    s = rigid_state(Pose(), motion, 1.25)
    np.testing.assert_allclose(s.origin, [0.75, 0, 0])
    np.testing.assert_allclose(s.velocity_mps, [-1, 0, 0])
    s = rigid_state(Pose(), motion, 2.25)
    np.testing.assert_allclose(s.origin, [0.25, 0, 0])
    np.testing.assert_allclose(s.velocity_mps, [1, 0, 0])


def test_loop_wraps_around():
    motion = Motion(keyframes=[Keyframe(time_s=0.0), Keyframe(time_s=1.0, position_m=(1, 0, 0))],
                    repeat="loop")
    np.testing.assert_allclose(rigid_state(Pose(), motion, 3.25).origin, [0.25, 0, 0])


def test_keyframe_rotation_angular_velocity():
    motion = Motion(keyframes=[Keyframe(time_s=0.0),
                               Keyframe(time_s=2.0, rotation_deg=(0, 0, 90))])
    s = rigid_state(Pose(), motion, 1.0)
    yaw = Rotation.from_matrix(s.transform[:3, :3]).as_euler("xyz", degrees=True)[2]
    assert yaw == pytest.approx(45)
    np.testing.assert_allclose(s.angular_velocity_rps, [0, 0, np.pi / 4])


def test_keyframes_and_velocity_are_exclusive():
    with pytest.raises(ValueError, match="either keyframes or constant velocities"):
        Motion(velocity_mps=(1, 0, 0), keyframes=[Keyframe(time_s=0.0)])
