"""Whole-room ToF multipath with moving objects, to first order in what moves.

:func:`~simcore.sensors.tof.room_cache.room_indirect` solves the room exactly: every pair
of surfels, every bounce, every occluder. With something moving (the office's walker)
that costs seconds per frame, because each frame the moving object's surfels exchange
light with the whole room and its triangles may block any segment. This module keeps the
exact solution of the objects that stand still, and adds what the moving objects change
to first order in them (each term below is one interaction with a moving object):

1. **The light they take from the room.** The camera's illumination no longer reaches
   what a moving object shadows: the still surfels' first exitance ``E`` changes by
   ``ΔE`` (read from the camera's own render, as always). The still radiosity becomes
   ``B = B_ref + Σ_n K^n ΔE`` with ``K = ρ F V e^{ikd}`` the still exchange kept from the
   reference solve, summed until an order adds less than :data:`DELTA_TOLERANCE` of the
   whole exitance (exact to that tolerance: ``K`` is linear).
2. **The light they send.** Each moving surfel's exitance is its own first exitance plus
   ``ρ`` times the still room's light it receives (gathered with the exact form factors,
   visibility past the still objects); it lights the camera's receivers with the exact
   form factors and visibility past the still objects.
3. **The light they block.** A receiver loses the still senders whose segment crosses
   a moving object, tested against the moving object's surfels (its shape at the surfel
   size: the triangles of its cut faces, or per cluster of small triangles one triangle
   of the cluster's area).
4. **The light they receive.** A camera pixel on a moving object takes the irradiance
   of the moving surfel nearest to it that faces the same way (one value per surfel,
   its phase taken at the surfel's centre).

Left out, as second order in the moving objects: light that bounces off a moving object
and then off a still surface before reaching the camera, light between two moving
surfels, and what a moving object blocks between two still surfels (it changes the
higher orders of the still light). With nothing moving the result is the exact one.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.sensors.tof import radiosity as _radiosity
from simcore.sensors.tof.radiosity import (
    Room,
    Surfels,
    occluder_boxes,
    surfels_from_room,
)

F64 = NDArray[np.float64]
F32 = NDArray[np.float32]
C128 = NDArray[np.complex128]

#: A receiver lies on a moving object when it is inside one of its objects' bounding boxes
#: grown by this much (m).
ON_MOVER_M = 0.01
#: Proxy triangles of the moving objects are tested for blocking in chunks of this many
#: (each chunk's bounding box first).
PROXY_CHUNK = 8


@dataclass(frozen=True)
class StillOperator:
    """The still objects' exchange as kernels, and ``I − K`` factorised to solve it.

    Attributes
    ----------
    key : tuple
        What it was made from (the still objects, the surfel size, the wavenumbers).
    kernels : tuple of ndarray, shape (S, S)
        Per wavenumber ``K = ρ_i F_ij V_ij e^{i k d_ij}`` (float32 for ``k = 0``, else
        complex64).
    lu : tuple, or None
        Per wavenumber the LU factors of ``I − K`` (:func:`scipy.linalg.lu_factor`); None
        above :data:`LU_MAX_SURFELS` surfels (the series is summed instead).
    """

    key: tuple[object, ...]
    kernels: tuple[NDArray[np.float32] | NDArray[np.complex64], ...]
    lu: tuple[tuple[NDArray[np.generic], NDArray[np.int32]], ...] | None


#: The still exchange is factorised (``O(S³)`` once, ``O(S²)`` a frame) up to this many
#: surfels; above, each frame sums the Neumann series.
LU_MAX_SURFELS = 5000
_OPERATOR: dict[str, StillOperator] = {}
_LOCK = threading.Lock()


def series(kernels: tuple[NDArray[np.float32] | NDArray[np.complex64], ...],
           wavenumbers: list[float], start: C128, *, orders: int,
           tolerance: float = 1e-5) -> C128:
    """``Σ_n K^n start`` per wavenumber: ``orders`` terms.

    0: until an order adds less than ``tolerance`` of the first term. For ``k = 0`` the
    kernel is real and so is the start.
    """
    total = np.array(start, dtype=np.complex128)
    for q, k in enumerate(wavenumbers):
        term: NDArray[np.float32] | NDArray[np.complex64]
        term = start[q].real.astype(np.float32) if k == 0.0 else start[q].astype(np.complex64)
        _radiosity.neumann_into(total[q], kernels[q], term, orders=orders, tolerance=tolerance)
    return total


def still_operator(key: tuple[object, ...], factor: F32, distance: F32, albedo: F64,
                   wavenumbers: list[float]) -> StillOperator:
    """The kept :class:`StillOperator` of the still objects named by ``key``, made on first use."""
    from scipy.linalg import lu_factor

    full = (key, tuple(wavenumbers))
    with _LOCK:
        kept = _OPERATOR.get("still")
    if kept is not None and kept.key == full:
        return kept
    weighted = factor * albedo[:, None].astype(np.float32)
    kernels = tuple(weighted if k == 0.0 else _radiosity._phase_kernel(weighted, distance, k)
                    for k in wavenumbers)
    lu = None
    if len(albedo) <= LU_MAX_SURFELS:
        lu = tuple(lu_factor(np.eye(len(albedo), dtype=m.dtype) - m, check_finite=False)
                   for m in kernels)
    kept = StillOperator(full, kernels, lu)
    with _LOCK:
        _OPERATOR.clear()
        _OPERATOR["still"] = kept
    return kept


def still_radiosity(operator: StillOperator, emitted: C128, wavenumbers: list[float], *,
                    bounces: int) -> C128:
    """The still surfels' radiosity over ``bounces`` orders (0: all).

    For first exitance ``emitted`` (shape (K, S)): ``(I − K)⁻¹ E`` by the LU factors, or
    the series.
    """
    from scipy.linalg import lu_solve

    if bounces != 0 or operator.lu is None:
        return series(operator.kernels, wavenumbers, emitted, orders=bounces)
    out = np.zeros_like(emitted, dtype=np.complex128)
    for q, k in enumerate(wavenumbers):
        rhs = emitted[q].real.astype(np.float32) if k == 0.0 else emitted[q].astype(np.complex64)
        out[q] = lu_solve(operator.lu[q], rhs, check_finite=False)
    return out


def mover_surfels(mover_room: Room, patch_m: float) -> Surfels:
    """The moving objects' surfels: all their faces, cut and clustered as the still ones.

    A face that faces nothing exchanges no light (its form factors are zero).
    """
    return surfels_from_room(mover_room, patch_m=patch_m,
                             facing=np.ones(len(mover_room.triangles), dtype=bool))


def mover_exitance(movers: Surfels, still: Surfels, still_room: Room, still_total: C128,
                   emitted: C128, wavenumbers: list[float], *, bounces: int
                   ) -> tuple[C128, C128]:
    """The moving surfels' exitance (own first exitance + ρ × the still light they receive).

    Returns
    -------
    exitance : ndarray of complex, shape (K, M)
    received : ndarray of complex, shape (K, M)
        The still room's irradiance at each moving surfel (units of ``cos θ / R²``).
    """
    if len(movers.area) == 0:
        empty = np.zeros((len(wavenumbers), 0), dtype=np.complex128)
        return empty, empty
    points = movers.centre + _radiosity.LIFT_M * movers.normal
    received = _radiosity.gather(points, movers.normal, still, still_room, still_total,
                                 wavenumbers)
    if bounces == 1:
        return emitted, received
    return emitted + movers.albedo[None, :] * received, received


def proxy_occluders(movers: Surfels) -> tuple[F64, NDArray[np.int64], F64, F64]:
    """The moving surfels as blocking triangles, in chunks: (tris, start, lo, hi)."""
    tris = np.ascontiguousarray(movers.vertices, dtype=np.float64)
    start = np.unique(np.append(np.arange(0, len(tris), PROXY_CHUNK), len(tris)))
    start = start.astype(np.int64)
    lo = np.array([tris[a:b].reshape(-1, 3).min(axis=0) for a, b in zip(start[:-1], start[1:],
                                                                           strict=True)])
    hi = np.array([tris[a:b].reshape(-1, 3).max(axis=0) for a, b in zip(start[:-1], start[1:],
                                                                           strict=True)])
    return tris, start, lo.reshape(-1, 3), hi.reshape(-1, 3)


def on_movers(points: F64, mover_room: Room) -> NDArray[np.bool_]:
    """Which receiver points lie on a moving object (inside one of its grown boxes)."""
    lo, hi = occluder_boxes(mover_room)
    out = np.zeros(len(points), dtype=bool)
    if len(lo) == 0:
        return out
    near = np.flatnonzero(((points >= lo.min(axis=0) - ON_MOVER_M)
                           & (points <= hi.max(axis=0) + ON_MOVER_M)).all(axis=1))
    p = points[near]
    inside = (p[:, None, :] >= lo[None] - ON_MOVER_M) & (p[:, None, :] <= hi[None] + ON_MOVER_M)
    out[near] = np.all(inside, axis=2).any(axis=1)
    return out


def nearest_mover(points: F64, normals: F64, movers: Surfels) -> NDArray[np.int64]:
    """Per receiver, the nearest moving surfel that faces its way (any, if none does)."""
    d2 = ((points[:, None, :] - movers.centre[None]) ** 2).sum(axis=2)
    facing = normals @ movers.normal.T > 0.0
    return np.where(facing, d2, d2 + 1e6).argmin(axis=1)


def spread(points: F64, normals: F64, node_points: F64, node_normals: F64
           ) -> tuple[NDArray[np.int64], F64]:
    """Weights that spread values at nodes to receivers: the nodes on the receiver's surface.

    Among the eight nearest nodes (in space), those whose normal is within 25° of the
    receiver's, weighted by inverse squared distance; the nearest node where none is.

    Returns
    -------
    index : ndarray of int, shape (R, 8)
    weight : ndarray, shape (R, 8)
        Each row sums to 1.
    """
    from scipy.spatial import cKDTree

    count = min(8, len(node_points))
    dist, idx = cKDTree(node_points).query(points, k=count)
    idx = np.asarray(idx).reshape(len(points), count)
    dist = np.asarray(dist).reshape(len(points), count)
    same = np.einsum("rkc,rc->rk", node_normals[idx], normals) > np.cos(np.radians(25.0))
    same[~same.any(axis=1), 0] = True
    weight = np.where(same, 1.0 / np.maximum(dist, 1e-3) ** 2, 0.0)
    return idx, weight / weight.sum(axis=1, keepdims=True)


__all__ = ["LU_MAX_SURFELS", "StillOperator", "mover_exitance", "mover_surfels",
           "nearest_mover", "on_movers", "proxy_occluders", "series", "spread",
           "still_operator", "still_radiosity"]
