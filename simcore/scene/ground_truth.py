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
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
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
    radar_nearest_range_m : ndarray, shape (K,), float64
        Distance from the radar to the nearest point of the object's surface (m; NaN
        without a radar): where the radar sees the object begin — a box centred at 2 m
        whose face towards the radar is at 1.75 m reads 1.75 m (:func:`nearest_range`).
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
    radar_nearest_range_m: NDArray[np.float64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.float64))

    def sensor_items(self, name: str) -> H5Items:
        """The ``radar_*`` truth as a named radar's: ``/objects/<name>/range``, ...

        For any radar but the built-in one (whose truth is ``/objects/radar_range``, ...).
        """
        return {
            f"/objects/{name}/range": (self.radar_range_m, "m"),
            f"/objects/{name}/radial_velocity": (self.radar_radial_velocity_mps, "m/s"),
            f"/objects/{name}/azimuth": (self.radar_azimuth_deg, "deg"),
            f"/objects/{name}/elevation": (self.radar_elevation_deg, "deg"),
        }

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


@dataclass
class _Kept:
    """One object's results (:class:`TruthCache`) and the inputs they hold for."""

    points: NDArray[np.floating]
    triangles: NDArray[np.integer] | None
    transform: bytes
    aabb: NDArray[np.float64]
    center: NDArray[np.float64]
    size: NDArray[np.float64]
    radar: bytes | None = None
    nearest: float = float("nan")


@dataclass
class TruthCache:
    """Per-object results of :func:`object_ground_truth` kept from one frame to the next.

    An object whose surface (the same arrays) and pose (the same transform, bit for bit)
    are those of the previous frame keeps its boxes, and with the radar where it was, its
    nearest range: a still asset of many triangles is then neither transformed nor
    searched again every frame. Everything kept is keyed by the inputs it was computed
    from, so the results equal those computed without the cache.
    """

    _objects: dict[int, _Kept] = field(default_factory=dict)
    #: Each surface's local box (its points array, lower and upper corners), by object:
    #: a moving object's points are the same arrays in every frame.
    _local: dict[int, tuple[NDArray[np.floating], NDArray[np.float64], NDArray[np.float64]]] \
        = field(default_factory=dict)

    def clear(self) -> None:
        """Forget every object."""
        self._objects.clear()
        self._local.clear()

    def local_box(self, i: int, pts: NDArray[np.floating]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper corners of object ``i``'s points ``pts`` (kept while the same)."""
        kept = self._local.get(i)
        if kept is None or kept[0] is not pts:
            p = np.asarray(pts, np.float64)
            kept = (pts, p.min(axis=0), p.max(axis=0))
            self._local[i] = kept
        return kept[1], kept[2]


def object_ground_truth(project: Project, snapshot: SceneSnapshot,
                        local_points: Sequence[NDArray[np.floating] | None], *,
                        local_triangles: Sequence[NDArray[np.integer] | None] | None = None,
                        cache: TruthCache | None = None, sensor: str = "radar"
                        ) -> ObjectTruth:
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
    local_triangles : sequence of (ndarray, shape (T, 3), int) or None, optional
        Vertex indices of each object's triangles into its ``local_points``; with them the
        nearest range is that of the nearest point of the surface, without them that of
        the nearest vertex.
    cache : TruthCache, optional
        Results of the previous frames: objects that did not move (nor the radar, for
        their nearest range) are not computed again. The arrays of ``local_points`` and
        ``local_triangles`` must not be modified in place between calls.
    sensor : str
        The radar whose range, radial velocity, angles and nearest range the ``radar_*``
        fields hold (default the built-in ``radar``); NaN when the snapshot has no such
        sensor.

    Returns
    -------
    ObjectTruth
    """
    k = len(project.objects)
    if len(local_points) != k or len(snapshot.objects) != k:
        raise ValueError("one set of local points and one state per object expected")
    triangles = [None if local_triangles is None or pts is None else local_triangles[i]
                 for i, pts in enumerate(local_points)]
    boxes = _object_boxes(snapshot, local_points, triangles, cache)
    rot = np.tile(np.eye(3), (k, 1, 1))
    origin = np.zeros((k, 3))
    vel = np.zeros((k, 3))
    ang = np.zeros((k, 3))
    ref = np.zeros((k, 3))
    for i, (obj, state) in enumerate(zip(project.objects, snapshot.objects, strict=True)):
        rot[i] = state.transform[:3, :3]
        origin[i] = state.transform[:3, 3]
        vel[i] = state.velocity_mps
        ang[i] = state.angular_velocity_rps
        analytic = isinstance(obj.geometry, (CornerReflector, PointTarget))
        ref[i] = state.origin if analytic else boxes.center[i]
    radar = snapshot.sensors.get(sensor)
    nearest = np.full(k, np.nan)
    if radar is not None:
        nearest = _nearest_surface_ranges(np.asarray(radar.position, np.float64), snapshot,
                                          local_points, triangles, boxes, ref)
    if cache is not None:
        cache._objects = boxes.kept
    # Each reference point's velocity as a point of its body (RigidState.point_velocity).
    ref_vel = vel + np.cross(ang, ref - origin)
    rng, v_r, az, el = _relative_to(snapshot, sensor, ref, ref_vel)
    return ObjectTruth(vel, ang, boxes.aabb, boxes.center, rot, boxes.size, ref, rng, v_r, az,
                       el, nearest)


@dataclass
class _Boxes:
    """Every object's boxes, the world points computed for them, and what the cache keeps."""

    aabb: NDArray[np.float64]                       # (K, 2, 3)
    center: NDArray[np.float64]                     # (K, 3)
    size: NDArray[np.float64]                       # (K, 3)
    world: list[NDArray[np.float64] | None]         # world points where computed
    kept: dict[int, _Kept]                          # the cache's entries for this frame


def _object_boxes(snapshot: SceneSnapshot,
                  local_points: Sequence[NDArray[np.floating] | None],
                  triangles: Sequence[NDArray[np.integer] | None],
                  cache: TruthCache | None) -> _Boxes:
    """Axis-aligned and oriented boxes of every object, from the cache where still valid."""
    k = len(local_points)
    boxes = _Boxes(np.zeros((k, 2, 3)), np.zeros((k, 3)), np.zeros((k, 3)), [None] * k, {})
    kept_before = {} if cache is None else cache._objects
    for i, (state, pts) in enumerate(zip(snapshot.objects, local_points, strict=True)):
        t = state.transform
        tri = triangles[i]
        t_key = np.ascontiguousarray(t, dtype=np.float64).tobytes()
        kept = kept_before.get(i)
        if kept is not None and not (pts is not None and kept.points is pts
                                     and kept.triangles is tri and kept.transform == t_key):
            kept = None
        if kept is None:
            p = np.zeros((1, 3)) if pts is None or len(pts) == 0 else np.asarray(pts, np.float64)
            lo, hi = (cache.local_box(i, pts) if cache is not None and pts is not None
                      and len(pts) else (p.min(axis=0), p.max(axis=0)))
            world = p @ t[:3, :3].T + t[:3, 3]
            boxes.world[i] = world
            boxes.aabb[i] = world.min(axis=0), world.max(axis=0)
            boxes.center[i] = t[:3, :3] @ (0.5 * (lo + hi)) + t[:3, 3]
            boxes.size[i] = hi - lo
            if pts is not None and cache is not None:
                kept = _Kept(pts, tri, t_key, boxes.aabb[i].copy(), boxes.center[i].copy(),
                             boxes.size[i].copy())
        else:
            boxes.aabb[i], boxes.center[i], boxes.size[i] = kept.aabb, kept.center, kept.size
        if kept is not None:
            boxes.kept[i] = kept
    return boxes


def _nearest_surface_ranges(radar_position: NDArray[np.float64], snapshot: SceneSnapshot,
                            local_points: Sequence[NDArray[np.floating] | None],
                            triangles: Sequence[NDArray[np.integer] | None], boxes: _Boxes,
                            ref: NDArray[np.float64]) -> NDArray[np.float64]:
    """Nearest range of every object's surface from the radar; kept ones from the cache."""
    radar_key = radar_position.tobytes()
    nearest = np.full(len(local_points), np.nan)
    todo: list[int] = []
    surfaces: list[tuple[NDArray[np.float64], NDArray[np.integer] | None]] = []
    for i, (state, pts) in enumerate(zip(snapshot.objects, local_points, strict=True)):
        kept = boxes.kept.get(i)
        if kept is not None and kept.radar == radar_key:
            nearest[i] = kept.nearest
            continue
        if pts is None:
            surfaces.append((ref[i:i + 1], None))
        else:
            world = boxes.world[i]
            if world is None:
                t = state.transform
                p = np.zeros((1, 3)) if len(pts) == 0 else np.asarray(pts, np.float64)
                world = p @ t[:3, :3].T + t[:3, 3]
            surfaces.append((world, triangles[i]))
        todo.append(i)
    if todo:
        nearest[todo] = nearest_ranges(radar_position, surfaces)
        for i in todo:
            kept = boxes.kept.get(i)
            if kept is not None:
                kept.radar, kept.nearest = radar_key, float(nearest[i])
    return nearest


def nearest_range(origin: NDArray[np.floating], points: NDArray[np.floating],
                  triangles: NDArray[np.integer] | None = None) -> float:
    """Distance from ``origin`` to the nearest point of a triangle surface (m).

    Parameters
    ----------
    origin : ndarray, shape (3,)
        The sensor's position (m).
    points : ndarray, shape (P, 3)
        Vertex positions, same frame as ``origin`` (m).
    triangles : ndarray, shape (T, 3), int, optional
        Vertex indices of the triangles. Without them (or with none) the distance is that
        of the nearest vertex.

    Returns
    -------
    float
        The smallest distance from ``origin`` to any point of any triangle (its faces,
        edges and corners), or to any vertex without triangles; NaN for no points.

    Examples
    --------
    >>> square = np.array([[1.0, -1, -1], [1, 1, -1], [1, 1, 1], [1, -1, 1]])
    >>> nearest_range(np.zeros(3), square, np.array([[0, 1, 2], [0, 2, 3]]))
    1.0
    """
    return float(nearest_ranges(origin, [(points, triangles)])[0])


def nearest_ranges(origin: NDArray[np.floating],
                   surfaces: Sequence[tuple[NDArray[np.floating], NDArray[np.integer] | None]]
                   ) -> NDArray[np.float64]:
    """:func:`nearest_range` of several surfaces at once, shape (K,) (m).

    ``surfaces`` holds one (points, triangles or None) pair per object. All triangles are
    handled in one vectorised pass; a triangle that cannot come nearer than its surface's
    nearest vertex (its farthest vertex minus its longest edge is beyond it) is skipped.
    """
    o = np.asarray(origin, dtype=np.float64).reshape(3)
    k = len(surfaces)
    pts: list[NDArray[np.float64]] = []
    tris: list[NDArray[np.int64]] = []
    tri_owner: list[NDArray[np.int64]] = []
    counts = np.zeros(k, dtype=np.int64)
    offset = 0
    for i, (points, triangles) in enumerate(surfaces):
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        pts.append(p)
        counts[i] = len(p)
        if len(p) and triangles is not None and len(triangles):
            t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
            tris.append(t + offset)
            tri_owner.append(np.full(len(t), i, dtype=np.int64))
        offset += len(p)
    out = np.full(k, np.nan)
    if offset == 0:
        return out
    all_p = np.concatenate(pts)
    d = np.sqrt(np.sum((all_p - o) ** 2, axis=1))
    has = counts > 0
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    # The nearest vertex: an upper bound, and the answer without triangles.
    out[has] = np.minimum.reduceat(d, starts[has])
    if not tris:
        return out
    _nearest_on_triangles(o, all_p, d, np.concatenate(tris), np.concatenate(tri_owner), out)
    return out


@kernel
def _nearest_on_triangles(o: NDArray[np.float64], points: NDArray[np.float64],
                          dist: NDArray[np.float64], triangles: NDArray[np.int64],
                          owner: NDArray[np.int64], out: NDArray[np.float64]) -> None:
    """Lower ``out[owner[k]]`` to the distance from ``o`` to triangle ``k``, for each.

    ``dist`` holds each point's distance from ``o``; ``out`` starts at each surface's
    nearest vertex. A triangle whose farthest corner minus its longest edge is beyond its
    surface's nearest distance so far cannot come nearer and is skipped. The closest point
    is Ericson's (*Real-Time Collision Detection*, 5.1.5), with :func:`_closest_on_triangles`'
    order of regions: corners a, b, c, then edges ab, ac, bc, then the face; a degenerate
    (zero-area) triangle's nearest corner.
    """
    for k in range(triangles.shape[0]):
        i, j, m = triangles[k, 0], triangles[k, 1], triangles[k, 2]
        longest = 0.0
        for u, v in ((i, j), (j, m), (m, i)):
            e = ((points[u, 0] - points[v, 0]) ** 2 + (points[u, 1] - points[v, 1]) ** 2
                 + (points[u, 2] - points[v, 2]) ** 2)
            longest = max(longest, e)
        far = max(dist[i], max(dist[j], dist[m]))
        if far - np.sqrt(longest) > out[owner[k]]:
            continue
        a0, a1, a2 = points[i, 0], points[i, 1], points[i, 2]
        b0, b1, b2 = points[j, 0], points[j, 1], points[j, 2]
        c0, c1, c2 = points[m, 0], points[m, 1], points[m, 2]
        ab0, ab1, ab2 = b0 - a0, b1 - a1, b2 - a2
        ac0, ac1, ac2 = c0 - a0, c1 - a1, c2 - a2
        ap0, ap1, ap2 = o[0] - a0, o[1] - a1, o[2] - a2
        bp0, bp1, bp2 = o[0] - b0, o[1] - b1, o[2] - b2
        cp0, cp1, cp2 = o[0] - c0, o[1] - c1, o[2] - c2
        d1 = ab0 * ap0 + ab1 * ap1 + ab2 * ap2
        d2 = ac0 * ap0 + ac1 * ap1 + ac2 * ap2
        d3 = ab0 * bp0 + ab1 * bp1 + ab2 * bp2
        d4 = ac0 * bp0 + ac1 * bp1 + ac2 * bp2
        d5 = ab0 * cp0 + ab1 * cp1 + ab2 * cp2
        d6 = ac0 * cp0 + ac1 * cp1 + ac2 * cp2
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        if d1 <= 0 and d2 <= 0:
            q0, q1, q2 = a0, a1, a2
        elif d3 >= 0 and d4 <= d3:
            q0, q1, q2 = b0, b1, b2
        elif d6 >= 0 and d5 <= d6:
            q0, q1, q2 = c0, c1, c2
        elif vc <= 0 and d1 >= 0 and d3 <= 0:
            t = d1 / (d1 - d3) if d1 != d3 else np.nan
            q0, q1, q2 = a0 + t * ab0, a1 + t * ab1, a2 + t * ab2
        elif vb <= 0 and d2 >= 0 and d6 <= 0:
            t = d2 / (d2 - d6) if d2 != d6 else np.nan
            q0, q1, q2 = a0 + t * ac0, a1 + t * ac1, a2 + t * ac2
        elif va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
            den = (d4 - d3) + (d5 - d6)
            t = (d4 - d3) / den if den != 0 else np.nan
            q0, q1, q2 = b0 + t * (c0 - b0), b1 + t * (c1 - b1), b2 + t * (c2 - b2)
        else:
            denom = va + vb + vc
            v, w = (vb / denom, vc / denom) if denom != 0 else (np.nan, np.nan)
            q0, q1, q2 = a0 + v * ab0 + w * ac0, a1 + v * ab1 + w * ac1, a2 + v * ab2 + w * ac2
        # A degenerate (zero-area) triangle: 0/0 in the numpy reference, NaN here.
        if not (np.isfinite(q0) and np.isfinite(q1) and np.isfinite(q2)):
            near = min(dist[i], min(dist[j], dist[m]))      # degenerate: a corner
        else:
            near = np.sqrt((q0 - o[0]) ** 2 + (q1 - o[1]) ** 2 + (q2 - o[2]) ** 2)
        if near < out[owner[k]]:
            out[owner[k]] = near


def _closest_on_triangles(o: NDArray[np.float64], a: NDArray[np.float64],
                          b: NDArray[np.float64], c: NDArray[np.float64]
                          ) -> NDArray[np.float64]:
    """Closest point to ``o`` on each triangle (a, b, c: shape (T, 3)), shape (T, 3).

    Ericson, *Real-Time Collision Detection*, 5.1.5: the Voronoi region of ``o`` among the
    triangle's corners, edges and face, decided by barycentric signs; vectorised.
    """
    ab, ac, ap = b - a, c - a, o - a
    d1, d2 = _dot(ab, ap), _dot(ac, ap)
    bp = o - b
    d3, d4 = _dot(ab, bp), _dot(ac, bp)
    cp = o - c
    d5, d6 = _dot(ab, cp), _dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v_face, w_face = vb / denom, vc / denom
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    out = a + v_face[:, None] * ab + w_face[:, None] * ac
    # Later assignments win: edges over the face, corners over the edges.
    cases = [
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + t_bc[:, None] * (c - b)),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + t_ac[:, None] * ac),
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + t_ab[:, None] * ab),
        ((d6 >= 0) & (d5 <= d6), c),
        ((d3 >= 0) & (d4 <= d3), b),
        ((d1 <= 0) & (d2 <= 0), a),
    ]
    for mask, point in cases:
        out = np.where(mask[:, None], point, out)
    # Degenerate (zero-area) triangles: their corners.
    bad = ~np.all(np.isfinite(out), axis=1)
    if bad.any():
        corners = np.stack([a[bad], b[bad], c[bad]], axis=1)
        k = np.argmin(np.sum((corners - o) ** 2, axis=2), axis=1)
        out[bad] = corners[np.arange(len(k)), k]
    return out


def _dot(u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.einsum("ij,ij->i", u, v)


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
