"""The compiled facet pass equals the numpy implementation it replaced, facet for facet.

``reference_facet_returns`` and its helpers below are the numpy implementation of
:func:`simcore.sensors.radar.surfaces.facet_returns` as it was before the compiled pass
(``simcore/sensors/radar/facet_kernel.py``), kept here verbatim as the reference: the same
facets must be seen, with the same positions and amplitudes to rounding, on moving and
turning rigs, through glass, on a pixel subset, without speckle, and for near-field
facets that are split. The triangle integral is also checked against quadrature.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from simcore.render import SceneRenderer
from simcore.render.buffers import RenderBuffers
from simcore.render.meshes import TriangleMesh
from simcore.resources import example_path
from simcore.scene import Box, Pose, Project, SceneObject, load_project
from simcore.scene.materials import DualBandMaterial
from simcore.scene.model import SensorRig
from simcore.scene.project_io import material_table
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors.radar.facet_kernel import triangle_integral_1
from simcore.sensors.radar.scatterers import _object_meshes
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.sensor import RadarSensor
from simcore.sensors.radar.surfaces import (
    VISIBILITY_TOLERANCE_M,
    FacetReturns,
    _phases,
    _radar_materials,
    _RadarMaterial,
    _template,
    facet_returns,
    surface_facets,
)

SMALL = 1e-3

# ----------------------------------------------------------------- the numpy reference

def triangle_integral(alpha: NDArray[np.float64], beta: NDArray[np.float64]
                      ) -> NDArray[np.complex128]:
    """``∫∫ e^{j(α s + β t)} ds dt`` over the unit simplex (s, t ≥ 0, s + t ≤ 1).

    Closed form (Gordon 1975): ``−(1/β) [(e^{jα} − e^{jβ})/(α − β) − (e^{jα} − 1)/α]``,
    with the near-singular arguments (α, β or α − β within 10⁻³ of 0) nudged apart, which
    changes the value by less than 10⁻³ of the facet's area. Equals 1/2 at α = β = 0.
    """
    a = np.asarray(alpha, dtype=np.float64).copy()
    b = np.asarray(beta, dtype=np.float64).copy()
    a = np.where(np.abs(a) < SMALL, np.where(a < 0, -SMALL, SMALL), a)
    b = np.where(np.abs(b) < SMALL, np.where(b < 0, -SMALL, SMALL), b)
    close = np.abs(a - b) < SMALL
    b = np.where(close, a + np.where(b >= a, 1.0, -1.0) * SMALL * 1.5, b)
    b = np.where(np.abs(b) < SMALL, np.where(b < 0, -2 * SMALL, 2 * SMALL), b)
    ea, eb = np.exp(1j * a), np.exp(1j * b)
    return np.asarray(-((ea - eb) / (a - b) - (ea - 1.0) / a) / b, dtype=np.complex128)


def far_field_integral(v: NDArray[np.float64], dist: NDArray[np.float64], k: float
                       ) -> NDArray[np.complex128]:
    """``∫ e^{j 2k (|r| − dist)} dA`` over each triangle, the phase linear between its corners."""
    phi = 2.0 * k * (np.linalg.norm(v, axis=2) - dist[:, None])            # (M, 3)
    area2 = np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
    return (area2 * triangle_integral(phi[:, 1] - phi[:, 0], phi[:, 2] - phi[:, 0])
            * np.exp(1j * phi[:, 0]))


def facet_integral(v: NDArray[np.float64] | Callable[[NDArray[np.intp]], NDArray[np.float64]],
                   c: NDArray[np.float64], dist: NDArray[np.float64], k: float, *,
                   e1: NDArray[np.float64], e2: NDArray[np.float64], d0: NDArray[np.float64],
                   area2: NDArray[np.float64], edge: NDArray[np.float64]
                   ) -> NDArray[np.complex128]:
    """The PO phase integral ``∫ e^{j 2k (|r| − |c|)} dA`` of each facet (m²).

    Gordon's closed form per facet with the phase linear between its exact corner values;
    a facet longer than 0.4 √(λR/4) whose phase changes by less than 60 rad across it is
    split into n² similar pieces, each with its own exact corner phases.

    Parameters
    ----------
    v : ndarray, shape (M, 3, 3), or callable
        Facet corners in the radar frame (m), or a function of facet indices giving
        them: needed only for the facets that are split.
    c, dist : ndarray, shapes (M, 3) and (M,)
        Centroids and their ranges (m), in a frame where dot products with ``e1``, ``e2``
        and ``d0`` are the radar frame's (the object's own frame works: only the
        direction is rotated, not every corner).
    k : float
        Wavenumber 2π/λ (rad/m).
    e1, e2, d0 : ndarray, shape (M, 3)
        Edge vectors v1 − v0, v2 − v0 and the corner v0 − centroid, in ``c``'s frame (m).
    area2, edge : ndarray, shape (M,)
        Twice each facet's area (m²) and its longest edge (m).
    """
    every = v(np.arange(len(dist))) if callable(v) else v
    out = far_field_integral(every, dist, k)
    phi = 2.0 * k * np.linalg.norm(every, axis=2)
    alpha, beta = phi[:, 1] - phi[:, 0], phi[:, 2] - phi[:, 0]
    limit = 0.4 * np.sqrt(np.pi * dist / (2.0 * k))              # 0.4 √(λR/4)
    span = np.maximum(np.maximum(np.abs(alpha), np.abs(beta)), np.abs(alpha - beta))
    n = np.ceil(edge / limit).astype(np.int64)
    refine = (n > 1) & (span < 60.0)
    if not refine.any():
        return out
    for count in np.unique(n[refine]):
        sel = np.flatnonzero(refine & (n == count))
        corners = v(sel) if callable(v) else v[sel]
        bary = _template(int(min(count, 16)))
        sub = np.einsum("pkj,tjd->tpkd", bary, corners)                # (m, p, 3, 3)
        m, p = sub.shape[:2]
        sub = sub.reshape(-1, 3, 3)
        part = far_field_integral(sub, np.repeat(dist[sel], p), k)
        out[sel] = part.reshape(m, p).sum(axis=1)
    return out


def reference_facet_returns(project: Project, snapshot: SceneSnapshot, buffers: RenderBuffers,
                  meshes: Sequence[TriangleMesh | None], *, wavelength_m: float,
                  materials: Mapping[str, DualBandMaterial], speckle: bool = True,
                  seed: int = 0, exclude: NDArray[np.bool_] | None = None,
                  pixels: NDArray[np.bool_] | None = None,
                  see_through: RenderBuffers | None = None) -> FacetReturns:
    """The surface facets of every object that the radar render shows, with their returns.

    Parameters
    ----------
    project, snapshot : Project, SceneSnapshot
        Objects, materials and the frame's poses.
    buffers : RenderBuffers
        The radar render of ``snapshot`` (visibility only).
    meshes : sequence of TriangleMesh or None
        Each object's mesh in its own frame (None: no surface).
    wavelength_m : float
        Radar wavelength (m).
    materials : mapping
        Material table of the project.
    speckle : bool
        Give the diffuse parts their surface-attached random phase (else 0).
    seed : int
        Speckle realisation.
    exclude : ndarray of bool, shape (objects,), optional
        Objects left out (analytic targets).
    pixels : ndarray of bool, shape (H, W), optional
        Keep only the facets whose centroid falls on these render pixels.
    see_through : RenderBuffers, optional
        The same render with the partially transparent objects hidden. Facets of the other
        objects are then seen in it, and a transparent object nearer on the facet's pixel
        in ``buffers`` multiplies the facet's return by its two-way transmission T².
        Without it, every object is opaque.
    """
    k = 2.0 * math.pi / wavelength_m
    mat = _radar_materials(project.objects, materials, wavelength_m)
    radar = snapshot.sensors["radar"]
    world_to_radar = np.linalg.inv(radar.transform)
    intr = buffers.intrinsics
    h, w = intr.height, intr.width
    full_obj = buffers.object_index.ravel()
    full_rng = buffers.range_m.ravel()
    trans = mat.transmission
    through_obj = None if see_through is None else see_through.object_index.ravel()
    through_rng = None if see_through is None else see_through.range_m.ravel()
    pix_angle = 1.0 / min(intr.fx, intr.fy)
    n_obj = len(project.objects)
    wanted = None if pixels is None else pixels.ravel()
    # Objects shown at all (in the wanted pixels): the others' facets are not looked at.
    shown = np.bincount((full_obj if wanted is None else full_obj[wanted]) + 1,
                        minlength=n_obj + 1)[1:] > 0
    if through_obj is not None:
        shown |= np.bincount((through_obj if wanted is None else through_obj[wanted]) + 1,
                             minlength=n_obj + 1)[1:] > 0

    parts: list[tuple[NDArray[Any], ...]] = []
    corner_fns: list[Callable[[NDArray[np.intp]], NDArray[np.float64]]] = []
    for i, (o, mesh) in enumerate(zip(project.objects, meshes, strict=True)):
        if mesh is None or not shown[i] or (exclude is not None and exclude[i]):
            continue
        facets = surface_facets(mesh)
        # Opaque objects are looked for behind the transparent ones, if that pass exists.
        behind = through_obj is not None and trans[i] == 0
        obj_img = through_obj if behind else full_obj
        rng_img = through_rng if behind else full_rng
        assert obj_img is not None and rng_img is not None
        m = world_to_radar @ snapshot.objects[i].transform
        rot, off = m[:3, :3], m[:3, 3]
        # Source triangles facing the radar (a plane faces it on all of its points).
        src_n = facets.source_normals @ rot.T
        facing = np.einsum("ij,ij->i", src_n, facets.source_points @ rot.T + off) < 0
        cand = np.flatnonzero(facing[facets.source])
        if not len(cand):
            continue
        c = facets.centroids[cand] @ rot.T + off
        z = c[:, 2]
        ok = z > 1e-6
        zz = np.where(ok, z, 1.0)
        col = np.floor(intr.fx * c[:, 0] / zz + intr.cx)
        row = np.floor(intr.fy * c[:, 1] / zz + intr.cy)
        ok &= (col >= 0) & (col < w) & (row >= 0) & (row < h)
        sel = np.flatnonzero(ok)
        pix = (row[sel] * w + col[sel]).astype(np.int64)
        first = obj_img[pix] == i
        if wanted is not None:
            first &= wanted[pix]
        sel, pix = sel[first], pix[first]
        c = c[sel]
        cand = cand[sel]
        dist = np.linalg.norm(c, axis=1)
        u = c / dist[:, None]                                              # radar → facet
        cos_t = -np.einsum("ij,ij->i", facets.normals[cand] @ rot.T, u)
        area2 = facets.area2[cand]
        # Seen: the pixel shows this object at the facet's range (within its spread).
        cos_s = np.clip(cos_t, 0.05, 1.0)
        tol = VISIBILITY_TOLERANCE_M + 1.5 * dist * pix_angle * np.sqrt(
            1.0 - cos_s * cos_s) / cos_s + 0.5 * np.sqrt(area2)
        seen = (cos_t > 0) & (np.abs(rng_img[pix] - dist) <= tol)
        sel = np.flatnonzero(seen)
        if not len(sel):
            continue
        pix, c, dist, cos_t, area2, cand = (pix[sel], c[sel], dist[sel], cos_t[sel],
                                            area2[sel], cand[sel])
        # Dot products with the facet's edges are frame independent: take the direction
        # into the object's frame instead of the corners into the radar's.
        c_obj = c @ rot                                                    # Rᵀ c
        edges = facets.edges[cand]
        geometry = (c_obj, edges[:, 0], edges[:, 1], edges[:, 2], area2, facets.longest[cand])
        corners = corners_getter(facets.vertices, cand, rot, off)
        if speckle:
            phase = _phases(seed, o.id, len(facets))[cand]
        else:
            phase = np.zeros(len(cand))
        if behind:
            # Through the nearer transparent object on the facet's pixel, in and out.
            front = full_obj[pix]
            nearer = (front >= 0) & (front != i) & (full_rng[pix] < dist)
            path = np.where(nearer, trans[front] ** 2, 1.0 + 0j)
        else:
            path = np.ones(len(cand), dtype=np.complex128)
        parts.append((c, dist, cos_t, phase, path, np.full(len(cand), i, dtype=np.int32),
                      pix, *geometry))
        corner_fns.append(corners)
    if not parts:
        return FacetReturns(np.zeros((0, 3)), np.zeros(0, np.complex128),
                            np.zeros(0, np.int32), np.zeros(0, np.int64))
    c, dist, cos_t, phase, path, obj, pix, c_obj, e1, e2, d0, area2, longest = (
        np.concatenate([p[j] for p in parts]) for j in range(13))
    offsets = np.cumsum([0] + [len(p[0]) for p in parts])

    def corners_of(sel: NDArray[np.intp]) -> NDArray[np.float64]:
        """Radar-frame corners of the (concatenated) facets ``sel``."""
        out = np.empty((len(sel), 3, 3))
        part = np.searchsorted(offsets, sel, side="right") - 1
        for j in np.unique(part):
            mask = part == j
            out[mask] = corner_fns[j](sel[mask] - offsets[j])
        return out

    def coherent(sel: NDArray[np.intp]) -> NDArray[np.complex128]:
        if len(sel) == len(dist):                                  # every facet: no gathers
            return facet_integral(corners_of, c_obj, dist, k, e1=e1, e2=e2, d0=d0,
                                  area2=area2, edge=longest)
        return facet_integral(lambda local: corners_of(sel[local]), c_obj[sel], dist[sel],
                              k, e1=e1[sel], e2=e2[sel], d0=d0[sel], area2=area2[sel],
                              edge=longest[sel])

    amp = amplitudes(mat, obj, cos_t, 0.5 * area2, phase, coherent,
                      wavelength_m=wavelength_m, speckle=speckle)
    return FacetReturns(c, amp * path, obj, pix)


def corners_getter(vertices: NDArray[np.float64], cand: NDArray[np.intp], rot: NDArray[np.float64],
             off: NDArray[np.float64]) -> Callable[[NDArray[np.intp]], NDArray[np.float64]]:
    """Radar-frame corners of facets ``cand[local]``, computed when asked."""
    def get(local: NDArray[np.intp]) -> NDArray[np.float64]:
        return np.asarray(vertices[cand[local]] @ rot.T + off, dtype=np.float64)
    return get


def amplitudes(mat: _RadarMaterial, obj: NDArray[np.int32], cos_t: NDArray[np.float64],
                area: NDArray[np.float64], phase: NDArray[np.float64],
                coherent: Callable[[NDArray[np.intp]], NDArray[np.complex128]], *,
                wavelength_m: float, speckle: bool) -> NDArray[np.complex128]:
    """Coherent PO plus diffuse amplitude (√m² with phase) of every seen facet.

    ``coherent(sel)`` gives the PO phase integral (m²) of the facets ``sel``.
    """
    cos_i = np.clip(cos_t, 0.0, 1.0)
    smooth = np.take(mat.smooth, obj)
    amp = np.zeros(len(obj), dtype=np.complex128)
    rho2 = np.ones(len(obj))
    sel = np.flatnonzero(smooth)
    if len(sel):
        o = obj[sel]
        g = 4.0 * math.pi * np.take(mat.height_rms, o) * cos_i[sel] / wavelength_m
        rho2[sel] = np.exp(-g * g)
        amp[sel] = (2j * math.sqrt(math.pi) / wavelength_m * np.take(mat.gamma, o)
                    * np.sqrt(rho2[sel]) * cos_i[sel]) * coherent(sel)
    # Diffuse part: the band response with the lobe's incoherent fraction.
    cc = np.clip(cos_i, 1e-6, 1.0)
    m2 = np.take(mat.roughness, obj) ** 2
    tan2 = (1.0 - cc * cc) / (cc * cc)
    lobe = np.take(mat.specular, obj) * np.exp(-tan2 / m2) / (m2 * cc**4)
    incoherent = np.where(smooth, 1.0 - rho2, 1.0)
    sigma0 = ((1.0 - np.take(mat.metallic, obj)) * np.take(mat.reflectance, obj) * cc
              + lobe * incoherent + np.take(mat.retro_gain, obj))
    diffuse = np.sqrt(sigma0 * area)
    if speckle:
        amp += diffuse * np.exp(1j * phase)
    else:
        amp += diffuse
    return amp


# ----------------------------------------------------------------------------- tests


def _frames(project: Project, times: list[float]
            ) -> list[tuple[SceneSnapshot, RenderBuffers, RenderBuffers | None,
                            list[TriangleMesh | None]]]:
    renderer = SceneRenderer(project, base_dir=example_path("office").parent)
    sensor = RadarSensor()
    request, hide = sensor.render_request(project), sensor.see_through(project)
    out = []
    try:
        for t in times:
            snap = take_snapshot(project, t)
            buffers = renderer.render(snap, request)
            through = None if hide is None else renderer.render(snap, request, hide=hide)
            out.append((snap, buffers, through, list(_object_meshes(project.objects, buffers))))
    finally:
        renderer.close()
    return out


def kernel_facet_returns(project: Project, snapshot: SceneSnapshot, buffers: RenderBuffers,
                         meshes: Sequence[TriangleMesh | None], *,
                         materials: Mapping[str, DualBandMaterial], **kw: Any) -> FacetReturns:
    """:func:`facet_returns` on the project's radar slice (``materials`` is the slice's)."""
    scene = RadarScene.from_project(project, snapshot)
    scene = dataclasses.replace(scene, materials=materials)
    return facet_returns(scene, buffers, meshes, **kw)


def _assert_same(ref: FacetReturns, new: FacetReturns) -> None:
    assert len(ref.pixel) > 0
    np.testing.assert_array_equal(new.pixel, ref.pixel)
    np.testing.assert_array_equal(new.object_index, ref.object_index)
    np.testing.assert_allclose(new.positions_m, ref.positions_m, rtol=0, atol=1e-12)
    scale = float(np.abs(ref.amplitude).max())
    np.testing.assert_allclose(new.amplitude, ref.amplitude, rtol=1e-9, atol=1e-12 * scale)


def _moving_office(velocity: tuple[float, float, float],
                   turn_dps: tuple[float, float, float]) -> Project:
    project = load_project(example_path("office"))
    motion = project.rig.motion.model_copy(update={"velocity_mps": velocity,
                                                   "angular_velocity_dps": turn_dps})
    return project.model_copy(update={"rig": project.rig.model_copy(update={"motion": motion})})


@pytest.mark.parametrize("velocity, turn", [((0.7, 0.2, 0.0), (0.0, 0.0, 0.0)),
                                            ((0.0, 0.0, 0.0), (3.0, -5.0, 25.0))])
def test_kernel_equals_numpy_reference_on_a_moving_rig(velocity: tuple[float, float, float],
                                                       turn: tuple[float, float, float]
                                                       ) -> None:
    project = _moving_office(velocity, turn)
    lam = project.rig.radar.wavelength_m
    table = material_table(project)
    for snap, buffers, through, meshes in _frames(project, [0.0, 1.3]):
        for speckle, seed in [(True, 7), (False, 0)]:
            kw: dict[str, Any] = dict(wavelength_m=lam, materials=table, speckle=speckle,
                                      seed=seed, see_through=through)
            _assert_same(reference_facet_returns(project, snap, buffers, meshes, **kw),
                         kernel_facet_returns(project, snap, buffers, meshes, **kw))
        # Without the see-through pass, on a pixel subset, with an object left out.
        rng = np.random.default_rng(1)
        pixels = rng.random(buffers.range_m.shape) < 0.3
        exclude = np.zeros(len(project.objects), dtype=bool)
        exclude[0] = True
        kw = dict(wavelength_m=lam, materials=table, seed=2, pixels=pixels, exclude=exclude)
        _assert_same(reference_facet_returns(project, snap, buffers, meshes, **kw),
                     kernel_facet_returns(project, snap, buffers, meshes, **kw))


def test_kernel_splits_near_field_facets_like_the_reference() -> None:
    """A large metal plate at 1 m: facets beyond their far field are split into pieces."""
    project = Project(objects=[SceneObject(
        id=1, name="plate", geometry=Box(size_m=(0.002, 0.4, 0.4)), material="aluminium",
        pose=Pose(position_m=(1.0, 0.0, 0.0), rotation_deg=(0.0, 2.0, 3.0)))], rig=SensorRig())
    lam = project.rig.radar.wavelength_m
    table = material_table(project)
    (snap, buffers, through, meshes), = _frames(project, [0.0])
    kw: dict[str, Any] = dict(wavelength_m=lam, materials=table, seed=4, see_through=through)
    ref = reference_facet_returns(project, snap, buffers, meshes, **kw)
    _assert_same(ref, kernel_facet_returns(project, snap, buffers, meshes, **kw))
    # The case is the one meant: some seen facets are split (longer than √(λR/4)).
    facets = surface_facets(meshes[0])  # type: ignore[arg-type]
    dist = np.linalg.norm(ref.positions_m, axis=1)
    assert np.any(facets.longest.max() > np.sqrt(lam * dist / 4.0))


@pytest.mark.parametrize("alpha, beta", [(0.0, 0.0), (2.3, -0.7), (5.0, 5.0004),
                                         (-11.0, 0.0002), (0.4, 17.0)])
def test_triangle_integral_matches_quadrature(alpha: float, beta: float) -> None:
    """∫∫ e^{j(αs + βt)} over the unit simplex, by a fine midpoint rule (known answer)."""
    n = 1200
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    # Cells inside count once, cells the hypotenuse cuts in half count half.
    weight = np.where(i + j < n - 1, 1.0, np.where(i + j == n - 1, 0.5, 0.0))
    s, t = (i + 0.5) / n, (j + 0.5) / n
    quad = np.sum(weight * np.exp(1j * (alpha * s + beta * t))) / n**2
    got = triangle_integral_1(alpha, beta)
    nudged = min(abs(alpha), abs(beta), abs(alpha - beta)) < SMALL
    assert abs(got - quad) < (6e-4 if nudged else 1e-4)
    assert got == pytest.approx(complex(triangle_integral(np.array([alpha]),
                                                          np.array([beta]))[0]), rel=1e-12)
