"""Per-object ground truth of one frame: velocities, bounding boxes, and what the radar sees.

Everything is computed from the frame's :class:`~simcore.scene.snapshot.SceneSnapshot` and
each object's surface points in its local frame (its mesh vertices), so it holds for any
geometry. Bounding boxes are in the world frame: the axis-aligned box of the transformed
vertices, and the oriented box of the local vertices' box carried by the object's pose.

The *reference point* of an object is the apex of corner reflectors and point targets (the
point the radar sees) and the centre of its oriented box otherwise; range, radial velocity
and angles relative to the radar are those of that point in the radar's optical frame
(x right, y down, z boresight; azimuth positive right, elevation positive up, radial
velocity positive moving away).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.scene.geometry import CornerReflector, PointTarget
from simcore.scene.model import Project
from simcore.scene.snapshot import SceneSnapshot

H5Items = dict[str, tuple[NDArray[np.generic], str]]


@dataclass(frozen=True)
class ObjectTruth:
    """Ground truth of every object of one frame (``K`` objects, project order).

    Attributes
    ----------
    velocity_mps : ndarray, shape (K, 3), float64
        Linear velocity of each object's origin, world frame (m/s).
    angular_velocity_rps : ndarray, shape (K, 3), float64
        Angular velocity, world frame (rad/s).
    aabb_m : ndarray, shape (K, 2, 3), float64
        Axis-aligned world box: row 0 the minimum corner, row 1 the maximum (m).
    obb_center_m : ndarray, shape (K, 3), float64
        Centre of the oriented box, world frame (m).
    obb_rotation : ndarray, shape (K, 3, 3), float64
        Box axes → world (the object's rotation; columns are the box axes).
    obb_size_m : ndarray, shape (K, 3), float64
        Edge lengths of the oriented box along its axes (m).
    reference_m : ndarray, shape (K, 3), float64
        Reference point, world frame (m; module docstring).
    radar_range_m : ndarray, shape (K,), float64
        Distance of the reference point from the radar (m; NaN without a radar).
    radar_radial_velocity_mps : ndarray, shape (K,), float64
        Its velocity relative to the radar along the line of sight (m/s, + = away).
    radar_azimuth_deg, radar_elevation_deg : ndarray, shape (K,), float64
        Its direction from the radar (deg).
    """

    velocity_mps: NDArray[np.float64]
    angular_velocity_rps: NDArray[np.float64]
    aabb_m: NDArray[np.float64]
    obb_center_m: NDArray[np.float64]
    obb_rotation: NDArray[np.float64]
    obb_size_m: NDArray[np.float64]
    reference_m: NDArray[np.float64]
    radar_range_m: NDArray[np.float64]
    radar_radial_velocity_mps: NDArray[np.float64]
    radar_azimuth_deg: NDArray[np.float64]
    radar_elevation_deg: NDArray[np.float64]

    def take(self, index: NDArray[np.integer]) -> ObjectTruth:
        """The truth of objects ``index`` (e.g. a person's torso for the person)."""
        return ObjectTruth(*(getattr(self, f)[index] for f in self.__dataclass_fields__))

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets of the ``/objects`` group: path → (array, unit)."""
        return {
            "/objects/velocity": (self.velocity_mps, "m/s"),
            "/objects/angular_velocity": (self.angular_velocity_rps, "rad/s"),
            "/objects/aabb": (self.aabb_m, "m"),
            "/objects/obb_center": (self.obb_center_m, "m"),
            "/objects/obb_rotation": (self.obb_rotation, "1"),
            "/objects/obb_size": (self.obb_size_m, "m"),
            "/objects/reference_point": (self.reference_m, "m"),
            "/objects/radar_range": (self.radar_range_m, "m"),
            "/objects/radar_radial_velocity": (self.radar_radial_velocity_mps, "m/s"),
            "/objects/radar_azimuth": (self.radar_azimuth_deg, "deg"),
            "/objects/radar_elevation": (self.radar_elevation_deg, "deg"),
        }


def object_ground_truth(project: Project, snapshot: SceneSnapshot,
                        local_points: Sequence[NDArray[np.floating] | None]) -> ObjectTruth:
    """Ground truth of every object of a frame.

    Parameters
    ----------
    project : Project
        The project (its objects' geometry kinds).
    snapshot : SceneSnapshot
        The frame's snapshot (poses and velocities).
    local_points : sequence of (ndarray, shape (P, 3)) or None
        Each object's surface points in its local frame (m), project order; None for an
        object without surface (point target: a box of size 0 at its origin).

    Returns
    -------
    ObjectTruth
    """
    k = len(project.objects)
    if len(local_points) != k or len(snapshot.objects) != k:
        raise ValueError("one set of local points and one state per object expected")
    vel = np.zeros((k, 3))
    ang = np.zeros((k, 3))
    aabb = np.zeros((k, 2, 3))
    center = np.zeros((k, 3))
    rot = np.tile(np.eye(3), (k, 1, 1))
    size = np.zeros((k, 3))
    ref = np.zeros((k, 3))
    ref_vel = np.zeros((k, 3))
    for i, (obj, state, pts) in enumerate(zip(project.objects, snapshot.objects, local_points,
                                              strict=True)):
        t = state.transform
        p = np.zeros((1, 3)) if pts is None or len(pts) == 0 else np.asarray(pts, np.float64)
        lo, hi = p.min(axis=0), p.max(axis=0)
        world = p @ t[:3, :3].T + t[:3, 3]
        aabb[i] = world.min(axis=0), world.max(axis=0)
        center[i] = t[:3, :3] @ (0.5 * (lo + hi)) + t[:3, 3]
        rot[i] = t[:3, :3]
        size[i] = hi - lo
        vel[i] = state.velocity_mps
        ang[i] = state.angular_velocity_rps
        analytic = isinstance(obj.geometry, (CornerReflector, PointTarget))
        ref[i] = state.origin if analytic else center[i]
        ref_vel[i] = state.point_velocity(ref[i])
    rng, v_r, az, el = _relative_to(snapshot, "radar", ref, ref_vel)
    return ObjectTruth(vel, ang, aabb, center, rot, size, ref, rng, v_r, az, el)


def _relative_to(snapshot: SceneSnapshot, sensor: str, points: NDArray[np.float64],
                 velocities: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], ...]:
    """Range (m), radial velocity (m/s), azimuth and elevation (deg) from a sensor."""
    k = len(points)
    if sensor not in snapshot.sensors:
        nan = np.full(k, np.nan)
        return nan, nan.copy(), nan.copy(), nan.copy()
    s = snapshot.sensors[sensor]
    local = (points - s.position) @ s.rotation  # optical frame
    rel_v = (velocities - s.velocity_mps) @ s.rotation  # range rate: frame rotation drops out
    rng = np.linalg.norm(local, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        v_r = np.where(rng > 0, np.einsum("ij,ij->i", rel_v, local) / rng, 0.0)
    az = np.degrees(np.arctan2(local[:, 0], local[:, 2]))
    el = np.degrees(np.arctan2(-local[:, 1], np.hypot(local[:, 0], local[:, 2])))
    return rng, v_r, az, el
