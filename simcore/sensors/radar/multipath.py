"""Radar multipath by the image method: ghosts of targets seen via planar specular reflectors.

A large smooth planar face (a wall of concrete, plaster, wood or glass, a metal plate)
acts as a mirror at 60 GHz, with its Fresnel reflection at the path's angle. A target
``p`` in front of it is then also reached over the paths

* (a) Tx → plane → p → Rx and (b) Tx → p → plane → Rx (order 1, amplitude × Γ), and
* (c) Tx → plane → p → plane → Rx (order 2, amplitude × Γ²),

whose lengths are those of straight paths to the mirror images: the mirrored leg of (a)
has the length ``|p − Tx'|`` with ``Tx'`` the Tx mirrored in the plane, and (c) is the
image ``p'`` of ``p`` seen by the real array. So (a) and (b) are synthesised as the real
scatterers with mirrored Tx (Rx) positions (``tx_positions_m=`` / ``rx_positions_m=`` of
:func:`~simcore.sensors.radar.synthesis.synthesize_if`) and (c) as image scatterers with
mirrored positions and velocities. The delays are the exact bistatic delays of the unfolded
paths and the spreading is the radar equation over them, so the ghosts come out at the
ranges ``R``, ``(R + R_m)/2`` and ``R_m`` (``R_m`` = range of the image), the Doppler of the
image and, for (c), the angle of the image; their IF is added to the ideal IF before the
receiver, so every DSP stage sees them.

Reflectors (:func:`find_reflectors`) are the planar faces of ``Box`` and ``Plane`` objects
whose radar material has ``|Γ| ≥`` :data:`MIN_REFLECTION` at normal incidence (any
material with a smooth interface: a bounce more than 26 dB down is dropped) and whose
area is at least :data:`MIN_AREA_M2`; a ``Plane`` reflects on both sides, a box face on
its outer side. Curved surfaces (spheres, cylinders) and mesh files are left single-bounce.
Each path's Γ is the Fresnel TE/TM coefficient of the material's slab at the path's
incidence angle, mixed by the radar's ``polarization`` (:func:`polarised_reflection`),
times the Kirchhoff coherent factor of the material's rms height at that angle.

Order 2 also adds the ghosts over two different surfaces (Tx → face A → target → face B
→ Rx, :func:`two_surface_ghosts`) and over two faces on one leg (Tx → A → B → target → Rx,
:func:`~simcore.sensors.radar.legs.one_leg_double_ghosts`); from order 1 the room's own
bounces between its faces (edges, corners, echoes:
:func:`simcore.sensors.radar.room.room_returns`) are added.
Facets of planar objects get no image ghosts (:func:`image_ghost_rows`): their paths
between faces are the room's returns, which exist only where the geometry allows.

A path counts only when (1) the radar and the target are on the reflecting side of the
plane, (2) the mirrored leg (from the array origin towards the image) crosses the plane
inside the reflector's rectangle (aperture test) and (3) the radar render shows the
reflector at that crossing point (nothing in front of it; a crossing point outside the
render is accepted, the element pattern weighs it) and (4) the leg from the crossing point
to the target crosses no opaque object's triangles (:func:`second_leg_clear`).

Element patterns: each leg uses the direction in which it leaves the real array, i.e.
towards the real target for a direct leg and towards the image (the reflection point) for a
mirrored leg. Path (c) gets this from the image position; for (a) and (b), synthesised at
the real position, the mirrored leg's gain ratio ``g(image)/g(target)`` (of the first Tx or
Rx's pattern) is folded into the ghost's RCS. Target aspect: a trihedral corner reflector
takes its RCS in the direction of the image radar for (c) and, a retro-reflector, its
aperture's diffraction lobe between the two directions on the bistatic paths
(:func:`_corner_bistatic`); a curved object's facets are one ghost source with the
object's monostatic return (:func:`ghost_sources`), a sphere's at its bistatic specular
point on each path (:func:`~simcore.sensors.radar.legs.sphere_placement`). The
reflector's motion relative to the radar along its normal is included for (c) (the image
velocity) and neglected for (a) and (b) (exact when the radar moves parallel to the
reflector or not at all).

The rig's own front (``RadarConfig.rig_front_*``, a flat rectangle in the board plane) is a
reflector for the reflectors' own echoes: :func:`rig_front_ghosts` adds, from order 1, the
path radar → reflector → rig front → reflector → radar as the reflector's image of the rig
front (twice the reflector's distance, flat-plate RCS × Γ² × Γ_front).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.render.buffers import RenderBuffers
from simcore.scene.base import Model
from simcore.scene.geometry import Box, CornerReflector, Plane, corner_reflector_axes
from simcore.scene.materials import DualBandMaterial
from simcore.scene.radar_config import SPEED_OF_LIGHT, ElementPattern, RadarConfig
from simcore.sensors.radar.equation import element_gain
from simcore.sensors.radar.leg_kernel import legs_blocked, triangle_hit
from simcore.sensors.radar.legs import (
    Place,
    one_leg_double_ghosts,
    reflect_many,
    sphere_centres,
    sphere_factor,
    sphere_placement,
    sphere_sources,
)
from simcore.sensors.radar.reflectors import (
    MIN_DISTANCE_M,
    GhostSet,
    Reflector,
    _reflector_seen,
    antenna_fields,
    copolar_fields,
    polarization_vector,
)
from simcore.sensors.radar.room import room_returns
from simcore.sensors.radar.scatterers import (
    KIND_CORNER_REFLECTOR,
    KIND_FACET,
    KIND_POINT_TARGET,
    Scatterers,
    trihedral_effective_area,
)
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import ComplexCube, synthesize_if_sets

#: Smallest normal-incidence |Γ| of a reflector's material (metal 1, glass ≈ 0.5, concrete
#: ≈ 0.4, an 18 mm wood panel ≈ 0.2): a bounce 26 dB down, below which a ghost of even the
#: strongest target sinks under the clutter of the direct returns.
MIN_REFLECTION = 0.05
#: Smallest area of a reflecting face (m²).
MIN_AREA_M2 = 0.04
#: Smallest gain of a direct leg for the pattern ratio of a mirrored one (power).
MIN_GAIN = 1e-9


def _faces(geometry: Box | Plane) -> list[tuple[NDArray[np.float64], NDArray[np.float64],
                                                NDArray[np.float64], NDArray[np.float64],
                                                bool]]:
    """(centre, axes (2, 3), half sizes (2,), normal, two-sided) of a shape's faces, local."""
    return list(_local_faces("plane" if isinstance(geometry, Plane) else "box",
                             tuple(float(v) for v in geometry.size_m)))


@lru_cache(maxsize=256)
def _local_faces(kind: str, size_m: tuple[float, ...]) -> tuple[
        tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
              NDArray[np.float64], bool], ...]:
    """:func:`_faces` of a plane or box (``kind``) of a size, cached (read-only arrays)."""
    eye = np.eye(3)
    out = []
    if kind == "plane":
        a, b = size_m
        out.append((np.zeros(3), eye[:2].copy(), 0.5 * np.array([a, b]), eye[2].copy(), True))
    else:
        size = np.asarray(size_m, dtype=np.float64)
        for k in range(3):
            i, j = (k + 1) % 3, (k + 2) % 3
            half = 0.5 * np.array([size[i], size[j]])
            for sign in (1.0, -1.0):
                out.append((sign * 0.5 * size[k] * eye[k], eye[[i, j]].copy(), half,
                            sign * eye[k], False))
    for face in out:
        for arr in face[:4]:
            arr.setflags(write=False)
    return tuple(out)


def _cross3(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.cross`` of two 3-vectors, in its order of operations (without its overhead)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def find_reflectors(scene: RadarScene, wavelength_m: float, *,
                    min_reflection: float = MIN_REFLECTION, min_area_m2: float = MIN_AREA_M2
                    ) -> list[Reflector]:
    """The significant planar specular reflectors of a frame, in the radar optical frame.

    Parameters
    ----------
    scene : RadarScene
        The objects, their materials and states at the frame, and the radar's state.
    wavelength_m : float
        Radar wavelength (Γ is evaluated at ``c / λ``), m.
    min_reflection, min_area_m2 : float
        Thresholds on the normal-incidence |Γ| and on the face area (m²).
    """
    table = scene.materials
    radar = scene.radar
    radar_key = tuple(np.ascontiguousarray(a, dtype=np.float64).tobytes()
                      for a in (radar.rotation, radar.position, radar.velocity_mps))
    freq = SPEED_OF_LIGHT / wavelength_m
    out: list[Reflector] = []
    for i, o in enumerate(scene.objects):
        if not isinstance(o.geometry, (Box, Plane)):
            continue
        mat = table.get(o.material)
        if mat is None:
            continue
        band = mat.band("radar")
        if band.opacity <= 0:
            continue
        gamma = complex(band.coefficients(freq)[0])
        if abs(gamma) < min_reflection:
            continue
        state = scene.snapshot.objects[i]
        faces = _world_faces(
            "plane" if isinstance(o.geometry, Plane) else "box",
            tuple(float(v) for v in o.geometry.size_m),
            np.ascontiguousarray(state.transform, dtype=np.float64).tobytes(),
            np.ascontiguousarray(state.velocity_mps, dtype=np.float64).tobytes(), radar_key,
            float(min_area_m2))
        for center, axes, half_w, normal, two, speed in faces:
            out.append(Reflector(
                object_index=i, center_m=center, axes=axes, half_size_m=half_w, normal=normal,
                two_sided=two, gamma=gamma, height_rms_m=float(band.height_rms_m),
                normal_speed_mps=speed, band=band, frequency_hz=freq))
    return out


#: One face of :func:`_world_faces`: centre, axes, half sizes, normal (radar frame), whether
#: two-sided, speed along the normal relative to the radar.
_Face = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
              NDArray[np.float64], bool, float]


@lru_cache(maxsize=1024)
def _world_faces(kind: str, size_m: tuple[float, ...], transform: bytes, velocity: bytes,
                 radar: tuple[bytes, ...], min_area_m2: float) -> tuple[_Face, ...]:
    """The faces of a box or plane (``kind``) in the radar frame, by size, pose and the radar's.

    Cached: a still object seen by a still radar has the same faces every frame. The
    arrays are read-only (shared by the frames' reflectors).
    """
    t = np.frombuffer(transform).reshape(4, 4)
    r_rad = np.frombuffer(radar[0]).reshape(3, 3)
    p_rad, v_rad = np.frombuffer(radar[1]), np.frombuffer(radar[2])
    rel_v = (np.frombuffer(velocity) - v_rad) @ r_rad
    out = []
    for c, axes, half, n, two in _local_faces(kind, size_m):
        # World (object transforms may scale), then the radar frame.
        c_w = t[:3, :3] @ c + t[:3, 3]
        ax_w = axes @ t[:3, :3].T
        scale = np.linalg.norm(ax_w, axis=1)
        half_w = half * scale
        if 4.0 * half_w[0] * half_w[1] < min_area_m2:
            continue
        n_w = _cross3(ax_w[0], ax_w[1])
        n_w /= max(float(np.linalg.norm(n_w)), 1e-300)
        if n_w @ (t[:3, :3] @ n) < 0:
            n_w = -n_w
        normal = n_w @ r_rad
        arrays = ((c_w - p_rad) @ r_rad, (ax_w / scale[:, None]) @ r_rad, half_w, normal)
        for a in arrays:
            a.setflags(write=False)
        out.append((*arrays, two, float(rel_v @ normal)))
    return tuple(out)


@dataclass(frozen=True)
class ImagePaths:
    """The valid image paths of one reflector (rows of the primary scatterers).

    Attributes
    ----------
    reflector : Reflector
        The reflector, its normal turned towards the radar.
    rows : ndarray of int, shape (K,)
        Primary scatterers with a valid path.
    images_m : ndarray, shape (K, 3)
        Their mirror images (m).
    gamma : ndarray, shape (K,), complex128
        Effective reflection coefficient of each path (Γ × coherent factor).
    crossing_m : ndarray, shape (K, 3)
        The reflection points: where the leg towards the image crosses the plane (m).
    fields : ndarray, shape (K, 3), complex128, or None
        The reflected E at the target for a unit co-polar E sent (radar frame): ``gamma``
        is its co-polar part; a metal sphere mirrors all of it (:func:`~simcore.sensors.
        radar.legs.sphere_factor`).
    """

    reflector: Reflector
    rows: NDArray[np.intp]
    images_m: NDArray[np.float64]
    gamma: NDArray[np.complex128]
    crossing_m: NDArray[np.float64]
    fields: NDArray[np.complex128] | None = None


def _facing_radar(refl: Reflector) -> tuple[Reflector, float] | None:
    """The reflector turned towards the radar, and the radar's distance to its plane.

    None when the radar is (nearly) in the plane or behind a one-sided face.
    """
    s0 = float(-refl.center_m @ refl.normal)            # signed distance of the radar
    if abs(s0) < MIN_DISTANCE_M:
        return None
    if s0 < 0:
        if not refl.two_sided:
            return None
        refl = dataclasses.replace(refl, normal=-refl.normal,
                                   normal_speed_mps=-refl.normal_speed_mps)
        s0 = -s0
    return refl, s0


def polarised_reflection(reflector: Reflector, directions: NDArray[np.float64],
                         polarization: NDArray[np.float64]) -> NDArray[np.complex128]:
    """Co-polar reflection coefficient of each leg's bounce on ``reflector``, shape (K,).

    ``directions`` (K, 3) are the legs from the radar to the reflection points and
    ``polarization`` the antennas' E direction on boresight (radar frame). The wave's E
    (the antenna's towards the leg, ``ê = p̂(d̂)``,
    :func:`~simcore.sensors.radar.reflectors.antenna_fields`) splits into TE (along
    ``ŝ = n × d̂``, parallel to the surface) and TM (in the plane of incidence); the
    reflected E (:func:`~simcore.sensors.radar.room.reflect_field`:
    ``−M (−Γ_TE E_TE + Γ_TM E_TM)``, the image of a dipole ``p`` in a perfect conductor
    being ``−M p``, M the mirror) arrives at the target along the reflected ray
    ``d̂_r = M d̂`` and is received there by the same polarisation in that ray's frame,
    ``p̂(d̂_r)`` (the target keeps the polarisation in the ray's own frame, as a sphere or
    a trihedral does). Where ``M ê = ±p̂(d̂_r)`` up to the TE/TM split this is

        Γ = Γ_TE c_TE² ∓ Γ_TM (1 − c_TE²),      c_TE = ê · ŝ,

    with Born & Wolf's Γ_TE, Γ_TM at the leg's incidence angle θ
    (:meth:`~simcore.scene.materials.BandMaterial.oblique_coefficients`), evaluated as
    vectors. At normal incidence it is the material's Γ; a metal gives −1 for E parallel to
    the surface (H on a side wall, either on a front wall) and +1 for E in the plane of
    incidence at grazing (V over a metal floor); a dielectric gives −1 at grazing for both.
    (Received along the incident leg instead, ``p̂(d̂)``, the TM part carried a spurious
    ``cos 2θ``: a V ghost via a concrete floor 49° off its normal came out 17 dB low
    against Sionna RT, ``tests/test_radar_sionna_targets.py``.) Without a band
    (:class:`Reflector` made by hand) the reflector's ``gamma``.
    """
    d = directions / np.maximum(np.linalg.norm(directions, axis=1, keepdims=True), 1e-300)
    cos_i = np.abs(d @ reflector.normal)
    if reflector.band is None:
        return np.full(len(d), complex(reflector.gamma))
    r_te, r_tm = reflector.band.oblique_coefficients(reflector.frequency_hz, cos_i)
    n = reflector.normal
    s = np.cross(n, d)
    s_norm = np.linalg.norm(s, axis=1)
    e = antenna_fields(polarization, d)
    d_r = d - 2.0 * (d @ n)[:, None] * n[None, :]
    e_r = copolar_fields(polarization, d_r)
    ok = s_norm > 1e-9
    out = np.asarray(r_te, dtype=np.complex128).copy()       # normal incidence: Γ_TE
    s_hat = s[ok] / s_norm[ok, None]
    e_te = np.einsum("ij,ij->i", e[ok], s_hat)[:, None] * s_hat
    scaled = -r_te[ok, None] * e_te + r_tm[ok, None] * (e[ok] - e_te)
    mirrored = scaled - 2.0 * (scaled @ n)[:, None] * n[None, :]
    out[ok] = -np.einsum("ij,ij->i", mirrored, e_r[ok])
    return out


def image_paths(reflector: Reflector, scatterers: Scatterers, buffers: RenderBuffers | None,
                wavelength_m: float, *, polarization: NDArray[np.float64] | None = None,
                eligible: NDArray[np.bool_] | None = None) -> ImagePaths | None:
    """Primary scatterers with a valid path via ``reflector`` (module docstring), or None.

    ``polarization``: the antennas' E direction (radar frame; default V,
    :func:`polarization_vector`) for the Fresnel coefficient at each path's angle.
    ``eligible`` (scatterers,): the rows that may have a path (default all).
    """
    facing = _facing_radar(reflector)
    if facing is None:
        return None
    refl, s0 = facing
    intr = None if buffers is None else buffers.intrinsics
    labels = (np.zeros((0, 0), dtype=np.int32) if buffers is None
              else np.ascontiguousarray(buffers.object_index, dtype=np.int32))
    # One compiled pass over the scatterers (the steps of the module docstring).
    rows, images, q = _image_candidates(
        np.ascontiguousarray(scatterers.positions_m, dtype=np.float64),
        np.ascontiguousarray(scatterers.object_index, dtype=np.int64),
        np.ascontiguousarray(scatterers.rcs_m2 if eligible is None
                             else np.where(eligible, scatterers.rcs_m2, 0.0),
                             dtype=np.float64),
        np.ascontiguousarray(refl.center_m, dtype=np.float64),
        np.ascontiguousarray(refl.normal, dtype=np.float64),
        np.ascontiguousarray(refl.axes, dtype=np.float64),
        np.ascontiguousarray(refl.half_size_m, dtype=np.float64), float(s0),
        int(refl.object_index), labels,
        np.zeros(4) if intr is None else np.array([intr.fx, intr.fy, intr.cx, intr.cy],
                                                  dtype=np.float64))
    if not len(rows):
        return None
    cos_i = s0 / np.maximum(np.linalg.norm(q, axis=1), 1e-300)
    g = 4.0 * np.pi * refl.height_rms_m * cos_i / wavelength_m
    pol = polarization_vector("V") if polarization is None else polarization
    gamma = polarised_reflection(refl, q, pol) * np.exp(-0.5 * g * g)
    fields = reflect_many(refl, q, antenna_fields(pol, q).astype(np.complex128), wavelength_m)
    return ImagePaths(refl, rows, images, gamma.astype(np.complex128), q, fields)


@kernel
def _image_candidates(pos: NDArray[np.float64], object_index: NDArray[np.int64],
                      rcs: NDArray[np.float64], center: NDArray[np.float64],
                      normal: NDArray[np.float64], axes: NDArray[np.float64],
                      half: NDArray[np.float64], s0: float, reflector: int,
                      labels: NDArray[np.int32], intrinsics: NDArray[np.float64]
                      ) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
    """The scatterers with a path via the reflector: rows, images and crossing points.

    A scatterer of another object, with a cross-section, in front of the plane (signed
    distance ``s > MIN_DISTANCE_M``) has the image ``P − 2 s n``; the leg from the radar to
    the image crosses the plane at ``q = s0 / (s0 + s) · image``, which must lie within the
    reflector's rectangle and, with a render (``labels`` not empty), be seen as the
    reflector where it falls inside the image (:func:`_reflector_seen`).
    """
    n = pos.shape[0]
    rows = np.empty(n, dtype=np.intp)
    images = np.empty((n, 3))
    crossing = np.empty((n, 3))
    h, w = labels.shape
    fx, fy, cx, cy = intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]
    img = np.empty(3)
    q = np.empty(3)
    k = 0
    for i in range(n):
        s = ((pos[i, 0] - center[0]) * normal[0] + (pos[i, 1] - center[1]) * normal[1]
             + (pos[i, 2] - center[2]) * normal[2])
        if not (s > MIN_DISTANCE_M and object_index[i] != reflector and rcs[i] > 0):
            continue
        f = s0 / (s0 + s)
        for c in range(3):
            img[c] = pos[i, c] - 2.0 * s * normal[c]
            q[c] = f * img[c]
        inside = True
        for a in range(2):
            local = ((q[0] - center[0]) * axes[a, 0] + (q[1] - center[1]) * axes[a, 1]
                     + (q[2] - center[2]) * axes[a, 2])
            if not abs(local) <= half[a]:
                inside = False
        if not inside:
            continue
        if h > 0 and q[2] > 0:
            col = math.floor(fx * q[0] / q[2] + cx)
            row = math.floor(fy * q[1] / q[2] + cy)
            if 0 <= col < w and 0 <= row < h and labels[int(row), int(col)] != reflector:
                continue
        rows[k] = i
        for c in range(3):
            images[k, c] = img[c]
            crossing[k, c] = q[c]
        k += 1
    return rows[:k].copy(), images[:k].copy(), crossing[:k].copy()


#: The second leg (reflection point → target) ends this far before the target (m): a
#: scatterer lies on its object's surface (a tessellated curve: up to a few mm inside it).
LEG_END_MARGIN_M = 0.005

def _local_triangles(geometry: Model) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """(triangle corners (T, 3, 3), AABB (2, 3)) of a geometry in its local frame.

    None for geometries without a surface (point targets) or a mesh file that cannot be
    read from here (a relative path without the project's folder).
    """
    return _triangles_of(type(geometry), geometry.model_dump_json())


@lru_cache(maxsize=256)
def _triangles_of(kind: type[Model], spec: str
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """:func:`_local_triangles` by geometry class and JSON.

    The cache is bounded: every size a drag in the GUI passes through is a new geometry.
    """
    from simcore.render.meshes import build_mesh

    try:
        mesh = build_mesh(kind.model_validate_json(spec))  # type: ignore[arg-type]
    except (OSError, ValueError):
        return None
    if mesh is None or not len(mesh.triangles):
        return None
    tri = np.asarray(mesh.points, dtype=np.float64)[mesh.triangles]
    return tri, np.array([mesh.points.min(axis=0), mesh.points.max(axis=0)])


def _segments_hit_box(a: NDArray[np.float64], b: NDArray[np.float64],
                      box: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether segments a → b (n, 3) meet the axis-aligned box (2, 3) (slab test)."""
    d = b - a
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / d
        t1, t2 = (box[0] - a) * inv, (box[1] - a) * inv
    lo = np.where(np.isnan(t1), -np.inf, np.minimum(t1, t2))
    hi = np.where(np.isnan(t2), np.inf, np.maximum(t1, t2))
    # A segment parallel to a slab: inside it or not, whatever t.
    par = d == 0
    outside = par & ((a < box[0]) | (a > box[1]))
    lo = np.where(par, -np.inf, lo)
    hi = np.where(par, np.inf, hi)
    t_in, t_out = np.max(lo, axis=1), np.min(hi, axis=1)
    return ~np.any(outside, axis=1) & (t_in <= t_out) & (t_out >= 0.0) & (t_in <= 1.0)


def _segments_hit_triangles(a: NDArray[np.float64], b: NDArray[np.float64],
                            tri: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether segments a → b (n, 3) cross any of the triangles (T, 3, 3) (Möller–Trumbore).

    One compiled pass (:func:`_hit_kernel`), each segment stopping at its first hit;
    :func:`_segments_hit_triangles_numpy` is the same test in numpy.
    """
    hit = np.zeros(len(a), dtype=np.bool_)
    if len(a) and len(tri):
        _hit_kernel(np.ascontiguousarray(a, dtype=np.float64),
                    np.ascontiguousarray(b, dtype=np.float64),
                    np.ascontiguousarray(tri, dtype=np.float64), hit)
    return hit


@kernel
def _hit_kernel(a: NDArray[np.float64], b: NDArray[np.float64], tri: NDArray[np.float64],
                hit: NDArray[np.bool_]) -> None:
    """``hit[i]`` = segment ``a[i] → b[i]`` crosses a triangle (0 < t < 1, inclusive edges)."""
    for i in range(a.shape[0]):
        if triangle_hit(a[i], b[i], tri, 0, tri.shape[0]):
            hit[i] = True


def _segments_hit_triangles_numpy(a: NDArray[np.float64], b: NDArray[np.float64],
                                  tri: NDArray[np.float64]) -> NDArray[np.bool_]:
    """:func:`_segments_hit_triangles` in numpy (the reference of the compiled pass)."""
    hit = np.zeros(len(a), dtype=bool)
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    step = max(1, 200_000 // max(len(tri), 1))
    for lo in range(0, len(a), step):
        o, d = a[lo:lo + step, None, :], (b - a)[lo:lo + step, None, :]      # (m, 1, 3)
        p = np.cross(d, e2[None])                                             # (m, T, 3)
        det = np.einsum("mtk,tk->mt", p, e1)
        ok = np.abs(det) > 1e-12
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = o - tri[None, :, 0]
        u = np.einsum("mtk,mtk->mt", s, p) * inv
        q = np.cross(s, e1[None])
        v = np.einsum("mtk,mtk->mt", np.broadcast_to(d, q.shape), q) * inv
        t = np.einsum("mtk,tk->mt", q, e2) * inv
        inside = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < 1)
        hit[lo:lo + step] = np.any(inside, axis=1)
    return hit


#: An object that stops a second leg: (object index, its triangles (T, 3, 3) and AABB (2, 3)
#: in its local frame, radar frame → local frame (4, 4)).
_Blocker = tuple[int, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def leg_blockers(scene: RadarScene, wavelength_m: float) -> list[_Blocker]:
    """The objects that stop a second leg (:func:`second_leg_clear`), once per frame.

    Every object that the radar band sees, that transmits nothing and that has triangles
    (a mesh file given by a path relative to the project folder has none here), with its
    triangles and the transform from the radar frame to its local frame.
    """
    table = scene.materials
    world_to_radar = np.linalg.inv(scene.radar.transform)
    freq = SPEED_OF_LIGHT / wavelength_m
    out: list[_Blocker] = []
    for i, o in enumerate(scene.objects):
        mat = table.get(o.material)
        if mat is None:
            continue
        band = mat.band("radar")
        if band.opacity <= 0 or abs(band.coefficients(freq)[1]) > 0:
            continue
        local = _local_triangles(o.geometry)
        if local is None:
            continue
        # Radar frame → the object's local frame (its transform may scale).
        m = np.linalg.inv(world_to_radar @ scene.snapshot.objects[i].transform)
        out.append((i, local[0], local[1], np.asarray(m, dtype=np.float64)))
    return out


def second_leg_clear(scene: RadarScene, paths: ImagePaths, scatterers: Scatterers,
                     wavelength_m: float) -> NDArray[np.bool_]:
    """Whether the leg from each path's reflection point to its target is unobstructed.

    The first leg (radar → reflection point) is tested against the radar render
    (:func:`image_paths`); this one against the scene's triangles: every object that the
    radar band sees and that transmits nothing (a thin slab passes the wave; an object of
    opacity 0 is not there for the radar), except the reflector itself, stops the leg. The
    target's own object counts (a facet on the far side of its object from the reflection
    point is shadowed), except for corner reflectors and point targets, which scatter from
    their apex. The leg ends :data:`LEG_END_MARGIN_M` before the target.

    Returns
    -------
    ndarray of bool, shape (K,)
        One flag per row of ``paths``.
    """
    return second_legs_clear(scene, [paths], scatterers, wavelength_m)[0]


def second_legs_clear(scene: RadarScene, group: Sequence[ImagePaths], scatterers: Scatterers,
                      wavelength_m: float, *, blockers: Sequence[_Blocker] | None = None
                      ) -> list[NDArray[np.bool_]]:
    """:func:`second_leg_clear` of several reflectors' paths, tested together.

    One pass per blocking object over every reflector's legs (the objects' triangles and
    transforms, :func:`leg_blockers`, found once: ``blockers`` when the caller has them).

    Returns
    -------
    list of ndarray of bool
        One flag per row of each of ``group``.
    """
    if not group:
        return []
    if blockers is None:
        blockers = leg_blockers(scene, wavelength_m)
    a = np.concatenate([g.crossing_m for g in group])
    rows = np.concatenate([g.rows for g in group])
    reflector = np.concatenate([np.full(len(g.rows), g.reflector.object_index)
                                for g in group])
    p = scatterers.positions_m[rows]
    d = p - a
    length = np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    b = p - d / length * np.minimum(LEG_END_MARGIN_M, 0.5 * length)
    own = scatterers.object_index[rows]
    own_ok = scatterers.kind[rows] != KIND_FACET
    clear = np.ones(len(a), dtype=bool)
    if blockers:
        # Every leg in every blocker's local frame, then one compiled pass: the reflector
        # does not stop its own legs, nor a target's own object where it scatters from
        # outside it (corner reflectors, point targets); a leg hit once stays hit.
        index = np.array([i for i, _, _, _ in blockers])
        la = np.stack([a @ m[:3, :3].T + m[:3, 3] for _, _, _, m in blockers])
        lb = np.stack([b @ m[:3, :3].T + m[:3, 3] for _, _, _, m in blockers])
        skip = ((own[None, :] == index[:, None]) & own_ok[None, :]) | (
            reflector[None, :] == index[:, None])
        tri = np.concatenate([t for _, t, _, _ in blockers])
        starts = np.concatenate([[0], np.cumsum([len(t) for _, t, _, _ in blockers])])
        legs_blocked(la, lb, skip, np.stack([box for _, _, box, _ in blockers]),
                     np.ascontiguousarray(tri, dtype=np.float64), starts.astype(np.int64),
                     clear)
    return np.split(clear, np.cumsum([len(g.rows) for g in group])[:-1])


def _corner_aspect(scene: RadarScene, scatterers: Scatterers,
                   rows: NDArray[np.intp], towards: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """RCS ratio σ(towards) / σ(radar) of the corner reflectors among ``rows`` (1 elsewhere).

    ``towards`` (K, 3) are the points (radar frame) the reflector is seen from instead of
    the radar origin.
    """
    out = np.ones(len(rows))
    kinds = scatterers.kind[rows]
    sel = np.flatnonzero(kinds == KIND_CORNER_REFLECTOR)
    if not len(sel):
        return out
    r_rad = scene.radar.rotation
    edges = corner_reflector_axes()
    for k in sel:
        i = int(scatterers.object_index[rows[k]])
        geom = scene.objects[i].geometry
        if not isinstance(geom, CornerReflector):
            continue
        r_obj = scene.snapshot.objects[i].transform[:3, :3]
        apex = scatterers.positions_m[rows[k]]
        areas = []
        for target in (np.zeros(3), towards[k]):
            d = target - apex
            d /= max(float(np.linalg.norm(d)), 1e-300)
            areas.append(float(trihedral_effective_area(edges @ (r_obj.T @ (r_rad @ d)),
                                                        geom.edge_m)))
        out[k] = (areas[1] / areas[0]) ** 2 if areas[0] > 0 else 0.0
    return out


def _corner_bistatic(scene: RadarScene, scatterers: Scatterers, rows: NDArray[np.intp],
                     seen_a: NDArray[np.float64], seen_b: NDArray[np.float64],
                     wavelength_m: float) -> NDArray[np.float64]:
    """RCS ratio σ(a → b) / σ(radar) of the corner reflectors among ``rows`` (1 elsewhere).

    A trihedral is a retro-reflector: a wave from ``seen_a`` (K, 3; the radar or an image
    of it, radar frame) leaves it towards ``seen_a`` again, as a beam as wide as the
    diffraction of its effective aperture. Seen from ``seen_b`` at the bistatic angle β
    it returns ``σ = 4π A_a A_b / λ² · |2 J₁(x)/x|²``, ``x = k √(√(A_a A_b)/π) sin β``
    (the GO effective areas ``A`` towards each, a circular aperture of their mean area):
    a ghost over one reflection only (out direct, back via a wall) is 30 dB or more below
    the corner's own return once β exceeds a few beamwidths, as Sionna RT and GO find.
    """
    from scipy.special import j1

    mean = np.sqrt(_corner_aspect(scene, scatterers, rows, seen_a)
                   * _corner_aspect(scene, scatterers, rows, seen_b))
    corner = np.flatnonzero(scatterers.kind[rows] == KIND_CORNER_REFLECTOR)
    if not len(corner):
        return mean
    apex = scatterers.positions_m[rows[corner]]
    ua = seen_a[corner] - apex
    ub = seen_b[corner] - apex
    cos_b = np.einsum("ij,ij->i", ua, ub) / np.maximum(
        np.linalg.norm(ua, axis=1) * np.linalg.norm(ub, axis=1), 1e-300)
    sin_b = np.sqrt(np.clip(1.0 - cos_b**2, 0.0, 1.0))
    sigma0 = scatterers.rcs_m2[rows[corner]]                  # towards the radar
    area = np.sqrt(mean[corner] * sigma0) * wavelength_m / np.sqrt(4.0 * np.pi)
    x = 2.0 * np.pi / wavelength_m * np.sqrt(area / np.pi) * sin_b
    with np.errstate(divide="ignore", invalid="ignore"):
        lobe = np.where(x > 1e-9, 2.0 * j1(x) / np.where(x > 1e-9, x, 1.0), 1.0)
    mean[corner] *= lobe**2
    return mean


def _sphere_gammas(paths: ImagePaths, pos: NDArray[np.float64], centres: NDArray[np.float64],
                   pol: NDArray[np.float64], origin_image: NDArray[np.float64]
                   ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """The paths' amplitudes over one bounce (a, b) and two (c), the spheres' whole-field.

    Γ and Γ² for most targets; a metal sphere mirrors the whole field, not only its
    co-polar part (:func:`~simcore.sensors.radar.legs.sphere_factor`).
    """
    gamma, gamma2 = paths.gamma.copy(), paths.gamma**2
    sph = np.isfinite(centres[paths.rows, 0])
    if np.any(sph) and paths.fields is not None:
        c, f = centres[paths.rows[sph]], paths.fields[sph]
        direct = antenna_fields(pol, pos[sph]).astype(np.complex128)
        gamma[sph] = sphere_factor(f, direct, origin_image - c, -c)
        gamma2[sph] = sphere_factor(f, f, origin_image - c, origin_image - c)
    return gamma, gamma2


def _ghosts(scatterers: Scatterers, rows: NDArray[np.intp], positions: NDArray[np.float64],
            velocities: NDArray[np.float64], accelerations: NDArray[np.float64] | None,
            amplitude: NDArray[np.complex128]) -> Scatterers:
    """Scatterers ``rows`` moved to ``positions`` with complex amplitude × ``amplitude``."""
    rcs = scatterers.rcs_m2[rows] * np.abs(amplitude) ** 2
    return Scatterers(
        time_s=scatterers.time_s, wavelength_m=scatterers.wavelength_m,
        positions_m=np.ascontiguousarray(positions), velocities_mps=velocities,
        rcs_m2=rcs, phase_rad=scatterers.phase_rad[rows] + np.angle(amplitude),
        object_index=scatterers.object_index[rows], kind=scatterers.kind[rows],
        accelerations_mps2=accelerations)


def image_ghost_rows(scene: RadarScene, scatterers: Scatterers) -> NDArray[np.bool_]:
    """The scatterers that get image ghosts: all but the facets of planar objects.

    A facet keeps its monostatic amplitude on a ghost path, which is right for a small
    or curved scatterer but not for a facet of a large flat face: mirrored in another
    face, the facets of a wall's specular spot would add ghosts where no geometric path
    exists. Paths between planar faces are the room's own returns instead
    (:func:`~simcore.sensors.radar.room.room_returns`: the specular geometry of each
    pair or triple of faces).
    """
    planar = np.array([isinstance(o.geometry, (Box, Plane)) for o in scene.objects] + [False],
                      dtype=bool)
    return ~((scatterers.kind == KIND_FACET) & planar[scatterers.object_index])


def ghost_sources(scatterers: Scatterers, eligible: NDArray[np.bool_]) -> Scatterers:
    """The scatterers whose ghosts are drawn: each curved object's facets as one scatterer.

    The eligible facets (:func:`image_ghost_rows`) of one object are summed coherently
    into one point scatterer at their power-weighted centroid: its amplitude is the
    object's monostatic return (the phasors ``√σ e^{j(2k r + φ)}`` summed, referred to the
    centroid's range), its velocity and acceleration the power-weighted means. A curved
    object's specular return is about the same on a bistatic path as on the monostatic one
    (a sphere's is πr² either way, geometric optics), which its facets, each with its
    monostatic amplitude on the bistatic path, do not reproduce; and a person's thousands
    of facets become a dozen ghost sources. Corner reflectors and point targets stay as
    they are.

    Returns
    -------
    Scatterers
        The eligible non-facet rows, then one row per object with eligible facets
        (kind point target: it scatters from its centroid, not from a facet's face).
    """
    keep = np.flatnonzero(eligible & (scatterers.kind != KIND_FACET))
    facets = np.flatnonzero(eligible & (scatterers.kind == KIND_FACET))
    if not len(facets):
        return scatterers.subset(keep)
    k = 2.0 * np.pi / scatterers.wavelength_m
    obj = scatterers.object_index[facets]
    owners, group = np.unique(obj, return_inverse=True)
    pos = scatterers.positions_m[facets]
    power = scatterers.rcs_m2[facets]
    weight = np.bincount(group, power, minlength=len(owners))
    weight = np.where(weight > 0, weight, 1.0)

    def mean(values: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.stack([np.bincount(group, power * values[:, c], minlength=len(owners))
                         for c in range(3)], axis=1) / weight[:, None]

    centroid = mean(pos)
    r = np.linalg.norm(pos, axis=1)
    phasor = np.sqrt(power) * np.exp(1j * (2.0 * k * r + scatterers.phase_rad[facets]))
    total = (np.bincount(group, phasor.real, minlength=len(owners))
             + 1j * np.bincount(group, phasor.imag, minlength=len(owners)))
    total *= np.exp(-2j * k * np.linalg.norm(centroid, axis=1))
    acc = scatterers.accelerations_mps2
    merged = Scatterers(
        time_s=scatterers.time_s, wavelength_m=scatterers.wavelength_m,
        positions_m=centroid, velocities_mps=mean(scatterers.velocities_mps[facets]),
        rcs_m2=np.abs(total) ** 2, phase_rad=np.angle(total),
        object_index=owners.astype(np.int32),
        kind=np.full(len(owners), KIND_POINT_TARGET, dtype=np.int8),
        accelerations_mps2=None if acc is None else mean(acc[facets]))
    return _concat([scatterers.subset(keep), merged])


def _subset_paths(paths: ImagePaths, keep: NDArray[np.bool_]) -> ImagePaths:
    return ImagePaths(paths.reflector, paths.rows[keep], paths.images_m[keep],
                      paths.gamma[keep], paths.crossing_m[keep],
                      None if paths.fields is None else paths.fields[keep])


def two_surface_ghosts(scatterers: Scatterers, paths: Sequence[ImagePaths],
                       tx_positions_m: NDArray[np.float64], rx_positions_m: NDArray[np.float64],
                       *, scene: RadarScene | None = None, wavelength_m: float = 0.0,
                       patterns: tuple[ElementPattern, ElementPattern] | None = None,
                       place: Place | None = None,
                       centres: NDArray[np.float64] | None = None) -> list[GhostSet]:
    """Ghosts over two different surfaces: Tx → face A → target → face B → Rx.

    For every ordered pair of reflectors (A, B), A ≠ B, and every target with a valid
    path via each (:func:`image_paths`, :func:`second_leg_clear`), the path's length is
    ``|p − Tx_A| + |p − Rx_B|`` with the Tx mirrored in A and the Rx in B (the image
    method on each leg), its amplitude Γ_A Γ_B (each at its leg's angle and
    polarisation): synthesised at the real position with both antenna sets mirrored.
    With ``scene``, a corner reflector's is its bistatic return between the radar's two
    images (:func:`_corner_bistatic`). With ``patterns`` (Tx, Rx element patterns), each
    leg's gain ratio towards its reflection point (the target's image in its face) over
    the target's direction, where the ghost is synthesised. ``place``: where each target
    scatters between the two images (:func:`~simcore.sensors.radar.legs.sphere_placement`);
    ``centres``: the spheres' (:func:`~simcore.sensors.radar.legs.sphere_centres`), whose
    rows take the legs' whole fields (:func:`~simcore.sensors.radar.legs.sphere_factor`).
    """
    out: list[GhostSet] = []
    for a in paths:
        for b in paths:
            if a is b or a.reflector.object_index == b.reflector.object_index and \
                    np.allclose(a.reflector.normal, b.reflector.normal):
                continue
            rows, ia, ib = np.intersect1d(a.rows, b.rows, return_indices=True)
            if not len(rows):
                continue
            vel = scatterers.velocities_mps[rows]
            acc = (None if scatterers.accelerations_mps2 is None
                   else scatterers.accelerations_mps2[rows])
            amp = a.gamma[ia] * b.gamma[ib]
            if centres is not None and a.fields is not None and b.fields is not None:
                sph = np.isfinite(centres[rows, 0])
                if np.any(sph):
                    c = centres[rows[sph]]
                    amp[sph] = sphere_factor(a.fields[ia][sph], b.fields[ib][sph],
                                             a.reflector.mirror(np.zeros(3)) - c,
                                             b.reflector.mirror(np.zeros(3)) - c)
            if patterns is not None:
                pos = scatterers.positions_m[rows]
                amp = amp * np.sqrt(
                    element_gain(patterns[0], a.images_m[ia])
                    / np.maximum(element_gain(patterns[0], pos), MIN_GAIN)
                    * element_gain(patterns[1], b.images_m[ib])
                    / np.maximum(element_gain(patterns[1], pos), MIN_GAIN))
            if scene is not None:
                n = len(rows)
                amp = amp * np.sqrt(_corner_bistatic(
                    scene, scatterers, rows,
                    np.broadcast_to(a.reflector.mirror(np.zeros(3)), (n, 3)).copy(),
                    np.broadcast_to(b.reflector.mirror(np.zeros(3)), (n, 3)).copy(),
                    wavelength_m))
            where = scatterers.positions_m[rows]
            if place is not None:
                n = len(rows)
                where = place(rows, where,
                              np.broadcast_to(a.reflector.mirror(np.zeros(3)), (n, 3)),
                              np.broadcast_to(b.reflector.mirror(np.zeros(3)), (n, 3)))
            out.append(GhostSet(
                _ghosts(scatterers, rows, where, vel, acc, amp),
                2, a.reflector.object_index, tx_positions_m=a.reflector.mirror(tx_positions_m),
                rx_positions_m=b.reflector.mirror(rx_positions_m)))
    return out


def ghost_scatterers(scene: RadarScene, scatterers: Scatterers,
                     config: RadarConfig, *, buffers: RenderBuffers | None = None,
                     order: int | None = None,
                     reflectors: list[Reflector] | None = None) -> list[GhostSet]:
    """The multipath ghosts of a frame's primary scatterers, by kind of path.

    Parameters
    ----------
    scene : RadarScene
        Objects, materials and states (reflector geometry, corner reflectors'
        orientation) and the radar's state.
    scatterers : Scatterers
        The frame's primary (single-bounce) scatterers, radar frame.
    config : RadarConfig
        The radar (antenna positions, patterns, wavelength).
    buffers : RenderBuffers, optional
        The frame's radar render: the reflection point must be seen in it (None: no test).
    order : int, optional
        1 or 2 (default ``config.multipath_order``); 0 gives no ghosts.
    reflectors : list of Reflector, optional
        Default :func:`find_reflectors`.

    Returns
    -------
    list of GhostSet
        Per reflector: path (a) (mirrored Tx), path (b) (mirrored Rx) and, for order 2,
        path (c) (image scatterers, real antennas).
    """
    order = config.multipath_order if order is None else int(order)
    if order <= 0 or len(scatterers) == 0:
        return []
    lam = config.wavelength_m
    if reflectors is None:
        reflectors = find_reflectors(scene, lam)
    p_tx, p_rx = config.tx_positions_m(), config.rx_positions_m()
    pat_t = config.tx[0].pattern or config.element_pattern
    pat_r = config.rx[0].pattern or config.element_pattern
    scatterers = sphere_sources(scene, ghost_sources(scatterers,
                                                     image_ghost_rows(scene, scatterers)))
    place = sphere_placement(scene, scatterers)
    centres = sphere_centres(scene, scatterers)[0]
    out: list[GhostSet] = []
    pol = polarization_vector(config.polarization)
    found = [p for p in (image_paths(refl, scatterers, buffers, lam, polarization=pol)
                         for refl in reflectors) if p is not None]
    # Every reflector's second legs in one test (one pass per blocking object).
    flags = second_legs_clear(scene, found, scatterers, lam)
    valid = [_subset_paths(p, c) for p, c in zip(found, flags, strict=True) if np.any(c)]
    for paths in valid:
        out += _reflector_ghosts(paths, scene, scatterers, antennas=(p_tx, p_rx),
                                 patterns=(pat_t, pat_r), place=place, centres=centres,
                                 pol=pol, wavelength_m=lam, order=order)
    if order >= 2:
        out += two_surface_ghosts(scatterers, valid, p_tx, p_rx, scene=scene, wavelength_m=lam,
                                  patterns=(pat_t, pat_r), place=place, centres=centres)
        sc = scatterers
        out += one_leg_double_ghosts(
            sc, reflectors, polarization=config.polarization, wavelength_m=lam,
            tx_positions_m=p_tx, rx_positions_m=p_rx, patterns=(pat_t, pat_r),
            buffers=buffers, aspect=lambda rows, src: _corner_bistatic(
                scene, sc, rows, src, np.zeros_like(src), lam), place=place, centres=centres)
    # The room's own multiple bounces between its faces: edges, corners, echoes.
    out += room_returns(scene, config, reflectors, buffers=buffers, order=order,
                        time_s=scatterers.time_s)
    # The rig's own front returns every reflector's echo to it once more (from order 1).
    out += rig_front_ghosts(scene.materials, config, reflectors, time_s=scatterers.time_s,
                            buffers=buffers)
    return out


def _reflector_ghosts(paths: ImagePaths, scene: RadarScene, scatterers: Scatterers, *,
                      antennas: tuple[NDArray[np.float64], NDArray[np.float64]],
                      patterns: tuple[ElementPattern, ElementPattern], place: Place,
                      centres: NDArray[np.float64], pol: NDArray[np.float64],
                      wavelength_m: float, order: int) -> list[GhostSet]:
    """One reflector's ghost sets (:func:`ghost_scatterers`): paths (a) and (b), and (c).

    (a) Tx mirrored and (b) Rx mirrored (order 1): the scatterers at their real (bistatic)
    positions, weighted by the pattern ratio on the mirrored leg; (c) (order 2): the
    scatterers' images seen with the real antennas.
    """
    (p_tx, p_rx), (pat_t, pat_r), lam = antennas, patterns, wavelength_m
    rows, images, r = paths.rows, paths.images_m, paths.reflector
    pos = scatterers.positions_m[rows]
    vel = scatterers.velocities_mps[rows]
    acc = (None if scatterers.accelerations_mps2 is None
           else scatterers.accelerations_mps2[rows])
    origin_image = r.mirror(np.zeros(3))
    aspect2 = _corner_aspect(scene, scatterers, rows,
                             np.broadcast_to(origin_image, images.shape).copy())
    # Order 1: real positions, one mirrored antenna set; pattern ratio on that leg.
    g_direct_t = np.maximum(element_gain(pat_t, pos), MIN_GAIN)
    g_direct_r = np.maximum(element_gain(pat_r, pos), MIN_GAIN)
    ratio_t = element_gain(pat_t, images) / g_direct_t
    ratio_r = element_gain(pat_r, images) / g_direct_r
    aspect1 = _corner_bistatic(scene, scatterers, rows, np.zeros_like(images),
                               np.broadcast_to(origin_image, images.shape).copy(), lam)
    zero = np.zeros_like(images)
    image_of_radar = np.broadcast_to(origin_image, images.shape)
    gamma, gamma2 = _sphere_gammas(paths, pos, centres, pol, origin_image)
    bistatic = place(rows, pos, image_of_radar, zero)
    out = [GhostSet(_ghosts(scatterers, rows, bistatic, vel, acc,
                            gamma * np.sqrt(ratio_t * aspect1)),
                    1, r.object_index, tx_positions_m=r.mirror(p_tx)),
           GhostSet(_ghosts(scatterers, rows, bistatic, vel, acc,
                            gamma * np.sqrt(ratio_r * aspect1)),
                    1, r.object_index, rx_positions_m=r.mirror(p_rx))]
    if order >= 2:
        v_img = r.mirror_vectors(vel) + 2.0 * r.normal_speed_mps * r.normal
        a_img = None if acc is None else r.mirror_vectors(acc)
        seen = r.mirror(place(rows, pos, image_of_radar, image_of_radar))
        out.append(GhostSet(
            _ghosts(scatterers, rows, seen, v_img, a_img, gamma2 * np.sqrt(aspect2)),
            2, r.object_index))
    return out


def flat_plate_rcs(width_m: float, height_m: float, wavelength_m: float,
                   direction: NDArray[np.float64], normal: NDArray[np.float64],
                   axes: NDArray[np.float64]) -> float:
    """Monostatic physical-optics RCS of a flat perfectly conducting rectangle (m²).

    ``σ = 4π (a b)² / λ² · cos²θ · sinc²(k a sinθ cosφ) · sinc²(k b sinθ sinφ)`` with
    ``k = 2π/λ`` and ``a``, ``b`` the full side lengths (Knott, Shaeffer & Tuley, *Radar
    Cross Section*, 2nd ed., Table 5.2), seen from the unit ``direction``; ``normal`` is the
    plate's normal on the lit side and ``axes`` (2, 3) its edge directions (along ``a``,
    ``b``). Zero when it is seen from behind or edge-on.
    """
    cos_t = float(direction @ normal)
    if cos_t <= 0:
        return 0.0
    k = 2.0 * np.pi / wavelength_m
    u_a, u_b = float(direction @ axes[0]), float(direction @ axes[1])
    # np.sinc(x) = sin(πx)/(πx): sin(k a u)/(k a u) = np.sinc(k a u / π).
    pattern = np.sinc(k * width_m * u_a / np.pi) * np.sinc(k * height_m * u_b / np.pi)
    return float(4.0 * np.pi * (width_m * height_m) ** 2 / wavelength_m**2
                 * cos_t**2 * pattern**2)


def rig_front_ghosts(materials: Mapping[str, DualBandMaterial], config: RadarConfig,
                     reflectors: Sequence[Reflector], *, time_s: float,
                     buffers: RenderBuffers | None = None) -> list[GhostSet]:
    """The double bounce between the scene's planar reflectors and the rig's own front.

    ``materials`` is the material table (the rig front's material is looked up in it).

    Path radar → reflector → rig front → reflector → radar: by the image method, the real
    array sees the reflector's mirror image of the rig front (a flat plate
    ``config.rig_front_width_m × rig_front_height_m`` in the board plane, centred on the
    radar origin, facing the boresight), at twice the radar's distance ``s0`` to the plane
    when it faces the radar. Its amplitude is the monostatic flat-plate RCS
    (:func:`flat_plate_rcs`) of that image seen from the radar, × Γ² of the reflector (two
    reflections, with its coherent factor at normal incidence) × Γ of the rig front's
    material (with its own coherent factor). The reflection point (the foot of the
    perpendicular from the radar to the plane) must lie inside the reflector's rectangle and
    be seen in the render (as for :func:`image_paths`); the image moves at twice the
    reflector's normal speed. One scatterer per reflector, attributed to the reflector's
    object (a detection of it is labelled ``ghost`` with that id).

    Returns
    -------
    list of GhostSet
        Per reflector with the path, one set of order 2 (an image scatterer, real
        antennas); empty when the rig front is off (a zero size), its
        material does not reflect or no reflector faces the radar.
    """
    width, height = config.rig_front_width_m, config.rig_front_height_m
    if width <= 0 or height <= 0 or not reflectors:
        return []
    mat = materials.get(config.rig_front_material)
    if mat is None:
        return []
    band = mat.band("radar")
    lam = config.wavelength_m
    gamma_front = complex(band.coefficients(SPEED_OF_LIGHT / lam)[0])
    if band.opacity <= 0 or gamma_front == 0:
        return []
    g = 4.0 * np.pi * band.height_rms_m / lam          # coherent factor at normal incidence
    gamma_front *= float(np.exp(-0.5 * g * g))
    eye = np.eye(3)
    positions, velocities, rcs, phase, owner = [], [], [], [], []
    for reflector in reflectors:
        facing = _facing_radar(reflector)
        if facing is None:
            continue
        refl, s0 = facing
        image = refl.mirror(np.zeros(3))                 # the rig front's image: 2 s0 away
        foot = 0.5 * image                               # the reflection point
        local = (foot - refl.center_m) @ refl.axes.T
        if not np.all(np.abs(local) <= refl.half_size_m):
            continue
        if buffers is not None and not _reflector_seen(buffers, foot[None],
                                                       refl.object_index)[0]:
            continue
        towards_radar = -image / (2.0 * s0)
        sigma = flat_plate_rcs(width, height, lam, towards_radar,
                               refl.mirror_vectors(eye[2]), refl.mirror_vectors(eye[:2]))
        if sigma <= 0:
            continue
        g = 4.0 * np.pi * refl.height_rms_m / lam
        amplitude = refl.gamma**2 * np.exp(-g * g) * gamma_front
        positions.append(image)
        velocities.append(2.0 * refl.normal_speed_mps * refl.normal)
        rcs.append(sigma * abs(amplitude) ** 2)
        phase.append(float(np.angle(amplitude)))
        owner.append(refl.object_index)
    return [GhostSet(Scatterers(
        time_s=time_s, wavelength_m=lam, positions_m=p[None], velocities_mps=v[None],
        rcs_m2=np.array([a]), phase_rad=np.array([ph]),
        object_index=np.array([i], dtype=np.int32),
        kind=np.array([KIND_POINT_TARGET], dtype=np.int8)), 2, i)
        for p, v, a, ph, i in zip(positions, velocities, rcs, phase, owner, strict=True)]


def multipath_if(scene: RadarScene, scatterers: Scatterers,
                 config: RadarConfig, *, buffers: RenderBuffers | None = None,
                 order: int | None = None, threads: int | None = None) -> ComplexCube:
    """Ideal IF of all the multipath ghosts of a frame (to add to the direct IF).

    :func:`ghost_scatterers` then :func:`synthesize_ghosts`.

    Returns
    -------
    ndarray, shape (chirps, tx*rx, samples), complex128
        Zeros when there are no ghosts.
    """
    sets = ghost_scatterers(scene, scatterers, config, buffers=buffers, order=order)
    return synthesize_ghosts(sets, config, threads=threads)


def synthesize_ghosts(sets: Sequence[GhostSet], config: RadarConfig, *,
                      threads: int | None = None) -> ComplexCube:
    """Ideal IF of ghost sets (:func:`ghost_scatterers`).

    Every set keeps its own (mirrored or real) antennas, and all of them share one
    transform per Tx–Rx pair (:func:`~simcore.sensors.radar.synthesis.synthesize_if_sets`):
    the sets are many (two per reflector, one per pair of faces at order 2) and small (a
    curved object's facets are one ghost source), so a transform each cost far more than
    their points.

    Returns
    -------
    ndarray, shape (chirps, tx*rx, samples), complex128
        Zeros when there are no ghosts.
    """
    parts = [(g.scatterers, g.tx_positions_m, g.rx_positions_m) for g in sets
             if len(g.scatterers)]
    n = sum(len(sc) for sc, _, _ in parts)
    return synthesize_if_sets(parts, config,
                              threads=threads if threads is not None or n >= SMALL_SET else 1)


#: Ghost sets smaller than this (all sets together) are synthesised on the calling thread:
#: their transforms cost little more than their fixed part, and the pool's threads would
#: contend for the interpreter (600 office ghosts at order 2: 6.8 ms here, 11 ms pooled).
SMALL_SET = 4096


def _concat(sets: list[Scatterers]) -> Scatterers:
    """One :class:`Scatterers` of several (same time and wavelength).

    A set without accelerations counts as unaccelerated when another has them.
    """
    if len(sets) == 1:
        return sets[0]
    acc = None
    if any(s.accelerations_mps2 is not None for s in sets):
        acc = np.concatenate([np.zeros_like(s.positions_m) if s.accelerations_mps2 is None
                              else s.accelerations_mps2 for s in sets])
    return Scatterers(
        time_s=sets[0].time_s, wavelength_m=sets[0].wavelength_m,
        positions_m=np.concatenate([s.positions_m for s in sets]),
        velocities_mps=np.concatenate([s.velocities_mps for s in sets]),
        rcs_m2=np.concatenate([s.rcs_m2 for s in sets]),
        phase_rad=np.concatenate([s.phase_rad for s in sets]),
        object_index=np.concatenate([s.object_index for s in sets]),
        kind=np.concatenate([s.kind for s in sets]),
        accelerations_mps2=acc)


__all__ = ["MIN_AREA_M2", "MIN_REFLECTION", "GhostSet", "ImagePaths", "Reflector",
           "find_reflectors", "flat_plate_rcs", "ghost_scatterers", "image_paths",
           "leg_blockers", "multipath_if", "rig_front_ghosts", "second_leg_clear",
           "second_legs_clear", "synthesize_ghosts"]
