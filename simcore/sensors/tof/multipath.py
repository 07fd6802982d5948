"""ToF multipath interference (MPI): light that reaches a pixel through a second surface.

The camera's illumination lights a surface point Q; Q's diffuse reflection lights the
point P a pixel sees, which reflects it back to the camera. The pixel integrates this
light over the longer path ``R_Q + |Q − P| + R_P`` on top of its direct return (path
``2 R_P``); both are phasors of the modulation frequency, so the pixel's phase — its depth —
is pulled towards the longer path: depth is over-estimated, most in concave corners and
next to bright walls.

With the radiometry of :mod:`simcore.scene.tof_config` (signal ``S = k f(θ) / R²`` for a
surface response ``f``; Lambertian ``f = ρ cos θ``), the one-bounce signal at P is::

    S_ind(P) = k ρ_P Σ_Q (ρ_Q / π) Ω_Q cos θ_Q,out cos θ_P,in / |Q − P|²

where the senders Q are the surface points the camera sees (pixels of its render, each
lit by the solid angle ``Ω_Q`` of its pixel), ``ρ`` the diffuse albedo of the ToF band
(``(1 − metallic) · reflectance``), and the cosines are taken between each normal and the
segment Q–P (pairs facing away contribute nothing). The sum runs over senders on a coarse
grid (every ``stride``-th render pixel, its solid angle scaled accordingly).

Assumptions and limits: one bounce, diffuse (specular bounces off mirrors and metal are not
modelled); only surfaces the camera sees act as senders (screen space: a wall behind the
camera lights nothing); no occlusion test between Q and P (an object between two surfaces
does not shadow the indirect light). A flat surface cannot light itself (its points see
each other edge-on), so a single wall shows no MPI.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.scene.tof_config import SPEED_OF_LIGHT

F32 = NDArray[np.float32]
_MIN_DIST_SQ = np.float32(1e-6)
#: Receivers per block of the pair sums (bounds the temporaries to ≈ 10 MB per array).
BLOCK = 4096


@dataclass(frozen=True)
class Senders:
    """The lit surface points that re-emit light, shape (N,) per attribute.

    Attributes
    ----------
    points_m : ndarray, shape (N, 3)
        Positions in the camera's optical frame (m).
    normals : ndarray, shape (N, 3)
        Unit normals facing the camera.
    weight : ndarray, shape (N,)
        ``ρ_Q Ω_Q / π``: diffuse albedo × lit solid angle (sr) / π.
    range_m : ndarray, shape (N,)
        Distance from the camera (m).
    slot_index : ndarray of int, shape (N,), optional
        Each sender's position on the sender grid of shape ``grid_shape`` (flat index).
    tile_start : ndarray of int, shape (T + 1,), optional
        The senders are ordered by tile (``TILE × TILE`` blocks of the sender grid); tile
        ``t`` holds senders ``tile_start[t]:tile_start[t + 1]``. The one-bounce sums are
        added per tile, so that :class:`OneBounceCache` can redo only the changed tiles and
        still give the very same numbers. ``None``: one tile.
    """

    points_m: F32
    normals: F32
    weight: F32
    range_m: F32
    slot_index: NDArray[np.int64] | None = None
    grid_shape: tuple[int, int] = (0, 0)
    tile_start: NDArray[np.int64] | None = None

    def tiles(self) -> NDArray[np.int64]:
        """``tile_start``, or one tile of all senders."""
        if self.tile_start is None:
            return np.array([0, len(self.weight)], dtype=np.int64)
        return self.tile_start


def senders_from_render(points_m: F32, normals: F32, albedo: F32, solid_angle_sr: F32,
                        valid: NDArray[np.bool_], *, stride: int) -> Senders:
    """Every ``stride``-th render pixel (both axes) that sees a surface, as a sender.

    Parameters
    ----------
    points_m, normals : ndarray, shape (H, W, 3)
        Surface points and unit normals of the render, optical frame.
    albedo : ndarray, shape (H, W)
        Diffuse albedo of the ToF band at each pixel.
    solid_angle_sr : ndarray, shape (H, W)
        Solid angle of each render pixel (sr).
    valid : ndarray of bool, shape (H, W)
        Pixels that see a surface.
    stride : int
        Subsampling step; each sender stands for ``stride²`` pixels.
    """
    sl = (slice(stride // 2, None, stride), slice(stride // 2, None, stride))
    keep = valid[sl] & (albedo[sl] > 0)
    slot = np.flatnonzero(keep)
    tile = _tile_of(slot, keep.shape)
    order = np.argsort(tile, kind="stable")
    slot, tile = slot[order], tile[order]
    pts = points_m[sl].reshape(-1, 3)[slot].astype(np.float32)
    weight = (albedo[sl].ravel()[slot] * solid_angle_sr[sl].ravel()[slot]
              * (stride * stride / np.pi))
    n_tiles = _tile_of(np.array([keep.size - 1]), keep.shape)[0] + 1
    return Senders(points_m=pts, normals=normals[sl].reshape(-1, 3)[slot].astype(np.float32),
                   weight=weight.astype(np.float32),
                   range_m=np.linalg.norm(pts, axis=1).astype(np.float32),
                   slot_index=slot, grid_shape=keep.shape,
                   tile_start=np.searchsorted(tile, np.arange(n_tiles + 1)).astype(np.int64))


#: Side of the square tiles of the sender grid whose sums are kept apart (senders).
TILE = 4


def _tile_of(slot: NDArray[np.int64], grid_shape: tuple[int, int]) -> NDArray[np.int64]:
    """Tile of each flat sender-grid position (row-major ``TILE × TILE`` blocks)."""
    cols = grid_shape[1]
    tiles_x = -(-cols // TILE)
    return ((slot // cols) // TILE * tiles_x + (slot % cols) // TILE).astype(np.int64)


def one_bounce(points_m: F32, normals: F32, senders: Senders, frequencies_hz: list[float]
               ) -> tuple[F32, list[tuple[F32, F32]]]:
    """Indirect signal factor and its phasors at receiver points.

    Parameters
    ----------
    points_m, normals : ndarray, shape (M, 3)
        Receiver surface points and unit normals (optical frame, m).
    senders : Senders
        From :func:`senders_from_render`.
    frequencies_hz : list of float
        Modulation frequencies.

    Returns
    -------
    magnitude : ndarray, shape (M,)
        ``Σ_Q w_Q cos θ_Q cos θ_P / |Q − P|²`` (1/m²; multiply by ``k ρ_P`` for electrons).
    phasors : list of (re, im), each ndarray of shape (M,)
        Per frequency ``Σ_Q (same term) · exp(i 2π f (R_Q + |Q − P| + R_P) / c)`` as real
        and imaginary parts, in the same units; the phase of the direct return is
        ``2π f · 2 R_P / c``.
    """
    m = len(points_m)
    magnitude = np.zeros(m, dtype=np.float32)
    phasors = [(np.zeros(m, dtype=np.float32), np.zeros(m, dtype=np.float32))
               for _ in frequencies_hz]
    if m == 0 or len(senders.weight) == 0:
        return magnitude, phasors
    q, nq = senders.points_m, senders.normals
    q_sq = np.einsum("ij,ij->i", q, q)
    nq_dot_q = np.einsum("ij,ij->i", nq, q)
    r_p = np.linalg.norm(points_m, axis=1).astype(np.float32)
    k = [np.float32(2.0 * np.pi * f / SPEED_OF_LIGHT) for f in frequencies_hz]
    for lo in range(0, m, BLOCK):
        sl = slice(lo, min(lo + BLOCK, m))
        p, n_p = points_m[sl].astype(np.float32), normals[sl].astype(np.float32)
        # d = Q − P for every pair, through three small matrix products.
        dist_sq = (q_sq[None, :] + np.einsum("ij,ij->i", p, p)[:, None] - 2.0 * (p @ q.T))
        np.maximum(dist_sq, np.float32(1e-6), out=dist_sq)
        cos_p = n_p @ q.T - np.einsum("ij,ij->i", n_p, p)[:, None]      # n_P · d
        cos_q = (p @ nq.T) - nq_dot_q[None, :]                            # −n_Q · d
        np.maximum(cos_p, 0.0, out=cos_p)
        np.maximum(cos_q, 0.0, out=cos_q)
        # cos θ_P cos θ_Q / |d|² = (n_P·d)(−n_Q·d) / |d|⁴
        term = cos_p * cos_q / (dist_sq * dist_sq) * senders.weight[None, :]
        magnitude[sl] = term.sum(axis=1)
        path = np.sqrt(dist_sq) + senders.range_m[None, :] + r_p[sl, None]
        for (re, im), kk in zip(phasors, k, strict=True):
            phase = path * kk
            re[sl] = (term * np.cos(phase)).sum(axis=1)
            im[sl] = (term * np.sin(phase)).sum(axis=1)
    return magnitude, phasors


#: Receiver grid step of :func:`one_bounce_image` (sensor pixels): the indirect light is
#: computed exactly on every ``RECEIVER_STEP``-th pixel and interpolated in between.
RECEIVER_STEP = 4
#: Two receivers lie on the same smooth surface when their normals agree to this cosine …
SAME_SURFACE_COS = 0.95
#: … and each lies within this fraction of their distance (plus ``SAME_SURFACE_TOL_M``) of
#: the other's tangent plane.
SAME_SURFACE_SLOPE = 0.1
SAME_SURFACE_TOL_M = 0.005
#: A pixel with a pixel of another surface facing it within this many pixels (a concave
#: crease) is summed exactly: next to such a crease the nearest senders' ``1/|Q − P|⁴``
#: makes the indirect light too steep for interpolation between nodes (on the office the
#: interpolated bias was 40 % off the exact sum within 2 px of a crease, 2 % beyond).
CREASE_GUARD_PX = 2


def _node_axis(size: int, step: int) -> NDArray[np.int64]:
    """Node positions along one axis: every ``step``-th pixel and the last one."""
    nodes = np.arange(0, size, step)
    return nodes if nodes[-1] == size - 1 else np.append(nodes, size - 1)


def _cell_of(size: int, nodes: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.float32]]:
    """For every pixel of an axis: the node interval it lies in and its fraction there."""
    pos = np.arange(size)
    if len(nodes) == 1:
        return np.zeros(size, dtype=np.int64), np.zeros(size, dtype=np.float32)
    cell = np.clip(np.searchsorted(nodes, pos, side="right") - 1, 0, len(nodes) - 2)
    frac = (pos - nodes[cell]) / (nodes[cell + 1] - nodes[cell])
    return cell.astype(np.int64), frac.astype(np.float32)


@kernel
def _relation(points: F32, normals: F32, y: int, x: int, yy: int, xx: int) -> int:
    """How pixel (yy, xx)'s surface point relates to pixel (y, x)'s.

    0: the same smooth surface (normals within ``SAME_SURFACE_COS``, each point within
    ``SAME_SURFACE_SLOPE · distance + SAME_SURFACE_TOL_M`` of the other's tangent plane);
    2: another surface facing it across a concave crease (each point in front of the
    other's tangent plane by more than that tolerance); 1: another surface otherwise
    (convex edge, depth edge).
    """
    cos = 0.0
    gap_p = 0.0
    gap_q = 0.0
    dist = 0.0
    for c in range(3):
        d = points[yy, xx, c] - points[y, x, c]
        cos += normals[y, x, c] * normals[yy, xx, c]
        gap_p += normals[y, x, c] * d
        gap_q += normals[yy, xx, c] * d
        dist += d * d
    tol = SAME_SURFACE_SLOPE * math.sqrt(dist) + SAME_SURFACE_TOL_M
    if not (cos < SAME_SURFACE_COS or abs(gap_p) > tol or abs(gap_q) > tol):
        return 0
    if gap_p > tol and -gap_q > tol:
        return 2
    return 1


@kernel
def _facing(points: F32, normals: F32, y: int, x: int, yy: int, xx: int) -> bool:
    """Whether ``_relation(...) == 2``: a concave crease between the two pixels.

    The common case, a point on or behind the other's tangent plane, is rejected before
    any square root.
    """
    d0 = points[yy, xx, 0] - points[y, x, 0]
    d1 = points[yy, xx, 1] - points[y, x, 1]
    d2 = points[yy, xx, 2] - points[y, x, 2]
    gap_p = normals[y, x, 0] * d0 + normals[y, x, 1] * d1 + normals[y, x, 2] * d2
    if gap_p <= SAME_SURFACE_TOL_M:
        return False
    gap_q = normals[yy, xx, 0] * d0 + normals[yy, xx, 1] * d1 + normals[yy, xx, 2] * d2
    if -gap_q <= SAME_SURFACE_TOL_M:
        return False
    tol = SAME_SURFACE_SLOPE * math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) + SAME_SURFACE_TOL_M
    return gap_p > tol and -gap_q > tol


@kernel
def _near_crease(points: F32, normals: F32, seen: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Seen pixels with a seen pixel facing them across a concave crease within the guard.

    Within ``CREASE_GUARD_PX`` (both axes) of each other. :func:`_facing` is symmetric
    bit for bit (swapping the two pixels negates ``d`` exactly and swaps and negates the
    two gaps), so each pair is tested once and marks both pixels.
    """
    h, w = seen.shape
    g = CREASE_GUARD_PX
    near = np.zeros((h, w), dtype=np.bool_)
    for y in range(h):
        for x in range(w):
            if not seen[y, x]:
                continue
            for yy in range(y, min(y + g + 1, h)):
                for xx in range(max(x - g, 0) if yy > y else x + 1, min(x + g + 1, w)):
                    if seen[yy, xx] and _facing(points, normals, y, x, yy, xx):
                        near[y, x] = True
                        near[yy, xx] = True
    return near


@kernel
def _node_weights(points: F32, normals: F32, seen: NDArray[np.bool_],
                  node_rows: NDArray[np.int64], node_cols: NDArray[np.int64],
                  node_seen: NDArray[np.bool_],
                  cell_y: NDArray[np.int64], frac_y: F32,
                  cell_x: NDArray[np.int64], frac_x: F32
                  ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Each pixel's weights of the four nodes around it, and the pixels to sum exactly.

    Of the four nodes around a pixel, only those on the pixel's own smooth surface (normals
    within ``SAME_SURFACE_COS``; each point near the other's tangent plane) are blended, with
    their bilinear weights (renormalised by :func:`_blend_nodes`). A seen pixel without such
    a node, or with a pixel of another surface facing it across a concave crease within
    ``CREASE_GUARD_PX`` (and not itself a node), is flagged. The weights do not depend on
    the node values, so the flagged pixels are known before any sum: the nodes and they
    are summed in one pass (:class:`OneBounceCache`).

    Parameters
    ----------
    points, normals : ndarray, shape (H, W, 3)
        Receiver points (m) and unit normals.
    seen : ndarray of bool, shape (H, W)
    node_rows, node_cols : ndarray of int, shapes (NY,), (NX,)
        Pixel coordinates of the node grid.
    node_seen : ndarray of bool, shape (NY, NX)
    cell_y, frac_y, cell_x, frac_x : ndarray, shapes (H,), (H,), (W,), (W,)
        From :func:`_cell_of`.

    Returns
    -------
    weights : ndarray, shape (H, W, 4), float64
        Weight of node ``(cell_y + dy, cell_x + dx)`` at ``2 dy + dx`` (0: not blended).
    missing : ndarray of bool, shape (H, W)
        Seen pixels with no node on their surface or next to a concave crease (to be
        computed exactly).
    """
    h, w = seen.shape
    weights = np.zeros((h, w, 4))
    missing = np.zeros((h, w), dtype=np.bool_)
    near_crease = _near_crease(points, normals, seen)
    for y in range(h):
        for x in range(w):
            _pixel_weights(points, normals, seen, node_rows, node_cols, node_seen, cell_y,
                           frac_y, cell_x, frac_x, near_crease, y, x, weights, missing)
    return weights, missing


@kernel
def _pixel_weights(points: F32, normals: F32, seen: NDArray[np.bool_],
                   node_rows: NDArray[np.int64], node_cols: NDArray[np.int64],
                   node_seen: NDArray[np.bool_], cell_y: NDArray[np.int64], frac_y: F32,
                   cell_x: NDArray[np.int64], frac_x: F32, near_crease: NDArray[np.bool_],
                   y: int, x: int, weights: NDArray[np.float64], missing: NDArray[np.bool_]
                   ) -> None:
    """:func:`_node_weights` of pixel (y, x), written into ``weights`` and ``missing``.

    ``near_crease[y, x]``: whether the pixel has another surface facing it across a
    concave crease within ``CREASE_GUARD_PX`` (:func:`_near_crease`).
    """
    for v in range(4):
        weights[y, x, v] = 0.0
    missing[y, x] = False
    if not seen[y, x]:
        return
    # A node keeps its own exact value; other pixels near a crease are flagged.
    node = ((frac_y[y] == 0.0 or frac_y[y] == 1.0)
            and (frac_x[x] == 0.0 or frac_x[x] == 1.0))
    if near_crease[y, x] and not node:
        missing[y, x] = True
        return
    total = 0.0
    for dy in range(2):
        iy = min(cell_y[y] + dy, len(node_rows) - 1)
        wy = frac_y[y] if dy else 1.0 - frac_y[y]
        for dx in range(2):
            ix = min(cell_x[x] + dx, len(node_cols) - 1)
            wx = frac_x[x] if dx else 1.0 - frac_x[x]
            if not node_seen[iy, ix]:
                continue
            if _relation(points, normals, y, x, node_rows[iy], node_cols[ix]):
                continue
            weight = wy * wx + 1e-6
            total += weight
            weights[y, x, 2 * dy + dx] = weight
    if total <= 0.0:
        missing[y, x] = True


@kernel
def _dilate_line(flags: NDArray[np.bool_], reach: int, out: NDArray[np.bool_]) -> None:
    """Set ``out[i]`` where a flag lies within ``reach`` of ``i`` (a 1-D box dilation)."""
    n = flags.shape[0]
    last = -reach - 1
    for i in range(n):
        if flags[i]:
            last = i
        if i - last <= reach:
            out[i] = True
    last = n + reach + 1
    for i in range(n - 1, -1, -1):
        if flags[i]:
            last = i
        if last - i <= reach:
            out[i] = True


@kernel
def _update_node_weights(points: F32, normals: F32, seen: NDArray[np.bool_],
                         node_rows: NDArray[np.int64], node_cols: NDArray[np.int64],
                         node_seen: NDArray[np.bool_], cell_y: NDArray[np.int64],
                         frac_y: F32, cell_x: NDArray[np.int64], frac_x: F32,
                         last_points: F32, last_normals: F32, last_seen: NDArray[np.bool_],
                         weights: NDArray[np.float64], missing: NDArray[np.bool_],
                         reach: int) -> int:
    """Redo :func:`_node_weights` in place only where the receivers changed.

    ``weights`` and ``missing`` hold the last frame's, computed from ``last_points``,
    ``last_normals`` and ``last_seen``. A pixel's result reads its own receiver, its four
    nodes (within ``reach − CREASE_GUARD_PX`` pixels: the node step) and the pixels within
    ``CREASE_GUARD_PX`` (the crease guard), so every pixel within ``reach`` of a changed
    receiver (point, normal or seen, bit for bit) is redone; the others keep theirs — the
    same numbers as a fresh :func:`_node_weights`. Returns the number of pixels redone.
    """
    h, w = seen.shape
    changed = np.zeros((h, w), dtype=np.bool_)
    for y in range(h):
        for x in range(w):
            if seen[y, x] != last_seen[y, x]:
                changed[y, x] = True
                continue
            if not seen[y, x]:
                continue
            for c in range(3):
                if (points[y, x, c] != last_points[y, x, c]
                        or normals[y, x, c] != last_normals[y, x, c]):
                    changed[y, x] = True
    # Box dilation by ``reach``, one axis at a time.
    rows = np.zeros((h, w), dtype=np.bool_)
    for y in range(h):
        _dilate_line(changed[y], reach, rows[y])
    redo = np.zeros((h, w), dtype=np.bool_)
    for x in range(w):
        _dilate_line(rows[:, x], reach, redo[:, x])
    g = CREASE_GUARD_PX
    count = 0
    near_crease = np.zeros((h, w), dtype=np.bool_)
    for y in range(h):
        for x in range(w):
            if not redo[y, x]:
                continue
            count += 1
            near = False
            if seen[y, x]:
                for yy in range(max(y - g, 0), min(y + g + 1, h)):
                    for xx in range(max(x - g, 0), min(x + g + 1, w)):
                        if ((yy != y or xx != x) and seen[yy, xx]
                                and _facing(points, normals, y, x, yy, xx)):
                            near = True
            near_crease[y, x] = near
            _pixel_weights(points, normals, seen, node_rows, node_cols, node_seen, cell_y,
                           frac_y, cell_x, frac_x, near_crease, y, x, weights, missing)
    return count


@kernel
def _blend_nodes(seen: NDArray[np.bool_], weights: NDArray[np.float64],
                 missing: NDArray[np.bool_], node_values: F32,
                 cell_y: NDArray[np.int64], cell_x: NDArray[np.int64],
                 exact_index: NDArray[np.int64], exact_values: F32, points: F32,
                 k: F32) -> F32:
    """Indirect light per pixel: nodes blended by :func:`_node_weights`, or the exact sum.

    The blend adds the weighted node values in float64 and divides by the weights' sum;
    pixels in ``missing`` take their exact sum (``exact_values`` row of their flat pixel
    index in ``exact_index``, the last such row). Then each receiver's own leg
    ``exp(i k_f R_P)`` is put back on the phasors, in float32 throughout (``R_P = |P|``,
    the phase, its cosine and sine, and the complex product as numpy's complex64 one).

    Returns
    -------
    ndarray, shape (1 + 2F, H, W), float32
        The magnitude and per frequency the phasor's real and imaginary parts; 0 where
        not ``seen``.
    """
    h, w = seen.shape
    nv = node_values.shape[2]
    ny, nx = node_values.shape[0], node_values.shape[1]
    out = np.zeros((nv, h, w), dtype=np.float32)
    row = np.full(h * w, -1, dtype=np.int64)
    for i in range(exact_index.shape[0]):
        row[exact_index[i]] = i
    acc = np.zeros(nv)
    val = np.zeros(nv, dtype=np.float32)
    for y in range(h):
        for x in range(w):
            if not seen[y, x]:
                continue
            if missing[y, x]:
                r = row[y * w + x]
                for v in range(nv):
                    val[v] = exact_values[r, v]
            else:
                total = 0.0
                acc[:] = 0.0
                for dy in range(2):
                    iy = min(cell_y[y] + dy, ny - 1)
                    for dx in range(2):
                        weight = weights[y, x, 2 * dy + dx]
                        if weight == 0.0:
                            continue
                        ix = min(cell_x[x] + dx, nx - 1)
                        total += weight
                        for v in range(nv):
                            acc[v] += weight * node_values[iy, ix, v]
                for v in range(nv):
                    val[v] = acc[v] / total
            out[0, y, x] = val[0]
            px, py, pz = points[y, x, 0], points[y, x, 1], points[y, x, 2]
            r_p = math.sqrt(px * px + py * py + pz * pz)
            for f in range(k.shape[0]):
                phase = k[f] * r_p
                c, s = math.cos(phase), math.sin(phase)
                re, im = val[1 + 2 * f], val[2 + 2 * f]
                # numpy's complex64 product, fused: fma(re, c, −im·s), fma(re, s, im·c)
                # (the float32 products are exact in float64).
                out[1 + 2 * f, y, x] = np.float64(re) * np.float64(c) - np.float64(im * s)
                out[2 + 2 * f, y, x] = np.float64(re) * np.float64(s) + np.float64(im * c)
    return out


def one_bounce_image(points_m: F32, normals: F32, seen: NDArray[np.bool_], senders: Senders,
                     frequencies_hz: list[float], *, step: int = RECEIVER_STEP,
                     cache: OneBounceCache | None = None, camera: Hashable = None
                     ) -> tuple[F32, list[tuple[F32, F32]]]:
    """:func:`one_bounce` for every pixel of an image, exact on a coarse grid of receivers.

    The indirect light varies slowly over a smooth surface: it is summed exactly
    (:func:`one_bounce`) on the receivers of every ``step``-th row and column (and the last
    ones), and each pixel blends the nodes around it that lie on its own surface
    (:func:`_interpolate_nodes`); pixels with no such node (depth and crease edges, small
    objects) are summed exactly. The phasors are interpolated without their receiver's
    own leg, ``exp(i 2π f R_P / c)``, which is put back per pixel, so only the slow
    ``R_Q + |Q − P|`` part is interpolated. ``step = 1`` is :func:`one_bounce` itself.

    Parameters
    ----------
    points_m, normals : ndarray, shape (H, W, 3)
        Receiver points (optical frame, m) and unit normals; only ``seen`` pixels are used.
    seen : ndarray of bool, shape (H, W)
    senders : Senders
    frequencies_hz : list of float
    step : int, keyword-only
        Node spacing (pixels).
    cache : OneBounceCache, keyword-only, optional
        Reuse of the previous call's exact sums where only part of the render changed
        (:class:`OneBounceCache`); the result is the same sum.
    camera : hashable, keyword-only, optional
        Which camera the receivers are (its pose): the cache keeps each camera's last
        frame apart, so several cameras do not evict each other's sums.

    Returns
    -------
    magnitude : ndarray, shape (H, W)
        As :func:`one_bounce` (0 where not ``seen``).
    phasors : list of (re, im), each ndarray of shape (H, W)
    """
    h, w = seen.shape
    nf = len(frequencies_hz)
    if step <= 1:
        mag_s, ph_s = one_bounce(points_m[seen], normals[seen], senders, frequencies_hz)
        magnitude = np.zeros((h, w), dtype=np.float32)
        magnitude[seen] = mag_s
        phasors = []
        for re_s, im_s in ph_s:
            re, im = np.zeros_like(magnitude), np.zeros_like(magnitude)
            re[seen], im[seen] = re_s, im_s
            phasors.append((re, im))
        return magnitude, phasors
    rows, cols = _node_axis(h, step), _node_axis(w, step)
    grid = np.ix_(rows, cols)
    node_seen = np.ascontiguousarray(seen[grid])
    k = [2.0 * np.pi * f / SPEED_OF_LIGHT for f in frequencies_hz]
    pts = np.ascontiguousarray(points_m, dtype=np.float32)
    nrm = np.ascontiguousarray(normals, dtype=np.float32)
    cy, fy = _cell_of(h, rows)
    cx, fx = _cell_of(w, cols)
    # Which pixels blend which nodes, and which are summed exactly, before any sum: the
    # nodes and those pixels are then summed in one pass.
    seen = np.ascontiguousarray(seen)
    # The last record is taken out of the cache and updated in place (an exception leaves
    # none behind): its weights become this frame's, its receivers are overwritten.
    reuse = cache.take_weights((camera, h, w, step)) if cache is not None else None
    if reuse is None:
        weights, missing = _node_weights(pts, nrm, seen, rows, cols, node_seen, cy, fy, cx,
                                         fx)
        record = (pts.copy(), nrm.copy(), seen.copy(), weights, missing)
    else:
        last_pts, last_nrm, last_seen, weights, missing = reuse
        _update_node_weights(pts, nrm, seen, rows, cols, node_seen, cy, fy, cx, fx, last_pts,
                             last_nrm, last_seen, weights, missing, step + CREASE_GUARD_PX)
        np.copyto(last_pts, pts)
        np.copyto(last_nrm, nrm)
        np.copyto(last_seen, seen)
        record = reuse
    if cache is not None:
        cache.keep_weights((camera, h, w, step), record)
    node_index = (rows[:, None] * w + cols[None, :])[node_seen]
    index = np.concatenate([node_index, np.flatnonzero(missing)])
    with (cache or OneBounceCache()).frame(senders, (h, w), k, camera=camera) as exact:
        sums = exact(index, pts.reshape(-1, 3)[index], nrm.reshape(-1, 3)[index])
    values = np.zeros((len(rows), len(cols), 1 + 2 * nf), dtype=np.float32)
    values[node_seen] = sums[:len(node_index)]
    out = _blend_nodes(np.ascontiguousarray(seen), weights, missing, values, cy, cx, index,
                       sums, pts, np.asarray(k, dtype=np.float32))
    return out[0], [(out[1 + 2 * j], out[2 + 2 * j]) for j in range(nf)]


@dataclass
class _Sums:
    """:class:`OneBounceCache`'s record of one frame: its senders and receivers' tile sums."""

    key: tuple[object, ...]
    slot_points: F32                 # (S, 3) on the sender grid, zeros where none
    slot_normals: F32                # (S, 3)
    slot_weight: F32                 # (S,), 0 where a grid position sends nothing
    row: NDArray[np.int64]           # (H·W,) each pixel's receiver row, −1 where none
    points: F32                      # (C, 3) the rows' points (a pool: rows no pixel
    normals: F32                     # (C, 3)   holds are unused)
    tiles: NDArray[np.float64]       # (C, T, 1 + 2F) their sums per sender tile


#: A frame's receiver points, normals and seen mask with its node weights and flags.
_Weights = tuple[F32, F32, NDArray[np.bool_], NDArray[np.float64], NDArray[np.bool_]]


def _slots(senders: Senders) -> tuple[F32, F32, F32]:
    """The senders scattered onto their grid: points, normals, weights (0: no sender)."""
    assert senders.slot_index is not None
    n = senders.grid_shape[0] * senders.grid_shape[1]
    pts, nrm = np.zeros((n, 3), dtype=np.float32), np.zeros((n, 3), dtype=np.float32)
    wgt = np.zeros(n, dtype=np.float32)
    pts[senders.slot_index] = senders.points_m
    nrm[senders.slot_index] = senders.normals
    wgt[senders.slot_index] = senders.weight
    return pts, nrm, wgt


class OneBounceCache:
    """The last frame's one-bounce sums per receiver and sender tile, reused where unchanged.

    A still camera watching a scene in which one object moves (a person walking through
    the office) changes only a few senders and receivers from frame to frame. The sums
    are kept per receiver and per tile of the sender grid (:data:`TILE`): a receiver whose
    point and normal are bit-identical to the last frame's takes the last frame's tile sums
    and redoes only the tiles in which a sender changed; new or moved receivers are summed
    over every tile (the receivers keep their rows of tile sums from frame to frame, in a
    pool: nothing is copied for a kept receiver). The tile sums are then
    added in tile order, exactly as without the cache, so the result does not depend on
    which frames came before (bit-identical).
    The last frame is kept per camera (up to :attr:`KEEP` cameras, least recently used
    dropped), so the cameras of several rigs do not evict each other's sums.
    Thread-safe: one frame at a time.
    """

    #: Cameras whose last frame is kept.
    KEEP = 8

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._last: OrderedDict[Hashable, _Sums] = OrderedDict()
        self._weights: OrderedDict[Hashable, _Weights] = OrderedDict()

    def clear(self) -> None:
        """Forget the last frames (the next ones are summed in full)."""
        with self._lock:
            self._last.clear()
            self._weights.clear()

    def weights_record(self, key: Hashable) -> _Weights | None:
        """The last receivers and node weights (:func:`_node_weights`) kept for ``key``."""
        with self._lock:
            return self._weights.get(key)

    def take_weights(self, key: Hashable) -> _Weights | None:
        """:meth:`weights_record`, taken out of the cache.

        The caller may update it in place and keep it again with :meth:`keep_weights`.
        """
        with self._lock:
            return self._weights.pop(key, None)

    def keep_weights(self, key: Hashable, record: _Weights) -> None:
        """Keep this frame's receivers and node weights for ``key``'s next frame."""
        with self._lock:
            self._weights[key] = record
            self._weights.move_to_end(key)
            while len(self._weights) > self.KEEP:
                self._weights.popitem(last=False)

    @contextmanager
    def frame(self, senders: Senders, shape: tuple[int, int], k: list[float], *,
              camera: Hashable = None
              ) -> Iterator[Callable[[NDArray[np.int64], F32, F32], F32]]:
        """Sums of one frame: yields ``exact(flat_index, points, normals) -> (M, 1 + 2F)``.

        ``flat_index`` is each receiver's pixel (``y·W + x`` on ``shape``); every receiver
        of this frame must be asked for inside the ``with`` block (the others are dropped).
        ``camera`` names whose frame it is (compared with that camera's last frame).
        """
        if senders.slot_index is None:           # no grid: nothing to compare with
            yield lambda _idx, pts, nrm: _reduced(pts, nrm, senders, k)
            return
        kk = np.asarray(k, dtype=np.float32)
        bounds = senders.tiles()
        every = np.arange(len(bounds) - 1, dtype=np.int64)
        with self._lock:
            key = (shape, senders.grid_shape, tuple(k))
            slot_pts, slot_nrm, slot_wgt = _slots(senders)
            # Taken out now: an exception leaves no half record behind.
            prev = self._last.pop(camera, None)
            last = prev if prev is not None and prev.key == key else None
            redo = every
            if last is not None:
                changed = ~((slot_pts == last.slot_points).all(axis=1)
                            & (slot_nrm == last.slot_normals).all(axis=1)
                            & (slot_wgt == last.slot_weight))
                redo = np.unique(_tile_of(np.flatnonzero(changed), senders.grid_shape))
                if len(redo) > len(every) // 2:
                    last = None
            nv = len(kk) * 2 + 1
            # The receivers' rows live in a pool kept from frame to frame: a kept receiver
            # keeps its row (its redone tiles written in place), a new one takes a row no
            # receiver of the last frame or of this one holds.
            pool = _Pool.reuse(prev, len(every), nv)
            taken = np.zeros(len(pool.tiles), dtype=np.bool_)
            if last is not None:
                taken[last.row[last.row >= 0]] = True
            parts: list[tuple[NDArray[np.int64], NDArray[np.int64]]] = []

            def exact(index: NDArray[np.int64], pts: F32, nrm: F32) -> F32:
                nonlocal pool, taken
                index = np.ascontiguousarray(index, dtype=np.int64)
                pts = np.ascontiguousarray(pts, dtype=np.float32)
                nrm = np.ascontiguousarray(nrm, dtype=np.float32)
                if last is not None:
                    old = _kept_rows(index, pts, nrm, last.row, pool.points, pool.normals)
                else:
                    old = np.full(len(index), -1, dtype=np.int64)
                same = old >= 0
                redone = np.zeros((0, len(redo), nv))
                if same.any() and len(redo):
                    redone = _tile_sums(pts[same], nrm[same], senders, kk, redo)
                fresh = np.zeros((0, len(every), nv))
                new_rows = np.zeros(0, dtype=np.int64)
                if not same.all():
                    fresh = _tile_sums(pts[~same], nrm[~same], senders, kk, every)
                    free = np.flatnonzero(~taken)
                    if len(free) < len(fresh):
                        pool, taken = pool.grown(len(fresh) - len(free), taken)
                        free = np.flatnonzero(~taken)
                    new_rows = free[:len(fresh)]
                    taken[new_rows] = True
                    pool.points[new_rows] = pts[~same]
                    pool.normals[new_rows] = nrm[~same]
                rows = np.where(same, old, -1)
                rows[~same] = new_rows
                # One compiled pass: redone tiles into kept rows, fresh rows, totals.
                total = _merge_tiles(old, np.ascontiguousarray(redo), redone, fresh,
                                     new_rows, pool.tiles)
                parts.append((index, rows))
                return total

            yield exact
            if parts:
                row = np.full(shape[0] * shape[1], -1, dtype=np.int64)
                for index, rows in parts:
                    row[index] = rows
                self._last[camera] = _Sums(key, slot_pts, slot_nrm, slot_wgt, row,
                                           pool.points, pool.normals, pool.tiles)
                while len(self._last) > self.KEEP:
                    self._last.popitem(last=False)


@dataclass
class _Pool:
    """Receiver rows kept from frame to frame: points, normals and tile sums per row."""

    points: F32                      # (C, 3)
    normals: F32                     # (C, 3)
    tiles: NDArray[np.float64]       # (C, T, 1 + 2F)

    @staticmethod
    def reuse(prev: _Sums | None, nt: int, nv: int) -> _Pool:
        """The last record's pool if its tiles fit ``(T, 1 + 2F)``, else an empty one."""
        if prev is not None and prev.tiles.shape[1:] == (nt, nv):
            return _Pool(prev.points, prev.normals, prev.tiles)
        return _Pool(np.zeros((0, 3), dtype=np.float32), np.zeros((0, 3), dtype=np.float32),
                     np.zeros((0, nt, nv)))

    def grown(self, more: int, taken: NDArray[np.bool_]
              ) -> tuple[_Pool, NDArray[np.bool_]]:
        """A larger pool (at least ``more`` rows more, with room to grow), rows kept."""
        c = len(self.tiles)
        size = c + more + c // 4 + 64
        grown = _Pool(np.zeros((size, 3), dtype=np.float32),
                      np.zeros((size, 3), dtype=np.float32),
                      np.empty((size, *self.tiles.shape[1:])))
        grown.points[:c], grown.normals[:c], grown.tiles[:c] = (self.points, self.normals,
                                                                self.tiles)
        wider = np.zeros(size, dtype=np.bool_)
        wider[:c] = taken
        return grown, wider


@kernel
def _kept_rows(index: NDArray[np.int64], points: F32, normals: F32, row: NDArray[np.int64],
               last_points: F32, last_normals: F32) -> NDArray[np.int64]:
    """Each receiver's row in the last frame's record, −1 unless bit-identical there.

    Identical: the same pixel with the same point and normal.
    """
    out = np.full(index.shape[0], -1, dtype=np.int64)
    for i in range(index.shape[0]):
        p = index[i]
        if p < 0 or p >= row.shape[0]:
            continue
        r = row[p]
        if r < 0:
            continue
        same = True
        for c in range(3):
            if last_points[r, c] != points[i, c] or last_normals[r, c] != normals[i, c]:
                same = False
        if same:
            out[i] = r
    return out


@kernel
def _merge_tiles(old: NDArray[np.int64], redo: NDArray[np.int64],
                 redone: NDArray[np.float64], fresh: NDArray[np.float64],
                 new_rows: NDArray[np.int64], tiles: NDArray[np.float64]) -> F32:
    """A frame's tile sums, in place in the pool ``tiles``, and its receiver totals.

    Receiver ``i`` with ``old[i] ≥ 0`` keeps pool row ``old[i]``, with the tiles ``redo``
    replaced by its next row of ``redone``; the others take their next row of ``fresh``
    (every tile), written to their next row of ``new_rows``. Totals as :func:`_total`
    (tiles added in order, float64).
    """
    m = old.shape[0]
    nv = tiles.shape[2]
    total = np.zeros((m, nv), dtype=np.float32)
    kept = 0
    new = 0
    for i in range(m):
        if old[i] >= 0:
            r = old[i]
            if kept < redone.shape[0]:
                for u in range(redo.shape[0]):
                    tiles[r, redo[u]] = redone[kept, u]
            kept += 1
        else:
            r = new_rows[new]
            tiles[r] = fresh[new]
            new += 1
        _add_tiles(tiles[r], total[i])
    return total


@kernel
def _add_tiles(tiles: NDArray[np.float64], out: F32) -> None:
    """``out[v] = Σ_t tiles[t, v]``, the tiles added in order (float64), for every ``v``.

    The values' sums are independent chains: they run side by side (tile outer, value
    inner), each still adding its tiles in order, so every total is the same number.
    """
    nt, nv = tiles.shape
    if nv == 3:                        # one frequency: three chains held in registers
        a0 = a1 = a2 = 0.0
        for t in range(nt):
            a0 += tiles[t, 0]
            a1 += tiles[t, 1]
            a2 += tiles[t, 2]
        out[0], out[1], out[2] = a0, a1, a2
        return
    acc = np.zeros(nv)
    for t in range(nt):
        for v in range(nv):
            acc[v] += tiles[t, v]
    for v in range(nv):
        out[v] = acc[v]


@kernel
def _total(tiles: NDArray[np.float64]) -> F32:
    """Receiver sums (M, V) from their tile sums (M, T, V): added in tile order (float64)."""
    m, _nt, nv = tiles.shape
    out = np.zeros((m, nv), dtype=np.float32)
    for i in range(m):
        _add_tiles(tiles[i], out[i])
    return out


@kernel
def _pair_sums(points: F32, normals: F32, q: F32, nq: F32, weight: F32, range_q: F32,
               k: F32, bounds: NDArray[np.int64], tiles: NDArray[np.int64]
               ) -> NDArray[np.float64]:
    """Compiled one-bounce sums per sender tile, phasors without the receiver's own leg.

    Parameters
    ----------
    points, normals : ndarray, shape (M, 3)
        Receivers (m) and unit normals.
    q, nq : ndarray, shape (N, 3)
        Senders and their normals.
    weight, range_q : ndarray, shape (N,)
        :attr:`Senders.weight` and :attr:`Senders.range_m`.
    k : ndarray, shape (F,), float32
        ``2π f / c`` per modulation frequency (rad/m).
    bounds : ndarray of int, shape (T + 1,)
        :meth:`Senders.tiles`.
    tiles : ndarray of int, shape (U,)
        The tiles to sum.

    Returns
    -------
    ndarray, shape (M, U, 1 + 2F), float64
        Pair terms and phases in float32 like :func:`one_bounce`, sums in float64.
        Per receiver and tile ``Σ term`` and, per frequency, the real and imaginary parts
        of ``Σ term · exp(i k (R_Q + |Q − P|))`` (:func:`one_bounce` times
        ``exp(−i k R_P)``).
    """
    m, nf, nt = points.shape[0], k.shape[0], tiles.shape[0]
    out = np.zeros((m, nt, 1 + 2 * nf))
    for i in range(m):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        nx, ny, nz = normals[i, 0], normals[i, 1], normals[i, 2]
        acc = np.zeros(1 + 2 * nf)
        for u in range(nt):
            t = tiles[u]
            acc[:] = 0.0
            for j in range(bounds[t], bounds[t + 1]):
                dx, dy, dz = q[j, 0] - px, q[j, 1] - py, q[j, 2] - pz
                cos_p = nx * dx + ny * dy + nz * dz
                cos_q = -(nq[j, 0] * dx + nq[j, 1] * dy + nq[j, 2] * dz)
                if cos_p <= 0.0 or cos_q <= 0.0:
                    continue
                dist_sq = max(dx * dx + dy * dy + dz * dz, _MIN_DIST_SQ)
                term = cos_p * cos_q / (dist_sq * dist_sq) * weight[j]
                acc[0] += term
                path = math.sqrt(dist_sq) + range_q[j]
                for f in range(nf):
                    phase = k[f] * path
                    acc[1 + 2 * f] += term * math.cos(phase)
                    acc[2 + 2 * f] += term * math.sin(phase)
            for v in range(1 + 2 * nf):
                out[i, u, v] = acc[v]
    return out


def _tile_sums(points_m: F32, normals: F32, senders: Senders, k: NDArray[np.float32],
               tiles: NDArray[np.int64]) -> NDArray[np.float64]:
    """:func:`_pair_sums` of the given sender tiles: shape (M, len(tiles), 1 + 2F)."""
    return _pair_sums(np.ascontiguousarray(points_m, dtype=np.float32),
                      np.ascontiguousarray(normals, dtype=np.float32),
                      np.ascontiguousarray(senders.points_m, dtype=np.float32),
                      np.ascontiguousarray(senders.normals, dtype=np.float32),
                      np.ascontiguousarray(senders.weight, dtype=np.float32),
                      np.ascontiguousarray(senders.range_m, dtype=np.float32),
                      k, senders.tiles(), np.ascontiguousarray(tiles, dtype=np.int64))


def _reduced(points_m: F32, normals: F32, senders: Senders, k: list[float]) -> F32:
    """:func:`one_bounce` at receivers, phasors without the receiver's leg: shape (M, 1 + 2F).

    Summed per sender tile and the tiles added in order, like :class:`OneBounceCache`.
    """
    every = np.arange(len(senders.tiles()) - 1, dtype=np.int64)
    return _total(_tile_sums(points_m, normals, senders, np.asarray(k, dtype=np.float32),
                             every))
