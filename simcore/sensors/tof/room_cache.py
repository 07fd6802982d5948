"""The room's surfel exchange, kept for the objects that stand still between frames.

A room changes between frames only where something moves (the office's walker). The
exchange between surfels of objects that stand still — their form factors, and their
visibility past every other still object — is computed once and kept; each frame then
computes only what a moving object changes:

- the pairs that involve one of its surfels (both form factors, visibility past everything);
- the shadow it casts on the still pairs: a still pair whose segment crosses a moving
  object's bounding box is tested against that object's triangles.

The result is the exchange a full recomputation gives, pair for pair (the same kernels on
the same surfels; only the order of the surfels differs). An object counts as still when
its triangles are the ones of the kept exchange bit for bit, so no pose is ever taken from a
stale cache. When an object that stood still starts to move, the kept block is cut down to
the objects still standing, and the still pairs that the object used to shadow are
recomputed.

An edit of still objects (the GUI moves a desk) is taken the same way by the first-order
path (:func:`_edited_block`): pairs of surfels that both were kept keep their form
factors, and their visibility unless their segment crosses the box of an object taken out
or put in; the kept receivers likewise (:func:`_edited_receivers`). The result is a fresh
computation's bit for bit, so a frame never depends on the edits before it.

Surfels of still objects are cut with :func:`~simcore.sensors.tof.radiosity.facing_any`
among still objects only (a still triangle that faces nothing but a moving object is left
out: it would have to face it and nothing else in the room).
"""

from __future__ import annotations

import hashlib
import math
import os
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.tof_config import SPEED_OF_LIGHT
from simcore.sensors.tof import radiosity as _radiosity
from simcore.sensors.tof import room_movers as _movers
from simcore.sensors.tof.multipath import (
    CREASE_GUARD_PX,
    RECEIVER_STEP,
    _blend_nodes,
    _cell_of,
    _node_axis,
    _node_weights,
    _update_node_weights,
)
from simcore.sensors.tof.radiosity import (
    LIFT_M,
    Room,
    Surfels,
    _exchange,
    _segment_clear,
    facing_any,
    first_exitance,
    occluder_boxes,
    radiosity,
    surfels_from_room,
)

F64 = NDArray[np.float64]
F32 = NDArray[np.float32]


@dataclass(frozen=True)
class StillBlock:
    """The exchange among the surfels of the objects that stand still.

    Attributes
    ----------
    digests : tuple of bytes
        Each still object's geometry digest (:func:`group_digests`), in room order.
    room : Room
        The still objects alone.
    surfels : Surfels
        Their surfels (``S``).
    factor, distance : ndarray, shape (S, S), float32
        Form factor × visibility past the still objects, and centre distances (m).
    """

    digests: tuple[bytes, ...]
    room: Room
    surfels: Surfels
    factor: F32
    distance: F32


def group_digests(room: Room) -> list[bytes]:
    """A digest of each object's triangles, normals and albedo."""
    out = []
    for g in range(len(room.occluder_start) - 1):
        sl = slice(room.occluder_start[g], room.occluder_start[g + 1])
        out.append(hashlib.sha1(b"".join((room.triangles[sl].tobytes(),
                                          room.normals[sl].tobytes(),
                                          room.albedo[sl].tobytes()))).digest())
    return out


def sub_room(room: Room, groups: list[int]) -> Room:
    """The objects ``groups`` of ``room`` (in that order)."""
    parts = [slice(room.occluder_start[g], room.occluder_start[g + 1]) for g in groups]
    sizes = [p.stop - p.start for p in parts]
    start = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    moving = None if room.moving is None else room.moving[np.asarray(groups, dtype=np.int64)]
    if not parts:
        return Room(np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros(0), start, moving)
    return Room(np.concatenate([room.triangles[p] for p in parts]),
                np.concatenate([room.normals[p] for p in parts]),
                np.concatenate([room.albedo[p] for p in parts]), start, moving)


def join(a: Surfels, b: Surfels) -> Surfels:
    """Surfels ``a`` then ``b``."""
    return Surfels(*(np.concatenate([x, y]) for x, y in zip(
        (a.vertices, a.centre, a.normal, a.area, a.albedo, a.size),
        (b.vertices, b.centre, b.normal, b.area, b.albedo, b.size), strict=True)))


def _surfel_arrays(s: Surfels) -> tuple[F64, F64, F64, F64, F64]:
    return (np.ascontiguousarray(s.centre), np.ascontiguousarray(s.normal),
            np.ascontiguousarray(s.vertices), np.ascontiguousarray(s.area),
            np.ascontiguousarray(s.size))


@kernel
def _pair(i: int, j: int, centre: F64, normal: F64, vertices: F64, area: F64, size: F64,
          tris: F64, start: NDArray[np.int64], lo: F64, hi: F64, a: F64, b: F64
          ) -> tuple[float, float]:
    """Both form factors of surfels ``i`` and ``j`` with their visibility (0 when blocked)."""
    fij = _exchange(centre[i], normal[i], j, centre, normal, vertices, area, size)
    fji = _exchange(centre[j], normal[j], i, centre, normal, vertices, area, size)
    if fij == 0.0 and fji == 0.0:
        return 0.0, 0.0
    for c in range(3):
        a[c] = centre[i, c] + LIFT_M * normal[i, c]
        b[c] = centre[j, c] + LIFT_M * normal[j, c]
    if _segment_clear(a, b, tris, start, lo, hi):
        return fij, fji
    return 0.0, 0.0


@kernel
def _crosses(a: F64, b: F64, lo: F64, hi: F64) -> bool:
    """Whether the segment ``a → b`` meets any of the boxes ``lo``–``hi`` (slab test)."""
    for g in range(lo.shape[0]):
        t0, t1 = 0.0, 1.0
        miss = False
        for c in range(3):
            d = b[c] - a[c]
            if abs(d) < 1e-300:
                if a[c] < lo[g, c] or a[c] > hi[g, c]:
                    miss = True
                    break
            else:
                ta, tb = (lo[g, c] - a[c]) / d, (hi[g, c] - a[c]) / d
                if ta > tb:
                    ta, tb = tb, ta
                t0, t1 = max(t0, ta), min(t1, tb)
                if t0 > t1:
                    miss = True
                    break
        if not miss:
            return True
    return False


@kernel
def _moving_pairs(centre: F64, normal: F64, vertices: F64, area: F64, size: F64, first: int,
                  tris: F64, start: NDArray[np.int64], lo: F64, hi: F64,
                  factor: F32, dist: F32) -> None:
    """Fill the pairs with a surfel ``≥ first`` (the moving ones) into ``factor``/``dist``."""
    nn = centre.shape[0]
    a = np.empty(3)
    b = np.empty(3)
    for j in range(first, nn):
        for i in range(j):
            dx, dy, dz = centre[j, 0] - centre[i, 0], centre[j, 1] - centre[i, 1], \
                centre[j, 2] - centre[i, 2]
            dist[i, j] = dist[j, i] = np.sqrt(dx * dx + dy * dy + dz * dz)
            fij, fji = _pair(i, j, centre, normal, vertices, area, size, tris, start, lo, hi,
                             a, b)
            factor[i, j] = fij
            factor[j, i] = fji


@kernel
def _shadow(centre: F64, normal: F64, count: int, factor: F32, tris: F64,
            start: NDArray[np.int64], lo: F64, hi: F64, all_lo: F64, all_hi: F64) -> None:
    """Zero the pairs among the first ``count`` surfels that the triangles block."""
    a = np.empty(3)
    b = np.empty(3)
    for i in range(count):
        for j in range(i + 1, count):
            if factor[i, j] == 0.0 and factor[j, i] == 0.0:
                continue
            for c in range(3):
                a[c] = centre[i, c] + LIFT_M * normal[i, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            if not _crosses(a, b, all_lo, all_hi):
                continue
            if not _segment_clear(a, b, tris, start, lo, hi):
                factor[i, j] = 0.0
                factor[j, i] = 0.0


@kernel
def _unshadow(centre: F64, normal: F64, vertices: F64, area: F64, size: F64, factor: F32,
              tris: F64, start: NDArray[np.int64], lo: F64, hi: F64, gone_lo: F64,
              gone_hi: F64, all_lo: F64, all_hi: F64) -> None:
    """Recompute the pairs whose segment crosses a box of ``gone`` (objects taken out)."""
    nn = centre.shape[0]
    a = np.empty(3)
    b = np.empty(3)
    for i in range(nn):
        for j in range(i + 1, nn):
            for c in range(3):
                a[c] = centre[i, c] + LIFT_M * normal[i, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            if not _crosses(a, b, all_lo, all_hi) or not _crosses(a, b, gone_lo, gone_hi):
                continue
            fij, fji = _pair(i, j, centre, normal, vertices, area, size, tris, start, lo, hi,
                             a, b)
            factor[i, j] = fij
            factor[j, i] = fji


def _full_block(room: Room, digests: tuple[bytes, ...], patch_m: float) -> StillBlock:
    """The exchange among all the objects of ``room`` (every one standing still).

    :func:`~simcore.sensors.tof.radiosity.transfer` on two threads: the first
    ``n (1 − 1/√2)`` rows hold half the pairs ``(i, j > i)``.
    """
    surfels = surfels_from_room(room, patch_m=patch_m)
    n = len(surfels.area)
    _check_size(n, patch_m)
    factor = np.zeros((n, n), dtype=np.float32)
    distance = np.zeros((n, n), dtype=np.float32)
    lo, hi = occluder_boxes(room)
    arrays = _surfel_arrays(surfels)

    def rows(sl: slice) -> None:
        _radiosity._transfer_rows(*arrays, room.triangles, room.occluder_start, lo, hi,
                                  sl.start, sl.stop, factor, distance)

    _by_halves(n, rows, cut=int(n * (1.0 - math.sqrt(0.5))))
    return StillBlock(digests, room, surfels, factor, distance)


def _narrow(block: StillBlock, keep: list[int], patch_m: float) -> StillBlock:
    """``block`` cut down to its objects ``keep``; the pairs the others shadowed recomputed."""
    room = sub_room(block.room, keep)
    surfels = surfels_from_room(room, patch_m=patch_m)
    old = _index_of(block.surfels, surfels)
    if old is None:                        # the cut changed (a triangle faced a removed one)
        return _full_block(room, tuple(block.digests[g] for g in keep), patch_m)
    factor = np.ascontiguousarray(block.factor[np.ix_(old, old)])
    distance = np.ascontiguousarray(block.distance[np.ix_(old, old)])
    gone = [g for g in range(len(block.digests)) if g not in set(keep)]
    glo, ghi = occluder_boxes(sub_room(block.room, gone))
    lo, hi = occluder_boxes(room)
    _unshadow(*_surfel_arrays(surfels), factor, room.triangles, room.occluder_start, lo, hi,
              glo, ghi, *_union(glo, ghi))
    return StillBlock(tuple(block.digests[g] for g in keep), room, surfels, factor, distance)


@dataclass(frozen=True)
class _Edit:
    """How the still objects changed between two kept blocks (:func:`_edited_block`).

    Attributes
    ----------
    before, after : tuple of bytes
        The digests of the block before and after.
    old : ndarray of int, shape (S,)
        Each new surfel's index among the old block's (−1: a new surfel).
    lo, hi : ndarray, shape (C, 3)
        Boxes of the objects taken out (where they were) and put in (where they are).
    """

    before: tuple[bytes, ...]
    after: tuple[bytes, ...]
    old: NDArray[np.int64]
    lo: F64
    hi: F64


def _surfel_keys(s: Surfels) -> list[bytes]:
    """One key per surfel: its whole geometry, bit for bit."""
    return [b"".join((v.tobytes(), c.tobytes(), n.tobytes(), a.tobytes(), z.tobytes()))
            for v, c, n, a, z in zip(s.vertices, s.centre, s.normal, s.area, s.size,
                                     strict=True)]


def _edited_block(old: StillBlock, room: Room, digests: tuple[bytes, ...], patch_m: float
                  ) -> tuple[StillBlock, _Edit] | None:
    """The exchange of ``room``'s objects, computed from ``old`` where no edit can change it.

    The still objects changed (an object moved, was reshaped, added or removed): the pairs
    of surfels that both were in ``old`` keep their form factors, and their visibility
    unless their segment crosses the box of an object taken out or put in; every other
    pair is computed afresh. The result is :func:`_full_block`'s bit for bit (the same
    kernels on the same surfels, in the same order). None when the surfels kept changed
    order (then :func:`_full_block` is the way).
    """
    surfels = surfels_from_room(room, patch_m=patch_m)
    _check_size(len(surfels.area), patch_m)
    table = {key: i for i, key in enumerate(_surfel_keys(old.surfels))}
    index = np.array([table.get(key, -1) for key in _surfel_keys(surfels)], dtype=np.int64)
    matched = index[index >= 0]
    if len(matched) == 0 or np.any(np.diff(matched) <= 0):
        return None
    before, after = set(old.digests), set(digests)
    out_lo, out_hi = occluder_boxes(sub_room(old.room, [g for g, d in enumerate(old.digests)
                                                        if d not in after]))
    in_lo, in_hi = occluder_boxes(sub_room(room, [g for g, d in enumerate(digests)
                                                  if d not in before]))
    lo, hi = np.concatenate([out_lo, in_lo]), np.concatenate([out_hi, in_hi])
    tlo, thi = occluder_boxes(room)
    factor, distance = _patch_pairs(*_surfel_arrays(surfels), index, old.factor,
                                    room.triangles, room.occluder_start, tlo, thi, lo, hi,
                                    *_union(lo, hi))
    edit = _Edit(old.digests, digests, index, lo, hi)
    return StillBlock(digests, room, surfels, factor, distance), edit


@kernel
def _patch_pairs(centre: F64, normal: F64, vertices: F64, area: F64, size: F64,
                 old: NDArray[np.int64], old_factor: F32, tris: F64, start: NDArray[np.int64],
                 lo: F64, hi: F64, edit_lo: F64, edit_hi: F64, all_lo: F64, all_hi: F64
                 ) -> tuple[F32, F32]:
    """:func:`~simcore.sensors.tof.radiosity._transfer`, old pairs reused.

    See :func:`_edited_block`; ``old``: each surfel's index in ``old_factor`` (−1: new).
    """
    nn = centre.shape[0]
    factor = np.zeros((nn, nn), dtype=np.float32)
    dist = np.zeros((nn, nn), dtype=np.float32)
    a = np.empty(3)
    b = np.empty(3)
    for i in range(nn):
        for j in range(i + 1, nn):
            dx, dy, dz = centre[j, 0] - centre[i, 0], centre[j, 1] - centre[i, 1], \
                centre[j, 2] - centre[i, 2]
            dist[i, j] = dist[j, i] = math.sqrt(dx * dx + dy * dy + dz * dz)
            oi, oj = old[i], old[j]
            if oi >= 0 and oj >= 0:
                for c in range(3):
                    a[c] = centre[i, c] + LIFT_M * normal[i, c]
                    b[c] = centre[j, c] + LIFT_M * normal[j, c]
                if not _crosses(a, b, all_lo, all_hi) or not _crosses(a, b, edit_lo, edit_hi):
                    factor[i, j] = old_factor[oi, oj]
                    factor[j, i] = old_factor[oj, oi]
                    continue
            fij, fji = _pair(i, j, centre, normal, vertices, area, size, tris, start, lo, hi,
                             a, b)
            factor[i, j] = fij
            factor[j, i] = fji
    return factor, dist


@kernel
def _patch_rows(points: F64, normals: F64, centre: F64, normal: F64, vertices: F64,
                area: F64, size: F64, old: NDArray[np.int64], old_factor: F32, old_dist: F32,
                tris: F64, start: NDArray[np.int64], lo: F64, hi: F64, edit_lo: F64,
                edit_hi: F64, all_lo: F64, all_hi: F64, factor: F32, dist: F32) -> None:
    """:func:`_receiver_rows`, old values (rows of ``old_factor``) reused.

    Where no edit can change them (:func:`_edited_block`); ``old``: each surfel's column
    in ``old_factor`` (−1: new). Written into ``factor`` and ``dist`` (zeros).
    """
    m, count = points.shape[0], centre.shape[0]
    a = np.empty(3)
    b = np.empty(3)
    for r in range(m):
        for j in range(count):
            for c in range(3):
                a[c] = points[r, c] + LIFT_M * normals[r, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            oj = old[j]
            if oj >= 0 and (not _crosses(a, b, all_lo, all_hi)
                            or not _crosses(a, b, edit_lo, edit_hi)):
                factor[r, j] = old_factor[r, oj]
                dist[r, j] = old_dist[r, oj]
                continue
            f = _exchange(points[r], normals[r], j, centre, normal, vertices, area, size)
            if f == 0.0 or not _segment_clear(a, b, tris, start, lo, hi):
                continue
            factor[r, j] = f
            dist[r, j] = np.sqrt((centre[j, 0] - points[r, 0]) ** 2
                                 + (centre[j, 1] - points[r, 1]) ** 2
                                 + (centre[j, 2] - points[r, 2]) ** 2)


def _edited_receivers(kept: _Receivers, block: StillBlock, edit: _Edit) -> _Receivers:
    """``kept``'s rows against ``block`` after ``edit`` (:func:`_patch_rows`)."""
    tlo, thi = occluder_boxes(block.room)
    arrays = _surfel_arrays(block.surfels)
    ulo, uhi = _union(edit.lo, edit.hi)
    factor, distance, kernels = _row_arrays(len(kept.factor), len(block.surfels.area),
                                            kept.wavenumbers)

    def rows(sl: slice) -> None:
        _patch_rows(kept.points[sl], kept.normals[sl], *arrays, edit.old, kept.factor[sl],
                    kept.distance[sl], block.room.triangles, block.room.occluder_start,
                    tlo, thi, edit.lo, edit.hi, ulo, uhi, factor[sl], distance[sl])
        _kernels_into(factor[sl], distance[sl], kept.wavenumbers, [k[sl] for k in kernels])

    _by_halves(len(kept.keys), rows)
    return _Receivers(block.digests, kept.keys, factor, distance, tuple(kernels),
                      kept.wavenumbers, kept.points, kept.normals)


def _row_arrays(rows: int, count: int, wavenumbers: tuple[float, ...] | list[float]
                ) -> tuple[F32, F32, list[NDArray[np.complex64]]]:
    """Zeroed receiver arrays: factor, distance, and a phase kernel per wavenumber ≠ 0."""
    return (np.zeros((rows, count), dtype=np.float32), np.zeros((rows, count), dtype=np.float32),
            [np.zeros((rows, count) if k != 0.0 else (0, 0), dtype=np.complex64)
             for k in wavenumbers])


def _kernels_into(factor: F32, distance: F32, wavenumbers: tuple[float, ...] | list[float],
                  out: list[NDArray[np.complex64]]) -> None:
    """The phase kernel of each wavenumber ≠ 0 into ``out`` (k = 0: an empty placeholder)."""
    for k, o in zip(wavenumbers, out, strict=True):
        if k != 0.0:
            _radiosity._phase_kernel_into(factor, distance, k, o)


#: Fewer rows than this are not split between two threads (:func:`_by_halves`).
SPLIT_ROWS = 64


def _by_halves(count: int, rows: Callable[[slice], None], *, cut: int | None = None
               ) -> None:
    """``rows(slice(0, count))``, its first part on the helper thread (compiled, no GIL).

    ``rows`` writes each row on its own, so the parts are the whole bit for bit. ``cut``:
    where the parts meet (default half way). Serial on the helper thread itself, and for
    fewer than :data:`SPLIT_ROWS` rows.
    """
    if count < SPLIT_ROWS or threading.current_thread().name.startswith("tof-room"):
        rows(slice(0, count))
        return
    half = count // 2 if cut is None else cut
    first = _pool().submit(rows, slice(0, half))
    rows(slice(half, count))
    first.result()


def _union(lo: F64, hi: F64) -> tuple[F64, F64]:
    """The box (shape (1, 3) corners) around the boxes ``lo``–``hi``."""
    if len(lo) == 0:
        return np.full((1, 3), np.inf), np.full((1, 3), -np.inf)
    return lo.min(axis=0)[None], hi.max(axis=0)[None]


def _index_of(big: Surfels, small: Surfels) -> NDArray[np.int64] | None:
    """Where each surfel of ``small`` is in ``big`` (None when one is not there)."""
    table = {v.tobytes(): i for i, v in enumerate(big.vertices)}
    out = [table.get(v.tobytes(), -1) for v in small.vertices]
    if any(i < 0 for i in out):
        return None
    return np.asarray(out, dtype=np.int64)


def _check_size(count: int, patch_m: float) -> None:
    """One clear error when the exchange would need more than ``MAX_TRANSFER_BYTES``."""
    need = 2 * 4 * count ** 2
    limit = _radiosity.MAX_TRANSFER_BYTES
    if need > limit:
        raise ValueError(
            f"rig.tof.multipath_surfel_m = {patch_m} m cuts the scene into "
            f"{count} surfels, whose exchange needs {need / 2**30:.1f} GiB "
            f"(at most {limit / 2**30:.0f}): use larger surfels")


_BLOCK: dict[float, StillBlock] = {}
_LOCK = threading.Lock()


def still_block(room: Room, patch_m: float) -> tuple[StillBlock, list[int]]:
    """The kept exchange of the objects of ``room`` that stand still, and those that move.

    The first call keeps every object; later calls keep the objects whose geometry is the
    kept one bit for bit (the block cut down when one of them starts to move).

    Returns
    -------
    block : StillBlock
    moving : list of int
        The groups of ``room`` that are not in the block.
    """
    digests = group_digests(room)
    with _LOCK:
        block = _BLOCK.get(patch_m)
    kept = set() if block is None else set(block.digests)
    still = [g for g, d in enumerate(digests) if d in kept]
    if block is None or not still:
        block = _full_block(room, tuple(digests), patch_m)
        still = list(range(len(digests)))
    elif len(still) < len(block.digests):
        where = {d: g for g, d in enumerate(block.digests)}
        block = _narrow(block, [where[digests[g]] for g in still], patch_m)
    with _LOCK:
        _BLOCK.clear()
        _BLOCK[patch_m] = block
    return block, [g for g in range(len(digests)) if g not in set(still)]


def room_transfer(room: Room, patch_m: float) -> tuple[Surfels, F32, F32]:
    """Surfels of ``room`` and their exchange (form factor × visibility, distance).

    As :func:`~simcore.sensors.tof.radiosity.surfels_from_room` followed by
    :func:`~simcore.sensors.tof.radiosity.transfer`, with the still objects' block kept
    from the last call (see the module's description).

    Returns
    -------
    surfels : Surfels
        ``N`` surfels: the still objects' first.
    factor, distance : ndarray, shape (N, N), float32
    """
    block, moving = still_block(room, patch_m)
    if not moving:
        return block.surfels, block.factor, block.distance
    return _with_moving(room, block, moving, patch_m)


def _with_moving(room: Room, block: StillBlock, moving: list[int], patch_m: float
                 ) -> tuple[Surfels, F32, F32]:
    """The still block with the moving objects' surfels, pairs and shadows added."""
    ordered = sub_room(room, [g for g in range(len(room.occluder_start) - 1)
                              if g not in set(moving)] + moving)
    first_tri = int(block.room.occluder_start[-1])
    facing = facing_any(ordered.triangles, ordered.normals)        # movers' against all
    mover_room = sub_room(room, moving)
    movers = surfels_from_room(mover_room, patch_m=patch_m, facing=facing[first_tri:])
    surfels = join(block.surfels, movers)
    ns, nn = len(block.surfels.area), len(surfels.area)
    _check_size(nn, patch_m)
    factor = np.zeros((nn, nn), dtype=np.float32)
    distance = np.zeros((nn, nn), dtype=np.float32)
    factor[:ns, :ns] = block.factor
    distance[:ns, :ns] = block.distance
    mlo, mhi = occluder_boxes(mover_room)
    arrays = _surfel_arrays(surfels)
    _shadow(arrays[0], arrays[1], ns, factor, mover_room.triangles, mover_room.occluder_start,
            mlo, mhi, *_union(mlo, mhi))
    lo, hi = occluder_boxes(ordered)
    _moving_pairs(*arrays, ns, ordered.triangles, ordered.occluder_start, lo, hi, factor,
                  distance)
    return surfels, factor, distance


@kernel
def _receiver_rows(points: F64, normals: F64, centre: F64, normal: F64, vertices: F64,
                   area: F64, size: F64, count: int, tris: F64, start: NDArray[np.int64],
                   lo: F64, hi: F64, factor: F32, dist: F32) -> None:
    """Form factor × visibility and distance from each receiver to the first ``count`` surfels.

    Written into ``factor`` and ``dist`` (zeros, shape (receivers, ``count``)).
    """
    m = points.shape[0]
    a = np.empty(3)
    b = np.empty(3)
    for r in range(m):
        for j in range(count):
            f = _exchange(points[r], normals[r], j, centre, normal, vertices, area, size)
            if f == 0.0:
                continue
            for c in range(3):
                a[c] = points[r, c] + LIFT_M * normals[r, c]
                b[c] = centre[j, c] + LIFT_M * normal[j, c]
            if not _segment_clear(a, b, tris, start, lo, hi):
                continue
            factor[r, j] = f
            dist[r, j] = np.sqrt((centre[j, 0] - points[r, 0]) ** 2
                                 + (centre[j, 1] - points[r, 1]) ** 2
                                 + (centre[j, 2] - points[r, 2]) ** 2)


@kernel
def _cluster_misses(px: float, py: float, pz: float, centre: F64, radius: float,
                    wx: float, wy: float, wz: float, w2: float, radius2: float) -> bool:
    """Whether no segment from ``p`` into the sphere (``centre``, ``radius``) can meet another.

    The other sphere is centred at ``p + w`` with squared radius ``radius2``: their cones
    from ``p`` are apart, or the first lies wholly nearer than the second.
    """
    vx, vy, vz = centre[0] - px, centre[1] - py, centre[2] - pz
    v = math.sqrt(vx * vx + vy * vy + vz * vz)
    w = math.sqrt(w2)
    if v <= radius or w2 <= radius2:
        return False
    if v + radius < w - math.sqrt(radius2):
        return True
    sin_c, sin_m = radius / v, math.sqrt(radius2) / w
    cos_c, cos_m = math.sqrt(1.0 - sin_c * sin_c), math.sqrt(1.0 - sin_m * sin_m)
    cos_vw = (vx * wx + vy * wy + vz * wz) / (v * w)
    return cos_vw < cos_c * cos_m - sin_c * sin_m


@kernel
def _blocked(points: F64, normals: F64, rows: NDArray[np.int64], centre: F64, normal: F64,
             factor: F32, dist: F32, exitance: NDArray[np.complex128], k: F64, tris: F64,
             start: NDArray[np.int64], lo: F64, hi: F64, all_lo: F64, all_hi: F64,
             clusters: tuple[NDArray[np.int64], NDArray[np.int64], F64, F64]
             ) -> NDArray[np.complex128]:
    """The kept receivers' irradiance from still senders that the triangles now block.

    ``clusters`` (:func:`sender_clusters`) group the senders in space: a receiver skips a
    group whose bounding sphere cannot put a segment through the triangles' bounding
    sphere.
    """
    order, cstart, ccentre, cradius = clusters
    out = np.zeros((k.shape[0], points.shape[0]), dtype=np.complex128)
    a = np.empty(3)
    b = np.empty(3)
    mid = np.empty(3)
    radius2 = 0.0
    for c in range(3):
        mid[c] = 0.5 * (all_lo[0, c] + all_hi[0, c])
        radius2 += (0.5 * (all_hi[0, c] - all_lo[0, c])) ** 2
    for r in range(points.shape[0]):
        row = rows[r]
        wx, wy, wz = mid[0] - points[r, 0], mid[1] - points[r, 1], mid[2] - points[r, 2]
        w2 = wx * wx + wy * wy + wz * wz
        for g in range(cstart.shape[0] - 1):
            if _cluster_misses(points[r, 0], points[r, 1], points[r, 2], ccentre[g],
                               cradius[g], wx, wy, wz, w2, radius2):
                continue
            for s in range(cstart[g], cstart[g + 1]):
                j = order[s]
                f = factor[row, j]
                if f == 0.0:
                    continue
                for c in range(3):
                    a[c] = points[r, c] + LIFT_M * normals[r, c]
                    b[c] = centre[j, c] + LIFT_M * normal[j, c]
                if not _crosses(a, b, all_lo, all_hi):
                    continue
                if _segment_clear(a, b, tris, start, lo, hi):
                    continue
                d = dist[row, j]
                for q in range(k.shape[0]):
                    out[q, r] += f * exitance[q, j] * complex(np.cos(k[q] * d),
                                                              np.sin(k[q] * d))
    return out


#: Senders are grouped for :func:`_blocked` in cubes of this side (m).
CLUSTER_M = 1.0


def sender_clusters(centre: F64, *, cube_m: float = CLUSTER_M
                    ) -> tuple[NDArray[np.int64], NDArray[np.int64], F64, F64]:
    """Surfels grouped by the cube of side ``cube_m`` their centre falls in.

    Returns
    -------
    order : ndarray of int, shape (S,)
        Surfel indices, group after group.
    start : ndarray of int, shape (G + 1,)
        Group ``g`` is ``order[start[g]:start[g + 1]]``.
    centre, radius : ndarray, shapes (G, 3) and (G,)
        Each group's bounding sphere (its centres' mean, the farthest centre) (m).
    """
    if len(centre) == 0:
        return (np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64), np.zeros((0, 3)),
                np.zeros(0))
    cell = np.floor(centre / cube_m).astype(np.int64)
    _, label = np.unique(cell, axis=0, return_inverse=True)
    label = label.ravel()
    order = np.argsort(label, kind="stable").astype(np.int64)
    counts = np.bincount(label)
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    mean = np.stack([np.bincount(label, weights=centre[:, c]) for c in range(3)],
                    axis=1) / counts[:, None]
    radius = np.zeros(len(counts))
    np.maximum.at(radius, label, np.linalg.norm(centre - mean[label], axis=1))
    return order, start, mean, radius


@dataclass(frozen=True)
class _Receivers:
    """The exchange of a still camera's receiver points with the still surfels."""

    digests: tuple[bytes, ...]
    keys: dict[bytes, int]
    factor: F32
    distance: F32
    kernels: tuple[NDArray[np.complex64], ...]
    wavenumbers: tuple[float, ...]
    points: F64
    normals: F64


_RECEIVERS: dict[float, _Receivers] = {}
#: The first-order path's kept receivers (:func:`_grown_receivers`), apart from the exact
#: path's (:func:`room_gather` starts its own afresh).
_GROWN: dict[float, _Receivers] = {}


def room_gather(points: F64, normals: F64, surfels: Surfels, room: Room,
                exitance: NDArray[np.complex128], wavenumbers: list[float], *, patch_m: float
                ) -> NDArray[np.complex128]:
    """:func:`~simcore.sensors.tof.radiosity.gather`, the still part kept between frames.

    Receivers whose point and normal are those of the last frame (a still camera on still
    surfaces) reuse their form factors and visibility to the still objects' surfels; the
    light that a moving object now blocks is taken off pair by pair, and the moving
    objects' surfels and the new receivers are summed afresh. Equal to the full gather to
    float32 rounding of the kept factors.
    """
    with _LOCK:
        block = _BLOCK.get(patch_m)
    ns = 0 if block is None else len(block.surfels.area)
    if block is None or ns == 0 or ns > len(surfels.area) \
            or not np.array_equal(block.surfels.vertices, surfels.vertices[:ns]):
        return _radiosity.gather(points, normals, surfels, room, exitance, wavenumbers)
    points = np.ascontiguousarray(points, dtype=np.float64)
    normals = np.ascontiguousarray(normals, dtype=np.float64)
    keys = [p.tobytes() + n.tobytes() for p, n in zip(points, normals, strict=True)]
    with _LOCK:
        kept = _RECEIVERS.get(patch_m)
    if kept is None or kept.digests != block.digests \
            or kept.wavenumbers != tuple(wavenumbers) \
            or sum(key in kept.keys for key in keys) < len(keys) // 2:
        kept = _keep_receivers(points, normals, keys, block, wavenumbers)
        with _LOCK:
            _RECEIVERS.clear()
            _RECEIVERS[patch_m] = kept
    rows = np.array([kept.keys.get(key, -1) for key in keys], dtype=np.int64)
    hit = rows >= 0
    out = np.zeros((len(wavenumbers), len(points)), dtype=np.complex128)
    still = exitance[:, :ns]
    for q, k in enumerate(wavenumbers):
        if k == 0.0:          # the intensity: the factors themselves (no phase)
            out[q, hit] = (kept.factor @ still[q].real.astype(np.float32)
                           + 1j * (kept.factor @ still[q].imag.astype(np.float32)))[rows[hit]]
        else:
            out[q, hit] = (kept.kernels[q] @ still[q].astype(np.complex64))[rows[hit]]
    movers = sub_room(room, [g for g in range(len(room.occluder_start) - 1)
                             if not _in_block(room, g, block)])
    ks = np.asarray(wavenumbers, dtype=np.float64)
    if len(movers.triangles):
        mlo, mhi = occluder_boxes(movers)
        whole_lo, whole_hi = _union(mlo, mhi)
        arrays = _surfel_arrays(surfels)
        out[:, hit] -= _blocked(points[hit], normals[hit], rows[hit], arrays[0], arrays[1],
                                kept.factor, kept.distance, np.ascontiguousarray(still), ks,
                                movers.triangles, movers.occluder_start, mlo, mhi,
                                whole_lo, whole_hi, sender_clusters(arrays[0][:ns]))
    moving = np.zeros_like(exitance)
    moving[:, ns:] = exitance[:, ns:]
    if ns < len(surfels.area):
        out[:, hit] += _radiosity.gather(points[hit], normals[hit], surfels, room, moving,
                                         wavenumbers)
    if (~hit).any():
        out[:, ~hit] = _radiosity.gather(points[~hit], normals[~hit], surfels, room, exitance,
                                         wavenumbers)
    return out


def _in_block(room: Room, g: int, block: StillBlock) -> bool:
    sl = slice(room.occluder_start[g], room.occluder_start[g + 1])
    digest = hashlib.sha1(b"".join((room.triangles[sl].tobytes(), room.normals[sl].tobytes(),
                                    room.albedo[sl].tobytes()))).digest()
    return digest in set(block.digests)


#: The moving objects' corrections are summed on every this-many-th node of the receiver
#: grid (in both directions) and spread to the other receivers.
CORRECTION_STRIDE = 2


def _coarse_nodes(nodes: _Nodes, exact: NDArray[np.int64]) -> NDArray[np.int64]:
    """Where in ``exact`` the coarse nodes are.

    Every :data:`CORRECTION_STRIDE`-th node of the grid; all of ``exact`` when none is.
    """
    coarse = ((np.arange(len(nodes.rows)) % CORRECTION_STRIDE == 0)[:, None]
              & (np.arange(len(nodes.cols)) % CORRECTION_STRIDE == 0)[None, :])
    is_coarse = np.zeros(len(nodes.index), dtype=bool)
    is_coarse[:nodes.node_count] = coarse[nodes.node_seen]
    at = np.flatnonzero(is_coarse[exact])
    return at if len(at) else np.arange(len(exact))


def _blocked_light(nodes: _Nodes, at: NDArray[np.int64], rows: NDArray[np.int64],
                   kept: _Receivers, block: StillBlock, movers: Surfels,
                   still_total: NDArray[np.complex128], ks: list[float]
                   ) -> NDArray[np.complex128]:
    """The still light the moving surfels block at receivers ``at`` (kept ``rows``).

    Summed on the coarse nodes; :func:`_first_order` spreads it (with the moving surfels'
    own light) to every receiver from the coarse nodes on its surface nearest to it
    (:func:`~simcore.sensors.tof.room_movers.spread`).

    Returns
    -------
    ndarray of complex, shape (K, len(at))
    """
    tris, start, lo, hi = _movers.proxy_occluders(movers)
    arrays = _surfel_arrays(block.surfels)
    out: NDArray[np.complex128] = _blocked(
        nodes.world[at], nodes.normals[at], rows, arrays[0], arrays[1], kept.factor,
        kept.distance, np.ascontiguousarray(still_total), np.asarray(ks), tris, start, lo, hi,
        *_union(lo, hi), sender_clusters(block.surfels.centre))
    return out


@kernel
def _row_dots(matrix: NDArray[np.generic], rows: NDArray[np.int64], vector: NDArray[np.generic]
              ) -> NDArray[np.complex128]:
    """``matrix[rows] @ vector``, each row summed in the same order wherever it is kept.

    (Bound by reading the matrix: an explicit unrolling into four partial sums, or BLAS,
    is no faster here, and BLAS's rounding may depend on the row's place.)
    """
    out = np.zeros(rows.shape[0], dtype=np.complex128)
    for r in range(rows.shape[0]):
        acc = 0j
        row = rows[r]
        for j in range(vector.shape[0]):
            acc += matrix[row, j] * vector[j]
        out[r] = acc
    return out


def _grown_receivers(points: F64, normals: F64, block: StillBlock, wavenumbers: list[float],
                     *, patch_m: float) -> tuple[_Receivers, NDArray[np.int64]]:
    """The kept receivers' exchange with the still surfels, new receivers added to it.

    A still camera sees, frame after frame, the same points of the still objects; those a
    moving object uncovers are added as they appear (their rows computed once, written
    into spare rows: the arrays double when full). The kept set is started afresh when it
    outgrows four times the receivers asked for (the camera moved). Kept per surfel size
    ``patch_m`` (the block's digests are those of the objects, whatever their surfels).

    Returns
    -------
    kept : _Receivers
        Its first ``len(kept.keys)`` rows are filled.
    rows : ndarray of int, shape (R,)
        Each receiver's row in ``kept``.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    normals = np.ascontiguousarray(normals, dtype=np.float64)
    keys = [p.tobytes() + n.tobytes() for p, n in zip(points, normals, strict=True)]
    with _LOCK:
        kept = _GROWN.get(patch_m)
        edit = _EDITS.get(patch_m)
    if kept is not None and kept.digests != block.digests and edit is not None \
            and edit.before == kept.digests and edit.after == block.digests:
        kept = _edited_receivers(kept, block, edit)      # the still objects were edited
    if kept is None or kept.digests != block.digests \
            or kept.wavenumbers != tuple(wavenumbers) or len(kept.keys) > 4 * len(keys) + 64:
        kept = _keep_receivers(points, normals, keys, block, wavenumbers)
    else:
        new = [i for i, key in enumerate(keys) if key not in kept.keys]
        if new:
            more = _keep_receivers(points[new], normals[new], [keys[i] for i in new], block,
                                   wavenumbers)
            kept = _append_rows(kept, more)
    with _LOCK:
        _GROWN.clear()
        _GROWN[patch_m] = kept
    return kept, np.array([kept.keys[key] for key in keys], dtype=np.int64)


def _append_rows(kept: _Receivers, more: _Receivers) -> _Receivers:
    """``kept`` with the rows of ``more`` after its filled ones (capacity doubled if needed)."""
    base, extra = len(kept.keys), len(more.keys)
    arrays: list[Any] = [kept.points, kept.normals, kept.factor, kept.distance, *kept.kernels]
    if base + extra > len(kept.factor):
        size = max(2 * len(kept.factor), base + extra)
        grown: list[Any] = []
        for a in arrays:
            if a.size == 0:                          # the k = 0 placeholder
                grown.append(a)
                continue
            b = np.zeros((size, a.shape[1]), dtype=a.dtype)
            b[:base] = a[:base]
            grown.append(b)
        arrays = grown
    added: list[NDArray[Any]] = [more.points, more.normals, more.factor, more.distance,
                                 *more.kernels]
    for a, m in zip(arrays, added, strict=True):
        if m.size:
            a[base:base + extra] = m
    keys = dict(kept.keys)
    keys.update({key: base + i for key, i in more.keys.items()})
    return _Receivers(kept.digests, keys, arrays[2], arrays[3], tuple(arrays[4:]),
                      kept.wavenumbers, arrays[0], arrays[1])


def _keep_receivers(points: F64, normals: F64, keys: list[bytes], block: StillBlock,
                    wavenumbers: list[float]) -> _Receivers:
    """Form factors and visibility (past the still objects) of receivers to still surfels."""
    lo, hi = occluder_boxes(block.room)
    arrays = _surfel_arrays(block.surfels)
    count = len(block.surfels.area)
    factor, distance, kernels = _row_arrays(len(points), count, wavenumbers)

    def rows(sl: slice) -> None:
        _receiver_rows(points[sl], normals[sl], *arrays, count, block.room.triangles,
                       block.room.occluder_start, lo, hi, factor[sl], distance[sl])
        _kernels_into(factor[sl], distance[sl], wavenumbers, [k[sl] for k in kernels])

    _by_halves(len(points), rows)
    return _Receivers(block.digests, {key: i for i, key in enumerate(keys)}, factor, distance,
                      tuple(kernels), tuple(wavenumbers), points.copy(), normals.copy())


__all__ = ["StillBlock", "group_digests", "room_gather", "room_indirect", "room_transfer"]


def _room_transfer(room: Room, patch_m: float
                   ) -> tuple[Surfels, NDArray[np.float32], NDArray[np.float32]]:
    """:func:`surfels_from_room` and :func:`transfer`, the still objects' part kept.

    Kept in this module (:func:`room_transfer`).
    """
    return room_transfer(room, patch_m)


@dataclass(frozen=True)
class _Nodes:
    """The receivers of :func:`room_indirect`: grid nodes and pixels summed exactly."""

    rows: NDArray[np.int64]
    cols: NDArray[np.int64]
    node_seen: NDArray[np.bool_]
    cell_y: NDArray[np.int64]
    cell_x: NDArray[np.int64]
    weights: NDArray[np.float64]
    missing: NDArray[np.bool_]
    node_count: int
    index: NDArray[np.int64]
    world: F64
    normals: F64


_WEIGHTS: dict[tuple[object, ...], tuple[F32, F32, NDArray[np.bool_], NDArray[np.float64],
                                          NDArray[np.bool_]]] = {}


def _receiver_nodes(points: F32, normals: F32, seen: NDArray[np.bool_], camera: F64,
                    step: int) -> _Nodes:
    """The node scheme of :func:`~simcore.sensors.tof.multipath.one_bounce_image`, world frame.

    A still camera's weights are redone only around the pixels whose receiver changed
    (:func:`~simcore.sensors.tof.multipath._update_node_weights`: the same numbers).
    """
    h, w = seen.shape
    rows, cols = _node_axis(h, step), _node_axis(w, step)
    node_seen = np.ascontiguousarray(seen[np.ix_(rows, cols)])
    cy, fy = _cell_of(h, rows)
    cx, fx = _cell_of(w, cols)
    key = (camera.tobytes(), h, w, step)
    with _LOCK:
        last = _WEIGHTS.pop(key, None)      # taken out: an exception leaves none behind
    if last is None:
        weights, missing = _node_weights(points, normals, seen, rows, cols, node_seen, cy, fy,
                                         cx, fx)
        last = (points.copy(), normals.copy(), seen.copy(), weights, missing)
    else:                                   # redone only around the receivers that changed
        last_points, last_normals, last_seen, weights, missing = last
        _update_node_weights(points, normals, seen, rows, cols, node_seen, cy, fy, cx, fx,
                             last_points, last_normals, last_seen, weights, missing,
                             step + CREASE_GUARD_PX)
        np.copyto(last_points, points)
        np.copyto(last_normals, normals)
        np.copyto(last_seen, seen)
    with _LOCK:
        _WEIGHTS.clear()
        _WEIGHTS[key] = last
    weights, missing = weights.copy(), missing.copy()
    node_index = (rows[:, None] * w + cols[None, :])[node_seen]
    index = np.concatenate([node_index, np.flatnonzero(missing & ~_on_nodes(seen, rows, cols))])
    rot, origin = camera[:3, :3], camera[:3, 3]
    world = points.reshape(-1, 3)[index].astype(np.float64) @ rot.T + origin
    nrm_world = normals.reshape(-1, 3)[index].astype(np.float64) @ rot.T
    return _Nodes(rows, cols, node_seen, cy, cx, weights, missing, len(node_index), index,
                  np.ascontiguousarray(world), np.ascontiguousarray(nrm_world))


def _to_image(nodes: _Nodes, irradiance: NDArray[np.complex128], seen: NDArray[np.bool_],
              points: F32, ks: list[float]
              ) -> tuple[F32, list[tuple[F32, F32]]]:
    """The receivers' irradiance (shape (1 + F, R)) blended to the camera's pixels."""
    sums = np.empty((len(nodes.index), 2 * len(ks) - 1), dtype=np.float32)
    sums[:, 0] = irradiance[0].real
    sums[:, 1::2] = irradiance[1:].real.T
    sums[:, 2::2] = irradiance[1:].imag.T
    values = np.zeros((len(nodes.rows), len(nodes.cols), sums.shape[1]), dtype=np.float32)
    values[nodes.node_seen] = sums[:nodes.node_count]
    out = _blend_nodes(seen, nodes.weights, nodes.missing, values, nodes.cell_y, nodes.cell_x,
                       nodes.index, sums, points, np.asarray(ks[1:], dtype=np.float32))
    return out[0], [(out[1 + 2 * j], out[2 + 2 * j]) for j in range(len(ks) - 1)]


def room_indirect(room: Room, *, camera: F64, intrinsics: PinholeIntrinsics,
                  range_m: NDArray[np.floating], points_m: NDArray[np.floating],
                  normals: NDArray[np.floating], seen: NDArray[np.bool_],
                  frequencies_hz: list[float], patch_m: float, bounces: int = 0,
                  step: int = RECEIVER_STEP, moving: str = "first_order"
                  ) -> tuple[F32, list[tuple[F32, F32]]]:
    """Indirect light at the camera's pixels from the whole room, as :func:`one_bounce_image`.

    Parameters
    ----------
    room : Room
    camera : ndarray, shape (4, 4)
        Optical frame → world.
    intrinsics, range_m
        The render's grid and range (the light's shadow map, :func:`first_exitance`).
    points_m, normals : ndarray, shape (H, W, 3)
        Receivers: each pixel's surface point and unit normal (optical frame).
    seen : ndarray of bool, shape (H, W)
    frequencies_hz : list of float
    patch_m : float, keyword-only
        Surfel size.
    bounces : int, keyword-only
        Indirect bounces (1: one bounce); 0: all (to convergence).
    step : int, keyword-only
        Receiver node spacing (pixels): the sum is exact on every ``step``-th row and
        column and at the pixels without a node on their surface or next to a concave
        crease, and blended in between (the node scheme of
        :func:`simcore.sensors.tof.multipath.one_bounce_image`); 1: every pixel.
    moving : {"first_order", "exact"}, keyword-only
        Objects that moved since the last frame: to first order in them
        (:mod:`simcore.sensors.tof.room_movers`), or exactly (every pair recomputed).

    Returns
    -------
    magnitude : ndarray, shape (H, W), float32
        Indirect irradiance at each pixel's surface in units of the illumination's
        ``cos θ / R²`` (multiply by ``k ρ_P`` for electrons).
    phasors : list of (re, im), each ndarray of shape (H, W), float32
        Per frequency, the same with each path's phase ``e^{i 2π f L / c}`` (``L`` the whole
        optical path, camera leg included).
    """
    ks = [0.0] + [2.0 * np.pi * f / SPEED_OF_LIGHT for f in frequencies_hz]
    pts = np.ascontiguousarray(points_m, dtype=np.float32)
    nrm = np.ascontiguousarray(normals, dtype=np.float32)
    seen = np.ascontiguousarray(seen)
    flags = room.moving
    if moving == "first_order" and flags is not None and flags.any() and not flags.all():
        grid = _pool().submit(_receiver_nodes, pts, nrm, seen, camera, step)
        irradiance = _first_order(room, [int(g) for g in np.flatnonzero(flags)], grid,
                                  camera, intrinsics, range_m, ks, patch_m=patch_m,
                                  bounces=bounces)
        return _to_image(grid.result(), irradiance, seen, pts, ks)
    nodes = _receiver_nodes(pts, nrm, seen, camera, step)
    surfels, factor, distance = _room_transfer(room, patch_m)
    emitted = first_exitance(surfels, camera, intrinsics, range_m, ks)
    total = radiosity(factor, distance, surfels.albedo, emitted, ks, bounces=bounces)
    irradiance = room_gather(nodes.world, nodes.normals, surfels, room, total, ks,
                             patch_m=patch_m)                               # (1 + F, M)
    return _to_image(nodes, irradiance, seen, pts, ks)


def _still_objects(room: Room, groups: list[int], patch_m: float) -> StillBlock:
    """The exchange among the objects ``groups`` of ``room`` (kept while they are the same)."""
    still = sub_room(room, groups)
    digests = tuple(group_digests(still))
    with _LOCK:
        block = _STILL.get(patch_m)
    if block is None or block.digests != digests:
        edited = None if block is None else _edited_block(block, still, digests, patch_m)
        block = _full_block(still, digests, patch_m) if edited is None else edited[0]
        with _LOCK:
            _STILL.clear()
            _STILL[patch_m] = block
            _EDITS.clear()
            if edited is not None:
                _EDITS[patch_m] = edited[1]
    return block


_STILL: dict[float, StillBlock] = {}
#: The last change of the still objects (:func:`_edited_block`), for the kept receivers.
_EDITS: dict[float, _Edit] = {}


def _first_order(room: Room, moving: list[int], grid: Future[_Nodes], camera: F64,
                 intrinsics: PinholeIntrinsics, range_m: NDArray[np.floating],
                 ks: list[float], *, patch_m: float, bounces: int) -> NDArray[np.complex128]:
    """The receivers' irradiance with the moving objects to first order (:mod:`.room_movers`).

    The still light is exact at every receiver but those beside a moving object
    (:func:`_beside_movers`); the moving objects' corrections (light they send and block)
    are summed at coarse grid nodes and spread to the others on the same surface. Nothing
    depends on earlier frames but what is kept to save time. ``grid``: the receivers, being
    made on the helper thread meanwhile.
    """
    still_groups = [g for g in range(len(room.occluder_start) - 1) if g not in set(moving)]
    block = _still_objects(room, still_groups, patch_m)
    mover_room = sub_room(room, moving)
    one = Room(mover_room.triangles, mover_room.normals, mover_room.albedo,
               np.array([0, len(mover_room.triangles)], dtype=np.int64))
    movers = _movers.mover_surfels(one, patch_m)
    still = block.surfels
    emitted = first_exitance(join(still, movers), camera, intrinsics, range_m, ks)
    ns = len(still.area)
    operator = _movers.still_operator((block.digests, patch_m), block.factor, block.distance,
                                      still.albedo, ks)
    still_total = _movers.still_radiosity(operator, emitted[:, :ns], ks, bounces=bounces)
    # The moving surfels' light and the still light at the receivers run on a helper
    # thread beside the blocked light (compiled kernels without the GIL: two cores).
    exiting = _pool().submit(_movers.mover_exitance, movers, still, block.room, still_total,
                             emitted[:, ns:], ks, bounces=bounces)
    nodes = grid.result()
    on = _movers.on_movers(nodes.world, mover_room)
    beside = _beside_movers(nodes, on)
    exact = np.flatnonzero(~on & ~beside)
    kept, rows = _grown_receivers(nodes.world[exact], nodes.normals[exact], block, ks,
                                  patch_m=patch_m)
    lighting = _pool().submit(_still_light, kept, rows, still_total, ks)
    at = _coarse_nodes(nodes, exact)
    blocked = None
    if len(movers.area) and len(exact):
        # The helper thread takes the first part of the coarse nodes, this one the rest.
        cut = int(len(at) * HELPER_SHARE)
        first = _pool().submit(_blocked_light, nodes, exact[at[:cut]], rows[at[:cut]], kept,
                               block, movers, still_total, ks)
        rest = _blocked_light(nodes, exact[at[cut:]], rows[at[cut:]], kept, block, movers,
                              still_total, ks)
        blocked = np.concatenate([first.result(), rest], axis=1)
    mover_total, received = exiting.result()
    out = np.zeros((len(ks), len(nodes.index)), dtype=np.complex128)
    if on.any() and len(movers.area):
        near = _movers.nearest_mover(nodes.world[on], nodes.normals[on], movers)
        out[:, on] = received[:, near]
    out[:, exact] = lighting.result()
    if blocked is not None:
        points, normals = nodes.world[exact[at]], nodes.normals[exact[at]]
        change = _radiosity.gather(points, normals, movers, block.room, mover_total, ks)
        index, weight = _movers.spread(nodes.world[exact], nodes.normals[exact], points,
                                       normals)
        out[:, exact] += np.einsum("qrk,rk->qr", (change - blocked)[:, index], weight)
    on_grid = exact[exact < nodes.node_count]
    if beside.any() and len(on_grid):
        index, weight = _movers.spread(nodes.world[beside], nodes.normals[beside],
                                       nodes.world[on_grid], nodes.normals[on_grid])
        out[:, beside] = np.einsum("qrk,rk->qr", out[:, on_grid][:, index], weight)
    return out


def _still_light(kept: _Receivers, rows: NDArray[np.int64], still_total: NDArray[np.complex128],
                 ks: list[float]) -> NDArray[np.complex128]:
    """The still radiosity's light at the kept receivers ``rows``, shape (K, R)."""
    out = np.zeros((len(ks), len(rows)), dtype=np.complex128)
    for q, k in enumerate(ks):
        if k == 0.0:
            out[q] = _row_dots(kept.factor, rows, still_total[q].real.astype(np.float32))
        else:
            out[q] = _row_dots(kept.kernels[q], rows, still_total[q].astype(np.complex64))
    return out


#: The share of the blocked light's coarse nodes summed on the helper thread (which also
#: sums the moving surfels' exitance and the still light meanwhile).
HELPER_SHARE = 0.25

_POOL: list[ThreadPoolExecutor] = []
_POOL_LOCK = threading.Lock()


def _pool() -> ThreadPoolExecutor:
    """One helper thread for the room model's work beside the calling thread."""
    with _POOL_LOCK:
        if not _POOL:
            _POOL.append(ThreadPoolExecutor(max_workers=1, thread_name_prefix="tof-room"))
        return _POOL[0]


if hasattr(os, "register_at_fork"):      # a forked child has the pool but not its thread
    os.register_at_fork(after_in_child=_POOL.clear)


#: Receivers off the grid within this many pixels of a receiver on a moving object take
#: their light from the grid nodes on their surface (:func:`_beside_movers`).
BESIDE_PX = 2 * RECEIVER_STEP


def _beside_movers(nodes: _Nodes, on: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Receivers off the grid, on still surfaces, within :data:`BESIDE_PX` of a moving object.

    The node scheme sums them exactly because a moving object covers a node of their cell
    (the still surface around them has no node there); they take their light from the
    grid nodes on their own surface instead, so the receivers summed exactly are, frame
    after frame, the same ones (their rows are computed once).
    """
    from scipy.ndimage import maximum_filter

    h, w = len(nodes.cell_y), len(nodes.cell_x)
    mark = np.zeros(h * w, dtype=bool)
    mark[nodes.index[on]] = True
    grown = maximum_filter(mark.reshape(h, w), size=2 * BESIDE_PX + 1).ravel()
    off_grid = np.arange(len(nodes.index)) >= nodes.node_count
    return np.asarray(grown[nodes.index] & off_grid & ~on, dtype=bool)


def _on_nodes(seen: NDArray[np.bool_], rows: NDArray[np.int64], cols: NDArray[np.int64]
              ) -> NDArray[np.bool_]:
    """The pixels of the node grid (already summed as nodes)."""
    grid = np.zeros(seen.shape, dtype=bool)
    grid[np.ix_(rows, cols)] = True
    return grid & seen
