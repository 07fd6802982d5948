"""ToF multipath from the whole room: diffuse light bounced any number of times.

The camera's illumination lights the surfaces it reaches; each lit Lambertian surface
re-emits ``ρ E`` (its radiant exitance) in all directions, lighting every surface it sees,
which re-emits again, and so on; the camera's pixels collect all of it. Every path carries
its optical length, so each order adds a phasor of the modulation frequency on top of the
direct return and pulls the pixel's phase (its depth) towards longer paths.

The room is cut into surfels (small flat triangles, :func:`surfels_from_room`) from every
mesh of the scene — not only the surfaces the camera sees. With the radiometry of
:mod:`simcore.scene.tof_config` (direct signal ``S = k f(θ) / R²``, i.e. the illumination's
irradiance at range ``R`` is ``cos θ / R²`` in units of its radiant intensity), the phasor
radiosity of the surfels is solved as the Neumann series of the radiosity equation::

    M⁽¹⁾_j = ρ_j · L(ω_j) · cos θ_j / R_j² · lit_j · e^{i k R_j}
    M⁽ⁿ⁺¹⁾_i = ρ_i Σ_j F_ij V_ij e^{i k |c_i − c_j|} M⁽ⁿ⁾_j

(``k = 2π f / c``, ``L`` the illumination's angular profile, ``lit_j`` whether the light
reaches the surfel, from the camera's own render as a shadow map), summed to convergence
(or to a given number of bounces). ``F_ij`` is the exact point-to-triangle form factor from
the surfel's centre (Lambert's contour formula, clipped to the receiver's horizon), so
surfels that touch — the two walls of a crease — exchange the right amount of light, and
``V_ij`` the visibility of the segment between them (every triangle of the scene occludes).
A camera pixel at P (normal n_P, albedo ρ_P) then receives::

    S_ind(P) = k ρ_P e^{i k R_P} Σ_j F(P → j) V(P, c_j) e^{i k |P − c_j|} Σ_n M⁽ⁿ⁾_j

— one-bounce light (n = 1) and every higher order, from senders anywhere in the scene,
occluded by anything in between. The same sum with ``k = 0`` gives the indirect light's
offset (its intensity).

Assumptions and limits: Lambertian (diffuse) surfaces only — glossy and mirror paths are
:mod:`simcore.sensors.tof.specular`'s; radiosity is constant over a surfel (size
``patch_m``); visibility between surfels is decided centre to centre; the phase of a
sender is taken at its centre (at 20 MHz a 0.1 m surfel spans 0.04 rad).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.scene.camera import PinholeIntrinsics

F64 = NDArray[np.float64]
#: Surfels are displaced this far along their normal before a visibility test (m), so a
#: segment does not hit the surfaces it starts and ends on.
LIFT_M = 1e-4
#: A pair farther apart than this many surfel sizes uses the point form factor
#: ``A cos θ_i cos θ_j / (π d²)`` (within 1 % of the exact one there) instead of the exact
#: contour integral.
FAR_SIZES = 4.0
#: Pieces smaller than ``patch_m² / SLIVER_PARTS`` join a cluster (:func:`surfels_from_room`).
SLIVER_PARTS = 16.0


@dataclass(frozen=True)
class Room:
    """Every surface of a scene as triangles (world frame).

    Attributes
    ----------
    triangles : ndarray, shape (T, 3, 3)
        Vertices (m).
    normals : ndarray, shape (T, 3)
        Unit normal of the side that reflects light (a two-sided surface has a second,
        flipped triangle).
    albedo : ndarray, shape (T,)
        Diffuse albedo of the ToF band (``(1 − metallic) reflectance``).
    occluder_start : ndarray of int, shape (B + 1,)
        The triangles form ``B`` groups (objects): group ``b`` is
        ``triangles[occluder_start[b]:occluder_start[b + 1]]``; visibility tests skip a group
        whose bounding box a segment misses.
    moving : ndarray of bool, shape (B,), optional
        Which groups the project moves (a motion, a person's body); None: none is known to.
    """

    triangles: F64
    normals: F64
    albedo: F64
    occluder_start: NDArray[np.int64]
    moving: NDArray[np.bool_] | None = None

    def key(self) -> bytes:
        """A digest of the room's arrays (cache keys)."""
        moving = b"" if self.moving is None else self.moving.tobytes()
        return hashlib.sha1(b"".join((self.triangles.tobytes(), self.normals.tobytes(),
                                      self.albedo.tobytes(),
                                      self.occluder_start.tobytes(), moving))).digest()


def room_from_meshes(meshes: list[tuple[F64, NDArray[np.int64], F64]], albedo: list[float],
                     *, two_sided: list[bool], moving: list[bool] | None = None) -> Room:
    """A :class:`Room` from world-frame triangle meshes, one per object.

    Parameters
    ----------
    meshes : list of (points, triangles, vertex_normals)
        Per object: vertex positions (P, 3) in the world frame (m), vertex indices (T, 3)
        and unit vertex normals (P, 3) (world frame) that say which side is the outside.
    albedo : list of float
        Each object's diffuse albedo.
    two_sided : list of bool, keyword-only
        Objects whose triangles reflect on both sides (open surfaces such as planes).
    moving : list of bool, optional, keyword-only
        Objects the project moves (:attr:`Room.moving`).
    """
    tris, nrms, rhos, start = [], [], [], [0]
    for (points, faces, vnormals), rho, both in zip(meshes, albedo, two_sided, strict=True):
        t = points[faces]
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        length = np.linalg.norm(n, axis=1)
        keep = length > 1e-12
        t, n = t[keep], n[keep] / length[keep, None]
        outside = vnormals[faces[keep]].sum(axis=1)
        n = np.where((np.einsum("ij,ij->i", n, outside) < 0)[:, None], -n, n)
        if both:
            t = np.concatenate([t, t[:, ::-1]])
            n = np.concatenate([n, -n])
        tris.append(t)
        nrms.append(n)
        rhos.append(np.full(len(t), rho))
        start.append(start[-1] + len(t))
    if not tris:
        return Room(np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros(0),
                    np.zeros(1, dtype=np.int64))
    return Room(np.concatenate(tris), np.concatenate(nrms), np.concatenate(rhos),
                np.asarray(start, dtype=np.int64),
                None if moving is None else np.asarray(moving, dtype=bool))


@dataclass(frozen=True)
class Surfels:
    """Small flat triangles that carry the radiosity, shape (N, …) per attribute.

    Attributes
    ----------
    vertices : ndarray, shape (N, 3, 3)
        World-frame vertices (m).
    centre : ndarray, shape (N, 3)
    normal : ndarray, shape (N, 3)
        Unit normal of the reflecting side.
    area : ndarray, shape (N,)
        m².
    albedo : ndarray, shape (N,)
    size : ndarray, shape (N,)
        Longest edge (m).
    """

    vertices: F64
    centre: F64
    normal: F64
    area: F64
    albedo: F64
    size: F64


def surfels_from_room(room: Room, *, patch_m: float,
                      facing: NDArray[np.bool_] | None = None) -> Surfels:
    """Cut the triangles of ``room`` that can exchange light into pieces of about ``patch_m``.

    Each triangle is bisected at the midpoint of its longest edge until no edge exceeds
    ``√2 · patch_m`` (a square of side ``patch_m`` ends as two right triangles; the pieces
    tile the triangle exactly; a long sliver becomes a row of pieces, not a grid of
    slivers). Triangles that face no other triangle (:func:`facing_any`: the outer
    faces of a room's walls) are left out: no light reaches them. Triangles much smaller
    than a surfel (longest edge under ``patch_m / 2``: a fine mesh such as a person's) and
    slivers (pieces of area under ``patch_m² / SLIVER_PARTS``: the thin sides of a slab, a
    thin cylinder's facets) are merged per object into clusters (:func:`_clusters`), each
    one surfel.

    Parameters
    ----------
    facing : ndarray of bool, shape (T,), optional, keyword-only
        The triangles kept (default :func:`facing_any` over the whole room).
    """
    keep = facing_any(room.triangles, room.normals) if facing is None else facing
    group = np.repeat(np.arange(len(room.occluder_start) - 1), np.diff(room.occluder_start))
    longest = np.linalg.norm(np.roll(room.triangles, -1, axis=1) - room.triangles,
                             axis=2).max(axis=1) if len(room.triangles) else np.zeros(0)
    tiny = keep & (longest < patch_m / 2)
    big = keep & ~tiny
    cut, owner = _cut(room.triangles[big], room.normals[big], room.albedo[big],
                      patch_m=patch_m)
    sliver = cut.area < patch_m**2 / SLIVER_PARTS
    if not tiny.any() and not sliver.any():
        return cut
    v = np.concatenate([room.triangles[tiny], cut.vertices[sliver]])
    merged = _clusters(v, np.concatenate([room.normals[tiny], cut.normal[sliver]]),
                       np.concatenate([room.albedo[tiny], cut.albedo[sliver]]),
                       np.concatenate([group[tiny], group[big][owner[sliver]]]),
                       patch_m=patch_m)
    return Surfels(*(np.concatenate([a[~sliver], b]) for a, b in zip(
        (cut.vertices, cut.centre, cut.normal, cut.area, cut.albedo, cut.size),
        (merged.vertices, merged.centre, merged.normal, merged.area, merged.albedo,
         merged.size), strict=True)))


def _cut(tris: F64, normals: F64, albedo: F64, *, patch_m: float
         ) -> tuple[Surfels, NDArray[np.int64]]:
    """Bisect triangles (shape (T, 3, 3)) into surfels (:func:`surfels_from_room`).

    Returns the surfels and, per surfel, the index of the triangle it was cut from.
    """
    owner = np.arange(len(tris))
    done_v, done_o = [], []
    while len(tris):
        edges = np.linalg.norm(np.roll(tris, -1, axis=1) - tris, axis=2)   # edge a: a → a+1
        longest = edges.argmax(axis=1)
        small = edges.max(axis=1) <= patch_m * math.sqrt(2.0) * (1 + 1e-9)
        done_v.append(tris[small])
        done_o.append(owner[small])
        tris, owner, longest = tris[~small], owner[~small], longest[~small]
        a = longest
        b, c = (a + 1) % 3, (a + 2) % 3
        idx = np.arange(len(tris))
        va, vb, vc = tris[idx, a], tris[idx, b], tris[idx, c]
        mid = (va + vb) / 2
        tris = np.concatenate([np.stack([va, mid, vc], axis=1), np.stack([mid, vb, vc], axis=1)])
        owner = np.concatenate([owner, owner])
    v = np.concatenate(done_v) if done_v else np.zeros((0, 3, 3))
    who = np.concatenate(done_o) if done_o else np.zeros(0, dtype=np.int64)
    area = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
    size = np.linalg.norm(v - np.roll(v, 1, axis=1), axis=2).max(axis=1) if len(v) \
        else np.zeros(0)
    return Surfels(vertices=v, centre=v.mean(axis=1), normal=normals[who], area=area,
                   albedo=albedo[who], size=size), who


def _clusters(tris: F64, normals: F64, albedo: F64, group: NDArray[np.int64], *,
              patch_m: float) -> Surfels:
    """Merge small triangles into one surfel per object, ``patch_m`` cube and facing.

    Triangles of one object whose centroids fall in the same cube of side ``patch_m`` and
    whose normals share their dominant axis and its sign form a cluster. Its surfel is the
    equilateral triangle, centred on the area-weighted centroid, whose area vector is the
    cluster's (``Σ a_i n_i``: the area it shows in every direction it faces, to first
    order), albedo the area-weighted mean.
    """
    a = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]),
                             axis=1)
    c = tris.mean(axis=1)
    axis = np.abs(normals).argmax(axis=1)
    face = 2 * axis + (normals[np.arange(len(axis)), axis] < 0)
    cell = np.floor(c / patch_m).astype(np.int64)
    key = np.column_stack([group, face, cell])
    _, label = np.unique(key, axis=0, return_inverse=True)
    label = label.ravel()
    k = label.max() + 1
    vec = np.zeros((k, 3))
    np.add.at(vec, label, a[:, None] * normals)
    area = np.linalg.norm(vec, axis=1)
    weight = np.bincount(label, weights=a, minlength=k)
    centre = np.stack([np.bincount(label, weights=a * c[:, d], minlength=k)
                       for d in range(3)], axis=1) / np.maximum(weight, 1e-300)[:, None]
    rho = np.bincount(label, weights=a * albedo, minlength=k) / np.maximum(weight, 1e-300)
    ok = area > 1e-12
    vec, area, centre, rho = vec[ok], area[ok], centre[ok], rho[ok]
    n = vec / area[:, None]
    helper = np.where((np.abs(n[:, 0]) < 0.9)[:, None], [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    t2 = np.cross(n, t1)
    side = np.sqrt(4.0 * area / math.sqrt(3.0))
    radius = side / math.sqrt(3.0)
    angles = np.array([0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0])
    v = (centre[:, None, :] + radius[:, None, None]
         * (np.cos(angles)[None, :, None] * t1[:, None, :]
            + np.sin(angles)[None, :, None] * t2[:, None, :]))
    return Surfels(vertices=v, centre=centre, normal=n, area=area, albedo=rho, size=side)


def facing_any(triangles: F64, normals: F64, *, eps_m: float = 1e-6) -> NDArray[np.bool_]:
    """Which triangles face another one: each has a vertex in front of the other's plane.

    A triangle that faces no other cannot send light to one nor receive light from one;
    the triangle itself may still be lit by the camera, but then it lights nothing.

    Returns
    -------
    ndarray of bool, shape (T,)
    """
    if len(triangles) == 0:
        return np.zeros(0, dtype=bool)
    offset = np.einsum("ij,ij->i", normals, triangles[:, 0])                  # n_i · a_i
    return _facing(np.ascontiguousarray(triangles, dtype=np.float64),
                   np.ascontiguousarray(normals, dtype=np.float64), offset, eps_m)


@kernel
def _above(n: F64, offset: float, v: F64, eps_m: float) -> bool:
    """Whether a vertex of triangle ``v`` lies more than ``eps_m`` before plane ``(n, offset)``."""
    for a in range(3):
        if n[0] * v[a, 0] + n[1] * v[a, 1] + n[2] * v[a, 2] - offset > eps_m:
            return True
    return False


@kernel
def _facing(triangles: F64, normals: F64, offset: F64, eps_m: float) -> NDArray[np.bool_]:
    """:func:`facing_any`'s pair test, stopping at the first triangle found."""
    t = triangles.shape[0]
    out = np.zeros(t, dtype=np.bool_)
    for i in range(t):
        for j in range(t):
            if (_above(normals[i], offset[i], triangles[j], eps_m)
                    and _above(normals[j], offset[j], triangles[i], eps_m)):
                out[i] = True
                break
    return out


def occluder_boxes(room: Room) -> tuple[F64, F64]:
    """Bounding box (lower, upper corners, each shape (B, 3)) of each occluder group."""
    b = len(room.occluder_start) - 1
    lo, hi = np.zeros((b, 3)), np.zeros((b, 3))
    for g in range(b):
        t = room.triangles[room.occluder_start[g]:room.occluder_start[g + 1]].reshape(-1, 3)
        if len(t):
            lo[g], hi[g] = t.min(axis=0), t.max(axis=0)
        else:
            lo[g], hi[g] = np.inf, -np.inf
    return lo, hi


@kernel
def _segment_clear(o: F64, e: F64, tris: F64, start: NDArray[np.int64], lo: F64, hi: F64
                   ) -> bool:
    """Whether the segment ``o → e`` crosses no triangle (Möller–Trumbore, slab test first)."""
    d0, d1, d2 = e[0] - o[0], e[1] - o[1], e[2] - o[2]
    for g in range(start.shape[0] - 1):
        t0, t1 = 0.0, 1.0
        miss = False
        for a in range(3):
            da = d0 if a == 0 else (d1 if a == 1 else d2)
            if abs(da) < 1e-300:
                if o[a] < lo[g, a] or o[a] > hi[g, a]:
                    miss = True
                    break
            else:
                ta, tb = (lo[g, a] - o[a]) / da, (hi[g, a] - o[a]) / da
                if ta > tb:
                    ta, tb = tb, ta
                t0, t1 = max(t0, ta), min(t1, tb)
                if t0 > t1:
                    miss = True
                    break
        if miss:
            continue
        for t in range(start[g], start[g + 1]):
            ax, ay, az = tris[t, 0, 0], tris[t, 0, 1], tris[t, 0, 2]
            e1x, e1y, e1z = tris[t, 1, 0] - ax, tris[t, 1, 1] - ay, tris[t, 1, 2] - az
            e2x, e2y, e2z = tris[t, 2, 0] - ax, tris[t, 2, 1] - ay, tris[t, 2, 2] - az
            px, py, pz = d1 * e2z - d2 * e2y, d2 * e2x - d0 * e2z, d0 * e2y - d1 * e2x
            det = e1x * px + e1y * py + e1z * pz
            if abs(det) < 1e-18:
                continue
            inv = 1.0 / det
            sx, sy, sz = o[0] - ax, o[1] - ay, o[2] - az
            u = (sx * px + sy * py + sz * pz) * inv
            if u < 0.0 or u > 1.0:
                continue
            qx, qy, qz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
            v = (d0 * qx + d1 * qy + d2 * qz) * inv
            if v < 0.0 or u + v > 1.0:
                continue
            s = (e2x * qx + e2y * qy + e2z * qz) * inv
            if 1e-9 < s < 1.0 - 1e-9:
                return False
    return True


@kernel
def _form_factor(p: F64, n: F64, v: F64) -> float:
    """Exact form factor from a point (unit normal ``n``) to a Lambertian triangle ``v``.

    Lambert's contour integral ``(1/2π) Σ_edges γ_e (n · ĝ_e)`` over the part of the
    triangle above the point's horizon (the triangle clipped to ``n · (x − p) ≥ 0``);
    ``γ_e`` the angle an edge subtends, ``ĝ_e`` the unit normal of the plane through the
    point and the edge.
    """
    poly = np.empty((4, 3))
    m = 0
    for a in range(3):
        b = (a + 1) % 3
        ha = n[0] * (v[a, 0] - p[0]) + n[1] * (v[a, 1] - p[1]) + n[2] * (v[a, 2] - p[2])
        hb = n[0] * (v[b, 0] - p[0]) + n[1] * (v[b, 1] - p[1]) + n[2] * (v[b, 2] - p[2])
        if ha >= 0.0:
            for c in range(3):
                poly[m, c] = v[a, c] - p[c]
            m += 1
        if (ha >= 0.0) != (hb >= 0.0):
            s = ha / (ha - hb)
            for c in range(3):
                poly[m, c] = v[a, c] + s * (v[b, c] - v[a, c]) - p[c]
            m += 1
    if m < 3:
        return 0.0
    total = 0.0
    for a in range(m):
        b = (a + 1) % m
        la = math.sqrt(poly[a, 0] ** 2 + poly[a, 1] ** 2 + poly[a, 2] ** 2)
        lb = math.sqrt(poly[b, 0] ** 2 + poly[b, 1] ** 2 + poly[b, 2] ** 2)
        if la < 1e-15 or lb < 1e-15:
            continue
        ux, uy, uz = poly[a, 0] / la, poly[a, 1] / la, poly[a, 2] / la
        wx, wy, wz = poly[b, 0] / lb, poly[b, 1] / lb, poly[b, 2] / lb
        cx, cy, cz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
        lc = math.sqrt(cx * cx + cy * cy + cz * cz)
        if lc < 1e-15:
            continue
        gamma = math.atan2(lc, ux * wx + uy * wy + uz * wz)
        total += gamma * (n[0] * cx + n[1] * cy + n[2] * cz) / lc
    return abs(total) / (2.0 * math.pi)


@kernel
def _exchange(p: F64, n: F64, j: int, centre: F64, normal: F64, vertices: F64, area: F64,
              size: F64) -> float:
    """Form factor from point ``p`` (normal ``n``) to surfel ``j``, 0 behind either side.

    Exact (:func:`_form_factor`) when the surfel is within :data:`FAR_SIZES` of its sizes,
    the point form factor beyond.
    """
    dx, dy, dz = centre[j, 0] - p[0], centre[j, 1] - p[1], centre[j, 2] - p[2]
    d2 = dx * dx + dy * dy + dz * dz
    cos_q = -(normal[j, 0] * dx + normal[j, 1] * dy + normal[j, 2] * dz)
    if cos_q <= 0.0 or d2 <= 0.0:
        return 0.0
    if d2 > (FAR_SIZES * size[j]) ** 2:
        cos_p = n[0] * dx + n[1] * dy + n[2] * dz
        if cos_p <= 0.0:
            return 0.0
        return area[j] * cos_p * cos_q / (math.pi * d2 * d2)
    return _form_factor(p, n, vertices[j])


@kernel
def _transfer(centre: F64, normal: F64, vertices: F64, area: F64, size: F64, tris: F64,
              start: NDArray[np.int64], lo: F64, hi: F64
              ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Form factors × visibility between surfels (receiver row, sender column) and distances.

    Returns
    -------
    factor, distance : ndarray, shape (N, N), float32
    """
    nn = centre.shape[0]
    factor = np.zeros((nn, nn), dtype=np.float32)
    dist = np.zeros((nn, nn), dtype=np.float32)
    _transfer_rows(centre, normal, vertices, area, size, tris, start, lo, hi, 0, nn, factor,
                   dist)
    return factor, dist


@kernel
def _transfer_rows(centre: F64, normal: F64, vertices: F64, area: F64, size: F64, tris: F64,
                   start: NDArray[np.int64], lo: F64, hi: F64, first: int, last: int,
                   factor: NDArray[np.float32], dist: NDArray[np.float32]) -> None:
    """:func:`_transfer`'s pairs ``(i, j > i)`` for ``first ≤ i < last``, into the arrays.

    The pairs of two disjoint ranges of ``i`` touch disjoint entries: two threads may fill
    one matrix.
    """
    nn = centre.shape[0]
    a = np.empty(3)
    b = np.empty(3)
    for i in range(first, last):
        for j in range(i + 1, nn):
            dx, dy, dz = centre[j, 0] - centre[i, 0], centre[j, 1] - centre[i, 1], \
                centre[j, 2] - centre[i, 2]
            dist[i, j] = dist[j, i] = math.sqrt(dx * dx + dy * dy + dz * dz)
            fij = _exchange(centre[i], normal[i], j, centre, normal, vertices, area, size)
            fji = _exchange(centre[j], normal[j], i, centre, normal, vertices, area, size)
            if fij == 0.0 and fji == 0.0:
                continue
            for c in range(3):
                a[c] = centre[i, c] + LIFT_M * normal[i, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            if _segment_clear(a, b, tris, start, lo, hi):
                factor[i, j] = fij
                factor[j, i] = fji


def transfer(surfels: Surfels, room: Room
             ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Surfel-to-surfel form factors with visibility, and centre distances (m).

    Returns
    -------
    factor : ndarray, shape (N, N), float32
        ``F_ij V_ij``: the fraction of surfel ``j``'s exitance that reaches ``i``'s centre
        as irradiance, divided by ``j``'s exitance.
    distance : ndarray, shape (N, N), float32
        ``|c_i − c_j|`` (m).
    """
    lo, hi = occluder_boxes(room)
    return _transfer(surfels.centre, surfels.normal, surfels.vertices, surfels.area,
                     surfels.size, room.triangles, room.occluder_start, lo, hi)


def radiosity(factor: NDArray[np.float32], distance: NDArray[np.float32], albedo: F64,
              emitted: NDArray[np.complex128], wavenumbers: list[float], *, bounces: int = 0,
              tolerance: float = 1e-5
              ) -> NDArray[np.complex128]:
    """Total phasor exitance of every surfel over all orders (Neumann series).

    Parameters
    ----------
    factor, distance : ndarray, shape (N, N)
        From :func:`transfer`.
    albedo : ndarray, shape (N,)
    emitted : ndarray of complex, shape (K, N)
        First-order exitance ``M⁽¹⁾`` per wavenumber (its phase the light's path so far).
    wavenumbers : list of float, length K
        ``k = 2π f / c`` (rad/m) of each row (0: the intensity).
    bounces : int, keyword-only
        Orders summed (1: ``M⁽¹⁾`` alone); 0: until an order adds less than
        ``tolerance`` of the sum.
    tolerance : float, keyword-only

    Returns
    -------
    ndarray of complex, shape (K, N)
        ``Σ_n M⁽ⁿ⁾``.
    """
    total = np.array(emitted, dtype=np.complex128)
    weighted = factor * albedo[:, None].astype(np.float32)           # ρ_i F_ij V_ij
    for row, k in enumerate(wavenumbers):
        kernel_k: NDArray[np.float32] | NDArray[np.complex64]
        if k == 0.0 and not np.any(total[row].imag):                  # the intensity: real
            kernel_k = weighted
            term = total[row].real.astype(np.float32)
        else:
            kernel_k = _phase_kernel(weighted, distance, k)
            term = total[row].astype(np.complex64)
        neumann_into(total[row], kernel_k, term, orders=bounces, tolerance=tolerance)
    return total


def neumann_into(total: NDArray[np.complex128],
                 kernel: NDArray[np.float32] | NDArray[np.complex64],
                 term: NDArray[np.float32] | NDArray[np.complex64], *, orders: int,
                 tolerance: float) -> None:
    """Add ``K term``, ``K² term``, … to ``total`` (in place): ``orders − 1`` products.

    ``orders`` 0: until a product adds less than ``tolerance`` of the first term's
    absolute sum (at most 10 000).
    """
    order = 1
    scale = max(float(np.abs(term).sum()), 1e-300)
    while orders == 0 or order < orders:
        term = kernel @ term
        total += term
        order += 1
        if orders == 0 and (float(np.abs(term).sum()) < tolerance * scale
                            or order > 10_000):
            break


@kernel
def _phase_kernel(weighted: NDArray[np.float32], distance: NDArray[np.float32], k: float
                  ) -> NDArray[np.complex64]:
    """``weighted · e^{i k distance}`` (complex64) in one pass, zero where ``weighted`` is."""
    out = np.zeros(weighted.shape, dtype=np.complex64)
    _phase_kernel_into(weighted, distance, k, out)
    return out


@kernel
def _phase_kernel_into(weighted: NDArray[np.float32], distance: NDArray[np.float32], k: float,
                       out: NDArray[np.complex64]) -> None:
    """:func:`_phase_kernel` written into ``out`` (zeros) of the same shape."""
    n, m = weighted.shape
    for i in range(n):
        for j in range(m):
            w = weighted[i, j]
            if w != 0.0:
                phase = k * distance[i, j]
                out[i, j] = complex(w * math.cos(phase), w * math.sin(phase))


@kernel
def _gather(points: F64, normals: F64, centre: F64, normal: F64, vertices: F64, area: F64,
            size: F64, senders: NDArray[np.int64], exitance: NDArray[np.complex128],
            k: F64, tris: F64, start: NDArray[np.int64], lo: F64, hi: F64
            ) -> NDArray[np.complex128]:
    """Irradiance phasors at receiver points from the ``senders`` surfels' exitance."""
    m = points.shape[0]
    out = np.zeros((k.shape[0], m), dtype=np.complex128)
    a = np.empty(3)
    b = np.empty(3)
    for r in range(m):
        for s in range(senders.shape[0]):
            j = senders[s]
            f = _exchange(points[r], normals[r], j, centre, normal, vertices, area, size)
            if f == 0.0:
                continue
            for c in range(3):
                a[c] = points[r, c] + LIFT_M * normals[r, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            if not _segment_clear(a, b, tris, start, lo, hi):
                continue
            d = math.sqrt((centre[j, 0] - points[r, 0]) ** 2 + (centre[j, 1] - points[r, 1]) ** 2
                          + (centre[j, 2] - points[r, 2]) ** 2)
            for q in range(k.shape[0]):
                out[q, r] += f * exitance[q, j] * complex(math.cos(k[q] * d),
                                                          math.sin(k[q] * d))
    return out


def gather(points: F64, normals: F64, surfels: Surfels, room: Room,
           exitance: NDArray[np.complex128], wavenumbers: list[float]
           ) -> NDArray[np.complex128]:
    """Irradiance phasor at receiver points from every surfel (with occlusion).

    Parameters
    ----------
    points, normals : ndarray, shape (M, 3)
        Receiver points and unit normals (world frame).
    exitance : ndarray of complex, shape (K, N)
        :func:`radiosity`'s total exitance.
    wavenumbers : list of float, length K

    Returns
    -------
    ndarray of complex, shape (K, M)
        ``Σ_j F(P → j) V e^{i k |P − c_j|} M_j`` (in units of the illumination's irradiance
        ``cos θ / R²``).
    """
    lo, hi = occluder_boxes(room)
    senders = np.flatnonzero(np.abs(exitance).max(axis=0) > 0).astype(np.int64) \
        if exitance.size else np.zeros(0, dtype=np.int64)
    return _gather(np.ascontiguousarray(points, dtype=np.float64),
                   np.ascontiguousarray(normals, dtype=np.float64), surfels.centre,
                   surfels.normal, surfels.vertices, surfels.area, surfels.size, senders,
                   np.ascontiguousarray(exitance), np.asarray(wavenumbers, dtype=np.float64),
                   room.triangles, room.occluder_start, lo, hi)


def first_exitance(surfels: Surfels, camera: F64, intrinsics: PinholeIntrinsics,
                   range_m: NDArray[np.floating], wavenumbers: list[float]
                   ) -> NDArray[np.complex128]:
    """Exitance of each surfel lit directly by the camera's illumination, per wavenumber.

    The illumination sits at the camera's centre and fills its rectangular field of view
    with uniform radiant intensity (the radiometry of :mod:`simcore.scene.tof_config`: its
    angular profile is 1 inside the field, 0 outside); its irradiance at a surfel at range
    ``R`` is ``cos θ / R²``. Whether the light reaches the surfel is read from the camera's
    own render, a shadow map from the light's very position: at four points of the surfel
    (its centre and the centres of its three corner quarters), a point is lit when it lies in
    the field and no farther than the rendered surface along its ray (within the range the
    surface spans over a render pixel at its slope).

    Parameters
    ----------
    camera : ndarray, shape (4, 4)
        Optical frame → world.
    intrinsics : PinholeIntrinsics
        The render's grid.
    range_m : ndarray, shape (H, W)
        The render's range (NaN/inf: nothing).
    wavenumbers : list of float

    Returns
    -------
    ndarray of complex, shape (K, N)
        ``ρ_j lit_j cos θ_j / R_j² · e^{i k R_j}``.
    """
    rot, origin = camera[:3, :3], camera[:3, 3]
    v = surfels.vertices
    c = surfels.centre
    samples = np.stack([c, *[(4 * v[:, a] + v[:, (a + 1) % 3] + v[:, (a + 2) % 3]) / 6
                             for a in range(3)]], axis=1)                   # (N, 4, 3)
    local = (samples - origin) @ rot                                        # optical frame
    dist = np.linalg.norm(local, axis=2)
    to_light = origin - c
    r = np.linalg.norm(to_light, axis=1)
    cos = np.einsum("ij,ij->i", surfels.normal, to_light) / np.maximum(r, 1e-12)
    z = local[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = intrinsics.fx * local[..., 0] / z + intrinsics.cx
        w = intrinsics.fy * local[..., 1] / z + intrinsics.cy
    inside = (z > 0) & (u >= 0) & (u < intrinsics.width) & (w >= 0) & (w < intrinsics.height)
    ui = np.clip(np.where(inside, u, 0), 0, intrinsics.width - 1).astype(np.int64)
    wi = np.clip(np.where(inside, w, 0), 0, intrinsics.height - 1).astype(np.int64)
    seen = np.asarray(range_m, dtype=np.float64)[wi, ui]
    slope = np.sqrt(np.maximum(1.0 - cos**2, 0.0)) / np.maximum(cos, 1e-3)
    tol = 0.005 + 2.0 * dist * slope[:, None] / intrinsics.fx
    lit = inside & np.isfinite(seen) & (dist <= seen + tol)
    fraction = lit.mean(axis=1)
    irradiance = np.where(cos > 0, fraction * cos / np.maximum(r, 1e-12) ** 2, 0.0)
    base = surfels.albedo * irradiance
    return np.stack([base * np.exp(1j * k * r) for k in wavenumbers])


#: Largest surfel-to-surfel matrices built (bytes, both of them together).
MAX_TRANSFER_BYTES = 4 * 2**30


__all__ = ["Room", "Surfels", "first_exitance", "gather", "radiosity", "room_from_meshes",
           "surfels_from_room", "transfer"]
