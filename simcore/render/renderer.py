"""Headless per-band rendering of a scene snapshot.

Each band has one persistent offscreen VTK render window (EGL/OSMesa over Mesa where there
is no display or GPU). The GPU pass only rasterises a *triangle index* image: every
triangle is drawn in a flat, unlit colour that encodes its global index (24 bits), with
multisampling and anti-aliasing off so that indices never blend. Everything radiometric is
then computed in float64 numpy from that index: the exact ray–triangle intersection
(Möller–Trumbore) gives range and barycentric coordinates, which interpolate the vertex
normals; the material model gives the band intensity, and the objects' rigid motion gives
the exact velocity of every surface point.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL backend)
from numpy.typing import NDArray
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import (
    vtkActor,
    vtkPolyDataMapper,
    vtkRenderer,
    vtkRenderWindow,
)

from simcore.render.buffers import BANDS, RenderBuffers
from simcore.render.camera import PinholeIntrinsics
from simcore.render.meshes import TriangleMesh, build_mesh
from simcore.scene.geometry import Sphere
from simcore.scene.materials import band_response
from simcore.scene.model import Project
from simcore.scene.project_io import material_table
from simcore.scene.snapshot import SceneSnapshot, SensorState

NEAR_M = 0.02
FAR_M = 500.0
MAX_TRIANGLES = 2**24 - 2


def _vtk_matrix(m: NDArray[np.float64]) -> vtkMatrix4x4:
    out = vtkMatrix4x4()
    out.DeepCopy([float(x) for x in np.asarray(m, dtype=np.float64).ravel()])
    return out


def projection_matrix(intr: PinholeIntrinsics, near: float = NEAR_M, far: float = FAR_M
                      ) -> NDArray[np.float64]:
    """OpenGL clip matrix of a pinhole camera (VTK view frame: x right, y up, looking −z).

    Image row 0 (top) maps to NDC y = +1, so the read-back image flipped vertically has
    row 0 at the top as in :class:`PinholeIntrinsics`.
    """
    w, h = intr.width, intr.height
    return np.array(
        [
            [2 * intr.fx / w, 0.0, 1.0 - 2 * intr.cx / w, 0.0],
            [0.0, 2 * intr.fy / h, 2 * intr.cy / h - 1.0, 0.0],
            [0.0, 0.0, -(far + near) / (far - near), -2 * far * near / (far - near)],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )


@dataclass
class _Geometry:
    """All objects' triangles concatenated, with per-triangle object index."""

    meshes: list[TriangleMesh | None]
    point_offsets: NDArray[np.int64] = field(init=False)
    triangles: NDArray[np.int64] = field(init=False)
    triangle_object: NDArray[np.int64] = field(init=False)
    triangle_offsets: NDArray[np.int64] = field(init=False)

    def __post_init__(self) -> None:
        pts, tris, owner, tri_off = 0, [], [], [0]
        offsets = []
        for index, mesh in enumerate(self.meshes):
            offsets.append(pts)
            if mesh is not None:
                tris.append(mesh.triangles + pts)
                owner.append(np.full(len(mesh.triangles), index))
                pts += len(mesh.points)
            tri_off.append(tri_off[-1] + (0 if mesh is None else len(mesh.triangles)))
        self.point_offsets = np.array(offsets, dtype=np.int64)
        self.triangles = np.concatenate(tris) if tris else np.zeros((0, 3), np.int64)
        self.triangle_object = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        self.triangle_offsets = np.array(tri_off, dtype=np.int64)
        if len(self.triangles) > MAX_TRIANGLES:
            raise ValueError(f"scene has {len(self.triangles)} triangles; at most "
                             f"{MAX_TRIANGLES} can be rendered")

    def world_vertices(self, transforms: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                       NDArray[np.float64]]:
        """Vertex positions and normals of every object in the world frame."""
        pts, nrm = [], []
        for mesh, t in zip(self.meshes, transforms, strict=True):
            if mesh is None:
                continue
            pts.append(mesh.points @ t[:3, :3].T + t[:3, 3])
            nrm.append(mesh.normals @ t[:3, :3].T)
        if not pts:
            return np.zeros((0, 3)), np.zeros((0, 3))
        return np.concatenate(pts), np.concatenate(nrm)


class _IndexPass:
    """One persistent offscreen window that rasterises triangle indices for one band."""

    def __init__(self, geometry: _Geometry):
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetMultiSamples(0)
        self.window.SetAlphaBitPlanes(0)
        self.renderer = vtkRenderer()
        self.renderer.SetBackground(0.0, 0.0, 0.0)
        self.renderer.SetUseFXAA(False)
        self.renderer.SetAutomaticLightCreation(False)
        self.window.AddRenderer(self.renderer)
        self.actors: list[vtkActor | None] = []
        self.set_geometry(geometry)
        self._size: tuple[int, int] | None = None
        self._pixels = vtkUnsignedCharArray()

    def set_geometry(self, geometry: _Geometry) -> None:
        """Replace the actors (one per object) by those of ``geometry``."""
        self.renderer.RemoveAllViewProps()
        self.actors = []
        for index, mesh in enumerate(geometry.meshes):
            if mesh is None:
                self.actors.append(None)
                continue
            poly = mesh.to_polydata()
            first = geometry.triangle_offsets[index]
            ids = np.arange(first + 1, first + 1 + len(mesh.triangles), dtype=np.int64)
            rgb = np.stack([(ids >> 16) & 255, (ids >> 8) & 255, ids & 255], axis=1)
            colours = numpy_to_vtk(rgb.astype(np.uint8), deep=1)
            colours.SetName("triangle_index")
            poly.GetCellData().SetScalars(colours)
            mapper = vtkPolyDataMapper()
            mapper.SetInputData(poly)
            mapper.SetColorModeToDirectScalars()
            mapper.SetScalarModeToUseCellData()
            mapper.ScalarVisibilityOn()
            actor = vtkActor()
            actor.SetMapper(mapper)
            prop = actor.GetProperty()
            prop.LightingOff()
            prop.SetInterpolationToFlat()
            prop.BackfaceCullingOff()
            self.renderer.AddActor(actor)
            self.actors.append(actor)

    def render(self, intr: PinholeIntrinsics, sensor: SensorState,
               transforms: NDArray[np.float64], visible: list[bool]) -> NDArray[np.int64]:
        """Global triangle index per pixel, shape (H, W), −1 for background."""
        if self._size != (intr.width, intr.height):
            self.window.SetSize(intr.width, intr.height)
            self._size = (intr.width, intr.height)
        for actor, t, vis in zip(self.actors, transforms, visible, strict=True):
            if actor is None:
                continue
            actor.SetVisibility(bool(vis))
            actor.SetUserMatrix(_vtk_matrix(t))
        cam = self.renderer.GetActiveCamera()
        pos = sensor.position
        rot = sensor.rotation
        cam.SetPosition(*pos)
        cam.SetFocalPoint(*(pos + rot[:, 2]))
        cam.SetViewUp(*(-rot[:, 1]))
        cam.SetExplicitProjectionTransformMatrix(_vtk_matrix(projection_matrix(intr)))
        cam.SetUseExplicitProjectionTransformMatrix(True)
        self.window.Render()
        self.window.GetRGBACharPixelData(0, 0, intr.width - 1, intr.height - 1, 0,
                                         self._pixels, 0)
        rgba = vtk_to_numpy(self._pixels).reshape(intr.height, intr.width, 4)[::-1]
        index = (rgba[..., 0].astype(np.int64) << 16) | (rgba[..., 1].astype(np.int64) << 8) \
            | rgba[..., 2].astype(np.int64)
        return index - 1

    def close(self) -> None:
        self.renderer.RemoveAllViewProps()
        self.window.Finalize()


def _silence_vtk_display_warning() -> None:
    # VTK first tries X11 and warns "bad X server connection" before falling back to EGL.
    if not os.environ.get("DISPLAY"):
        from vtkmodules.vtkCommonCore import vtkObject

        vtkObject.GlobalWarningDisplayOff()


class SceneRenderer:
    """Renders a project's scene per band into :class:`RenderBuffers`.

    Meshes are triangulated once; each band keeps one offscreen window for the renderer's
    lifetime. ``render_count`` counts GPU passes (tests use it to check that antenna edits
    re-use the cached render).
    """

    def __init__(self, project: Project, *, base_dir: Path | None = None):
        _silence_vtk_display_warning()
        self.base_dir = base_dir
        self._passes: dict[str, _IndexPass] = {}
        self._mesh_cache: dict[str, TriangleMesh | None] = {}
        self.render_count = 0
        self.set_project(project)

    def set_project(self, project: Project) -> None:
        """Follow an edited project: re-triangulate only geometries that changed.

        Poses and motion need nothing here (they come with each snapshot); materials and
        the object list are re-read; the offscreen windows are kept.
        """
        meshes = []
        for obj in project.objects:
            key = obj.geometry.model_dump_json()
            if key not in self._mesh_cache:
                self._mesh_cache[key] = build_mesh(obj.geometry, base_dir=self.base_dir)
            meshes.append(self._mesh_cache[key])
        self.project = project
        self.geometry = _Geometry(meshes)
        for index_pass in self._passes.values():
            index_pass.set_geometry(self.geometry)
        materials = material_table(project)
        self._ids = np.array([o.id for o in project.objects], dtype=np.int32)
        # Spheres are refined analytically: exact range and normal, not the facet's.
        self._sphere_radius = np.array(
            [o.geometry.radius_m if isinstance(o.geometry, Sphere) else 0.0
             for o in project.objects])
        self._params: dict[str, dict[str, NDArray[np.float64]]] = {}
        self._opacity: dict[str, NDArray[np.float64]] = {}
        for band in BANDS:
            params = [materials[o.material].band(band) for o in project.objects]
            self._opacity[band] = np.array([p.opacity for p in params])
            self._params[band] = {
                name: np.array([getattr(p, name) for p in params], dtype=np.float64)
                for name in ("reflectance", "specular", "roughness", "metallic")
            }
            self._params[band]["retro_gain"] = np.array(
                [p.retro_gain if p.retroreflector else 0.0 for p in params])

    def visible_in(self, band: str) -> list[bool]:
        """Which objects are drawn in ``band``'s pass (opacity > 0 and a surface)."""
        return [bool(op > 0) and mesh is not None
                for op, mesh in zip(self._opacity[band], self.geometry.meshes, strict=True)]

    def render(self, snapshot: SceneSnapshot, band: str, intrinsics: PinholeIntrinsics
               ) -> RenderBuffers:
        """Render ``band`` from that band's sensor in ``snapshot``."""
        if band not in BANDS:
            raise ValueError(f"unknown band {band!r}; expected one of {BANDS}")
        sensor = snapshot.tof if band == "tof" else snapshot.radar
        transforms = snapshot.object_transforms()
        if band not in self._passes:
            self._passes[band] = _IndexPass(self.geometry)
        tri_index = self._passes[band].render(intrinsics, sensor, transforms,
                                              self.visible_in(band))
        self.render_count += 1
        return self._shade(snapshot, band, sensor, intrinsics, tri_index, transforms)

    def _shade(self, snapshot: SceneSnapshot, band: str, sensor: SensorState,
               intr: PinholeIntrinsics, tri_index: NDArray[np.int64],
               transforms: NDArray[np.float64]) -> RenderBuffers:
        h, w = intr.height, intr.width
        hit = (tri_index >= 0) & (tri_index < len(self.geometry.triangles))
        tri = tri_index[hit]
        rays_opt = intr.ray_directions()[hit]                      # (M, 3) optical
        rot = sensor.rotation
        origin = sensor.position
        d = rays_opt @ rot.T                                         # world directions
        vertices, vnormals = self.geometry.world_vertices(transforms)
        corners = self.geometry.triangles[tri]                       # (M, 3)
        a, b, c = (vertices[corners[:, k]] for k in range(3))
        e1, e2 = b - a, c - a
        p = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, p)
        ok = np.abs(det) > 1e-18
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = origin - a
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = np.einsum("ij,ij->i", d, q) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        ok &= t > 0
        # Pixels whose centre ray grazes a triangle edge: keep the plane hit, clamp weights.
        uc, vc = np.clip(u, 0, 1), np.clip(v, 0, 1)
        excess = np.maximum(uc + vc - 1.0, 0.0) / 2
        uc, vc = uc - excess, vc - excess
        n = ((1 - uc - vc)[:, None] * vnormals[corners[:, 0]] + uc[:, None]
             * vnormals[corners[:, 1]] + vc[:, None] * vnormals[corners[:, 2]])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        obj = self.geometry.triangle_object[tri]
        if self._sphere_radius.any():
            self._refine_spheres(obj, origin, d, transforms, t, n)
        n *= np.where(np.einsum("ij,ij->i", n, d) > 0, -1.0, 1.0)[:, None]
        dnorm = np.linalg.norm(d, axis=1)
        cos_inc = np.clip(-np.einsum("ij,ij->i", n, d) / dnorm, 0.0, 1.0)
        points_world = origin + t[:, None] * d

        # Exact rigid-body velocity of each surface point relative to the sensor origin.
        states = snapshot.objects
        lin = np.array([s.velocity_mps for s in states]).reshape(-1, 3)[obj]
        ang = np.array([s.angular_velocity_rps for s in states]).reshape(-1, 3)[obj]
        centre = transforms[obj, :3, 3]
        v_rel = lin + np.cross(ang, points_world - centre) - sensor.velocity_mps
        radial = np.einsum("ij,ij->i", v_rel, d) / dnorm

        params = {k: arr[obj] for k, arr in self._params[band].items()}
        intensity = band_response(cos_inc, **params)

        hit_idx = np.flatnonzero(hit)[ok]
        sel = ok

        def image(values: NDArray[Any], fill: float, dtype: type = np.float32,
                  channels: int = 0) -> NDArray[Any]:
            shape = (h * w, channels) if channels else (h * w,)
            out: NDArray[Any] = np.full(shape, fill, dtype=dtype)
            out[hit_idx] = values[sel]
            return out.reshape((h, w, channels) if channels else (h, w))

        index_img = image(obj, -1, np.int32)
        return RenderBuffers(
            band=band,
            time_s=snapshot.time_s,
            intrinsics=intr,
            sensor=sensor,
            range_m=image(t * dnorm, np.nan),
            points_m=image(t[:, None] * rays_opt, np.nan, channels=3),
            normals=image(n @ rot, 0.0, channels=3),
            cos_incidence=image(cos_inc, 0.0),
            object_index=index_img,
            object_id=np.where(index_img >= 0, self._ids[np.maximum(index_img, 0)], -1
                               ).astype(np.int32) if len(self._ids) else index_img,
            intensity=image(intensity, 0.0),
            velocity_mps=image(v_rel @ rot, 0.0, channels=3),
            radial_velocity_mps=image(radial, 0.0),
        )

    def _refine_spheres(self, obj: NDArray[np.int64], origin: NDArray[np.float64],
                        d: NDArray[np.float64], transforms: NDArray[np.float64],
                        t: NDArray[np.float64], n: NDArray[np.float64]) -> None:
        """Replace facet hits on spheres by the exact ray–sphere intersection (in place)."""
        radius = self._sphere_radius[obj]
        sel = np.flatnonzero(radius > 0)
        if not len(sel):
            return
        centre = transforms[obj[sel], :3, 3]
        ds = d[sel]
        oc = origin - centre
        a = np.einsum("ij,ij->i", ds, ds)
        b = np.einsum("ij,ij->i", ds, oc)
        c = np.einsum("ij,ij->i", oc, oc) - radius[sel] ** 2
        disc = b * b - a * c
        ok = disc >= 0          # rays through the facets but past the true limb keep the facet
        sel, root = sel[ok], (-b[ok] - np.sqrt(disc[ok])) / a[ok]
        t[sel] = root
        n[sel] = (origin + root[:, None] * d[sel] - centre[ok]) / radius[sel][:, None]

    def close(self) -> None:
        """Release the offscreen windows."""
        for p in self._passes.values():
            p.close()
        self._passes.clear()
