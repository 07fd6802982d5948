"""Radar surface scattering: physical-optics facets fixed to the objects' surfaces.

Every object's triangles are split, once, in the object's own frame, into *surface
facets* no longer than :data:`FACET_EDGE_M` (longest-edge bisection; a mesh's small
triangles stay whole). A facet is one scatterer at its centroid, with two parts:

* **coherent (physical optics)**: the PO integral over the flat facet (Gordon's closed
  form for a triangle, with the two-way phase taken exactly at its corners and linear
  between them; split into pieces near the specular direction),

      a_coh = j · (2√π / λ) · (−Γ) · √ρ_s · cos θ · ∫_facet e^{j 2k (|r| − |c|)} dA,

  so that a plate of area A at normal incidence sums to 4πA²/λ², a sphere of radius
  r to πr², and an infinite plane to its image, Γ √π R at the image's range (the factor
  j; the facets' exact delays do the rest in the IF synthesis). Γ is the
  material's reflection coefficient (metal −1, dielectrics from their permittivity,
  :meth:`~simcore.scene.materials.BandMaterial.coefficients`) and ``ρ_s = exp(−(4π h cos θ
  / λ)²)`` the Kirchhoff coherent fraction of a surface with rms height h;
* **diffuse (rough surface)**: power ``σ⁰(θ) · A`` from the material's band response, with
  the lobe reduced to its incoherent fraction ``1 − ρ_s`` for smooth-interface materials,
  and a random phase that is a fixed hash of (object id, facet, seed): the speckle is
  attached to the surface, not to the render grid.

The radar render decides only which facets are seen: a facet counts when its centroid's
render pixel shows the same object at the same range (within the pixel's range spread).
So the result does not depend on the render grid (beyond the visibility of facets at
silhouettes), and a static object seen from a moving rig keeps its scatterers: its
return changes only as the geometry (aspect, range) changes.

Limits (``docs/physics_radar.md``): the PO of each facet is a far-field formula (facets of
5 cm are in their far field beyond ≈ 0.5 m at 60 GHz); edge diffraction beyond PO,
polarisation and creeping waves are not modelled; the reflection coefficient is the
normal-incidence value; a facet is all visible or all hidden.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.render.meshes import TriangleMesh
from simcore.scene.materials import BandMaterial, DualBandMaterial
from simcore.scene.model import SceneObject
from simcore.sensors.radar.facet_kernel import object_facet_returns
from simcore.sensors.radar.scene import RadarScene

#: Longest edge of a surface facet (m): far-field PO per facet from ≈ 4 L²/λ = 0.5 m.
FACET_EDGE_M = 0.10
#: Longest over shortest edge above which a triangle is cut into strips before splitting.
ELONGATED_RATIO = 4.0
#: Facet range tolerance of the visibility test, on top of the pixel's range spread (m).
VISIBILITY_TOLERANCE_M = 0.01
#: Smallest one-way transmission |T| that counts (a slab transmitting less is opaque).
TRANSMISSIVE_MIN = 1e-9


@dataclass(frozen=True)
class SurfaceFacets:
    """The surface facets of one mesh, in the object's frame.

    Attributes
    ----------
    vertices : ndarray, shape (N, 3, 3)
        Facet corners (m).
    source : ndarray, shape (N,), int64
        Index of the mesh triangle each facet comes from.
    normals : ndarray, shape (N, 3)
        Outward unit normal of each facet (from the mesh's vertex normals, so that the
        triangles' winding does not matter).
    centroids : ndarray, shape (N, 3)
        Facet centroids (m).
    area2 : ndarray, shape (N,)
        Twice each facet's area (m²).
    source_normals, source_points : ndarray, shape (T, 3)
        Outward normal and one corner of every mesh triangle: a facet can face the radar
        only when its (planar) source triangle does.
    edges : ndarray, shape (N, 3, 3)
        Per facet: the edge vectors v1 − v0, v2 − v0 and the corner v0 − centroid (m).
    longest : ndarray, shape (N,)
        Longest edge (m).
    """

    vertices: NDArray[np.float64]
    source: NDArray[np.int64]
    normals: NDArray[np.float64]
    centroids: NDArray[np.float64]
    area2: NDArray[np.float64]
    source_normals: NDArray[np.float64]
    source_points: NDArray[np.float64]
    edges: NDArray[np.float64]
    longest: NDArray[np.float64]

    def __len__(self) -> int:
        return int(self.source.shape[0])


def _template(n: int) -> NDArray[np.float64]:
    """Barycentric corners of the n² sub-triangles of the regular subdivision, (n², 3, 3).

    Built row by row with numpy (a Python list of n² corners would cost ~40× the array).
    """
    rows = []
    for i in range(n):
        j = np.arange(n - i, dtype=np.float64)
        up = np.stack([np.stack([np.full_like(j, i), j], axis=1),
                       np.stack([np.full_like(j, i + 1), j], axis=1),
                       np.stack([np.full_like(j, i), j + 1], axis=1)], axis=1)   # (n−i, 3, 2)
        jd = j[:-1]
        down = np.stack([np.stack([np.full_like(jd, i + 1), jd], axis=1),
                         np.stack([np.full_like(jd, i + 1), jd + 1], axis=1),
                         np.stack([np.full_like(jd, i), jd + 1], axis=1)], axis=1)
        row = np.empty((2 * (n - i) - 1, 3, 2))
        row[0::2], row[1::2] = up, down                # up, down, up, … as j grows
        rows.append(row)
    ij = np.concatenate(rows) / n                                          # (n², 3, 2)
    return np.concatenate([1.0 - ij.sum(axis=2, keepdims=True), ij], axis=2)


def _strips(n: int) -> NDArray[np.float64]:
    """Barycentric corners of ``2n − 1`` strips across a sliver from its apex, (2n−1, 3, 3).

    Vertex 0 is the apex (opposite the short edge); strip i lies between the lines
    parallel to the short edge at i/n and (i + 1)/n of the way to it.
    """
    out = [[(0.0, 0.0), (1.0 / n, 0.0), (0.0, 1.0 / n)]]
    for i in range(1, n):
        a, b = i / n, (i + 1) / n
        out.append([(a, 0.0), (b, 0.0), (0.0, b)])
        out.append([(a, 0.0), (0.0, b), (0.0, a)])
    w = np.asarray(out, dtype=np.float64)                                  # (2n−1, 3, 2)
    return np.concatenate([1.0 - w.sum(axis=2, keepdims=True), w], axis=2)


def split_triangles(vertices: NDArray[np.float64], max_edge_m: float
                    ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Split triangles into pieces no longer than ``max_edge_m`` (slivers: than their base).

    A triangle whose shortest edge is within the limit (a sliver, e.g. a cylinder's side
    strip) is cut into strips parallel to that edge; a long thin one (longest edge over
    :data:`ELONGATED_RATIO` × its shortest) is cut into strips whose pieces, slivers, are
    cut into strips in turn; any other is subdivided regularly into n² similar triangles.
    Either way the pieces cover the triangle exactly and their number grows with its area
    (or length, for slivers), not faster.

    Parameters
    ----------
    vertices : ndarray, shape (T, 3, 3)
        Triangle corners.
    max_edge_m : float
        Largest edge length of the pieces (m).

    Returns
    -------
    (ndarray, ndarray)
        Pieces, shape (N, 3, 3), and the index of the input triangle each comes from, (N,).
    """
    tri = np.asarray(vertices, dtype=np.float64)
    edges = np.stack([np.linalg.norm(tri[:, 2] - tri[:, 1], axis=1),       # opposite v0
                      np.linalg.norm(tri[:, 0] - tri[:, 2], axis=1),       # opposite v1
                      np.linalg.norm(tri[:, 1] - tri[:, 0], axis=1)], axis=1)
    shortest = np.argmin(edges, axis=1)
    sliver = edges[np.arange(len(tri)), shortest] <= max_edge_m
    # Put the apex (opposite the shortest edge) first, keeping the orientation.
    order = (shortest[:, None] + np.arange(3)[None, :]) % 3
    tri = np.take_along_axis(tri, order[:, :, None], axis=1)
    n = np.maximum(np.ceil(edges.max(axis=1) / max_edge_m).astype(np.int64), 1)
    # A long thin triangle (not a sliver) regularly subdivided would give n² pieces, far
    # more than its area needs (a 4 m × 300 m one: 9·10⁶ instead of ~5·10⁵): it is cut
    # into strips first, whose pieces are slivers, then each of those into strips.
    elongated = ~sliver & (edges.max(axis=1) > ELONGATED_RATIO * edges.min(axis=1))
    out_v: list[NDArray[np.float64]] = []
    out_s: list[NDArray[np.int64]] = []
    for kind, mask in (("strips", sliver | elongated), ("regular", ~sliver & ~elongated)):
        for count in np.unique(n[mask]):
            sel = np.flatnonzero(mask & (n == count))
            bary = _strips(int(count)) if kind == "strips" else _template(int(count))
            out_v.append(np.einsum("pkj,tjd->tpkd", bary, tri[sel]).reshape(-1, 3, 3))
            out_s.append(np.repeat(sel, len(bary)))
    if not out_v:
        return np.zeros((0, 3, 3)), np.zeros(0, np.int64)
    verts, src = np.concatenate(out_v), np.concatenate(out_s)
    again = elongated[src]
    if again.any():
        # The strips' pieces have an edge ≤ L/n ≤ max_edge_m (the tolerance absorbs its
        # rounding), so they are slivers there and this recursion ends at once.
        sub, sub_src = split_triangles(verts[again], max_edge_m * (1.0 + 1e-9))
        verts = np.concatenate([verts[~again], sub])
        src = np.concatenate([src[~again], src[again][sub_src]])
    return verts, src


#: Facets by mesh identity (meshes hold arrays: not hashable), dropped with their mesh.
_FACETS: dict[int, tuple[weakref.ref[TriangleMesh], SurfaceFacets]] = {}


def surface_facets(mesh: TriangleMesh) -> SurfaceFacets:
    """The mesh's surface facets (computed once per mesh object)."""
    entry = _FACETS.get(id(mesh))
    if entry is not None and entry[0]() is mesh:
        return entry[1]
    verts, src = split_triangles(mesh.points[mesh.triangles], FACET_EDGE_M)
    tri = mesh.points[mesh.triangles]
    src_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    src_n /= np.maximum(np.linalg.norm(src_n, axis=1), 1e-300)[:, None]
    outward = mesh.normals[mesh.triangles].sum(axis=1)
    src_n[np.einsum("ij,ij->i", src_n, outward) < 0] *= -1.0
    e1, e2 = verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0]
    cross = np.cross(e1, e2)
    centroids = verts.mean(axis=1)
    longest = np.sqrt(np.max(np.stack([np.sum(e1 * e1, axis=1), np.sum(e2 * e2, axis=1),
                                       np.sum((e2 - e1) ** 2, axis=1)]), axis=0))
    facets = SurfaceFacets(verts, src, src_n[src], centroids, np.linalg.norm(cross, axis=1),
                           src_n, tri[:, 0].copy(),
                           np.stack([e1, e2, verts[:, 0] - centroids], axis=1), longest)
    key = id(mesh)
    _FACETS[key] = (weakref.ref(mesh, lambda _ref: _FACETS.pop(key, None)), facets)
    return facets


@dataclass(frozen=True)
class _RadarMaterial:
    """Per-object radar parameters of the facet model (arrays over objects + 1 'none')."""

    gamma: NDArray[np.complex128]       # −Γ (positive for metal)
    height_rms: NDArray[np.float64]
    smooth: NDArray[np.bool_]
    reflectance: NDArray[np.float64]
    specular: NDArray[np.float64]
    roughness: NDArray[np.float64]
    metallic: NDArray[np.float64]
    retro_gain: NDArray[np.float64]
    transmission: NDArray[np.complex128]   # one-way T (0: opaque), objects + 1 'none'


def _distinct_radar_bands(objects: Sequence[SceneObject],
                          table: Mapping[str, DualBandMaterial]
                          ) -> tuple[list[BandMaterial], NDArray[np.intp]]:
    """The radar bands of the objects' distinct materials, and each object's index.

    Per-material work is then done once per material, not once per object (an imported
    asset has many objects and few materials).
    """
    first: dict[str, int] = {}
    bands: list[BandMaterial] = []
    index = np.zeros(len(objects), dtype=np.intp)
    for i, o in enumerate(objects):
        k = first.get(o.material)
        if k is None:
            k = first[o.material] = len(bands)
            m = table.get(o.material)
            bands.append(m.band("radar") if m is not None else BandMaterial())
        index[i] = k
    return bands, index


def _radar_materials(objects: Sequence[SceneObject], table: Mapping[str, DualBandMaterial],
                     wavelength_m: float) -> _RadarMaterial:
    bands, index = _distinct_radar_bands(objects, table)
    frequency_hz = 299_792_458.0 / wavelength_m
    gam = np.array([-b.coefficients(frequency_hz)[0] if b.is_smooth_interface() else 0.0
                    for b in bands], dtype=np.complex128)
    return _RadarMaterial(
        transmission=transmission_coefficients(objects, table, wavelength_m),
        gamma=gam[index],
        height_rms=np.array([b.height_rms_m for b in bands], dtype=np.float64)[index],
        smooth=np.array([b.is_smooth_interface() for b in bands], dtype=bool)[index],
        reflectance=np.array([b.reflectance for b in bands], dtype=np.float64)[index],
        specular=np.array([b.specular for b in bands], dtype=np.float64)[index],
        roughness=np.array([b.roughness for b in bands], dtype=np.float64)[index],
        metallic=np.array([b.metallic for b in bands], dtype=np.float64)[index],
        retro_gain=np.array([b.retro_gain if b.retroreflector else 0.0 for b in bands],
                            dtype=np.float64)[index],
    )


def transmission_coefficients(objects: Sequence[SceneObject],
                              table: Mapping[str, DualBandMaterial],
                              wavelength_m: float) -> NDArray[np.complex128]:
    """One-way radar transmission T of every object (0: opaque; objects + 1 'none' row).

    ``objects`` are the scene's objects, ``table`` the material table.

    Objects not drawn in the radar pass (opacity 0) are not in the table's sense
    transmissive: the pass does not see them at all.
    """
    freq = 299_792_458.0 / wavelength_m
    bands, index = _distinct_radar_bands(objects, table)
    per_band = np.zeros(len(bands), dtype=np.complex128)
    for k, band in enumerate(bands):
        if band.opacity > 0:
            per_band[k] = band.coefficients(freq)[1]
    out = np.zeros(len(objects) + 1, dtype=np.complex128)
    out[:-1] = per_band[index]
    out[np.abs(out) <= TRANSMISSIVE_MIN] = 0.0
    return out


def transmissive_objects(objects: Sequence[SceneObject], table: Mapping[str, DualBandMaterial],
                         wavelength_m: float) -> tuple[bool, ...] | None:
    """Which objects partly transmit the radar wave; None when none does."""
    trans = transmission_coefficients(objects, table, wavelength_m)
    mask = tuple(bool(t != 0) for t in trans[:-1])
    return mask if any(mask) else None


@dataclass(frozen=True)
class FacetReturns:
    """The seen surface facets of a frame, in the radar's optical frame.

    Attributes
    ----------
    positions_m : ndarray, shape (M, 3)
        Facet centroids (m).
    amplitude : ndarray, shape (M,), complex128
        √RCS with phase (m): coherent PO part plus diffuse part.
    object_index : ndarray, shape (M,), int32
        Source object (index in the scene's objects).
    pixel : ndarray, shape (M,), int64
        Flat render pixel of each centroid.
    """

    positions_m: NDArray[np.float64]
    amplitude: NDArray[np.complex128]
    object_index: NDArray[np.int32]
    pixel: NDArray[np.int64]


def _hash_phase(seed: int, object_id: int, n: int) -> NDArray[np.float64]:
    """Uniform phases of facets ``0 … n−1`` of one object: a fixed hash (rad)."""
    x = np.arange(n, dtype=np.uint64)
    with np.errstate(over="ignore"):
        h = np.uint64((seed * 0x9E3779B1 + object_id * 0x85EBCA77 + 0x632BE5AB)
                      & 0xFFFFFFFFFFFFFFFF)
        for _ in range(2):
            x = x ^ h
            x = x + np.uint64(0x9E3779B97F4A7C15)
            x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
            x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
            x = x ^ (x >> np.uint64(31))
    return (x >> np.uint64(11)).astype(np.float64) * (2.0 * np.pi / 2.0**53)


@lru_cache(maxsize=256)
def _phases(seed: int, object_id: int, n: int) -> NDArray[np.float64]:
    """Speckle phases of an object's ``n`` facets (kept, read-only)."""
    out = _hash_phase(seed, object_id, n)
    out.setflags(write=False)
    return out


@lru_cache(maxsize=256)
def _speckle_phasors(seed: int, object_id: int, n: int) -> NDArray[np.complex128]:
    """``e^{jφ}`` of :func:`_phases`, kept: a facet's speckle phase never changes."""
    phase = _phases(seed, object_id, n)
    out = np.empty(n, dtype=np.complex128)
    np.cos(phase, out=out.real)
    np.sin(phase, out=out.imag)
    out.setflags(write=False)
    return out


def release_phase_caches() -> None:
    """Drop the kept speckle phases (a run moving on to a scene with another seed)."""
    _speckle_phasors.cache_clear()
    _phases.cache_clear()


def facet_returns(scene: RadarScene, buffers: RenderBuffers,
                  meshes: Sequence[TriangleMesh | None], *, wavelength_m: float,
                  speckle: bool = True,
                  seed: int = 0, exclude: NDArray[np.bool_] | None = None,
                  pixels: NDArray[np.bool_] | None = None,
                  see_through: RenderBuffers | None = None) -> FacetReturns:
    """The surface facets of every object that the radar render shows, with their returns.

    Parameters
    ----------
    scene : RadarScene
        Objects, materials, the frame's poses and the radar's.
    buffers : RenderBuffers
        The radar render of ``scene.snapshot`` (visibility only).
    meshes : sequence of TriangleMesh or None
        Each object's mesh in its own frame (None: no surface).
    wavelength_m : float
        Radar wavelength (m).
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
    mat = _radar_materials(scene.objects, scene.materials, wavelength_m)
    world_to_radar = np.linalg.inv(scene.radar.transform)
    intr = buffers.intrinsics
    h, w = intr.height, intr.width
    # Flat images in the kernel's dtypes (no copy when they already are).
    full_obj = np.ascontiguousarray(buffers.object_index.ravel(), dtype=np.int32)
    full_rng = np.ascontiguousarray(buffers.range_m.ravel(), dtype=np.float32)
    trans = mat.transmission
    through_obj = (None if see_through is None else
                   np.ascontiguousarray(see_through.object_index.ravel(), dtype=np.int32))
    through_rng = (None if see_through is None else
                   np.ascontiguousarray(see_through.range_m.ravel(), dtype=np.float32))
    pix_angle = 1.0 / min(intr.fx, intr.fy)
    n_obj = len(scene.objects)
    wanted = None if pixels is None else pixels.ravel()
    # Objects shown at all (in the wanted pixels): the others' facets are not looked at.
    shown = np.bincount((full_obj if wanted is None else full_obj[wanted]) + 1,
                        minlength=n_obj + 1)[1:] > 0
    if through_obj is not None:
        shown |= np.bincount((through_obj if wanted is None else through_obj[wanted]) + 1,
                             minlength=n_obj + 1)[1:] > 0

    # Each shown object's facets in one compiled pass (facet_kernel.object_facet_returns).
    wanted_arr = np.zeros(1, dtype=np.bool_) if wanted is None else wanted
    no_phase = np.ones(1, dtype=np.complex128)
    positions, amplitudes, objects, pixel_list = [], [], [], []
    for i, (o, mesh) in enumerate(zip(scene.objects, meshes, strict=True)):
        if mesh is None or not shown[i] or (exclude is not None and exclude[i]):
            continue
        facets = surface_facets(mesh)
        # Opaque objects are looked for behind the transparent ones, if that pass exists.
        behind = through_obj is not None and trans[i] == 0
        obj_img = through_obj if behind else full_obj
        rng_img = through_rng if behind else full_rng
        assert obj_img is not None and rng_img is not None
        m = world_to_radar @ scene.snapshot.objects[i].transform
        rot, off = np.ascontiguousarray(m[:3, :3]), np.ascontiguousarray(m[:3, 3])
        n_f = len(facets)
        pos = np.empty((n_f, 3))
        amp = np.empty(n_f, dtype=np.complex128)
        pix = np.empty(n_f, dtype=np.int64)
        count = object_facet_returns(
            facets.centroids, facets.normals, facets.area2, facets.source, facets.edges,
            facets.longest, facets.vertices, facets.source_normals, facets.source_points,
            _speckle_phasors(seed, o.id, n_f) if speckle else no_phase,
            rot, off, float(intr.fx), float(intr.fy), float(intr.cx), float(intr.cy),
            int(w), int(h), obj_img, rng_img, wanted_arr, wanted is not None, i,
            float(pix_angle), VISIBILITY_TOLERANCE_M,
            bool(behind), full_obj, full_rng, trans,
            k, float(wavelength_m), bool(mat.smooth[i]), complex(mat.gamma[i]),
            float(mat.height_rms[i]), float(mat.reflectance[i]), float(mat.specular[i]),
            float(mat.roughness[i]), float(mat.metallic[i]), float(mat.retro_gain[i]),
            bool(speckle), pos, amp, pix)
        if count:
            positions.append(pos[:count])
            amplitudes.append(amp[:count])
            objects.append(np.full(count, i, dtype=np.int32))
            pixel_list.append(pix[:count])
    if not positions:
        return FacetReturns(np.zeros((0, 3)), np.zeros(0, np.complex128),
                            np.zeros(0, np.int32), np.zeros(0, np.int64))
    return FacetReturns(np.concatenate(positions), np.concatenate(amplitudes),
                        np.concatenate(objects), np.concatenate(pixel_list))
