"""Radar scatterers of a frame: surface facets plus analytic point targets.

Surfaces are the objects' physical-optics facets fixed to their surfaces
(:mod:`simcore.sensors.radar.surfaces`): each seen facet is one scatterer at its centroid
whose complex amplitude (√RCS and phase) holds its coherent PO reflection and its diffuse,
rough-surface part with a surface-attached random phase. The radar render decides only
which facets are seen, so the scatterers do not depend on the render grid.

Trihedral corner reflectors (``CornerReflector`` geometry) are not faceted: their pixels
are dropped and replaced by one point scatterer at the apex whose RCS follows the
geometric-optics effective area of a triangular trihedral (peak 4πa⁴/(3λ²) on its
symmetry axis), if the apex is not hidden behind a nearer rendered surface.
``PointTarget`` objects (no surface) contribute their RCS when nothing rendered lies in
front of them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.render.buffers import RenderBuffers
from simcore.render.meshes import TriangleMesh, build_mesh
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.geometry import CornerReflector, PointTarget, corner_reflector_axes
from simcore.scene.materials import oblique_slab_transmission
from simcore.scene.model import SceneObject
from simcore.scene.snapshot import SensorState
from simcore.sensors.radar.kinematics import motion_maps_batch
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.surfaces import facet_returns, transmission_coefficients

#: A point scatterer is hidden when a rendered surface is nearer than this along its ray (m).
OCCLUSION_TOLERANCE_M = 0.01

KIND_FACET = 0
KIND_CORNER_REFLECTOR = 1
KIND_POINT_TARGET = 2


@dataclass(frozen=True)
class Scatterers:
    """Point scatterers of one frame, in the radar's optical frame at ``time_s``.

    Independent of the antenna layout, the receiver and the chirp timing: changing those
    re-uses the scatterers (and the render they come from).

    Attributes
    ----------
    time_s : float
        Snapshot time (s); the first chirp of the frame starts here.
    wavelength_m : float
        Wavelength used for the analytic RCS of corner reflectors (m).
    positions_m : ndarray, shape (M, 3), float64
        Scatterer positions, radar optical frame (x right, y down, z boresight), m.
    velocities_mps : ndarray, shape (M, 3), float64
        Velocities relative to the radar at ``time_s``, optical frame (m/s).
    rcs_m2 : ndarray, shape (M,), float64
        Radar cross-section of each scatterer (m²).
    phase_rad : ndarray, shape (M,), float64
        Extra scattering phase (speckle; 0 for analytic targets), rad.
    object_index : ndarray, shape (M,), int32
        Index of the source object in the scene's objects.
    kind : ndarray, shape (M,), int8
        ``KIND_FACET``, ``KIND_CORNER_REFLECTOR`` or ``KIND_POINT_TARGET``.
    facet_key : ndarray, shape (M,), int64, or None
        Render cell of each facet scatterer: ``(row * width + col) * n_objects +
        object_index`` of its centroid's cell on the facet grid (several facets may share
        a key); −1 for analytic targets. ``None`` when the scatterers do not come from a
        render. Two renders of the same static surface from the same pose give equal keys
        and equal values, which lets the IF of a still background be re-used
        (:mod:`simcore.sensors.radar.background`).
    accelerations_mps2 : ndarray, shape (M, 3), float64, or None
        Accelerations relative to the radar at ``time_s``, optical frame (m/s²); None means
        zeros. With the velocities they define the motion model of the synthesis over a
        frame, ``x(t) = x + v t + a t² / 2`` (t from ``time_s``); a rotating rig gives
        static points a relative (centripetal and Coriolis) acceleration
        (:mod:`simcore.sensors.radar.kinematics`).
    """

    time_s: float
    wavelength_m: float
    positions_m: NDArray[np.float64]
    velocities_mps: NDArray[np.float64]
    rcs_m2: NDArray[np.float64]
    phase_rad: NDArray[np.float64]
    object_index: NDArray[np.int32]
    kind: NDArray[np.int8]
    facet_key: NDArray[np.int64] | None = None
    accelerations_mps2: NDArray[np.float64] | None = None

    def __len__(self) -> int:
        return int(self.rcs_m2.shape[0])

    def subset(self, index: NDArray[np.integer] | NDArray[np.bool_] | slice) -> Scatterers:
        """The scatterers selected by ``index`` (integer or boolean array, or slice)."""
        return Scatterers(
            time_s=self.time_s, wavelength_m=self.wavelength_m,
            positions_m=self.positions_m[index], velocities_mps=self.velocities_mps[index],
            rcs_m2=self.rcs_m2[index], phase_rad=self.phase_rad[index],
            object_index=self.object_index[index], kind=self.kind[index],
            facet_key=None if self.facet_key is None else self.facet_key[index],
            accelerations_mps2=(None if self.accelerations_mps2 is None
                                else self.accelerations_mps2[index]),
        )

    def negated(self) -> Scatterers:
        """The same scatterers with opposite complex amplitude: phase + π, in [−π, π].

        Synthesising them subtracts what the scatterers add, so a removal and an addition
        can share one synthesis (:mod:`simcore.sensors.radar.background`).
        """
        phase = self.phase_rad
        return dataclasses.replace(self, phase_rad=np.where(phase > 0.0, phase - np.pi,
                                                            phase + np.pi))

    @staticmethod
    def concatenate(parts: Sequence[Scatterers]) -> Scatterers:
        """The scatterers of ``parts`` (at least one, of one frame) in order, as one set.

        Facet keys are kept when every part has them; accelerations are zeros where a part
        has none, and None when no part has any.
        """
        if not parts:
            raise ValueError("concatenate needs at least one Scatterers")
        first = parts[0]
        if len(parts) == 1:
            return first

        def cat(name: str) -> NDArray[Any]:
            return np.concatenate([getattr(p, name) for p in parts])

        keys = [p.facet_key for p in parts]
        with_acc = any(p.accelerations_mps2 is not None for p in parts)
        return Scatterers(
            time_s=first.time_s, wavelength_m=first.wavelength_m,
            positions_m=cat("positions_m"), velocities_mps=cat("velocities_mps"),
            rcs_m2=cat("rcs_m2"), phase_rad=cat("phase_rad"),
            object_index=cat("object_index"), kind=cat("kind"),
            facet_key=(None if any(k is None for k in keys)
                       else np.concatenate([k for k in keys if k is not None])),
            accelerations_mps2=(np.concatenate([p.accelerations for p in parts])
                                if with_acc else None),
        )

    @property
    def accelerations(self) -> NDArray[np.float64]:
        """``accelerations_mps2``, zeros when it is None; shape (M, 3), m/s²."""
        if self.accelerations_mps2 is None:
            return np.zeros((len(self), 3))
        return self.accelerations_mps2

    def moving(self) -> NDArray[np.bool_]:
        """Scatterers with a non-zero velocity or acceleration relative to the radar, (M,)."""
        vel = self.velocities_mps
        out = (vel[:, 0] != 0.0) | (vel[:, 1] != 0.0) | (vel[:, 2] != 0.0)
        if self.accelerations_mps2 is not None:
            out |= np.any(self.accelerations_mps2 != 0.0, axis=1)
        return out

    def positions_at(self, times_s: NDArray[np.floating]) -> NDArray[np.float64]:
        """Positions of the motion model at times after ``time_s``, shape (M, T, 3), m.

        ``x + v t + a t² / 2`` for every scatterer and every time in ``times_s`` (shape (T,),
        seconds from the frame start); the default trajectory of the synthesis.
        """
        t = np.asarray(times_s, dtype=np.float64).reshape(1, -1, 1)
        pos = self.positions_m[:, None, :] + self.velocities_mps[:, None, :] * t
        if self.accelerations_mps2 is not None:
            pos = pos + 0.5 * self.accelerations_mps2[:, None, :] * t**2
        return pos

    @classmethod
    def from_arrays(cls, positions_m: NDArray[np.floating], rcs_m2: NDArray[np.floating], *,
                    velocities_mps: NDArray[np.floating] | None = None,
                    phase_rad: NDArray[np.floating] | None = None, time_s: float = 0.0,
                    wavelength_m: float = 0.0,
                    accelerations_mps2: NDArray[np.floating] | None = None) -> Scatterers:
        """Build scatterers directly (tests, custom scenes); missing arrays are zeros.

        Parameters
        ----------
        positions_m : ndarray, shape (M, 3)
            Positions in the radar optical frame (m).
        rcs_m2 : ndarray, shape (M,)
            RCS (m²).
        velocities_mps : ndarray, shape (M, 3), optional
            Relative velocities, optical frame (m/s).
        phase_rad : ndarray, shape (M,), optional
            Extra scattering phase (rad).
        time_s, wavelength_m : float
            Frame start time (s); wavelength of the analytic RCS (0 = not applicable).
        accelerations_mps2 : ndarray, shape (M, 3), optional
            Relative accelerations, optical frame (m/s²); default none (zeros).
        """
        pos = np.asarray(positions_m, dtype=np.float64).reshape(-1, 3)
        m = len(pos)
        return cls(
            time_s=float(time_s), wavelength_m=float(wavelength_m), positions_m=pos,
            velocities_mps=(np.zeros((m, 3)) if velocities_mps is None
                            else np.asarray(velocities_mps, dtype=np.float64).reshape(m, 3)),
            rcs_m2=np.asarray(rcs_m2, dtype=np.float64).reshape(m),
            phase_rad=(np.zeros(m) if phase_rad is None
                       else np.asarray(phase_rad, dtype=np.float64).reshape(m)),
            object_index=np.full(m, -1, dtype=np.int32),
            kind=np.full(m, KIND_POINT_TARGET, dtype=np.int8),
            accelerations_mps2=(None if accelerations_mps2 is None else np.asarray(
                accelerations_mps2, dtype=np.float64).reshape(m, 3)),
        )


def trihedral_effective_area(directions: NDArray[np.floating], edge_m: float
                             ) -> NDArray[np.float64]:
    """Geometric-optics effective area of a triangular trihedral corner reflector.

    With ``l ≤ m ≤ n`` the direction cosines of the incidence direction on the three edges
    (all positive inside the reflector's octant), the area is ``a² · 4lm/(l+m+n)`` if
    ``l + m ≤ n`` and ``a² · (l+m+n − 2/(l+m+n))`` otherwise (Knott, *Radar Cross
    Section*); on the symmetry axis it is ``a²/√3``, giving the peak RCS 4πa⁴/(3λ²).

    Parameters
    ----------
    directions : ndarray, shape (..., 3)
        Unit vectors from the apex towards the radar, in the reflector's edge frame
        (components = cosines with the three edges).
    edge_m : float
        Inner edge length a (m).

    Returns
    -------
    ndarray, shape (...)
        Effective area (m²); 0 outside the octant.
    """
    d = np.sort(np.asarray(directions, dtype=np.float64), axis=-1)
    lo, mid, hi = d[..., 0], d[..., 1], d[..., 2]
    s = lo + mid + hi
    with np.errstate(divide="ignore", invalid="ignore"):
        inner = s - 2.0 / s
        outer = 4.0 * lo * mid / s
    area = np.where(lo + mid <= hi, outer, inner)
    return np.where(lo > 0, np.maximum(area, 0.0), 0.0) * edge_m**2


def _object_meshes(objects: Sequence[SceneObject], buffers: RenderBuffers
                   ) -> tuple[TriangleMesh | None, ...]:
    """Each object's mesh in its frame: the render's, else built here (no mesh files)."""
    if len(buffers.meshes) == len(objects):
        return buffers.meshes
    out: list[TriangleMesh | None] = []
    for o in objects:
        try:
            out.append(build_mesh(o.geometry))
        except (OSError, ValueError):
            out.append(None)
    return tuple(out)


def _facet_scatterers(scene: RadarScene, buffers: RenderBuffers,
                      facets: PinholeIntrinsics | None, exclude: NDArray[np.bool_], *,
                      wavelength_m: float, speckle: bool, seed: int, extra: int = 0,
                      pixels: NDArray[np.bool_] | None = None,
                      see_through: RenderBuffers | None = None
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                                 NDArray[np.float64], NDArray[np.int32], NDArray[np.int64]]:
    """Positions, velocities, RCS, phases, object indices and keys of the surface facets.

    The facets are the objects' surface facets seen in the render
    (:func:`~simcore.sensors.radar.surfaces.facet_returns`); the key of each is its
    facet-grid cell (of its centroid) times the number of objects plus its object. Every
    array has ``extra`` more rows at the end, left for the caller to fill.
    """
    found = facet_returns(scene, buffers, _object_meshes(scene.objects, buffers),
                          wavelength_m=wavelength_m, speckle=speckle,
                          seed=seed, exclude=exclude, pixels=pixels,
                          see_through=see_through)
    n = len(found.object_index)
    pos = np.empty((n + extra, 3))
    pos[:n] = found.positions_m
    vel = np.zeros((n + extra, 3))
    radar = scene.radar
    # Translation of each object relative to the radar (rotation: _rotation_kinematics).
    rel = np.array([(s.velocity_mps - radar.velocity_mps) @ radar.rotation
                    for s in scene.snapshot.objects]).reshape(-1, 3)
    if n and np.any(rel):
        vel[:n] = rel[found.object_index]
    rcs = np.zeros(n + extra)
    rcs[:n] = np.abs(found.amplitude) ** 2
    phase = np.zeros(n + extra)
    phase[:n] = np.angle(found.amplitude)
    obj = np.zeros(n + extra, dtype=np.int32)
    obj[:n] = found.object_index
    key = np.full(n + extra, -1, dtype=np.int64)
    render = buffers.intrinsics
    grid = render if facets is None else facets
    rows, cols = np.divmod(found.pixel, render.width)
    f_rows = np.minimum(rows * grid.height // render.height, grid.height - 1)
    f_cols = np.minimum(cols * grid.width // render.width, grid.width - 1)
    key[:n] = (f_rows * grid.width + f_cols) * max(len(scene.objects), 1) + found.object_index
    return pos, vel, rcs, phase, obj, key


def _radar_frame(radar: SensorState, world_points: NDArray[np.float64]
                 ) -> NDArray[np.float64]:
    t = radar.transform
    return (world_points - t[:3, 3]) @ t[:3, :3]


def _relative_velocity(scene: RadarScene, index: int, world_point: NDArray[np.float64]
                       ) -> NDArray[np.float64]:
    state = scene.snapshot.objects[index]
    v_world = state.point_velocity(world_point) - scene.radar.velocity_mps
    return v_world @ scene.radar.rotation


def _unoccluded(buffers: RenderBuffers, point_radar: NDArray[np.float64], object_index: int
                ) -> bool:
    """True unless a rendered surface of another object lies in front of ``point_radar``."""
    return _in_front(buffers, point_radar, object_index) < 0


def _in_front(buffers: RenderBuffers, point_radar: NDArray[np.float64], object_index: int
              ) -> int:
    """The other object a render shows in front of ``point_radar``, or −1."""
    if point_radar[2] <= 0:
        return -1  # behind the board: the antenna pattern decides
    intr = buffers.intrinsics
    u, v = intr.project(point_radar)
    col, row = int(np.floor(u)), int(np.floor(v))
    if not (0 <= col < intr.width and 0 <= row < intr.height):
        return -1  # outside the render: nothing known in front of it
    hit = int(buffers.object_index[row, col])
    rng = float(buffers.range_m[row, col])
    if hit < 0 or hit == object_index or not np.isfinite(rng):
        return -1
    return -1 if rng >= float(np.linalg.norm(point_radar)) - OCCLUSION_TOLERANCE_M else hit


def _path_factor(buffers: RenderBuffers, see_through: RenderBuffers | None,
                 trans: NDArray[np.complex128], point_radar: NDArray[np.float64],
                 object_index: int, *, scene: RadarScene | None = None,
                 wavelength_m: float = 0.005, polarization: str = "V",
                 retro: bool = False) -> complex:
    """Two-way amplitude factor of the path to an analytic target: 1, T², or 0 (hidden).

    With ``scene``, a partly transparent object in front is crossed face by face
    (:func:`_crossing_factor`: each sheet's TE/TM transmission at the ray's angle, the
    radar's polarisation followed); without, its normal-incidence T².
    """
    if see_through is None:
        return 1.0 if _unoccluded(buffers, point_radar, object_index) else 0.0
    if not _unoccluded(see_through, point_radar, object_index):
        return 0.0
    front = _in_front(buffers, point_radar, object_index)
    if front < 0:
        return 1.0
    if scene is not None:
        found = _crossing_factor(scene, front, point_radar, wavelength_m=wavelength_m,
                                 polarization=polarization, retro=retro)
        if found is not None:
            return found
    return complex(trans[front]) ** 2


def _crossings(scene: RadarScene, index: int, point_radar: NDArray[np.float64]
               ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where the line radar → ``point_radar`` crosses object ``index``'s triangles.

    Returns the distances from the radar (m, sorted, one per crossing: a hit on an edge
    two triangles share counts once) and the faces' unit normals there, radar frame.
    """
    mesh = build_mesh(scene.objects[index].geometry)
    if mesh is None or len(mesh.triangles) == 0:
        return np.zeros(0), np.zeros((0, 3))
    t = scene.snapshot.objects[index].transform
    pts = _radar_frame(scene.radar, mesh.points @ t[:3, :3].T + t[:3, 3])
    tri = pts[mesh.triangles]
    length = float(np.linalg.norm(point_radar))
    d = point_radar / length
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-15
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s0 = -tri[:, 0]
    u = np.einsum("ij,ij->i", s0, p) * inv
    q = np.cross(s0, e1)
    v = (q @ d) * inv
    dist = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (dist > 0) & (dist < length)
    normal = np.cross(e1[hit], e2[hit])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    dist = dist[hit]
    order = np.argsort(dist)
    dist, normal = dist[order], normal[order]
    keep = np.ones(dist.size, dtype=bool)
    keep[1:] = np.diff(dist) > 1e-6
    return dist[keep], normal[keep]


def _crossing_factor(scene: RadarScene, index: int, point_radar: NDArray[np.float64], *,
                     wavelength_m: float, polarization: str, retro: bool) -> complex | None:
    """Two-way transmission through a partly transparent object's faces, or None.

    Each face the line radar → target crosses is a sheet of the material's slab (a hollow
    box: the office's paper box is crossed twice each way), unless the object is no
    thicker than twice the slab (a pane modelled as a box of its own thickness: one slab).
    At each sheet the wave's E vector (the radar's polarisation, made transverse to the
    ray) is split into its TE part (along ``n × d``) and the rest (TM) and scaled by the
    slab's T_TE and T_TM at the crossing angle (:func:`~simcore.scene.materials.
    oblique_slab_transmission`); the ray goes on straight. The way back crosses the same
    sheets: a retro-reflector (a trihedral returns the field itself) gives ``E · E``, a
    co-polar target (point target) ``(E · p̂)²``. None where no face is crossed.
    """
    material = scene.materials.get(scene.objects[index].material)
    if material is None:
        return None
    band = material.band("radar")
    if band.permittivity is None or band.thickness_m is None:
        return None
    dist, normals = _crossings(scene, index, point_radar)
    if dist.size == 0:
        return None
    mesh = build_mesh(scene.objects[index].geometry)
    assert mesh is not None
    if float(np.min(np.ptp(mesh.points, axis=0))) <= 2.0 * band.thickness_m:
        normals = normals[:1]
    d = point_radar / float(np.linalg.norm(point_radar))
    pol = np.array([0.0, 1.0, 0.0]) if polarization == "V" else np.array([1.0, 0.0, 0.0])
    copol = pol - (pol @ d) * d
    copol /= np.linalg.norm(copol)
    cos = np.abs(normals @ d)
    t_te, t_tm = oblique_slab_transmission(band.permittivity, band.loss_tangent,
                                           band.thickness_m, 299_792_458.0 / wavelength_m,
                                           cos)
    field = copol.astype(np.complex128)
    for n, te_t, tm_t in zip(normals, t_te, t_tm, strict=True):
        te = np.cross(n, d)
        size = float(np.linalg.norm(te))
        if size < 1e-9:                                  # normal incidence: no TE/TM split
            field = field * te_t
            continue
        te /= size
        part = (field @ te) * te
        field = te_t * part + tm_t * (field - part)
    return complex(field @ field) if retro else complex(field @ copol) ** 2


def _analytic_targets(scene: RadarScene, buffers: RenderBuffers,
                      see_through: RenderBuffers | None, *, wavelength_m: float,
                      polarization: str) -> tuple[list[Any], ...]:
    """The corner reflectors and point targets the radar sees (:func:`scatterers_from_render`).

    Returns
    -------
    tuple of lists
        Positions (radar frame), velocities, RCS (m², the path's two-way factor in),
        phases (rad), object indices and kinds, one entry per target seen.
    """
    objects, snapshot = scene.objects, scene.snapshot
    table = scene.materials
    trans = transmission_coefficients(objects, table, wavelength_m)
    extra_pos, extra_vel, extra_rcs, extra_obj, extra_kind = [], [], [], [], []
    extra_phase: list[float] = []
    edge_axes = corner_reflector_axes()
    for i, o in enumerate(objects):
        geom = o.geometry
        if not isinstance(geom, (CornerReflector, PointTarget)):
            continue
        state = snapshot.objects[i]
        apex_world = state.origin
        apex = _radar_frame(scene.radar, apex_world[None, :])[0]
        if isinstance(geom, CornerReflector):
            material = table.get(o.material)
            if material is not None and material.band("radar").opacity <= 0:
                continue  # not drawn in the radar pass: the radar sees through it
            path = _path_factor(buffers, see_through, trans, apex, i, scene=scene,
                                wavelength_m=wavelength_m, polarization=polarization,
                                retro=True)
            if path == 0:
                continue
            to_radar_world = scene.radar.position - apex_world
            to_radar_world /= max(float(np.linalg.norm(to_radar_world)), 1e-300)
            local_dir = state.transform[:3, :3].T @ to_radar_world
            area = trihedral_effective_area(edge_axes @ local_dir, geom.edge_m)
            sigma = 4.0 * np.pi * float(area) ** 2 / wavelength_m**2
            kind = KIND_CORNER_REFLECTOR
        else:
            path = _path_factor(buffers, see_through, trans, apex, i, scene=scene,
                                wavelength_m=wavelength_m, polarization=polarization)
            if path == 0:
                continue
            sigma = geom.rcs_m2
            kind = KIND_POINT_TARGET
        if sigma <= 0:
            continue
        extra_pos.append(apex)
        extra_vel.append(_relative_velocity(scene, i, apex_world))
        extra_rcs.append(sigma * abs(path) ** 2)
        extra_phase.append(float(np.angle(path)))
        extra_obj.append(i)
        extra_kind.append(kind)
    return extra_pos, extra_vel, extra_rcs, extra_phase, extra_obj, extra_kind


def scatterers_from_render(scene: RadarScene, buffers: RenderBuffers,
                           *, wavelength_m: float, facets: PinholeIntrinsics | None = None,
                           speckle: bool = True, seed: int = 0,
                           pixels: NDArray[np.bool_] | None = None,
                           see_through: RenderBuffers | None = None,
                           polarization: str = "V") -> Scatterers:
    """All radar scatterers of a frame from its snapshot and radar render.

    Parameters
    ----------
    scene : RadarScene
        The objects (geometry, materials), the frame's snapshot (poses and velocities)
        and the radar's state.
    buffers : RenderBuffers
        The radar-band render of ``scene.snapshot`` (``band == "radar"``).
    wavelength_m : float
        Radar wavelength for the corner reflectors' RCS (m).
    facets : PinholeIntrinsics, optional
        Facet grid. When the render grid is this grid scaled by an integer ``s``, the
        ``s × s`` sub-pixels of each facet are merged per object (RCS summed, position and
        velocity RCS-weighted). Otherwise every render pixel is a facet.
    speckle : bool
        Give facet scatterers their random phase (else 0).
    seed : int
        Speckle realisation.
    pixels : ndarray of bool, shape (H, W), optional
        Use only these render pixels for the facets (whole facets when the render is
        supersampled); the facets they cover come out as from the whole render. Analytic
        targets are always included.
    see_through : RenderBuffers, optional
        The render with the partially transparent objects hidden (see
        :func:`~simcore.sensors.radar.surfaces.facet_returns`): what lies behind them is
        seen through them, attenuated by their two-way transmission.
    polarization : str
        The radar's linear polarisation (``"V"`` or ``"H"``): corner reflectors and point
        targets behind a partly transparent object are seen through its faces at the
        ray's angle in that polarisation (:func:`_crossing_factor`).

    Returns
    -------
    Scatterers
        Facet scatterers first (row-major facet order), then corner reflectors and point
        targets in project order.
    """
    if buffers.band != "radar":
        raise ValueError(f"radar scatterers need the radar render, got band {buffers.band!r}")
    objects, snapshot = scene.objects, scene.snapshot
    analytic = np.array([isinstance(o.geometry, (CornerReflector, PointTarget))
                         for o in objects], dtype=bool)

    # ---------------------------------------------------------------- analytic targets
    extra_pos, extra_vel, extra_rcs, extra_phase, extra_obj, extra_kind = _analytic_targets(
        scene, buffers, see_through, wavelength_m=wavelength_m, polarization=polarization)

    # ---------------------------------------------------------------- facets, then those
    n_extra = len(extra_rcs)
    pos, vel, rcs, phase, obj, key = _facet_scatterers(
        scene, buffers, facets, analytic, wavelength_m=wavelength_m,
        speckle=speckle, seed=seed, extra=n_extra, pixels=pixels,
        see_through=see_through)
    n = len(pos) - n_extra
    kinds = np.full(n + n_extra, KIND_FACET, dtype=np.int8)
    if n_extra:
        pos[n:] = extra_pos
        vel[n:] = extra_vel
        rcs[n:] = extra_rcs
        phase[n:] = extra_phase
        obj[n:] = extra_obj
        kinds[n:] = extra_kind
    acc = _rotation_kinematics(scene, pos, vel, obj)
    return Scatterers(
        time_s=float(snapshot.time_s),
        wavelength_m=float(wavelength_m),
        positions_m=pos,
        velocities_mps=vel,
        rcs_m2=rcs,
        phase_rad=phase,
        object_index=obj,
        kind=kinds,
        facet_key=key,
        accelerations_mps2=acc,
    )


@kernel
def _rigid_rows(pos: NDArray[np.float64], group: NDArray[np.int32],
                m_v: NDArray[np.float64], c_v: NDArray[np.float64],
                m_a: NDArray[np.float64], c_a: NDArray[np.float64],
                vel: NDArray[np.float64], acc: NDArray[np.float64]) -> None:
    """Each row's ``vel = M_v x + c_v`` and ``acc = M_a x + c_a``, with its group's maps.

    Maps have shape (groups, 3, 3) and (groups, 3); rows of group −1 keep ``vel`` and get
    ``acc`` 0.
    """
    for i in range(pos.shape[0]):
        g = group[i]
        if g < 0:
            acc[i, 0] = acc[i, 1] = acc[i, 2] = 0.0
            continue
        x0, x1, x2 = pos[i, 0], pos[i, 1], pos[i, 2]
        for r in range(3):
            vel[i, r] = m_v[g, r, 0] * x0 + m_v[g, r, 1] * x1 + m_v[g, r, 2] * x2 + c_v[g, r]
            acc[i, r] = m_a[g, r, 0] * x0 + m_a[g, r, 1] * x1 + m_a[g, r, 2] * x2 + c_a[g, r]


def _rotation_kinematics(scene: RadarScene, pos: NDArray[np.float64],
                         vel: NDArray[np.float64], obj: NDArray[np.int32]
                         ) -> NDArray[np.float64] | None:
    """Exact relative velocities (in place) and accelerations where something rotates.

    The render's velocities are exact for translating objects and a translating rig; a
    rotating object or a turning rig adds relative velocity (the rig's rotation) and
    acceleration (centripetal, Coriolis), from
    :func:`~simcore.sensors.radar.kinematics.rigid_point_motion`. None when nothing rotates
    (all accelerations zero).
    """
    snapshot = scene.snapshot
    rig_turns = bool(np.any(scene.rig.angular_velocity_rps))
    turning = [i for i, o in enumerate(snapshot.objects)
               if rig_turns or np.any(o.angular_velocity_rps)]
    if not turning or not len(pos):
        return None
    radar = scene.radar
    # One map per turning object, all in one batch (a person has a dozen turning segments).
    bodies = [snapshot.objects[i] for i in turning]
    m_v, c_v, m_a, c_a = motion_maps_batch(
        np.array([b.angular_velocity_rps for b in bodies], dtype=np.float64),
        np.array([b.velocity_mps for b in bodies], dtype=np.float64),
        np.array([b.origin for b in bodies], dtype=np.float64), scene.rig, radar)
    group_of = np.full(len(snapshot.objects) + 1, -1, dtype=np.int32)
    group_of[turning] = np.arange(len(turning), dtype=np.int32)
    acc = np.empty_like(pos)
    _rigid_rows(pos, np.take(group_of, obj), np.ascontiguousarray(m_v),
                np.ascontiguousarray(c_v), np.ascontiguousarray(m_a),
                np.ascontiguousarray(c_a), vel, acc)
    return acc
