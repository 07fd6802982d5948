"""Headless per-band rendering of a scene snapshot.

Each band has one persistent offscreen VTK render window (EGL/OSMesa over Mesa where there
is no display or GPU). The GPU pass only rasterises a *triangle index* image: every
triangle is drawn in a flat, unlit colour that encodes its global index (24 bits), with
multisampling and anti-aliasing off so that indices never blend. Everything radiometric is
then computed from that index, per pixel, in one compiled pass
(:mod:`simcore.render.shading_kernels`, GIL released): the exact ray–triangle-plane
intersection gives the range, barycentric coordinates of the hit interpolate the vertex
normals, the material model gives the band intensity, and the objects' rigid motion gives
the exact velocity of every surface point.
"""

from __future__ import annotations

import dataclasses
import os
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL backend)
from numpy.typing import NDArray
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkUnsignedCharArray
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import (
    vtkActor,
    vtkPolyDataMapper,
    vtkRenderer,
    vtkRenderWindow,
)

from simcore.render.buffers import RenderBuffers
from simcore.render.meshes import TriangleMesh, build_mesh
from simcore.render.shading_kernels import (
    MATERIAL_COLUMNS,
    shade_geometry,
    shade_surface,
)
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.geometry import Sphere
from simcore.scene.materials import BANDS
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
    smooth: NDArray[np.bool_] = field(init=False)
    label_object: NDArray[np.int32] = field(init=False)
    label_smooth: NDArray[np.bool_] = field(init=False)
    #: The last :meth:`world_vertices` result and the transforms it was for.
    _world: tuple[bytes, NDArray[np.float64], NDArray[np.float64]] | None = field(
        default=None, init=False, repr=False, compare=False)
    #: Each object's world points and normals (:meth:`world_vertices`) and its pose.
    _per_object: dict[int, tuple[bytes, NDArray[np.float64], NDArray[np.float64]]] = field(
        default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        pts, tris, owner = 0, [], []
        offsets = []
        for index, mesh in enumerate(self.meshes):
            offsets.append(pts)
            if mesh is not None:
                tris.append(mesh.triangles + pts)
                owner.append(np.full(len(mesh.triangles), index))
                pts += len(mesh.points)
        self.point_offsets = np.array(offsets, dtype=np.int64)
        self.triangles = np.concatenate(tris) if tris else np.zeros((0, 3), np.int64)
        self.triangle_object = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        # A triangle is smooth when its vertex normals differ (curved surface).
        flags = []
        for mesh in self.meshes:
            if mesh is not None:
                vn = mesh.normals[mesh.triangles]                      # (T, 3, 3)
                flags.append(np.any(np.abs(vn - vn[:, :1]) > 1e-6, axis=(1, 2)))
        self.smooth = np.concatenate(flags) if flags else np.zeros(0, bool)
        # Lookup tables by pixel label (0 = background, k + 1 = triangle k).
        self.label_object = np.concatenate([[-1], self.triangle_object]).astype(np.int32)
        self.label_smooth = np.concatenate([[False], self.smooth]).astype(bool)
        if len(self.triangles) > MAX_TRIANGLES:
            raise ValueError(f"scene has {len(self.triangles)} triangles; at most "
                             f"{MAX_TRIANGLES} can be rendered")

    def world_vertices(self, transforms: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                       NDArray[np.float64]]:
        """Vertex positions and normals of every object in the world frame (don't modify).

        The result is kept for the next call with the same transforms: every pass of a
        frame shades with them, and a still scene's never change.
        """
        key = np.ascontiguousarray(transforms, dtype=np.float64).tobytes()
        last = self._world
        if last is not None and last[0] == key:
            return last[1], last[2]
        pts, nrm = [], []
        done = self._per_object
        for index, (mesh, t) in enumerate(zip(self.meshes, transforms, strict=True)):
            if mesh is None:
                continue
            # Each object's own, kept while its pose stays: a still asset is not moved
            # again every time a person in the scene moves.
            t_key = np.ascontiguousarray(t, dtype=np.float64).tobytes()
            mine = done.get(index)
            if mine is None or mine[0] != t_key:
                mine = (t_key, mesh.points @ t[:3, :3].T + t[:3, 3], mesh.normals @ t[:3, :3].T)
                done[index] = mine      # one assignment, as below
            pts.append(mine[1])
            nrm.append(mine[2])
        if not pts:
            return np.zeros((0, 3)), np.zeros((0, 3))
        out = np.concatenate(pts), np.concatenate(nrm)
        self._world = (key, *out)   # one assignment: a concurrent reader sees old or new
        return out


#: At most this many actors per pass (runs of still and moving objects); beyond, one.
_MAX_CHUNKS = 8


@dataclass
class _Chunk:
    """A run of consecutive objects drawn by one actor (:class:`_IndexPass`)."""

    objects: slice
    points: slice
    actor: vtkActor
    vtk_points: Any
    poly: Any
    moving: bool
    key: bytes | None = None


class _IndexPass:
    """One persistent offscreen window that rasterises triangle indices for one band.

    The triangles of every object are drawn in index order by a few actors, each holding
    a run of consecutive objects whose points are moved to the world frame on the CPU
    when one of its poses changes. A VTK actor costs ≈ 0.25 ms per render whatever its
    size (24 objects: 7 ms of a 640 × 640 pass; one actor: ≈ 1.5 ms), but re-uploads all
    its points when one moves: once an object has moved, the objects are split into runs
    of still and moving ones (at most :data:`_MAX_CHUNKS`), so that a large still asset
    is not moved and re-uploaded every frame because a person walks. The actors draw in
    order, so the triangles are drawn in the same order as by one actor: the same labels.
    Hidden objects' points are collapsed onto one point behind the camera: their
    triangles have no area and lie outside the view, so they draw nothing.
    """

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
        self.set_geometry(geometry)
        self._size: tuple[int, int] | None = None
        self._pixels = vtkUnsignedCharArray()

    def set_geometry(self, geometry: _Geometry) -> None:
        """Replace the scene's triangles by those of ``geometry``."""
        self._geometry = geometry
        n_obj = len(geometry.meshes)
        self._moving = np.zeros(n_obj, dtype=bool)
        self._last: bytes | None = None
        meshes = [m for m in geometry.meshes if m is not None]
        self._model = (np.concatenate([m.points for m in meshes]).astype(np.float64)
                       if meshes else np.zeros((0, 3)))
        self._owner = np.concatenate(
            [np.full(len(m.points), i) for i, m in enumerate(geometry.meshes)
             if m is not None] or [np.zeros(0, np.int64)])
        self._world = self._model.copy()
        self._hidden = np.zeros(n_obj, dtype=bool)
        # Point and triangle offsets of each object, and one past the last.
        self._pt0 = np.append(geometry.point_offsets, len(self._model))
        self._tri0 = np.searchsorted(geometry.triangle_object, np.arange(n_obj + 1))
        self._build()

    def _build(self) -> None:
        """One actor per run of consecutive objects that are all still or all moving."""
        self.renderer.RemoveAllViewProps()
        self.chunks: list[_Chunk] = []
        moving = self._moving
        cuts = [0, *(np.flatnonzero(moving[1:] != moving[:-1]) + 1).tolist(), len(moving)]
        if len(cuts) - 1 > _MAX_CHUNKS:
            cuts = [0, len(moving)]
            moving = np.ones_like(moving)
        self._still: tuple[bytes, NDArray[np.uint32], NDArray[np.float32]] | None = None
        self._still_seen: bytes | None = None
        for o0, o1 in zip(cuts[:-1], cuts[1:], strict=True):
            t0, t1 = int(self._tri0[o0]), int(self._tri0[o1])
            if t1 > t0:
                self._add_chunk(slice(o0, o1), slice(int(self._pt0[o0]), int(self._pt0[o1])),
                                t0, t1, moving=bool(moving[o0]))

    def _add_chunk(self, objects: slice, points: slice, t0: int, t1: int, *,
                   moving: bool) -> None:
        world = self._world[points]
        poly = TriangleMesh(world, np.zeros_like(world),
                            self._geometry.triangles[t0:t1] - points.start).to_polydata()
        # Shallow: the polydata reads ``self._world``, which each pose change rewrites.
        vtk_points = poly.GetPoints()
        vtk_points.SetData(numpy_to_vtk(world, deep=0))
        ids = np.arange(t0 + 1, t1 + 1, dtype=np.int64)
        # Label k + 1 of triangle k in (R, G, B) = (low, middle, high byte): the RGBA
        # read-back viewed as little-endian uint32 is the label plus alpha << 24.
        rgb = np.stack([ids & 255, (ids >> 8) & 255, (ids >> 16) & 255], axis=1)
        colours = numpy_to_vtk(rgb.astype(np.uint8), deep=1)
        colours.SetName("triangle_index")
        poly.GetCellData().SetScalars(colours)
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(poly)
        mapper.SetColorModeToDirectScalars()
        mapper.SetScalarModeToUseCellData()
        mapper.ScalarVisibilityOn()
        # No shift and scale of the points by each actor's own bounds (VTK's automatic
        # choice): every run's points rounded alike, so runs draw as one actor would.
        mapper.SetVBOShiftScaleMethod(0)
        actor = vtkActor()
        actor.SetMapper(mapper)
        prop = actor.GetProperty()
        prop.LightingOff()
        prop.SetInterpolationToFlat()
        prop.BackfaceCullingOff()
        self.renderer.AddActor(actor)
        self.chunks.append(_Chunk(objects, points, actor, vtk_points, poly, moving))

    def _pose(self, transforms: NDArray[np.float64], visible: list[bool],
              behind: NDArray[np.float64]) -> None:
        """Move each actor's points to the world frame of ``transforms`` (if that changed)."""
        transforms = np.ascontiguousarray(transforms, dtype=np.float64)
        hidden = ~np.asarray(visible, dtype=bool)
        self._hidden = hidden
        if self._last is not None and self._last != transforms.tobytes():
            last = np.frombuffer(self._last).reshape(transforms.shape)
            moved = np.any(last != transforms, axis=(1, 2)) & ~self._moving
            if moved.any():
                self._moving |= moved
                self._build()
        self._last = transforms.tobytes()
        for chunk in self.chunks:
            part = chunk.objects
            chunk.actor.SetVisibility(not hidden[part].all())
            key = b"".join([transforms[part].tobytes(), hidden[part].tobytes(),
                            behind.tobytes() if hidden[part].any() else b""])
            if key == chunk.key:
                continue
            pts = chunk.points
            t = transforms[self._owner[pts]]                                 # (P, 4, 4)
            world = self._world[pts]
            np.einsum("pij,pj->pi", t[:, :3, :3], self._model[pts], out=world)
            world += t[:, :3, 3]
            world[hidden[self._owner[pts]]] = behind
            chunk.vtk_points.Modified()
            chunk.poly.Modified()
            chunk.key = key

    def render(self, intr: PinholeIntrinsics, sensor: SensorState,
               transforms: NDArray[np.float64], visible: list[bool]) -> NDArray[np.int64]:
        """Global triangle index per pixel, shape (H, W), −1 for background."""
        return self.labels(intr, sensor, transforms, visible).astype(np.int64) - 1

    def labels(self, intr: PinholeIntrinsics, sensor: SensorState,
               transforms: NDArray[np.float64], visible: list[bool]) -> NDArray[np.uint32]:
        """Triangle label per pixel (k + 1 for triangle k, 0 = background), shape (H, W)."""
        if self._size != (intr.width, intr.height):
            self.window.SetSize(intr.width, intr.height)
            self._size = (intr.width, intr.height)
        pos = np.asarray(sensor.position, dtype=np.float64)
        rot = np.asarray(sensor.rotation, dtype=np.float64)
        self._pose(transforms, visible, pos - rot[:, 2])
        cam = self.renderer.GetActiveCamera()
        cam.SetPosition(*pos)
        cam.SetFocalPoint(*(pos + rot[:, 2]))
        cam.SetViewUp(*(-rot[:, 1]))
        cam.SetExplicitProjectionTransformMatrix(_vtk_matrix(projection_matrix(intr)))
        cam.SetUseExplicitProjectionTransformMatrix(True)
        still = [c for c in self.chunks if not c.moving]
        if not still or all(c.moving and not c.actor.GetVisibility() for c in self.chunks
                            if c.moving) or not any(c.moving for c in self.chunks):
            return self._draw(intr)[0]
        key = b"".join([repr(intr).encode(), pos.tobytes(), rot.tobytes(),
                        *(c.key or b"" for c in still)])
        if key != self._still_seen:     # a still view seen twice: re-use its still part
            self._still_seen = key
            return self._draw(intr)[0]
        return self._over_still(intr, key, pos, rot)

    def _over_still(self, intr: PinholeIntrinsics, key: bytes, pos: NDArray[np.float64],
                    rot: NDArray[np.float64]) -> NDArray[np.uint32]:
        """The moving objects drawn alone, over the still ones' labels and depth (cached).

        A fragment passes the depth test when not farther than what is drawn (VTK's
        ``GL_LEQUAL``): of the triangles at the nearest depth the last drawn, the highest
        label, wins. The same rule on the two passes' labels and depths gives the labels
        of one pass with everything.

        Outside the pixel box of the moving objects (:meth:`_moving_box`) their pass holds
        the cleared label 0 at the far depth, which never wins: only that box is read back
        and merged, and when it is empty (nothing that moves is in view) nothing is drawn.
        """
        shown = [c.actor.GetVisibility() for c in self.chunks]
        if self._still is None or self._still[0] != key:
            for c in self.chunks:
                c.actor.SetVisibility(bool(c.actor.GetVisibility()) and not c.moving)
            self._still = (key, *self._draw(intr, depth=True))
            for c, v in zip(self.chunks, shown, strict=True):
                c.actor.SetVisibility(v)
        _, still_labels, still_depth = self._still
        box = self._moving_box(intr, pos, rot)
        if box is not None and (box[0] == box[1] or box[2] == box[3]):
            return still_labels.copy()
        for c in self.chunks:
            c.actor.SetVisibility(bool(c.actor.GetVisibility()) and c.moving)
        labels, depth = self._draw(intr, depth=True, box=box)
        for c, v in zip(self.chunks, shown, strict=True):
            c.actor.SetVisibility(v)
        if box is None:
            take = (depth < still_depth) | ((depth == still_depth) & (labels > still_labels))
            return np.where(take, labels, still_labels)
        r0, r1, c0, c1 = box
        sl, sd = still_labels[r0:r1, c0:c1], still_depth[r0:r1, c0:c1]
        take = (depth < sd) | ((depth == sd) & (labels > sl))
        out = still_labels.copy()
        out[r0:r1, c0:c1] = np.where(take, labels, sl)
        return out

    def _moving_box(self, intr: PinholeIntrinsics, pos: NDArray[np.float64],
                    rot: NDArray[np.float64]) -> tuple[int, int, int, int] | None:
        """Rows ``r0:r1`` and columns ``c0:c1`` that hold every pixel a moving object covers.

        The bounding box of the drawn moving objects' projected vertices (after
        :meth:`_pose`), one pixel wider on each side than any pixel centre they can cover,
        cut to the image; empty (r0 == r1 or c0 == c1) when none is in view. None (the
        whole image) when a vertex is not in front of the near plane: a triangle clipped
        there does not project within its vertices' box.
        """
        rows = [c.points for c in self.chunks if c.moving and c.actor.GetVisibility()]
        if not rows:
            return 0, 0, 0, 0
        idx = np.concatenate([np.arange(r.start, r.stop) for r in rows])
        idx = idx[~self._hidden[self._owner[idx]]]
        if not idx.size:
            return 0, 0, 0, 0
        p = (self._world[idx] - pos) @ rot                       # optical frame
        z = p[:, 2]
        if not np.all(z > NEAR_M):
            return None
        u = intr.fx * p[:, 0] / z + intr.cx
        v = intr.fy * p[:, 1] / z + intr.cy
        c0 = min(max(int(np.floor(u.min())) - 1, 0), intr.width)
        c1 = max(min(int(np.ceil(u.max())) + 1, intr.width), c0)
        r0 = min(max(int(np.floor(v.min())) - 1, 0), intr.height)
        r1 = max(min(int(np.ceil(v.max())) + 1, intr.height), r0)
        return r0, r1, c0, c1

    def _draw(self, intr: PinholeIntrinsics, *, depth: bool = False,
              box: tuple[int, int, int, int] | None = None
              ) -> tuple[NDArray[np.uint32], NDArray[np.float32]]:
        """Render; the labels and (with ``depth``, else empty) the depth buffer, (H, W).

        ``box`` (rows ``r0:r1``, columns ``c0:c1``, non-empty): read back only that part.
        """
        r0, r1, c0, c1 = (0, intr.height, 0, intr.width) if box is None else box
        h, w = r1 - r0, c1 - c0
        # The window's rows count from the bottom: image rows r0:r1 are rows
        # height − r1 … height − 1 − r0 there.
        x0, y0, x1, y1 = c0, intr.height - r1, c1 - 1, intr.height - 1 - r0
        self.window.Render()
        self.window.GetRGBACharPixelData(x0, y0, x1, y1, 0, self._pixels, 0)
        rgba = vtk_to_numpy(self._pixels).reshape(h, w, 4)[::-1]
        # A new array (the read-back buffer is re-used by the next render).
        labels = np.bitwise_and(rgba.view("<u4")[..., 0], np.uint32(0xFFFFFF))
        z = np.zeros((0, 0), dtype=np.float32)
        if depth:
            buf = vtkFloatArray()
            self.window.GetZbufferData(x0, y0, x1, y1, buf)
            z = vtk_to_numpy(buf).reshape(h, w)[::-1].copy()
        return labels, z

    def close(self) -> None:
        self.renderer.RemoveAllViewProps()
        self.window.Finalize()


_RAY_CACHE: dict[PinholeIntrinsics, tuple[NDArray[np.float32], NDArray[np.float32],
                                          NDArray[np.float32]]] = {}


def _ray_grid(intr: PinholeIntrinsics
              ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
    """Cached ray slopes and lengths of a pixel grid, flat (H * W,), float32, read-only.

    ``x/z`` and ``y/z`` of each pixel centre and the length of the ray ``(x/z, y/z, 1)``.
    """
    if intr not in _RAY_CACHE:
        if len(_RAY_CACHE) > 8:
            _RAY_CACHE.clear()
        rays = intr.ray_directions()
        u = rays[..., 0].astype(np.float32).ravel()
        v = rays[..., 1].astype(np.float32).ravel()
        norm = np.linalg.norm(rays, axis=-1).astype(np.float32).ravel()
        for arr in (u, v, norm):
            arr.setflags(write=False)
        _RAY_CACHE[intr] = (u, v, norm)
    return _RAY_CACHE[intr]


@dataclass(frozen=True)
class RenderRequest:
    """One render pass a sensor needs: seen from ``sensor``, in ``band``, on a pixel grid.

    Attributes
    ----------
    sensor : str
        Sensor name (a key of ``SceneSnapshot.sensors``): where the pass is seen from.
    band : str
        Material band (:data:`simcore.scene.materials.BANDS`): which objects are drawn
        (opacity > 0 in that band) and which reflectance parameters shade them.
    intrinsics : PinholeIntrinsics
        Pixel grid of the pass.
    geometry_only : bool
        Shade only what visibility needs: ``range_m``, ``object_index`` and
        ``object_id``. The other fields are read-only zeros (no normals, intensity or
        velocities), which makes shading several times cheaper.
    """

    sensor: str
    band: str
    intrinsics: PinholeIntrinsics
    geometry_only: bool = False


@dataclass(frozen=True)
class Raster:
    """Output of the GPU pass of one band, input of the (thread-safe, CPU) shading.

    Attributes
    ----------
    snapshot : SceneSnapshot
        The snapshot rendered.
    sensor : str
        Name of the sensor whose pose the pass is seen from.
    band : str
        Material band of the pass (:data:`simcore.scene.materials.BANDS`).
    intrinsics : PinholeIntrinsics
        Pixel grid.
    labels : ndarray, shape (H, W), uint32
        ``k + 1`` where triangle ``k`` is visible, 0 for background.
    visible : tuple of bool
        Which objects the pass drew.
    """

    snapshot: SceneSnapshot
    sensor: str
    band: str
    intrinsics: PinholeIntrinsics
    labels: NDArray[np.uint32]
    visible: tuple[bool, ...]
    geometry: _Geometry = field(repr=False)
    tables: _BandTables = field(repr=False)
    geometry_only: bool = False


@dataclass(frozen=True)
class _BandTables:
    """Per-object values of one band, with an extra last row for "no object"."""

    params: dict[str, NDArray[np.float64]]
    ids: NDArray[np.int32]
    sphere_radius: NDArray[np.float64]


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
        materials = material_table(project, copy=False)
        self._ids = np.array([o.id for o in project.objects], dtype=np.int32)
        # Spheres are refined analytically: exact range and normal, not the facet's.
        self._sphere_radius = np.array(
            [o.geometry.radius_m if isinstance(o.geometry, Sphere) else 0.0
             for o in project.objects])
        self._materials = [materials[o.material] for o in project.objects]
        self._tables: dict[str, _BandTables] = {}
        self._opacity: dict[str, NDArray[np.float64]] = {}

    def _band_tables(self, band: str) -> _BandTables:
        """Per-object parameters of ``band``, built on first use after each project edit."""
        if band not in BANDS:
            raise ValueError(f"unknown band {band!r}; known bands: {', '.join(BANDS)}")
        if band not in self._tables:
            bands = [m.band(band) for m in self._materials]
            self._opacity[band] = np.array([p.opacity for p in bands], dtype=np.float64)
            params = {name: np.array([getattr(p, name) for p in bands], dtype=np.float64)
                      for name in ("reflectance", "specular", "roughness", "metallic")}
            params["retro_gain"] = np.array(
                [p.retro_gain if p.retroreflector else 0.0 for p in bands], dtype=np.float64)
            # Lookup tables indexed by object index, −1 ("no object") hitting the extra row.
            self._tables[band] = _BandTables(
                params={k: np.append(arr, 0.0) for k, arr in params.items()},
                ids=np.append(self._ids, -1).astype(np.int32),
                sphere_radius=np.append(self._sphere_radius, 0.0))
        return self._tables[band]

    def visible_in(self, band: str) -> list[bool]:
        """Which objects are drawn in ``band``'s pass (opacity > 0 and a surface)."""
        self._band_tables(band)
        return [bool(op > 0) and mesh is not None
                for op, mesh in zip(self._opacity[band], self.geometry.meshes, strict=True)]

    def render(self, snapshot: SceneSnapshot, request: RenderRequest, *,
               hide: tuple[bool, ...] | None = None) -> RenderBuffers:
        """Render one pass (:meth:`rasterize` then :meth:`shade`), ``hide``: objects left out."""
        return self.shade(self.rasterize(snapshot, request, hide=hide))

    def rasterize(self, snapshot: SceneSnapshot, request: RenderRequest, *,
                  hide: Sequence[bool] | None = None) -> Raster:
        """The GPU pass of :meth:`render` (call it from the thread that owns the renderer).

        Each sensor keeps its own offscreen window. ``hide`` (one flag per object) leaves
        objects out of this pass, e.g. to render the static background of a scene.
        """
        tables = self._band_tables(request.band)
        sensor = snapshot.sensor(request.sensor)
        if request.sensor not in self._passes:
            self._passes[request.sensor] = _IndexPass(self.geometry)
        visible = self.visible_in(request.band)
        if hide is not None:
            visible = [v and not h for v, h in zip(visible, hide, strict=True)]
        labels = self._passes[request.sensor].labels(
            request.intrinsics, sensor, snapshot.object_transforms(), visible)
        self.render_count += 1
        return Raster(snapshot=snapshot, sensor=request.sensor, band=request.band,
                      intrinsics=request.intrinsics, labels=labels, visible=tuple(visible),
                      geometry=self.geometry, tables=tables,
                      geometry_only=request.geometry_only)

    def rasterize_see_through(self, full: Raster, request: RenderRequest,
                              hide: Sequence[bool]) -> Raster:
        """:meth:`rasterize` with ``hide`` left out, given the pass ``full`` with everything.

        Only the bounding box of the pixels where ``full`` shows a hidden object is
        rendered (the same pixel centres, in a cropped window); everywhere else the front
        surface is not a hidden object, so leaving those out changes nothing there and
        ``full``'s labels are kept. When ``full`` shows no hidden object nothing is rendered.
        """
        visible = [v and not h for v, h in zip(self.visible_in(request.band), hide,
                                               strict=True)]
        hidden = np.zeros(len(visible) + 1, dtype=bool)   # last row: label 0, no object
        hidden[:-1] = np.asarray(hide, dtype=bool)
        mask = hidden[self.geometry.label_object][full.labels]   # per label, then pixel
        labels = full.labels
        rows = np.flatnonzero(mask.any(axis=1))
        if rows.size:
            cols = np.flatnonzero(mask.any(axis=0))
            r0, r1, c0, c1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
            intr = request.intrinsics
            crop = PinholeIntrinsics(c1 - c0, r1 - r0, intr.fx, intr.fy, intr.cx - c0,
                                     intr.cy - r0)
            key = f"{request.sensor}:crop"
            if key not in self._passes:
                self._passes[key] = _IndexPass(self.geometry)
            snapshot = full.snapshot
            part = self._passes[key].labels(crop, snapshot.sensor(request.sensor),
                                            snapshot.object_transforms(), visible)
            labels = labels.copy()
            labels[r0:r1, c0:c1] = part
            self.render_count += 1
        return dataclasses.replace(full, labels=labels, visible=tuple(visible))

    def shade(self, raster: Raster, *, background: tuple[Raster, RenderBuffers] | None = None
              ) -> RenderBuffers:
        """Float geometry and radiometry of a :meth:`rasterize` output (CPU only).

        Thread-safe: it reads only the raster (which holds the geometry and material tables
        of its time), so it may run on another thread while the next pass rasterises.

        ``background`` is an earlier raster of the same band and its shading, e.g. the
        still objects alone (``rasterize(..., hide=...)``) seen from the same still
        sensor. When it applies (same sensor pose, geometry and materials; the objects it
        shows still and at the same poses), only pixels whose triangle differs from it
        are shaded and the others copied: the same values as shading them all.
        """
        return _shade(raster, background)

    def close(self) -> None:
        """Release the offscreen windows."""
        for p in self._passes.values():
            p.close()
        self._passes.clear()


def render_once(project: Project, request: RenderRequest, *, time_s: float = 0.0,
                base_dir: Path | None = None) -> RenderBuffers:
    """One pass of ``project`` at ``time_s``, with a renderer opened and closed for it.

    For scripts, reports and tests that need a single render; the engine keeps its
    renderer open across frames instead.
    """
    from simcore.scene.snapshot import take_snapshot

    renderer = SceneRenderer(project, base_dir=base_dir)
    try:
        return renderer.render(take_snapshot(project, time_s), request)
    finally:
        renderer.close()


def _shade(raster: Raster, background: tuple[Raster, RenderBuffers] | None = None
           ) -> RenderBuffers:
    """Exact ray–triangle geometry, velocities and band intensity of every pixel.

    Per-triangle planes are built in float64 and gathered per pixel in float32 (the
    buffers are float32): ``t = δ / (n · ray)`` with the ray ``(x/z, y/z, 1)``, so points
    are ``t · ray`` and ranges ``t |ray|``. Every pixel is computed on its own (no
    reduction across pixels), so shading a subset of pixels gives the same values as
    shading them all: with a ``background`` (see :meth:`SceneRenderer.shade`) only the
    pixels whose triangle differs from it are shaded, the rest are copied.
    """
    snapshot, band, intr = raster.snapshot, raster.band, raster.intrinsics
    sensor = snapshot.sensor(raster.sensor)
    h, w = intr.height, intr.width
    idx = changed_pixels(raster, background)
    if background is not None and idx is not None:
        bg = background[1]
        if idx.size == 0:
            return dataclasses.replace(bg, time_s=snapshot.time_s, sensor=sensor)
        px = _shade_pixels(raster, idx)
        out: dict[str, Any] = {}
        for name, values in px.items():
            old = getattr(bg, name)
            if _is_zeros(values) and _is_zeros(old):
                # A geometry-only field: read-only zeros, as when shading every pixel.
                out[name] = np.broadcast_to(values.reshape(-1)[:1], old.shape)
            else:
                out[name] = old.copy()
                out[name].reshape(-1, *values.shape[1:])[idx] = values
    else:
        px = _shade_pixels(raster, None)
        out = {name: values.reshape(h, w, *values.shape[1:]) for name, values in px.items()}
    return RenderBuffers(band=band, time_s=snapshot.time_s, intrinsics=intr, sensor=sensor,
                         meshes=tuple(raster.geometry.meshes), **out)


def _is_zeros(values: NDArray[np.generic]) -> bool:
    """Whether ``values`` is one zero broadcast to its shape (a geometry-only field)."""
    if not values.size or any(values.strides):
        return False
    first = values.reshape(-1)[0]
    return bool(first == 0 and not np.signbit(first))


#: Per-pixel fields of :class:`RenderBuffers`.
_PIXEL_FIELDS = ("range_m", "points_m", "normals", "cos_incidence", "object_index",
                 "object_id", "intensity", "velocity_mps", "radial_velocity_mps")


def changed_pixels(raster: Raster, background: tuple[Raster, RenderBuffers] | None
                   ) -> NDArray[np.intp] | None:
    """Flat indices of the pixels that differ from ``background``, None for all of them.

    The background must show the same band from the same, still sensor pose, with the
    same geometry and materials, and every object it shows must be at the same pose and
    still in both snapshots; then a pixel with the same triangle label shows the same
    surface point, shaded the same. None when that does not hold or when more than half
    the pixels differ.
    """
    if background is None:
        return None
    ref, _ = background
    if (ref.band != raster.band or ref.sensor != raster.sensor
            or ref.intrinsics != raster.intrinsics
            or ref.geometry is not raster.geometry or ref.tables is not raster.tables
            or ref.labels.shape != raster.labels.shape):
        return None
    if ref.snapshot is raster.snapshot:     # one instant: every pose and velocity the same
        return _differing(raster, ref)
    s_now, s_ref = raster.snapshot.sensor(raster.sensor), ref.snapshot.sensor(ref.sensor)
    if not (np.array_equal(s_now.transform, s_ref.transform)
            and not np.any(s_now.velocity_mps) and not np.any(s_ref.velocity_mps)
            and not np.any(s_now.angular_velocity_rps)
            and not np.any(s_ref.angular_velocity_rps)):
        return None
    # Every shown object at the same pose and still in both (arrays: no per-object cost).
    shown = np.flatnonzero(np.asarray(ref.visible, dtype=bool))
    if shown.size:
        if not np.array_equal(raster.snapshot.object_transforms()[shown],
                              ref.snapshot.object_transforms()[shown]):
            return None
        for snap in (raster.snapshot, ref.snapshot):
            states = [snap.objects[i] for i in shown]
            if (np.any([s.velocity_mps for s in states])
                    or np.any([s.angular_velocity_rps for s in states])):
                return None
    return _differing(raster, ref)


#: The last few :func:`_differing` results with the rasters they compared: the engine asks
#: for a frame's changed pixels and then shades over the same background, which asks again.
_DIFFERING: dict[tuple[int, int], tuple[Raster, Raster, NDArray[np.intp] | None]] = {}
_DIFFERING_LOCK = threading.Lock()


def _differing(raster: Raster, ref: Raster) -> NDArray[np.intp] | None:
    """Pixels whose label differs (read-only), None when they are more than half."""
    key = (id(raster), id(ref))
    with _DIFFERING_LOCK:
        hit = _DIFFERING.get(key)
    if hit is not None and hit[0] is raster and hit[1] is ref:
        return hit[2]
    changed = np.flatnonzero(raster.labels.ravel() != ref.labels.ravel())
    changed.setflags(write=False)
    out = changed if changed.size <= raster.labels.size // 2 else None
    with _DIFFERING_LOCK:
        while len(_DIFFERING) >= 8:     # the oldest first (insertion order)
            del _DIFFERING[next(iter(_DIFFERING))]
        _DIFFERING[key] = (raster, ref, out)
    return out


def _shade_pixels(raster: Raster, idx: NDArray[np.intp] | None
                  ) -> dict[str, NDArray[np.generic]]:
    """Per-pixel fields (flat, first axis = pixel) of all pixels or of ``idx``.

    The per-triangle planes and per-object tables are built here in float64 numpy; the
    per-pixel work is one compiled pass (:mod:`simcore.render.shading_kernels`).
    """
    snapshot, intr, geo = raster.snapshot, raster.intrinsics, raster.geometry
    tables = raster.tables
    sensor = snapshot.sensor(raster.sensor)
    transforms = snapshot.object_transforms()
    rot, origin = sensor.rotation, sensor.position
    u, v, ray_norm = _ray_grid(intr)                              # flat, (H * W,)
    labels = np.ascontiguousarray(raster.labels, dtype=np.uint32).ravel()  # 0 = background
    subset = idx is not None
    pixels = (np.ascontiguousarray(idx, dtype=np.int64) if idx is not None
              else np.zeros(0, dtype=np.int64))
    vertices, vnormals = geo.world_vertices(transforms)
    # The kernels read the plane of each shaded pixel's own label only: over a background,
    # the planes of the changed pixels' triangles (not of every triangle the pass shows).
    plane_n, plane_d = _planes(geo, vertices, rot, origin,
                               labels[pixels] if subset else labels)
    if raster.geometry_only:
        rng, obj, obj_id = shade_geometry(labels, pixels, subset, u, v, ray_norm, plane_n,
                                          plane_d, geo.label_object, tables.ids)
        n = obj.size
        zero = np.zeros(1, dtype=np.float32)
        return {
            "range_m": rng,
            "points_m": np.broadcast_to(zero, (n, 3)),
            "normals": np.broadcast_to(zero, (n, 3)),
            "cos_incidence": np.broadcast_to(zero, (n,)),
            "object_index": obj,
            "object_id": obj_id,
            "intensity": np.broadcast_to(zero, (n,)),
            "velocity_mps": np.broadcast_to(zero, (n, 3)),
            "radial_velocity_mps": np.broadcast_to(zero, (n,)),
        }
    lin, ang = _relative_motion(snapshot, sensor, transforms)
    n_obj = len(snapshot.objects)
    # Spheres are refined analytically around their centres (optical frame).
    centres = np.zeros((n_obj + 1, 3))
    if n_obj:
        centres[:n_obj] = (transforms[:, :3, 3] - origin) @ rot
    material = np.stack([tables.params[k] for k in MATERIAL_COLUMNS], axis=1)
    camera = np.array([intr.cx, intr.cy, intr.fx, intr.fy], dtype=np.float64)
    fields = shade_surface(
        labels, pixels, subset, intr.width, camera, u, v, ray_norm, plane_n, plane_d,
        geo.label_object, geo.label_smooth, np.ascontiguousarray(geo.triangles, np.int64),
        np.ascontiguousarray(vertices), np.ascontiguousarray(vnormals),
        np.ascontiguousarray(rot, dtype=np.float64),
        np.ascontiguousarray(origin, dtype=np.float64),
        np.ascontiguousarray(tables.sphere_radius, dtype=np.float64), centres, lin, ang,
        np.ascontiguousarray(material), tables.ids)
    return dict(zip(_PIXEL_FIELDS, fields, strict=True))


def _planes(geo: _Geometry, vertices: NDArray[np.float64], rot: NDArray[np.float64],
            origin: NDArray[np.float64], labels: NDArray[np.uint32] | None = None
            ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Per-label triangle planes in the optical frame, ``n · X = delta``, n facing the sensor.

    With ``labels`` (the raster's pixel labels) only the triangles that appear in it get
    their plane, the only rows the shading reads: a large imported asset has far more
    triangles than a frame shows.

    Returns
    -------
    plane_n : ndarray, shape (triangles + 1, 3), float32
        Row 0 is the background (normal 0), row k + 1 triangle k (0 where not shown).
    plane_d : ndarray, shape (triangles + 1,), float32
        NaN for row 0 (and for triangles not shown).
    """
    n_tri = len(geo.triangles)
    rows = np.arange(n_tri)
    if labels is not None:
        seen = np.zeros(n_tri + 1, dtype=bool)
        seen[labels.ravel()] = True
        rows = np.flatnonzero(seen[1:])
    corners = geo.triangles[rows]
    a = vertices[corners[:, 0]]
    face = np.cross(vertices[corners[:, 1]] - a, vertices[corners[:, 2]] - a)
    face /= np.maximum(np.linalg.norm(face, axis=1, keepdims=True), 1e-300)
    n_opt = face @ rot                                           # world → optical
    delta = np.einsum("ij,ij->i", face, a - origin)
    flip = np.where(delta > 0, -1.0, 1.0)
    plane_n = np.zeros((n_tri + 1, 3), dtype=np.float32)
    plane_n[rows + 1] = n_opt * flip[:, None]
    plane_d = np.full(n_tri + 1, np.nan, dtype=np.float32)
    plane_d[rows + 1] = delta * flip
    return plane_n, plane_d


def _relative_motion(snapshot: SceneSnapshot, sensor: SensorState,
                     transforms: NDArray[np.float64]
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rigid motion of every object relative to the sensor origin, optical frame.

    ``v(X) = v_obj + w x (X - c) - v_sensor = (v_obj - v_sensor - w x c) + w x X``.

    Returns
    -------
    lin, ang : ndarray, shape (objects + 1, 3), float64
        ``lin[k] + ang[k] x X`` is the velocity (m/s) of a point ``X`` of object ``k``
        (optical frame); the last rows ("no object") are zero.
    """
    rot, origin = sensor.rotation, sensor.position
    n_obj = len(snapshot.objects)
    lin = np.zeros((n_obj + 1, 3))
    ang = np.zeros((n_obj + 1, 3))
    if n_obj:
        v_w = np.array([s.velocity_mps for s in snapshot.objects])
        w_w = np.array([s.angular_velocity_rps for s in snapshot.objects])
        c_w = transforms[:, :3, 3] - origin
        lin[:n_obj] = (v_w - sensor.velocity_mps - np.cross(w_w, c_w)) @ rot
        ang[:n_obj] = w_w @ rot
    return lin, ang
