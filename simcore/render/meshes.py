"""Triangle meshes of scene objects, built once per geometry in the object's local frame.

Mesh files are parsed and checked by :mod:`simcore.scene.mesh_files` (counts, indices,
finiteness, size limits) before VTK sees them; VTK's own file readers are not used.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals, vtkTriangleFilter
from vtkmodules.vtkFiltersSources import (
    vtkCubeSource,
    vtkCylinderSource,
    vtkPlaneSource,
    vtkSphereSource,
)

from simcore.scene.geometry import (
    Box,
    CornerReflector,
    Cylinder,
    Ellipsoid,
    Geometry,
    Mesh,
    Plane,
    PointTarget,
    Sphere,
    corner_reflector_axes,
)
from simcore.scene.mesh_files import MeshError, read_mesh_arrays
from simcore.scene.people.config import Person
from simcore.scene.project_io import resolve_mesh_path

SPHERE_THETA_RESOLUTION = 160
SPHERE_PHI_RESOLUTION = 80
CYLINDER_RESOLUTION = 128


@dataclass(frozen=True)
class TriangleMesh:
    """Triangles of one object in its local frame.

    Attributes
    ----------
    points : ndarray, shape (points, 3)
        Vertex positions (m).
    normals : ndarray, shape (points, 3)
        Unit vertex normals (shared vertices of smooth surfaces, split at sharp edges).
    triangles : ndarray, shape (triangles, 3), int64
        Vertex indices of each triangle.
    """

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    triangles: NDArray[np.int64]

    def to_polydata(self) -> vtkPolyData:
        """Build a VTK polydata of the triangles (for rendering)."""
        from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray

        pts = vtkPoints()
        pts.SetData(numpy_to_vtk(np.ascontiguousarray(self.points), deep=1))
        cells = vtkCellArray()
        offsets = np.arange(0, 3 * len(self.triangles) + 1, 3, dtype=np.int64)
        cells.SetData(
            numpy_to_vtkIdTypeArray(offsets, deep=1),
            numpy_to_vtkIdTypeArray(np.ascontiguousarray(self.triangles.ravel()), deep=1),
        )
        poly = vtkPolyData()
        poly.SetPoints(pts)
        poly.SetPolys(cells)
        return poly


def _from_polydata(poly: vtkPolyData, *, smooth: bool) -> TriangleMesh:
    tri = vtkTriangleFilter()
    tri.SetInputData(poly)
    tri.PassLinesOff()
    tri.PassVertsOff()
    normals = vtkPolyDataNormals()
    normals.SetInputConnection(tri.GetOutputPort())
    normals.SetSplitting(not smooth)
    normals.SetFeatureAngle(40.0)
    normals.ConsistencyOn()
    normals.ComputePointNormalsOn()
    normals.ComputeCellNormalsOff()
    normals.Update()
    out = normals.GetOutput()
    if out.GetNumberOfPolys() == 0:
        raise MeshError("mesh has no triangles")
    conn = vtk_to_numpy(out.GetPolys().GetConnectivityArray()).astype(np.int64)
    points = vtk_to_numpy(out.GetPoints().GetData()).astype(np.float64)
    vnormals = vtk_to_numpy(out.GetPointData().GetNormals()).astype(np.float64)
    return TriangleMesh(points, vnormals, conn.reshape(-1, 3))


def _corner_reflector(geom: CornerReflector) -> TriangleMesh:
    e = corner_reflector_axes() * geom.edge_m
    points, normals, tris = [], [], []
    for k, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        n = np.cross(e[i], e[j])
        n /= np.linalg.norm(n)
        points += [np.zeros(3), e[i], e[j]]
        normals += [n, n, n]
        tris.append([3 * k, 3 * k + 1, 3 * k + 2])
    return TriangleMesh(np.array(points), np.array(normals), np.array(tris, dtype=np.int64))


#: Largest distance (m) between an ellipsoid and its triangles. A body has 17 ellipsoid
#: segments, drawn by three render passes every frame: each is cut only as finely as this
#: tolerance needs (a hand into fewer triangles than a chest). 5 mm is below the ToF
#: camera's depth noise and the radar's range resolution, and far below how closely
#: ellipsoids follow a body.
ELLIPSOID_TOLERANCE_M = 5e-3
#: Bounds of an ellipsoid's tessellation: sectors around its z axis, and rings pole to pole.
ELLIPSOID_THETA_RANGE = (8, SPHERE_THETA_RESOLUTION)
ELLIPSOID_PHI_RANGE = (4, SPHERE_PHI_RESOLUTION)


def ellipsoid_gap_bound(radii: NDArray[np.float64] | tuple[float, float, float],
                        n_theta: float, n_phi: float) -> float:
    """Bound (m) on the distance from a UV-sphere tessellation of an ellipsoid to its surface.

    The surface is ``S(θ, φ) = (a sin φ cos θ, b sin φ sin θ, c cos φ)`` and each triangle
    interpolates it linearly over a right triangle of parameter steps Δθ = 2π/n_θ and
    Δφ = π/n_φ. The linear interpolation error is at most ½ Σ λ_i Q(x_i − x) with Q the
    bound of S's second derivatives, ``|S_θθ|, |S_θφ| ≤ A = max(a, b)`` and
    ``|S_φφ| ≤ R = max(a, b, c)``; with 2|Δθ Δφ| ≤ Δθ² + Δφ², ``Q(v) ≤ 2A v_θ² + (R + A) v_φ²``,
    whose largest value of ½ Σ λ_i Q(x_i − x) over a right triangle is an eighth of Q at
    its hypotenuse: ``(2A Δθ² + (R + A) Δφ²) / 8``. Each point of a triangle then lies
    within that distance of the point S at its parameters, so of the surface.
    """
    r = np.abs(np.asarray(radii, dtype=np.float64))
    big_a, big_r = float(max(r[0], r[1])), float(r.max())
    d_theta, d_phi = 2.0 * np.pi / n_theta, np.pi / n_phi
    return (2.0 * big_a * d_theta**2 + (big_r + big_a) * d_phi**2) / 8.0


def ellipsoid_resolution(radii: NDArray[np.float64] | tuple[float, float, float],
                         tolerance_m: float = ELLIPSOID_TOLERANCE_M) -> tuple[int, int]:
    """Sectors and rings (θ and φ resolutions of a UV sphere) of an ellipsoid's triangles.

    The pair with the fewest triangles (2 n_θ (n_φ − 2)) whose
    :func:`ellipsoid_gap_bound` is within ``tolerance_m``, inside
    :data:`ELLIPSOID_THETA_RANGE` and :data:`ELLIPSOID_PHI_RANGE` (the finest pair when
    none is fine enough).
    """
    r = np.abs(np.asarray(radii, dtype=np.float64))
    big_a, big_r = float(max(r[0], r[1])), float(r.max())
    (t_lo, t_hi), (p_lo, p_hi) = ELLIPSOID_THETA_RANGE, ELLIPSOID_PHI_RANGE
    best: tuple[int, int, int] | None = None
    for n_theta in range(t_lo, t_hi + 1):
        # The sectors' share of the bound (its φ term vanishes with infinitely many rings).
        left = tolerance_m - ellipsoid_gap_bound(r, n_theta, np.inf)
        if left <= 0.0:
            continue
        # The fewest rings whose φ term, (R + A) Δφ² / 8, fits in what the sectors leave.
        n_phi = p_lo if big_r + big_a == 0.0 else max(
            p_lo, int(np.ceil(np.pi / np.sqrt(8.0 * left / (big_r + big_a)))))
        if n_phi > p_hi:
            continue
        triangles = 2 * n_theta * (n_phi - 2)
        if best is None or triangles < best[0]:
            best = (triangles, n_theta, n_phi)
    return (t_hi, p_hi) if best is None else (best[1], best[2])


def _ellipsoid(radii: NDArray[np.float64]) -> TriangleMesh:
    """Unit sphere scaled to ``radii`` (:func:`ellipsoid_resolution`), exact normals."""
    n_theta, n_phi = ellipsoid_resolution(radii)
    src = vtkSphereSource()
    src.SetRadius(1.0)
    src.SetThetaResolution(n_theta)
    src.SetPhiResolution(n_phi)
    src.Update()
    unit = _from_polydata(src.GetOutput(), smooth=True)
    points = unit.points * radii
    n = points / radii**2
    return TriangleMesh(points, n / np.linalg.norm(n, axis=1, keepdims=True), unit.triangles)


def _person_rest_mesh(person: Person, base_dir: Path | None = None) -> TriangleMesh:
    """A person's segments at t = 0 (its posture and motion then), one mesh in its frame.

    What the simulation renders is the segments (:mod:`simcore.scene.people.expand`);
    this mesh serves views and bounding boxes of the unexpanded object.
    """
    from simcore.scene.motion import Motion, Pose
    from simcore.scene.people.body import PersonBody
    from simcore.scene.people.bvh import BvhError

    still = person.model_copy(update={"motion": person.motion.model_copy(
        update={"sway_mm": 0.0})})
    try:
        body = PersonBody(still, Pose(), Motion(), base_dir=base_dir)
    except (BvhError, ValueError):  # a clip that cannot be read: the plain posture
        body = PersonBody(still.model_copy(update={"motion": still.motion.model_copy(
            update={"bvh": None})}), Pose(), Motion())
    transforms = body.segment_transforms(0.0)
    points, normals, tris = [], [], []
    offset = 0
    for i, transform in enumerate(transforms):
        part = _ellipsoid(body.skeleton.radii[i])
        rot = transform[:3, :3]
        points.append(part.points @ rot.T + transform[:3, 3])
        normals.append(part.normals @ rot.T)
        tris.append(part.triangles + offset)
        offset += len(part.points)
    return TriangleMesh(np.concatenate(points), np.concatenate(normals), np.concatenate(tris))


def _read_mesh_file(path: Path) -> vtkPolyData:
    """Parse and check a mesh file in Python, then hand VTK only the checked arrays."""
    points, triangles = read_mesh_arrays(path)
    return TriangleMesh(points, np.zeros_like(points), triangles).to_polydata()


def build_mesh(geometry: Geometry, *, base_dir: Path | None = None) -> TriangleMesh | None:
    """Triangulate a geometry in its local frame; ``None`` for point targets (no surface)."""
    if isinstance(geometry, PointTarget):
        return None
    if isinstance(geometry, CornerReflector):
        return _corner_reflector(geometry)
    if isinstance(geometry, Box):
        src = vtkCubeSource()
        src.SetXLength(geometry.size_m[0])
        src.SetYLength(geometry.size_m[1])
        src.SetZLength(geometry.size_m[2])
        src.Update()
        return _from_polydata(src.GetOutput(), smooth=False)
    if isinstance(geometry, Sphere):
        src = vtkSphereSource()
        src.SetRadius(geometry.radius_m)
        src.SetThetaResolution(SPHERE_THETA_RESOLUTION)
        src.SetPhiResolution(SPHERE_PHI_RESOLUTION)
        src.Update()
        mesh = _from_polydata(src.GetOutput(), smooth=True)
        # Exact sphere normals instead of averaged facet normals.
        n = mesh.points / np.linalg.norm(mesh.points, axis=1, keepdims=True)
        return TriangleMesh(mesh.points, n, mesh.triangles)
    if isinstance(geometry, Cylinder):
        src = vtkCylinderSource()
        src.SetRadius(geometry.radius_m)
        src.SetHeight(geometry.height_m)
        src.SetResolution(CYLINDER_RESOLUTION)
        src.CappingOn()
        src.Update()
        mesh = _from_polydata(src.GetOutput(), smooth=False)
        # vtkCylinderSource's axis is y; ours is z: rotate +90° about x.
        rot = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])
        return TriangleMesh(mesh.points @ rot.T, mesh.normals @ rot.T, mesh.triangles)
    if isinstance(geometry, Plane):
        sx, sy = geometry.size_m
        src = vtkPlaneSource()
        src.SetOrigin(-sx / 2, -sy / 2, 0)
        src.SetPoint1(sx / 2, -sy / 2, 0)
        src.SetPoint2(-sx / 2, sy / 2, 0)
        src.Update()
        return _from_polydata(src.GetOutput(), smooth=False)
    if isinstance(geometry, Ellipsoid):
        return _ellipsoid(np.asarray(geometry.radii_m, dtype=np.float64))
    if isinstance(geometry, Person):
        return _person_rest_mesh(geometry, base_dir)
    if isinstance(geometry, Mesh):
        path = resolve_mesh_path(base_dir or Path.cwd(), geometry.path)
        mesh = _from_polydata(_read_mesh_file(path), smooth=False)
        return TriangleMesh(mesh.points * geometry.scale, mesh.normals, mesh.triangles)
    raise TypeError(f"unsupported geometry {type(geometry).__name__}")


__all__ = ["MeshError", "TriangleMesh", "build_mesh"]
