"""Per-segment and vital-sign ground truth of a frame's people.

Written to ``/people/...`` (docs/dataset.md): every segment's pose, velocities and range,
radial velocity and direction from the radar (segment centre), and each person's
breathing and heartbeat chest displacement, their rates and the gait phase.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.scene.ground_truth import H5Items, _relative_to
from simcore.scene.people.expand import PeopleExpansion
from simcore.scene.people.skeleton import SEGMENTS
from simcore.scene.snapshot import SceneSnapshot


@dataclass(frozen=True)
class PeopleTruth:
    """Ground truth of the people of one frame (``P`` people, ``S = 17 P`` segments).

    Attributes
    ----------
    segment_pose : ndarray, shape (S, 4, 4)
        Segment (ellipsoid-centred) frame → world.
    segment_velocity_mps, segment_angular_velocity_rps : ndarray, shape (S, 3)
        Linear velocity of the segment centre and angular velocity, world frame.
    segment_radar_range_m, segment_radar_radial_velocity_mps : ndarray, shape (S,)
        Range and radial velocity (+ = away) of the segment centre from the radar.
    segment_radar_azimuth_deg, segment_radar_elevation_deg : ndarray, shape (S,)
        Direction of the segment centre from the radar (deg).
    breathing_m, heartbeat_m : ndarray, shape (P,)
        Chest-wall displacement by breathing and by the heartbeat (m, + outwards).
    breathing_rate_hz, heart_rate_hz : ndarray, shape (P,)
        Configured rates (0 without vital signs).
    gait_phase : ndarray, shape (P,)
        Gait cycles completed (integers at left heel strike; 0 when not walking).
    """

    segment_pose: NDArray[np.float64]
    segment_velocity_mps: NDArray[np.float64]
    segment_angular_velocity_rps: NDArray[np.float64]
    segment_radar_range_m: NDArray[np.float64]
    segment_radar_radial_velocity_mps: NDArray[np.float64]
    segment_radar_azimuth_deg: NDArray[np.float64]
    segment_radar_elevation_deg: NDArray[np.float64]
    breathing_m: NDArray[np.float64]
    heartbeat_m: NDArray[np.float64]
    breathing_rate_hz: NDArray[np.float64]
    heart_rate_hz: NDArray[np.float64]
    gait_phase: NDArray[np.float64]

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets of the ``/people`` group: path → (array, unit)."""
        return {
            "/people/segments/pose": (self.segment_pose, "m"),
            "/people/segments/velocity": (self.segment_velocity_mps, "m/s"),
            "/people/segments/angular_velocity": (self.segment_angular_velocity_rps, "rad/s"),
            "/people/segments/radar_range": (self.segment_radar_range_m, "m"),
            "/people/segments/radar_radial_velocity": (
                self.segment_radar_radial_velocity_mps, "m/s"),
            "/people/segments/radar_azimuth": (self.segment_radar_azimuth_deg, "deg"),
            "/people/segments/radar_elevation": (self.segment_radar_elevation_deg, "deg"),
            "/people/breathing_displacement": (self.breathing_m, "m"),
            "/people/heartbeat_displacement": (self.heartbeat_m, "m"),
            "/people/breathing_rate": (self.breathing_rate_hz, "Hz"),
            "/people/heart_rate": (self.heart_rate_hz, "Hz"),
            "/people/gait_phase": (self.gait_phase, "cycles"),
        }


def people_truth(people: PeopleExpansion, snapshot: SceneSnapshot) -> PeopleTruth:
    """Ground truth of every person of a frame from its (expanded) snapshot."""
    index = np.concatenate([np.arange(p.first, p.first + len(SEGMENTS)) for p in people.people])
    states = [snapshot.objects[i] for i in index]
    pose = np.stack([s.transform for s in states])
    vel = np.stack([s.velocity_mps for s in states])
    ang = np.stack([s.angular_velocity_rps for s in states])
    rng, v_r, az, el = _relative_to(snapshot, "radar", pose[:, :3, 3], vel)
    t = snapshot.time_s
    chest = np.array([p.body.chest_displacement(t) for p in people.people]).reshape(-1, 2)
    rates = np.array([
        (vs.breathing_rate_hz, vs.heart_rate_hz) if (vs := p.body.person.motion.vital_signs)
        else (0.0, 0.0) for p in people.people]).reshape(-1, 2)
    phase = np.array([p.body.gait_phase(t) for p in people.people])
    return PeopleTruth(pose, vel, ang, rng, v_r, az, el, chest[:, 0], chest[:, 1],
                       rates[:, 0], rates[:, 1], phase)


def people_radar_items(people: PeopleExpansion, snapshot: SceneSnapshot, radar: str
                       ) -> H5Items:
    """Per-segment truth seen from a named radar: ``/people/segments/<radar>/range``, ...

    The same quantities as :class:`PeopleTruth`'s ``segment_radar_*`` (which are the
    built-in radar's), from radar ``radar``'s pose in ``snapshot``.
    """
    index = np.concatenate([np.arange(p.first, p.first + len(SEGMENTS)) for p in people.people])
    states = [snapshot.objects[i] for i in index]
    pos = np.stack([s.transform[:3, 3] for s in states])
    vel = np.stack([s.velocity_mps for s in states])
    rng, v_r, az, el = _relative_to(snapshot, radar, pos, vel)
    return {
        f"/people/segments/{radar}/range": (rng, "m"),
        f"/people/segments/{radar}/radial_velocity": (v_r, "m/s"),
        f"/people/segments/{radar}/azimuth": (az, "deg"),
        f"/people/segments/{radar}/elevation": (el, "deg"),
    }


def people_static_items(people: PeopleExpansion) -> H5Items:
    """Run-constant ``/people`` datasets: names, ids, segment names and body-part ids."""
    seg_names = [f"{p.name}/{s}" for p in people.people for s in SEGMENTS]
    return {
        "/people/names": (np.array([p.name for p in people.people], dtype=str), ""),
        "/people/object_ids": (np.array([p.object_id for p in people.people], np.int32), "1"),
        "/people/body_part_names": (np.array(SEGMENTS, dtype=str), ""),
        "/people/segments/names": (np.array(seg_names, dtype=str), ""),
        "/people/segments/person": (np.repeat(np.arange(len(people.people)), len(SEGMENTS))
                                    .astype(np.int32), "1"),
        "/people/segments/body_part": (np.tile(np.arange(len(SEGMENTS)), len(people.people))
                                       .astype(np.int32), "1"),
    }


__all__ = ["PeopleTruth", "people_static_items", "people_truth"]
