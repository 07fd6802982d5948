"""Display meshes, colours and sensor frustums for the 3D viewport (pyvista, no Qt)."""

from __future__ import annotations

import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pyvista as pv
from numpy.typing import NDArray

from simcore.scene import Project
from simcore.scene.geometry import Geometry
from simcore.scene.motion import Motion, Pose, rigid_state

#: Display colours of the bundled materials (the viewport only; simulation ignores them).
MATERIAL_COLOURS = {
    "aluminium": "#b8bec6",
    "concrete": "#8d8d88",
    "wood": "#a0704a",
    "paper": "#e8dcb8",
    "fabric": "#4f6d9a",
    "black_plastic": "#34363a",
    "glass": "#a8d8f0",
    "ir_retroreflector_tape": "#f2d21b",
    "radar_absorber": "#2e4a3a",
    "skin": "#d9a98a",
    "white_paint": "#dcdcd6",
    "radar_retroreflector": "#e0b040",
}

TOF_COLOUR = "#3ddc97"
RADAR_COLOUR = "#ff9f40"
RGB_COLOUR = "#6ab0ff"
SELECTION_COLOUR = "#ffd54a"


def material_colour(name: str) -> str:
    """Display colour of a material: bundled palette, else a stable colour from the name."""
    if name in MATERIAL_COLOURS:
        return MATERIAL_COLOURS[name]
    h = zlib.crc32(name.encode()) & 0xFFFFFF
    r, g, b = 90 + (h >> 16) % 140, 90 + (h >> 8 & 255) % 140, 90 + (h & 255) % 140
    return f"#{r:02x}{g:02x}{b:02x}"


def display_mesh(geometry: Geometry, *, base_dir: Path) -> pv.PolyData:
    """A light display mesh of ``geometry`` in its local frame (m).

    Spheres and cylinders use fewer facets than the simulation's meshes; point targets
    (no surface) are shown as a small diamond.
    """
    kind = geometry.kind
    if kind == "box":
        sx, sy, sz = geometry.size_m
        return pv.Box(bounds=(-sx / 2, sx / 2, -sy / 2, sy / 2, -sz / 2, sz / 2))
    if kind == "sphere":
        return pv.Sphere(radius=geometry.radius_m, theta_resolution=40, phi_resolution=24)
    if kind == "cylinder":
        return pv.Cylinder(center=(0, 0, 0), direction=(0, 0, 1), radius=geometry.radius_m,
                           height=geometry.height_m, resolution=40, capping=True)
    if kind == "plane":
        sx, sy = geometry.size_m
        return pv.Plane(center=(0, 0, 0), direction=(0, 0, 1), i_size=sx, j_size=sy,
                        i_resolution=1, j_resolution=1)
    if kind == "point_target":
        return pv.Octahedron(radius=0.06)
    from simcore.render.meshes import build_mesh

    mesh = build_mesh(geometry, base_dir=base_dir)
    assert mesh is not None
    return pv.wrap(mesh.to_polydata())


def frustum(fov_h_deg: float, fov_v_deg: float, depth_m: float) -> pv.PolyData:
    """Pyramid of a sensor's field of view in its optical frame (x right, y down, z fwd)."""
    tx = np.tan(np.deg2rad(fov_h_deg) / 2) * depth_m
    ty = np.tan(np.deg2rad(fov_v_deg) / 2) * depth_m
    pts = np.array([[0, 0, 0], [-tx, -ty, depth_m], [tx, -ty, depth_m], [tx, ty, depth_m],
                    [-tx, ty, depth_m]], dtype=float)
    faces = np.hstack([[3, 0, 1, 2], [3, 0, 2, 3], [3, 0, 3, 4], [3, 0, 4, 1]])
    return pv.PolyData(pts, faces=faces)


def frustum_edges(fov_h_deg: float, fov_v_deg: float, depth_m: float) -> pv.PolyData:
    """The edges of :func:`frustum` (four rays and the far rectangle)."""
    f = frustum(fov_h_deg, fov_v_deg, depth_m)
    lines = np.hstack([[2, 0, 1], [2, 0, 2], [2, 0, 3], [2, 0, 4], [5, 1, 2, 3, 4, 1]])
    return pv.PolyData(f.points, lines=lines)


def radar_fov_v_deg(project: Project, radar: Any = None) -> float:
    """Vertical field of view of a radar's render grid (square pixels) (degrees).

    ``radar``: the radar's configuration (default the project's first radar).
    """
    r = next(iter(project.sensors_of_kind("radar").values())) if radar is None else radar
    return float(np.rad2deg(2 * np.arctan(np.tan(np.deg2rad(r.render_fov_h_deg) / 2)
                                          * r.render_height / r.render_width)))


def base_pose_for_world(pose: Pose, motion: Motion, t: float, world: NDArray[np.float64]
                        ) -> Pose:
    """The base pose that puts a body at the world transform ``world`` at time ``t``.

    The motion at ``t`` applies a rotation ``Ro`` and an offset ``o`` to the base pose
    (``R = Ro R0``, ``p = p0 + o``); this inverts it, so dragging a moving object moves
    its whole trajectory.
    """
    from scipy.spatial.transform import Rotation

    offset = rigid_state(Pose(), motion, t).transform
    ro, o = offset[:3, :3], offset[:3, 3]
    r0 = ro.T @ world[:3, :3]
    # Orthonormalise (drag matrices accumulate rounding).
    u, _, vt = np.linalg.svd(r0)
    r0 = u @ vt
    p0 = world[:3, 3] - o
    euler = Rotation.from_matrix(r0).as_euler("xyz", degrees=True)
    return Pose(position_m=tuple(float(round(v, 6)) for v in p0),
                rotation_deg=tuple(float(round(v, 4)) + 0.0 for v in euler))


class PersonPoser:
    """A person's display mesh (:func:`display_mesh`) posed as the simulation poses it.

    Same body, seed and path as :mod:`simcore.scene.people.expand`.
    The display mesh is the segments' ellipsoids one after the other; each keeps its
    points in its segment's frame here, and :meth:`points` puts them where the segments
    are at ``t`` in the world (walk, gesture, vital signs, sway, BVH clip).
    """

    def __init__(self, obj: Any, *, seed: int, base_dir: Path):
        from simcore.render.meshes import _ellipsoid
        from simcore.scene.people.body import PersonBody

        self.body = PersonBody(obj.geometry, obj.pose, obj.motion, object_id=obj.id,
                               seed=seed, base_dir=base_dir)
        parts = [_ellipsoid(r).points for r in self.body.skeleton.radii]
        self.local = np.concatenate(parts)
        self.owner = np.repeat(np.arange(len(parts)), [len(p) for p in parts])

    def points(self, t: float) -> NDArray[np.float64]:
        """World position of every display-mesh point at ``t`` (s), shape (P, 3)."""
        tr = self.body.segment_transforms(t)[self.owner]
        return np.einsum("pij,pj->pi", tr[:, :3, :3], self.local) + tr[:, :3, 3]
