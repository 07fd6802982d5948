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
#: A facet whose two-way phase changes by less than this across it (rad, ≈ 9.5 cycles) and
#: that is longer than :data:`PIECE_FRESNEL` × √(λR/4) is integrated in n² pieces; beyond
#: it, the linear phase between its exact corner values is close enough (measured against
#: the exact PO integral of plates at 1–4 m: ``tests/test_radar_po_plate.py``).
SPLIT_SPAN_RAD = 60.0
#: Largest piece of a split facet, as a fraction of √(λR/4): the phase's deviation from
#: linear within a piece stays below ≈ 0.06 rad.
PIECE_FRESNEL = 0.4


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
    """One radar-frame triangle's ``∫ e^{j 2k (|r| − dist_ref)} dA``.

    The phase is interpolated linearly between its exact values at the corners
    (:func:`vertex_phase_integral`).
    """
    e1x, e1y, e1z = v1[0] - v0[0], v1[1] - v0[1], v1[2] - v0[2]
    e2x, e2y, e2z = v2[0] - v0[0], v2[1] - v0[1], v2[2] - v0[2]
    nx = e1y * e2z - e1z * e2y
    ny = e1z * e2x - e1x * e2z
    nz = e1x * e2y - e1y * e2x
    area2 = math.sqrt(nx * nx + ny * ny + nz * nz)
    return area2 * vertex_phase_integral(
        2.0 * k * (math.sqrt(v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]) - dist_ref),
        2.0 * k * (math.sqrt(v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2]) - dist_ref),
        2.0 * k * (math.sqrt(v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]) - dist_ref))


@kernel
def vertex_phase_integral(phi0: float, phi1: float, phi2: float) -> complex:
    """``∫∫ e^{jφ} ds dt`` over the unit simplex, φ linear through its corner values.

    The phase of the PO integrand (two-way path, ``2k |r|``) is taken exactly at the
    facet's corners and interpolated linearly between them. Neighbouring facets then
    share the phase along their common edge (a continuous, piecewise-linear phase over a
    surface), so the contributions of interior edges cancel between them as they do in
    the exact integral of a flat plate; a phase linearised about each facet's own centroid
    jumps by up to ``k L²/(4R)`` across edges and leaves spurious edge terms that sum to
    decibels over a plate in the near field. Equals ``e^{jφ}/2`` at φ constant (times
    twice the facet's area: its area).
    """
    ph = complex(math.cos(phi0), math.sin(phi0))
    return triangle_integral_1(phi1 - phi0, phi2 - phi0) * ph


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
def _facing_sources(source_normals: NDArray[np.float64], source_points: NDArray[np.float64],
                    rot: NDArray[np.float64], off: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether each source triangle faces the radar (its plane seen from the front)."""
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
    return facing


# A named exception to the 80-line rule (issue 41): the per-facet loop stays one body.
# Moving its coherent PO block into a helper kernel made the kernel 3-6 % slower (thread
# CPU time over 100 facet passes of the office, walking-person and glTF office frames, 40
# interleaved repeats: 27.4-28.3 ms against 26.6-26.7 ms), and the loop would still be
# over 80 lines without moving its visibility tests too, a call per facet; the
# once-per-object step that splits at no cost (_facing_sources) is a helper.
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
    facing = _facing_sources(source_normals, source_points, rot, off)
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
            # Coherent PO part: the two-way phase at the corners (radar frame), relative to
            # the centroid's, interpolated linearly over the facet.
            for q in range(3):
                for r in range(3):
                    corners[q, r] = (rot[r, 0] * vertices[f, q, 0]
                                     + rot[r, 1] * vertices[f, q, 1]
                                     + rot[r, 2] * vertices[f, q, 2] + off[r])
                w[q] = 2.0 * k * (math.sqrt(corners[q, 0] * corners[q, 0]
                                            + corners[q, 1] * corners[q, 1]
                                            + corners[q, 2] * corners[q, 2]) - dist)
            alpha, beta = w[1] - w[0], w[2] - w[0]
            integral = area2[f] * vertex_phase_integral(w[0], w[1], w[2])
            limit = PIECE_FRESNEL * math.sqrt(math.pi * dist / (2.0 * k))   # × √(λR/4)
            span = max(max(abs(alpha), abs(beta)), abs(alpha - beta))
            pieces = math.ceil(longest[f] / limit)
            if pieces > 1 and span < SPLIT_SPAN_RAD:
                integral = _split_integral(corners, min(pieces, 16), k, dist)
            g = 4.0 * math.pi * height_rms * cos_i / wavelength
            rho2 = math.exp(-g * g)
            # j: the PO field of a surface seen at its stationary point is the image's
            # (an infinite plane reduces to Γ of the image, Γ √π R), not 90° off it.
            amp = (1j * sqrt_pi2 * gamma * math.sqrt(rho2) * cos_i) * integral
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


__all__ = ["object_facet_returns", "triangle_integral_1", "vertex_phase_integral"]
