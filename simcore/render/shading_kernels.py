"""Compiled per-pixel shading: one pass over the pixels instead of dozens of numpy passes.

The renderer (:func:`simcore.render.renderer._shade_pixels`) builds the small per-triangle
and per-object tables in numpy and hands them, with the rasterised triangle labels, to the
two kernels here:

* :func:`shade_geometry` (geometry-only passes): ray–plane range, object index and id;
* :func:`shade_surface` (full passes): the same, plus barycentric vertex-normal
  interpolation on smooth triangles, analytic ray–sphere refinement, points, incidence,
  band intensity (:func:`band_response_one`, the compiled twin of
  :func:`simcore.scene.materials.band_response`) and rigid-body velocities.

The kernels reproduce the numpy implementation they replace operation by operation: the
same precisions (float32 where the buffers are float32, float64 for the barycentric,
sphere and velocity arithmetic), the same order of additions (a 3-vector dot product is
``(x0 y0 + x2 y2) + x1 y1`` as numpy's ``einsum`` sums it; a norm ``sqrt((x0² + x1²) +
x2²)`` as ``numpy.linalg.norm``), and IEEE division semantics (a division by zero gives
±inf or NaN, as numpy does, instead of raising). Every pixel is computed on its own, so
shading a subset of pixels gives the same values as shading them all. The GIL is released
(:func:`simcore.jit.kernel`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel

_NAN32 = np.float32(np.nan)
_ZERO32 = np.float32(0.0)
_ONE32 = np.float32(1.0)

#: Columns of the per-object material table of :func:`shade_surface`.
MATERIAL_COLUMNS = ("reflectance", "specular", "roughness", "metallic", "retro_gain")
#: What :func:`shade_surface` returns: range, points, normals, cos_incidence, object
#: index, object id, intensity, velocity, radial velocity (flat, per pixel).
SurfaceFields = tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32],
                      NDArray[np.float32], NDArray[np.int32], NDArray[np.int32],
                      NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]


@kernel
def _div(a: float, b: float) -> float:
    """``a / b`` in float64 with numpy's semantics for ``b == 0`` (±inf or NaN)."""
    if b != 0.0:
        return a / b
    if a != a or a == 0.0:
        return math.nan
    return math.copysign(math.inf, a) * math.copysign(1.0, b)


@kernel
def _div32(a: np.float32, b: np.float32) -> np.float32:
    """``a / b`` in float32 with numpy's semantics for ``b == 0`` (±inf or NaN)."""
    if b != 0.0:
        return a / b
    if a != a or a == 0.0:
        return _NAN32
    return np.float32(math.copysign(math.inf, a) * math.copysign(1.0, b))


@kernel
def _dot(x0: float, x1: float, x2: float, y0: float, y1: float, y2: float) -> float:
    """3-vector dot product summed as numpy's ``einsum("ij,ij->i")`` sums it."""
    return (x0 * y0 + x2 * y2) + x1 * y1


@kernel
def band_response_one(cos_theta: float, reflectance: float, specular: float,
                      roughness: float, metallic: float, retro_gain: float) -> float:
    """Compiled twin of :func:`simcore.scene.materials.band_response` for one value.

    Parameters
    ----------
    cos_theta : float
        Cosine of the incidence angle (clipped to [1e-6, 1] as the numpy function does).
    reflectance, specular, roughness, metallic, retro_gain : float
        Material parameters of the band.

    Returns
    -------
    float
        ``f(theta)`` in float64; the numpy function returns it rounded to float32.

    Notes
    -----
    ``cos⁴ θ`` is computed as ``(c c)(c c)``, not with libm's ``pow`` as numpy's ``c**4``
    does (``pow`` is a third of the cost of the whole model). For a ``c`` that is a float32
    value, as the renderer's cosines are, ``c c`` is exact and the product is the
    correctly rounded ``c⁴``; glibc's ``pow`` is 1 ulp (float64) away from it for about
    0.1 % of the float32 values in [1e-6, 1]. After the rounding to float32 the two agree
    except where ``f`` lies within ~1e-16 (relative) of a float32 rounding boundary.
    """
    c = cos_theta
    if c < 1e-6:
        c = 1e-6
    elif c > 1.0:
        c = 1.0
    m2 = roughness * roughness
    cc = c * c
    tan2 = (1.0 - cc) / cc
    diffuse = (1.0 - metallic) * reflectance * c
    lobe = _div(specular * math.exp(_div(-tan2, m2)), m2 * (cc * cc))
    return diffuse + lobe + retro_gain


@kernel
def _plane_hit(label: int, uu: np.float32, vv: np.float32, plane_n: NDArray[np.float32],
               plane_d: NDArray[np.float32]) -> np.float32:
    """Ray parameter ``t`` of the pixel ray ``(u, v, 1)`` on the plane of ``label``.

    NaN for the background, grazing rays and planes behind the sensor (float32).
    """
    denom = plane_n[label, 0] * uu
    denom = denom + plane_n[label, 1] * vv
    denom = denom + plane_n[label, 2]
    t = _div32(plane_d[label], denom)
    if not t > 0:
        t = _NAN32
    return t


@kernel
def shade_geometry(labels: NDArray[np.uint32], pixels: NDArray[np.int64], subset: bool,
                   u: NDArray[np.float32], v: NDArray[np.float32],
                   ray_norm: NDArray[np.float32], plane_n: NDArray[np.float32],
                   plane_d: NDArray[np.float32], label_object: NDArray[np.int32],
                   ids: NDArray[np.int32]
                   ) -> tuple[NDArray[np.float32], NDArray[np.int32], NDArray[np.int32]]:
    """Range, object index and object id of every pixel (geometry-only passes).

    Parameters
    ----------
    labels : ndarray, shape (H * W,), uint32
        Triangle label per pixel (``k + 1`` for triangle ``k``, 0 = background).
    pixels : ndarray, shape (n,), int64
        Flat indices of the pixels to shade when ``subset``; ignored otherwise.
    subset : bool
        Shade ``pixels`` only (else all ``H * W`` pixels, in order).
    u, v, ray_norm : ndarray, shape (H * W,), float32
        Ray slopes ``x/z``, ``y/z`` and the length of ``(x/z, y/z, 1)`` per pixel.
    plane_n : ndarray, shape (triangles + 1, 3), float32
        Plane normal per label (optical frame, facing the sensor; row 0 = background).
    plane_d : ndarray, shape (triangles + 1,), float32
        Plane offset ``n · X`` per label (NaN for row 0).
    label_object : ndarray, shape (triangles + 1,), int32
        Object index per label (−1 for row 0).
    ids : ndarray, shape (objects + 1,), int32
        Object id per object index, the last row (−1) for "no object".

    Returns
    -------
    range_m : ndarray, shape (n,), float32
        Range along the pixel ray (m; NaN or inf where nothing is hit).
    object_index, object_id : ndarray, shape (n,), int32
        −1 where nothing is hit.
    """
    n = pixels.size if subset else labels.size
    range_m = np.empty(n, dtype=np.float32)
    obj_out = np.empty(n, dtype=np.int32)
    id_out = np.empty(n, dtype=np.int32)
    for i in range(n):
        p = pixels[i] if subset else i
        label = labels[p]
        t = _plane_hit(label, u[p], v[p], plane_n, plane_d)
        obj = label_object[label] if math.isfinite(t) else -1
        range_m[i] = t * ray_norm[p]
        obj_out[i] = obj
        id_out[i] = ids[obj]
    return range_m, obj_out, id_out


@kernel
def _pixel_ray(p: int, width: int, camera: NDArray[np.float64]) -> tuple[float, float]:
    """``x/z`` and ``y/z`` of the centre of flat pixel ``p`` in float64.

    ``camera`` holds ``(cx, cy, fx, fy)``.
    """
    row = p // width
    col = p - row * width
    return ((col + 0.5 - camera[0]) / camera[2], (row + 0.5 - camera[1]) / camera[3])


@kernel
def _smooth_normal(tri: int, t: float, r0: float, r1: float,
                   triangles: NDArray[np.int64], vertices: NDArray[np.float64],
                   vnormals: NDArray[np.float64], rot: NDArray[np.float64],
                   origin: NDArray[np.float64]) -> tuple[float, float, float]:
    """Barycentric interpolation of triangle ``tri``'s vertex normals at the hit point.

    The hit ``t · (r0, r1, 1)`` (optical frame) is taken to the world frame, projected on
    the triangle (barycentric weights clipped to it), and the interpolated normal is
    rotated back to the optical frame, normalised and turned towards the sensor.
    """
    ia, ib, ic = triangles[tri, 0], triangles[tri, 1], triangles[tri, 2]
    p0, p1, p2 = t * r0, t * r1, t * 1.0
    a0, a1, a2 = vertices[ia, 0], vertices[ia, 1], vertices[ia, 2]
    e10, e11, e12 = vertices[ib, 0] - a0, vertices[ib, 1] - a1, vertices[ib, 2] - a2
    e20, e21, e22 = vertices[ic, 0] - a0, vertices[ic, 1] - a1, vertices[ic, 2] - a2
    w0 = origin[0] + ((p0 * rot[0, 0] + p1 * rot[0, 1]) + p2 * rot[0, 2]) - a0
    w1 = origin[1] + ((p0 * rot[1, 0] + p1 * rot[1, 1]) + p2 * rot[1, 2]) - a1
    w2 = origin[2] + ((p0 * rot[2, 0] + p1 * rot[2, 1]) + p2 * rot[2, 2]) - a2
    d00 = _dot(e10, e11, e12, e10, e11, e12)
    d01 = _dot(e10, e11, e12, e20, e21, e22)
    d11 = _dot(e20, e21, e22, e20, e21, e22)
    d20 = _dot(w0, w1, w2, e10, e11, e12)
    d21 = _dot(w0, w1, w2, e20, e21, e22)
    den = d00 * d11 - d01 * d01
    bu = _div(d11 * d20 - d01 * d21, den)
    bv = _div(d00 * d21 - d01 * d20, den)
    bu = 0.0 if bu < 0.0 else (1.0 if bu > 1.0 else bu)
    bv = 0.0 if bv < 0.0 else (1.0 if bv > 1.0 else bv)
    excess = bu + bv - 1.0
    excess = (0.0 if excess < 0.0 else excess) / 2
    bu, bv = bu - excess, bv - excess
    bw = 1 - bu - bv
    m0 = (bw * vnormals[ia, 0] + bu * vnormals[ib, 0]) + bv * vnormals[ic, 0]
    m1 = (bw * vnormals[ia, 1] + bu * vnormals[ib, 1]) + bv * vnormals[ic, 1]
    m2 = (bw * vnormals[ia, 2] + bu * vnormals[ib, 2]) + bv * vnormals[ic, 2]
    n0 = (m0 * rot[0, 0] + m1 * rot[1, 0]) + m2 * rot[2, 0]
    n1 = (m0 * rot[0, 1] + m1 * rot[1, 1]) + m2 * rot[2, 1]
    n2 = (m0 * rot[0, 2] + m1 * rot[1, 2]) + m2 * rot[2, 2]
    norm = math.sqrt((n0 * n0 + n1 * n1) + n2 * n2)
    if norm < 1e-300:
        norm = 1e-300
    n0, n1, n2 = n0 / norm, n1 / norm, n2 / norm
    sign = -1.0 if _dot(n0, n1, n2, r0, r1, 1.0) > 0 else 1.0
    return n0 * sign, n1 * sign, n2 * sign


# A named exception to the 80-line rule (issue 41): the per-pixel loop stays one body.
# Moving its hit refinement (smooth normal, sphere) into a helper kernel, with or without
# numba's inline="always", made the kernel 11 % slower (thread CPU time of the 7 shading
# passes of office, walking-person and glTF office frames, median of 60 interleaved
# repeats: 9.5 ms against 8.5 ms); the steps that split at no measurable cost (8.5 ms
# against 8.5 ms) are the helper kernels below.
@kernel
def shade_surface(labels: NDArray[np.uint32], pixels: NDArray[np.int64], subset: bool,
                  width: int, camera: NDArray[np.float64], u: NDArray[np.float32],
                  v: NDArray[np.float32], ray_norm: NDArray[np.float32],
                  plane_n: NDArray[np.float32], plane_d: NDArray[np.float32],
                  label_object: NDArray[np.int32], label_smooth: NDArray[np.bool_],
                  triangles: NDArray[np.int64], vertices: NDArray[np.float64],
                  vnormals: NDArray[np.float64], rot: NDArray[np.float64],
                  origin: NDArray[np.float64], sphere_radius: NDArray[np.float64],
                  sphere_centre: NDArray[np.float64], lin: NDArray[np.float64],
                  ang: NDArray[np.float64], material: NDArray[np.float64],
                  ids: NDArray[np.int32]) -> SurfaceFields:
    """Every per-pixel field of a full pass in one pass over the pixels.

    Parameters
    ----------
    labels, pixels, subset, u, v, ray_norm, plane_n, plane_d, label_object, ids
        As for :func:`shade_geometry`.
    width : int
        Image width (pixels): flat index ``p`` is row ``p // width``, column ``p % width``.
    camera : ndarray, shape (4,), float64
        ``(cx, cy, fx, fy)`` of the pixel grid (pixels).
    label_smooth : ndarray, shape (triangles + 1,), bool
        Whether a label's triangle is smooth (its vertex normals are interpolated).
    triangles : ndarray, shape (triangles, 3), int64
        Vertex indices of each triangle.
    vertices, vnormals : ndarray, shape (vertices, 3), float64
        World vertex positions (m) and vertex normals.
    rot, origin : ndarray, shape (3, 3) and (3,), float64
        Sensor rotation (optical frame → world, columns are the optical axes) and
        position in the world (m).
    sphere_radius, sphere_centre : ndarray, shape (objects + 1,) and (objects + 1, 3)
        Radius of each object that is a sphere (m; 0 for the others and the last row)
        and the object origins in the optical frame (m), float64.
    lin, ang : ndarray, shape (objects + 1, 3), float64
        Rigid motion relative to the sensor in the optical frame: the velocity of a point
        ``X`` of object ``k`` is ``lin[k] + ang[k] × X`` (m/s); the last rows are 0.
    material : ndarray, shape (objects + 1, 5), float64
        Band parameters per object, columns :data:`MATERIAL_COLUMNS`.

    Returns
    -------
    range_m : ndarray, shape (n,), float32
    points_m, normals : ndarray, shape (n, 3), float32
    cos_incidence : ndarray, shape (n,), float32
    object_index, object_id : ndarray, shape (n,), int32
    intensity : ndarray, shape (n,), float32
    velocity_mps : ndarray, shape (n, 3), float32
    radial_velocity_mps : ndarray, shape (n,), float32
        The fields of :class:`~simcore.render.buffers.RenderBuffers`, flat.
    """
    n = pixels.size if subset else labels.size
    range_m = np.empty(n, dtype=np.float32)
    points = np.empty((n, 3), dtype=np.float32)
    normals = np.empty((n, 3), dtype=np.float32)
    cos_inc = np.empty(n, dtype=np.float32)
    obj_out = np.empty(n, dtype=np.int32)
    id_out = np.empty(n, dtype=np.int32)
    intensity = np.empty(n, dtype=np.float32)
    velocity = np.zeros((n, 3), dtype=np.float32)
    radial = np.zeros(n, dtype=np.float32)
    moving = _moving_objects(lin, ang)
    seen = np.zeros(lin.shape[0], dtype=np.bool_)
    for i in range(n):
        p = pixels[i] if subset else i
        label = labels[p]
        uu, vv, rn = u[p], v[p], ray_norm[p]
        t = _plane_hit(label, uu, vv, plane_n, plane_d)
        valid = math.isfinite(t)
        obj = label_object[label] if valid else -1
        nx, ny, nz = plane_n[label, 0], plane_n[label, 1], plane_n[label, 2]
        if valid and label_smooth[label]:
            r0, r1 = _pixel_ray(p, width, camera)
            s0, s1, s2 = _smooth_normal(label - 1, np.float64(t), r0, r1, triangles,
                                        vertices, vnormals, rot, origin)
            nx, ny, nz = np.float32(s0), np.float32(s1), np.float32(s2)
        if valid and sphere_radius[obj] > 0:
            t, nx, ny, nz = _sphere_hit(p, width, camera, sphere_radius[obj],
                                        sphere_centre[obj], t, nx, ny, nz)
        points[i, 0] = t * uu
        points[i, 1] = t * vv
        points[i, 2] = t
        normals[i, 0], normals[i, 1], normals[i, 2] = nx, ny, nz
        range_m[i] = t * rn
        obj_out[i] = obj
        id_out[i] = ids[obj]
        if valid:
            ci = _cos_incidence(nx, ny, nz, uu, vv, rn)
            cos_inc[i] = ci
            intensity[i] = np.float32(band_response_one(
                np.float64(ci), material[obj, 0], material[obj, 1], material[obj, 2],
                material[obj, 3], material[obj, 4]))
            if moving[obj]:
                seen[obj] = True
        else:
            cos_inc[i] = _ZERO32
            intensity[i] = _ZERO32
    if seen.any():
        _rigid_velocities(obj_out, points, pixels, subset, width, camera, lin, ang, moving,
                          seen, velocity, radial)
    return range_m, points, normals, cos_inc, obj_out, id_out, intensity, velocity, radial


@kernel
def _moving_objects(lin: NDArray[np.float64], ang: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether each object moves relative to the sensor (any non-zero lin or ang)."""
    n_obj = lin.shape[0]
    moving = np.zeros(n_obj, dtype=np.bool_)
    for k in range(n_obj):
        for j in range(3):
            if lin[k, j] != 0.0 or ang[k, j] != 0.0:
                moving[k] = True
    return moving


@kernel
def _sphere_hit(p: int, width: int, camera: NDArray[np.float64], r: float,
                centre: NDArray[np.float64], t: np.float32, nx: np.float32, ny: np.float32,
                nz: np.float32) -> tuple[np.float32, np.float32, np.float32, np.float32]:
    """Pixel ``p``'s ray on the true sphere of radius ``r`` about ``centre``: ``t``, normal.

    Rays through the facets but past the true limb keep the facet's ``t`` and normal.
    """
    r0, r1 = _pixel_ray(p, width, camera)
    c0, c1, c2 = centre[0], centre[1], centre[2]
    a = _dot(r0, r1, 1.0, r0, r1, 1.0)
    b = -_dot(r0, r1, 1.0, c0, c1, c2)
    c = _dot(c0, c1, c2, c0, c1, c2) - r * r
    disc = b * b - a * c
    if disc >= 0:
        root = (-b - math.sqrt(disc)) / a
        t = np.float32(root)
        nx = np.float32((root * r0 - c0) / r)
        ny = np.float32((root * r1 - c1) / r)
        nz = np.float32((root * 1.0 - c2) / r)
    return t, nx, ny, nz


@kernel
def _cos_incidence(nx: np.float32, ny: np.float32, nz: np.float32, uu: np.float32,
                   vv: np.float32, rn: np.float32) -> np.float32:
    """Cosine of incidence of the ray ``(u, v, 1)`` of length ``rn`` on normal ``n``, in [0, 1]."""
    ci = nx * uu
    ci = ci + ny * vv
    ci = ci + nz
    ci = ci / -rn
    if ci < 0:
        ci = _ZERO32
    elif ci > 1:
        ci = _ONE32
    return ci


@kernel
def _rigid_velocities(obj_out: NDArray[np.int32], points: NDArray[np.float32],
                      pixels: NDArray[np.int64], subset: bool, width: int,
                      camera: NDArray[np.float64], lin: NDArray[np.float64],
                      ang: NDArray[np.float64], moving: NDArray[np.bool_],
                      seen: NDArray[np.bool_], velocity: NDArray[np.float32],
                      radial: NDArray[np.float32]) -> None:
    """Velocity and radial velocity of every pixel of a moving object (in place)."""
    # The rotational term is added to every moving pixel when any moving pixel rotates
    # (adding a zero cross product only ever changes the sign of a zero).
    spin = False
    for k in range(lin.shape[0]):
        if seen[k] and (ang[k, 0] != 0.0 or ang[k, 1] != 0.0 or ang[k, 2] != 0.0):
            spin = True
    for i in range(obj_out.size):
        obj = obj_out[i]
        if obj < 0 or not moving[obj]:
            continue
        v0, v1, v2 = lin[obj, 0], lin[obj, 1], lin[obj, 2]
        if spin:
            x0, x1, x2 = np.float64(points[i, 0]), np.float64(points[i, 1]), \
                np.float64(points[i, 2])
            w0, w1, w2 = ang[obj, 0], ang[obj, 1], ang[obj, 2]
            v0 += w1 * x2 - w2 * x1
            v1 += w2 * x0 - w0 * x2
            v2 += w0 * x1 - w1 * x0
        velocity[i, 0], velocity[i, 1], velocity[i, 2] = v0, v1, v2
        r0, r1 = _pixel_ray(pixels[i] if subset else i, width, camera)
        norm = math.sqrt((r0 * r0 + r1 * r1) + 1.0 * 1.0)
        radial[i] = _dot(v0, v1, v2, r0, r1, 1.0) / norm


__all__ = ["MATERIAL_COLUMNS", "band_response_one", "shade_geometry", "shade_surface"]
