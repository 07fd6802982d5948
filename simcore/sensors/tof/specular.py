"""Specular near-IR inter-reflections: mirror paths through glossy surfaces back to the camera.

The direct return of a glossy surface (its monostatic lobe) is part of the render's band
response. What the render lacks is light that reaches a pixel *via* a mirror: the camera's
illumination lights a point Q, Q's reflection reaches the glossy point P₁ the pixel sees
(possibly through more glossy points), and P₁'s mirror reflection sends it to the camera.
By reciprocity such a path is traced from the pixel: the camera ray hits P₁, is mirrored
there (direction ``d − 2 (d·n) n``), travels to the next surface P₂, and so on for up to
``max_bounces`` surfaces. At every point P_k (k ≥ 2) the path connects to the illuminator
(the camera, at the origin): with ``l`` the unit vector from P_k to the camera and ``v``
the unit vector from P_k back along the path, P_k returns the response::

    f_k = ρ_k cos θ_l + F_k π D(θ_h) / (4 cos θ_v)        (GGX, G = 1)
    D(θ_h) = α² / (π (cos² θ_h (α² − 1) + 1)²),  cos θ_h = n · (l + v)/|l + v|

(``ρ`` the diffuse albedo, ``F`` the mirror reflectance, ``α`` the roughness), and the pixel
collects ``S = S₁ F₁ ⋯ F_{k−1} f_k / |P_k|²`` (radiance is conserved along mirror legs, so
only the irradiance at P_k falls off with its distance from the illuminator) over the
optical path ``|P₁| + |P₂ − P₁| + ⋯ + |P_k − P_{k−1}| + |P_k|``, the phasor of which is added
to the pixel's direct return before the phase is estimated.

A retroreflecting trihedral (three mutually perpendicular mirrors, apex A) sends the
triple-bounce ray back antiparallel to the camera ray ``u``: the unfolded path is the point
reflection ``X → 2A − X``, whose closest approach to the camera lies at the path length
``2 u · A`` — twice the distance from the camera to the projection of the apex on the ray,
so the pixel measures the apex's range along its ray, not the facet's.

The next surface along a mirror ray is found in screen space (:func:`_march`): the ray is
walked over the render's pixels (perspective-correct depth), and the first pixel whose
surface it passes behind is hit exactly on that pixel's tangent plane (exact for planar
facets).

Limits: only surfaces the camera sees can be hit (a mirror showing what is behind the
camera or outside the field of view shows nothing); a ray passing behind a nearer object
continues (it cannot know the hidden part); mirror legs between P_k and the camera are not
tested for occlusion; G = 1 (no masking), Fresnel F constant with angle.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.scene.materials import BandMaterial

F32 = NDArray[np.float32]
#: A material takes part as a mirror when its mirror reflectance reaches this …
MIN_MIRROR_REFLECTANCE = 0.02
#: … and its roughness (GGX α) is at most this.
MAX_MIRROR_ROUGHNESS = 0.5
#: Screen-space march: at most this many render pixels per ray.
MAX_MARCH_PX = 1024
#: Nearest depth a mirror ray is followed to (m).
NEAR_M = 0.02


def material_columns(bands: list[BandMaterial]) -> NDArray[np.float32]:
    """Per object ``(diffuse albedo, mirror reflectance F, GGX α)``, plus a zero row for −1.

    ``F = metallic · reflectance + (1 − metallic) · specular`` (a metal's reflectance is its
    Fresnel reflectance; a dielectric's ``specular`` its coat's), ``α = roughness``.

    Returns
    -------
    ndarray, shape (N + 1, 3), float32
    """
    rows = [((1.0 - b.metallic) * b.reflectance,
             b.metallic * b.reflectance + (1.0 - b.metallic) * b.specular,
             b.roughness) for b in bands]
    rows.append((0.0, 0.0, 1.0))
    return np.asarray(rows, dtype=np.float32)


def is_mirror(columns: NDArray[np.float32]) -> NDArray[np.bool_]:
    """Which rows of :func:`material_columns` reflect as mirrors, shape (N + 1,)."""
    return (columns[:, 1] >= MIN_MIRROR_REFLECTANCE) & (columns[:, 2] <= MAX_MIRROR_ROUGHNESS)


@kernel
def _march(points: F32, normals: F32, index: NDArray[np.int32], ox: float, oy: float,
           oz: float, dx: float, dy: float, dz: float, fx: float, fy: float, cx: float,
           cy: float, self_row: int, self_col: int) -> tuple[int, int, float]:
    """First render pixel whose surface the ray ``o + t d`` passes behind.

    Returns ``(row, col, t)`` with ``t`` the exact distance to that pixel's tangent plane, or
    ``(−1, −1, 0)`` when the ray leaves the image or the near plane.
    """
    h, w = index.shape
    t_max = 50.0
    if dz < 0.0:
        t_max = min(t_max, (oz - NEAR_M) / -dz)
    if t_max <= 0.0:
        return -1, -1, 0.0
    ex, ey, ez = ox + t_max * dx, oy + t_max * dy, oz + t_max * dz
    u0, v0 = fx * ox / oz + cx, fy * oy / oz + cy
    u1, v1 = fx * ex / ez + cx, fy * ey / ez + cy
    span = max(abs(u1 - u0), abs(v1 - v0)) + 1.0     # one render pixel per step
    inv0, inv1 = 1.0 / oz, 1.0 / ez
    for i in range(1, int(min(span, MAX_MARCH_PX)) + 1):
        a = i / span
        u, v = u0 + a * (u1 - u0), v0 + a * (v1 - v0)
        col, row = int(math.floor(u)), int(math.floor(v))
        if col < 0 or row < 0 or col >= w or row >= h:
            return -1, -1, 0.0
        if (row == self_row and col == self_col) or index[row, col] < 0:
            continue
        z_ray = 1.0 / (inv0 + a * (inv1 - inv0))
        if z_ray < points[row, col, 2]:
            continue
        nx, ny, nz = normals[row, col, 0], normals[row, col, 1], normals[row, col, 2]
        den = nx * dx + ny * dy + nz * dz
        if den >= 0.0:     # seen from behind: the ray passes behind this surface
            continue
        t = (nx * (points[row, col, 0] - ox) + ny * (points[row, col, 1] - oy)
             + nz * (points[row, col, 2] - oz)) / den
        if t > 1e-4:
            return row, col, t
    return -1, -1, 0.0


@kernel
def _response(nx: float, ny: float, nz: float, px: float, py: float, pz: float,
              vx: float, vy: float, vz: float, rho: float, mirror: float, alpha: float
              ) -> float:
    """``f_k`` of the module docstring at P (normal n; v: unit vector back along the path)."""
    dist = math.sqrt(px * px + py * py + pz * pz)
    lx, ly, lz = -px / dist, -py / dist, -pz / dist
    cos_l = nx * lx + ny * ly + nz * lz
    cos_v = nx * vx + ny * vy + nz * vz
    if cos_l <= 0.0 or cos_v <= 0.0:
        return 0.0
    f = rho * cos_l
    if mirror > 0.0:
        hx, hy, hz = lx + vx, ly + vy, lz + vz
        norm = math.sqrt(hx * hx + hy * hy + hz * hz)
        cos_h = (nx * hx + ny * hy + nz * hz) / norm
        a2 = alpha * alpha
        den = cos_h * cos_h * (a2 - 1.0) + 1.0
        d = a2 / (math.pi * den * den)
        f += mirror * math.pi * d / (4.0 * cos_v)
    return f


@kernel
def _trace(points: F32, normals: F32, index: NDArray[np.int32], columns: F32,
           mirror: NDArray[np.bool_], intrinsics: NDArray[np.float64], y: int, x: int,
           factor: F32, path: F32) -> None:
    """Trace the mirror path of render pixel (y, x) into ``factor[:, y, x]``, ``path[:, y, x]``."""
    fx, fy, cx, cy = intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]
    obj = index[y, x]
    ox, oy, oz = points[y, x, 0], points[y, x, 1], points[y, x, 2]
    length = math.sqrt(ox * ox + oy * oy + oz * oz)
    dx, dy, dz = ox / length, oy / length, oz / length
    nx, ny, nz = normals[y, x, 0], normals[y, x, 1], normals[y, x, 2]
    throughput = columns[obj, 1]
    row, col = y, x
    for k in range(factor.shape[0]):
        dn = dx * nx + dy * ny + dz * nz
        dx, dy, dz = dx - 2 * dn * nx, dy - 2 * dn * ny, dz - 2 * dn * nz
        row, col, t = _march(points, normals, index, ox, oy, oz, dx, dy, dz,
                             fx, fy, cx, cy, row, col)
        if row < 0:
            return
        ox, oy, oz = ox + t * dx, oy + t * dy, oz + t * dz
        length += t
        nxt = index[row, col]
        nx, ny, nz = normals[row, col, 0], normals[row, col, 1], normals[row, col, 2]
        is_m = mirror[nxt]
        f = _response(nx, ny, nz, ox, oy, oz, -dx, -dy, -dz, columns[nxt, 0],
                      columns[nxt, 1] if is_m else 0.0, columns[nxt, 2])
        r2 = ox * ox + oy * oy + oz * oz
        factor[k, y, x] = throughput * f / r2
        path[k, y, x] = length + math.sqrt(r2)
        if not is_m:
            return
        throughput *= columns[nxt, 1]


@kernel
def specular_paths(points: F32, normals: F32, index: NDArray[np.int32], columns: F32,
                   mirror: NDArray[np.bool_], intrinsics: NDArray[np.float64],
                   max_bounces: int, step: int) -> tuple[F32, F32]:
    """Signal factor and optical path of the mirror paths of every render pixel.

    One render pixel of each ``step × step`` block (the first that sees a mirror) is
    traced; the block's other pixels on the same object take its result.

    Parameters
    ----------
    points, normals : ndarray, shape (H, W, 3), float32
        Render points (optical frame, m) and unit normals.
    index : ndarray, shape (H, W), int32
        Object index (−1: nothing).
    columns : ndarray, shape (N + 1, 3), float32
        :func:`material_columns`.
    mirror : ndarray of bool, shape (N + 1,)
        :func:`is_mirror`.
    intrinsics : ndarray, shape (4,)
        ``fx, fy, cx, cy`` of the render grid (pixels).
    max_bounces : int
        Surfaces per path (2: one mirror; 3: a trihedral's triple bounce).
    step : int
        Block size (the ToF supersampling: one path per sensor pixel and object).

    Returns
    -------
    factor : ndarray, shape (max_bounces − 1, H, W), float32
        ``F₁ ⋯ F_{k−1} f_k / |P_k|²`` (1/m²) of the path ending at its k-th surface
        (axis 0: k − 2); times ``S₁`` it is the signal in electrons.
    path : ndarray, shape (max_bounces − 1, H, W), float32
        Its total optical path (m), camera to camera.
    """
    h, w = index.shape
    nb = max(max_bounces - 1, 1)
    factor = np.zeros((nb, h, w), dtype=np.float32)
    path = np.zeros((nb, h, w), dtype=np.float32)
    for by in range(0, h, step):
        for bx in range(0, w, step):
            ty, tx = -1, -1
            for y in range(by, min(by + step, h)):
                for x in range(bx, min(bx + step, w)):
                    if ty < 0 and index[y, x] >= 0 and mirror[index[y, x]]:
                        ty, tx = y, x
            if ty < 0:
                continue
            _trace(points, normals, index, columns, mirror, intrinsics, ty, tx, factor, path)
            for y in range(by, min(by + step, h)):
                for x in range(bx, min(bx + step, w)):
                    if index[y, x] == index[ty, tx] and (y != ty or x != tx):
                        for k in range(nb):
                            factor[k, y, x] = factor[k, ty, tx]
                            path[k, y, x] = path[k, ty, tx]
    return factor, path
