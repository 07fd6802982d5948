"""Compiled test of the image method's second legs against every blocking object at once.

:func:`~simcore.sensors.radar.multipath.second_legs_clear` tests each leg (reflection point
→ target) against the frame's blocking objects (:func:`~simcore.sensors.radar.multipath.
leg_blockers`): a slab test on the object's bounding box in its local frame, then
Möller–Trumbore on its triangles. :func:`legs_blocked` runs both for all the legs and all
the objects in one pass, with the arithmetic of the numpy reference
(``multipath._segments_hit_box``; the triangles' test is :func:`triangle_hit`, also that of
``multipath._hit_kernel``), instead of a round of numpy calls per object.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel


@kernel
def _box_hit(a: NDArray[np.float64], b: NDArray[np.float64], box: NDArray[np.float64]
             ) -> bool:
    """Whether segment a → b (3,) meets the axis-aligned box (2, 3): the slab test.

    ``multipath._segments_hit_box`` for one segment, NaN included (a NaN bound makes the
    test fail, as numpy's max and min propagate it).
    """
    t_in, t_out = -math.inf, math.inf
    for c in range(3):
        d = b[c] - a[c]
        if d == 0.0:                     # parallel to the slab: inside it or not
            if a[c] < box[0, c] or a[c] > box[1, c]:
                return False
            continue
        inv = 1.0 / d
        t1 = (box[0, c] - a[c]) * inv
        t2 = (box[1, c] - a[c]) * inv
        lo = -math.inf if math.isnan(t1) else (math.nan if math.isnan(t2) else min(t1, t2))
        hi = math.inf if math.isnan(t2) else (math.nan if math.isnan(t1) else max(t1, t2))
        t_in = math.nan if (math.isnan(lo) or math.isnan(t_in)) else max(t_in, lo)
        t_out = math.nan if (math.isnan(hi) or math.isnan(t_out)) else min(t_out, hi)
    return t_in <= t_out and t_out >= 0.0 and t_in <= 1.0


@kernel
def triangle_hit(a: NDArray[np.float64], b: NDArray[np.float64], tri: NDArray[np.float64],
                  lo: int, hi: int) -> bool:
    """Whether segment a → b crosses one of triangles ``lo … hi−1`` (Möller–Trumbore).

    0 < t < 1 along the segment, edges included; a triangle seen edge-on (|det| ≤ 1e-12)
    is not hit.
    """
    dx, dy, dz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    for t in range(lo, hi):
        e1x, e1y, e1z = tri[t, 1, 0] - tri[t, 0, 0], tri[t, 1, 1] - tri[t, 0, 1], \
            tri[t, 1, 2] - tri[t, 0, 2]
        e2x, e2y, e2z = tri[t, 2, 0] - tri[t, 0, 0], tri[t, 2, 1] - tri[t, 0, 1], \
            tri[t, 2, 2] - tri[t, 0, 2]
        px, py, pz = dy * e2z - dz * e2y, dz * e2x - dx * e2z, dx * e2y - dy * e2x
        det = px * e1x + py * e1y + pz * e1z
        if abs(det) <= 1e-12:
            continue
        inv = 1.0 / det
        sx, sy, sz = a[0] - tri[t, 0, 0], a[1] - tri[t, 0, 1], a[2] - tri[t, 0, 2]
        u = (sx * px + sy * py + sz * pz) * inv
        if u < 0.0 or u > 1.0:
            continue
        qx, qy, qz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
        v = (dx * qx + dy * qy + dz * qz) * inv
        if v < 0.0 or u + v > 1.0:
            continue
        tt = (qx * e2x + qy * e2y + qz * e2z) * inv
        if 0.0 < tt < 1.0:
            return True
    return False


@kernel
def legs_blocked(la: NDArray[np.float64], lb: NDArray[np.float64],
                 skip: NDArray[np.bool_], boxes: NDArray[np.float64],
                 triangles: NDArray[np.float64], starts: NDArray[np.int64],
                 clear: NDArray[np.bool_]) -> None:
    """Clear ``clear[k]`` where leg ``k`` crosses a blocking object, objects in order.

    Parameters
    ----------
    la, lb : ndarray, shape (objects, legs, 3)
        The legs' ends in each object's local frame (m).
    skip : ndarray of bool, shape (objects, legs)
        Object ``o`` does not stop leg ``k`` (its reflector, or the target's own object
        where it scatters from outside).
    boxes : ndarray, shape (objects, 2, 3)
        The objects' bounding boxes, local frame (m).
    triangles : ndarray, shape (T, 3, 3)
        Every object's triangles, local frame, object ``o``'s at ``starts[o] … starts[o+1]−1``.
    clear : ndarray of bool, shape (legs,)
        In: the legs still to test; out: False where a leg is blocked.
    """
    for o in range(la.shape[0]):
        for k in range(la.shape[1]):
            if not clear[k] or skip[o, k]:
                continue
            if not _box_hit(la[o, k], lb[o, k], boxes[o]):
                continue
            if triangle_hit(la[o, k], lb[o, k], triangles, starts[o], starts[o + 1]):
                clear[k] = False


__all__ = ["legs_blocked", "triangle_hit"]
