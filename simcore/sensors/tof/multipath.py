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

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.scene.tof_config import SPEED_OF_LIGHT

F32 = NDArray[np.float32]
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
    """

    points_m: F32
    normals: F32
    weight: F32
    range_m: F32


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
    pts = points_m[sl][keep].astype(np.float32)
    weight = (albedo[sl][keep] * solid_angle_sr[sl][keep] * (stride * stride / np.pi))
    return Senders(points_m=pts, normals=normals[sl][keep].astype(np.float32),
                   weight=weight.astype(np.float32),
                   range_m=np.linalg.norm(pts, axis=1).astype(np.float32))


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
