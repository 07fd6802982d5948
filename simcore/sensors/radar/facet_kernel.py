"""Compiled pass over one object's surface facets: visibility, PO integral, amplitude.

One loop per object does what :func:`~simcore.sensors.radar.surfaces.facet_returns`
describes (the formulas are documented there and in ``docs/physics_radar.md``): it keeps
the facets whose source triangle faces the radar and whose centroid's render pixel shows
the object at the facet's range, and gives each its amplitude — the coherent part (Gordon's
closed-form PO integral, split into n² pieces where the facet is not in its own far field)
plus the diffuse part, times the two-way transmission of a transparent object in front.
The numpy functions of :mod:`~simcore.sensors.radar.surfaces` (``facet_integral``,
``triangle_integral``) are the reference it is tested against.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
from simcore.render.shading_kernels import band_response_one

#: Near-singular guard of the triangle integral's divided differences (rad).
SMALL = 1e-3


@kernel
def triangle_integral_1(alpha: float, beta: float) -> complex:
    """``∫∫ e^{j(α s + β t)} ds dt`` over the unit simplex, one pair (Gordon 1975).

    The same guards as :func:`~simcore.sensors.radar.surfaces.triangle_integral`.
    """
    a, b = alpha, beta
    if abs(a) < SMALL:
        a = -SMALL if a < 0 else SMALL
    if abs(b) < SMALL:
        b = -SMALL if b < 0 else SMALL
    if abs(a - b) < SMALL:
        b = a + (1.0 if b >= a else -1.0) * SMALL * 1.5
    if abs(b) < SMALL:
        b = -2 * SMALL if b < 0 else 2 * SMALL
    ea = complex(math.cos(a), math.sin(a))
    eb = complex(math.cos(b), math.sin(b))
    return -((ea - eb) / (a - b) - (ea - 1.0) / a) / b


@kernel
def _far_field_piece(v0: NDArray[np.float64], v1: NDArray[np.float64],
                     v2: NDArray[np.float64], k: float, dist_ref: float) -> complex:
    """One radar-frame triangle's ``∫ e^{j 2k (|r| − dist_ref)} dA``, linearised at its centroid."""
    c0 = (v0[0] + v1[0] + v2[0]) / 3.0
    c1 = (v0[1] + v1[1] + v2[1]) / 3.0
    c2 = (v0[2] + v1[2] + v2[2]) / 3.0
    sd = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    s = 2.0 * k / sd
    w0, w1, w2 = s * c0, s * c1, s * c2
    e1x, e1y, e1z = v1[0] - v0[0], v1[1] - v0[1], v1[2] - v0[2]
    e2x, e2y, e2z = v2[0] - v0[0], v2[1] - v0[1], v2[2] - v0[2]
    alpha = w0 * e1x + w1 * e1y + w2 * e1z
    beta = w0 * e2x + w1 * e2y + w2 * e2z
    rel = w0 * (v0[0] - c0) + w1 * (v0[1] - c1) + w2 * (v0[2] - c2)
    nx = e1y * e2z - e1z * e2y
    ny = e1z * e2x - e1x * e2z
    nz = e1x * e2y - e1y * e2x
    area2 = math.sqrt(nx * nx + ny * ny + nz * nz)
    ph = rel + 2.0 * k * (sd - dist_ref)
    return area2 * triangle_integral_1(alpha, beta) * complex(math.cos(ph), math.sin(ph))


@kernel
def _split_integral(corners: NDArray[np.float64], n: int, k: float, dist: float) -> complex:
    """The PO integral of a facet split into n² similar pieces (regular subdivision)."""
    total = 0j
    a = corners[0]
    e1 = corners[1] - a
    e2 = corners[2] - a
    p0 = np.empty(3)
    p1 = np.empty(3)
    p2 = np.empty(3)
    inv = 1.0 / n
    for i in range(n):
        for j in range(n - i):
            # Upward piece (i, j), (i+1, j), (i, j+1) in units of 1/n along e1, e2.
            for d in range(3):
                p0[d] = a[d] + (i * e1[d] + j * e2[d]) * inv
                p1[d] = a[d] + ((i + 1) * e1[d] + j * e2[d]) * inv
                p2[d] = a[d] + (i * e1[d] + (j + 1) * e2[d]) * inv
            total += _far_field_piece(p0, p1, p2, k, dist)
            if i + j < n - 1:
                for d in range(3):
                    p0[d] = a[d] + ((i + 1) * e1[d] + j * e2[d]) * inv
                    p1[d] = a[d] + ((i + 1) * e1[d] + (j + 1) * e2[d]) * inv
                    p2[d] = a[d] + (i * e1[d] + (j + 1) * e2[d]) * inv
                total += _far_field_piece(p0, p1, p2, k, dist)
    return total


@kernel
def object_facet_returns(
        # the object's facets, in its own frame
        centroids: NDArray[np.float64], normals: NDArray[np.float64],
        area2: NDArray[np.float64], source: NDArray[np.int64], edges: NDArray[np.float64],
        longest: NDArray[np.float64], vertices: NDArray[np.float64],
        source_normals: NDArray[np.float64], source_points: NDArray[np.float64],
        speckle_phasors: NDArray[np.complex128],
        # object → radar frame
        rot: NDArray[np.float64], off: NDArray[np.float64],
        # the render the facets are looked for in
        fx: float, fy: float, cx: float, cy: float, width: int, height: int,
        obj_img: NDArray[np.int32], rng_img: NDArray[np.float32],
        wanted: NDArray[np.bool_], use_wanted: bool, index: int, pix_angle: float,
        visibility_tol: float,
        # a transparent object in front (behind=True: obj_img is the see-through pass)
        behind: bool, full_obj: NDArray[np.int32], full_rng: NDArray[np.float32],
        transmission: NDArray[np.complex128],
        # the object's radar material
        k: float, wavelength: float, smooth: bool, gamma: complex, height_rms: float,
        reflectance: float, specular: float, roughness: float, metallic: float,
        retro_gain: float, speckle: bool,
        # outputs, one row per seen facet (at most len(centroids))
        out_pos: NDArray[np.float64], out_amp: NDArray[np.complex128],
        out_pix: NDArray[np.int64]) -> int:
    """Seen facets of one object and their amplitudes (√m² with phase); returns their count.

    Rows ``0 … count−1`` of ``out_pos`` (radar-frame centroids, m), ``out_amp`` and
    ``out_pix`` (flat render pixel) are written, in facet order.
    """
    n_src = source_normals.shape[0]
    facing = np.empty(n_src, dtype=np.bool_)
    for s in range(n_src):
        acc = 0.0
        for r in range(3):
            nr = (rot[r, 0] * source_normals[s, 0] + rot[r, 1] * source_normals[s, 1]
                  + rot[r, 2] * source_normals[s, 2])
            pr = (rot[r, 0] * source_points[s, 0] + rot[r, 1] * source_points[s, 1]
                  + rot[r, 2] * source_points[s, 2] + off[r])
            acc += nr * pr
        facing[s] = acc < 0
    corners = np.empty((3, 3))
    c = np.empty(3)
    w = np.empty(3)
    sqrt_pi2 = 2.0 * math.sqrt(math.pi) / wavelength
    count = 0
    for f in range(centroids.shape[0]):
        if not facing[source[f]]:
            continue
        for r in range(3):
            c[r] = (rot[r, 0] * centroids[f, 0] + rot[r, 1] * centroids[f, 1]
                    + rot[r, 2] * centroids[f, 2] + off[r])
        z = c[2]
        if not z > 1e-6:
            continue
        col = math.floor(fx * c[0] / z + cx)
        row = math.floor(fy * c[1] / z + cy)
        if col < 0 or col >= width or row < 0 or row >= height:
            continue
        pix = int(row * width + col)
        if obj_img[pix] != index:
            continue
        if use_wanted and not wanted[pix]:
            continue
        dist = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
        cos_t = 0.0
        for r in range(3):
            nr = (rot[r, 0] * normals[f, 0] + rot[r, 1] * normals[f, 1]
                  + rot[r, 2] * normals[f, 2])
            cos_t -= nr * c[r] / dist
        if not cos_t > 0:
            continue
        cos_s = min(max(cos_t, 0.05), 1.0)
        tol = (visibility_tol + 1.5 * dist * pix_angle * math.sqrt(1.0 - cos_s * cos_s) / cos_s
               + 0.5 * math.sqrt(area2[f]))
        if not abs(rng_img[pix] - dist) <= tol:
            continue
        cos_i = min(cos_t, 1.0)
        amp = 0j
        rho2 = 1.0
        if smooth:
            # Coherent PO part: the direction into the object's frame (c_obj = Rᵀ c).
            scale = 2.0 * k / dist
            for d in range(3):
                w[d] = scale * (rot[0, d] * c[0] + rot[1, d] * c[1] + rot[2, d] * c[2])
            alpha = w[0] * edges[f, 0, 0] + w[1] * edges[f, 0, 1] + w[2] * edges[f, 0, 2]
            beta = w[0] * edges[f, 1, 0] + w[1] * edges[f, 1, 1] + w[2] * edges[f, 1, 2]
            rel = w[0] * edges[f, 2, 0] + w[1] * edges[f, 2, 1] + w[2] * edges[f, 2, 2]
            integral = (area2[f] * triangle_integral_1(alpha, beta)
                        * complex(math.cos(rel), math.sin(rel)))
            limit = math.sqrt(math.pi * dist / (2.0 * k))           # √(λR/4)
            span = max(max(abs(alpha), abs(beta)), abs(alpha - beta))
            pieces = math.ceil(longest[f] / limit)
            if pieces > 1 and span < 6.0 * math.pi:
                for q in range(3):
                    for r in range(3):
                        corners[q, r] = (rot[r, 0] * vertices[f, q, 0]
                                         + rot[r, 1] * vertices[f, q, 1]
                                         + rot[r, 2] * vertices[f, q, 2] + off[r])
                integral = _split_integral(corners, min(pieces, 16), k, dist)
            g = 4.0 * math.pi * height_rms * cos_i / wavelength
            rho2 = math.exp(-g * g)
            amp = (sqrt_pi2 * gamma * math.sqrt(rho2) * cos_i) * integral
        # Diffuse part: the band response with the lobe's incoherent fraction.
        incoherent = 1.0 - rho2 if smooth else 1.0
        sigma0 = band_response_one(cos_i, reflectance, specular * incoherent, roughness,
                                   metallic, retro_gain)
        diffuse = math.sqrt(sigma0 * 0.5 * area2[f])
        if speckle:
            amp += diffuse * speckle_phasors[f]
        else:
            amp += diffuse
        if behind:
            front = full_obj[pix]
            if front >= 0 and front != index and full_rng[pix] < dist:
                amp *= transmission[front] * transmission[front]
        out_pos[count, 0] = c[0]
        out_pos[count, 1] = c[1]
        out_pos[count, 2] = c[2]
        out_amp[count] = amp
        out_pix[count] = pix
        count += 1
    return count


__all__ = ["object_facet_returns", "triangle_integral_1"]
