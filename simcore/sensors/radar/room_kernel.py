"""Compiled search for the room's face sequences that may carry a path (a conservative filter).

:func:`~simcore.sensors.radar.room._room_paths` follows every sequence of two or three faces
(tens of faces: thousands of sequences) and traces each by the image method in Python;
almost all of them fail the geometry (a reflection point off its face, a leg through
another face). :func:`room_candidates` runs the same tests in one compiled pass over the
sequences, in the same order, each with a margin of :data:`MARGIN_M` towards keeping the
sequence, so it drops only sequences that the exact trace would drop too; the exact trace
then decides on the few that remain, and the paths (and their order) are those of the
trace alone.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel

#: Slack of every test of :func:`room_candidates` towards keeping a sequence (m): far above
#: the rounding of the same arithmetic done in another order (≈ 1e-15 of the room's size).
MARGIN_M = 1e-9


@kernel
def _oriented(center: NDArray[np.float64], normal: NDArray[np.float64], two_sided: bool,
              point: NDArray[np.float64], min_distance: float, out: NDArray[np.float64]
              ) -> bool:
    """The face's normal towards ``point`` into ``out``; False when none (behind, in it)."""
    s = ((point[0] - center[0]) * normal[0] + (point[1] - center[1]) * normal[1]
         + (point[2] - center[2]) * normal[2])
    if abs(s) < min_distance - MARGIN_M:
        return False
    if s > 0:
        out[:] = normal
        return True
    if not two_sided:
        return False
    out[:] = -normal
    return True


@kernel
def _mirror(point: NDArray[np.float64], center: NDArray[np.float64],
            normal: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    s = ((point[0] - center[0]) * normal[0] + (point[1] - center[1]) * normal[1]
         + (point[2] - center[2]) * normal[2])
    for c in range(3):
        out[c] = point[c] - 2.0 * s * normal[c]


@kernel
def _crossing(a: NDArray[np.float64], b: NDArray[np.float64], center: NDArray[np.float64],
              normal: NDArray[np.float64], axes: NDArray[np.float64],
              out: NDArray[np.float64], local: NDArray[np.float64]) -> None:
    """Where the line a → b meets the face's plane (``out``) and its face coordinates."""
    s_a = ((a[0] - center[0]) * normal[0] + (a[1] - center[1]) * normal[1]
           + (a[2] - center[2]) * normal[2])
    s_b = ((b[0] - center[0]) * normal[0] + (b[1] - center[1]) * normal[1]
           + (b[2] - center[2]) * normal[2])
    f = s_a / (s_a - s_b)
    for c in range(3):
        out[c] = a[c] + f * (b[c] - a[c])
    for k in range(2):
        local[k] = ((out[0] - center[0]) * axes[k, 0] + (out[1] - center[1]) * axes[k, 1]
                    + (out[2] - center[2]) * axes[k, 2])


@kernel
def _side(point: NDArray[np.float64], center: NDArray[np.float64],
          normal: NDArray[np.float64]) -> float:
    return ((point[0] - center[0]) * normal[0] + (point[1] - center[1]) * normal[1]
            + (point[2] - center[2]) * normal[2])


@kernel
def _local(point: NDArray[np.float64], center: NDArray[np.float64],
           axes: NDArray[np.float64]) -> tuple[float, float]:
    """A point's coordinates along a face's two axes from its centre (m)."""
    d0, d1, d2 = point[0] - center[0], point[1] - center[1], point[2] - center[2]
    return (d0 * axes[0, 0] + d1 * axes[0, 1] + d2 * axes[0, 2],
            d0 * axes[1, 0] + d1 * axes[1, 1] + d2 * axes[1, 2])


@kernel
def _may_trace(seq: NDArray[np.int64], n: int, normals: NDArray[np.float64],
               images: NDArray[np.float64], centers: NDArray[np.float64],
               axes: NDArray[np.float64], halves: NDArray[np.float64],
               face_normals: NDArray[np.float64], edge_tolerance: float,
               min_distance: float) -> int:
    """Whether ``_trace`` may find the path of ``seq[:n]``.

    0: it certainly does not; 1: it may, and no other face certainly blocks a leg between
    the reflection points; 2: it may, and a face may block a leg (the trace decides).
    ``normals[k]`` is face ``seq[k]``'s normal towards ``images[k]`` (``images[0]`` the
    radar, ``images[k + 1]`` its image in faces ``seq[:k + 1]``).
    """
    points = np.empty((n, 3))
    target = np.zeros(3)
    x = np.empty(3)
    local = np.empty(2)
    for k in range(n - 1, -1, -1):           # back-trace from the radar, faces in reverse
        f = seq[k]
        s_a = _side(target, centers[f], normals[k])
        s_b = _side(images[k + 1], centers[f], normals[k])
        if s_a <= -1e-9 - MARGIN_M or s_b >= -1e-9 + MARGIN_M:
            return 0
        _crossing(target, images[k + 1], centers[f], normals[k], axes[f], x, local)
        for j in range(2):
            if abs(local[j]) > halves[f, j] + edge_tolerance + MARGIN_M:
                return 0
        points[k] = x
        target[:] = x
    first = np.sqrt(points[0, 0] ** 2 + points[0, 1] ** 2 + points[0, 2] ** 2)
    last = np.sqrt(points[n - 1, 0] ** 2 + points[n - 1, 1] ** 2 + points[n - 1, 2] ** 2)
    if min(first, last) < min_distance - MARGIN_M:
        return 0
    # A leg between two reflection points through another face inside its rectangle.
    out = 1
    for k in range(n - 1):
        for g in range(centers.shape[0]):
            if g == seq[k] or g == seq[k + 1]:
                continue
            s_a = _side(points[k], centers[g], face_normals[g])
            s_b = _side(points[k + 1], centers[g], face_normals[g])
            if (s_a > MARGIN_M and s_b > MARGIN_M) or (s_a < -MARGIN_M and s_b < -MARGIN_M):
                continue                     # both ends on one side: no crossing
            # Both ends beyond one side of the face's inner rectangle: so is any point of
            # the leg, where it crosses the plane too.
            inner0 = halves[g, 0] - edge_tolerance + MARGIN_M
            inner1 = halves[g, 1] - edge_tolerance + MARGIN_M
            la0, la1 = _local(points[k], centers[g], axes[g])
            lb0, lb1 = _local(points[k + 1], centers[g], axes[g])
            if ((la0 > inner0 and lb0 > inner0) or (la0 < -inner0 and lb0 < -inner0)
                    or (la1 > inner1 and lb1 > inner1) or (la1 < -inner1 and lb1 < -inner1)):
                continue
            crosses = ((s_a > MARGIN_M and s_b < -MARGIN_M)
                       or (s_a < -MARGIN_M and s_b > MARGIN_M))
            if crosses:
                _crossing(points[k], points[k + 1], centers[g], face_normals[g], axes[g], x,
                          local)
                if (abs(local[0]) < inner0 - 2.0 * MARGIN_M
                        and abs(local[1]) < inner1 - 2.0 * MARGIN_M):
                    return 0                 # certainly blocked
                if abs(local[0]) > inner0 or abs(local[1]) > inner1:
                    continue                 # certainly outside the face's inner rectangle
            out = 2
    return out


@kernel
def _append(out: NDArray[np.int64], row: int, i: int, j: int, m: int, flag: int
            ) -> NDArray[np.int64]:
    """``out`` with row ``row`` set to (i, j, m, flag), doubled first when full."""
    if row == out.shape[0]:
        out = np.concatenate((out, np.full_like(out, -1)))
    out[row, 0], out[row, 1], out[row, 2], out[row, 3] = i, j, m, flag
    return out


@kernel
def room_candidates(centers: NDArray[np.float64], face_normals: NDArray[np.float64],
                    axes: NDArray[np.float64], halves: NDArray[np.float64],
                    two_sided: NDArray[np.bool_], follows: NDArray[np.bool_],
                    max_faces: int, edge_tolerance: float, min_distance: float
                    ) -> NDArray[np.int64]:
    """The face sequences (two or three faces) that may carry a path, in search order.

    The order of ``_room_paths``' depth-first search: for each first face, each second
    face (the pair, then its triples). Arrays: the faces' centres, normals (F, 3), axes
    (F, 2, 3), half sizes (F, 2), two-sidedness (F,), and ``follows[i, j]`` (F, F): face j
    may come after face i.

    Returns
    -------
    ndarray of int, shape (K, 4)
        Face indices (−1 after the last face of a pair), then 1 where no other face can
        block a leg between the reflection points (the trace need not test it), else 2.
    """
    n_faces = centers.shape[0]
    out = np.full((max(16, 4 * n_faces), 4), -1, dtype=np.int64)
    k_out = 0
    seq = np.full(3, -1, dtype=np.int64)
    normals = np.empty((3, 3))
    images = np.zeros((4, 3))
    for i in range(n_faces):
        if not _oriented(centers[i], face_normals[i], two_sided[i], images[0], min_distance,
                         normals[0]):
            continue
        _mirror(images[0], centers[i], normals[0], images[1])
        seq[0] = i
        if max_faces < 2:
            continue
        for j in range(n_faces):
            if j == i or not follows[i, j]:
                continue
            if not _oriented(centers[j], face_normals[j], two_sided[j], images[1],
                             min_distance, normals[1]):
                continue
            _mirror(images[1], centers[j], normals[1], images[2])
            seq[1] = j
            flag = _may_trace(seq, 2, normals, images, centers, axes, halves, face_normals,
                              edge_tolerance, min_distance)
            if flag:
                out = _append(out, k_out, i, j, -1, flag)
                k_out += 1
            if max_faces < 3:
                continue
            for m in range(n_faces):
                if m == j or not follows[j, m]:
                    continue
                if not _oriented(centers[m], face_normals[m], two_sided[m], images[2],
                                 min_distance, normals[2]):
                    continue
                _mirror(images[2], centers[m], normals[2], images[3])
                seq[2] = m
                flag = _may_trace(seq, 3, normals, images, centers, axes, halves,
                                  face_normals, edge_tolerance, min_distance)
                if flag:
                    out = _append(out, k_out, i, j, m, flag)
                    k_out += 1
            seq[2] = -1
    return out[:k_out].copy()


__all__ = ["MARGIN_M", "room_candidates"]
