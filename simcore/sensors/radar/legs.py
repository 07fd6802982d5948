"""Target ghosts with two bounces on one leg: radar → face A → face B → target → radar.

The image method on one leg (Allen & Berkley 1979): the radar's Tx mirrored in A, then in
B, is the source that the target sees along the unfolded leg; the path exists when the
straight line from the target back to that double image crosses B inside its rectangle,
then (mirrored back) A inside its rectangle, with the radar and the target on the faces'
reflecting sides, nothing of the room's other faces across the legs between the points,
and A's reflection point seen in the radar render. The other leg is direct; by
reciprocity the path back over B then A (target → B → A → radar) has the same length, so
each valid pair gives two ghost sets, one with the Tx array mirrored in A then B, one with
the Rx array so mirrored. Amplitude: the wave's E followed through both bounces
(:func:`~simcore.sensors.radar.room.reflect_field`, Fresnel TE/TM at each angle) and
received at the target across the arriving ray (:func:`~simcore.sensors.radar.multipath.
polarised_reflection`'s convention), times the element pattern's ratio towards A's
reflection point over the target's direction (where the ghost is synthesised).

In a room these are the ghosts that leave the radar sideways, bounce off a side wall into
the front wall (or the floor) and reach the target from there; against Sionna RT they are
−16 dB of a point target's direct return in the 6 × 4 × 3 m concrete room
(``tests/test_radar_sionna_targets.py``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.geometry import Sphere
from simcore.scene.radar_config import ElementPattern
from simcore.sensors.radar.equation import element_gain
from simcore.sensors.radar.reflectors import (
    MIN_DISTANCE_M,
    GhostSet,
    Reflector,
    _reflector_seen,
    antenna_fields,
    copolar_fields,
    polarization_vector,
)
from simcore.sensors.radar.room import (
    EDGE_TOLERANCE_M,
    _oriented,
)
from simcore.sensors.radar.scatterers import KIND_POINT_TARGET, Scatterers, _radar_frame
from simcore.sensors.radar.scene import RadarScene

#: Where a target scatters on a path lit from ``src`` (K, 3) and seen from ``rcv`` (K, 3):
#: ``place(rows, positions, src, rcv)`` (radar frame, m) → positions.
Place = Callable[[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64],
                  NDArray[np.float64]], NDArray[np.float64]]

#: Weakest |Γ_A Γ_B| followed (−40 dB).
MIN_PRODUCT = 0.01
_Patterns = tuple[ElementPattern, ElementPattern]
_Aspect = Callable[[NDArray[np.intp], NDArray[np.float64]], NDArray[np.float64]]


def sphere_centres(scene: RadarScene, scatterers: Scatterers
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centre (N, 3; NaN: not a sphere) and radius (N,) of each sphere's ghost source row."""
    centre = np.full((len(scatterers), 3), np.nan)
    radius = np.zeros(len(scatterers))
    for i, obj in enumerate(scene.objects):
        if not isinstance(obj.geometry, Sphere):
            continue
        rows = np.flatnonzero((scatterers.object_index == i)
                              & (scatterers.kind == KIND_POINT_TARGET))
        world = scene.snapshot.objects[i].transform[:3, 3]
        centre[rows] = _radar_frame(scene.radar, world[None])[0]
        radius[rows] = obj.geometry.radius_m
    return centre, radius


def sphere_sources(scene: RadarScene, scatterers: Scatterers) -> Scatterers:
    """Each sphere's ghost source moved to its monostatic specular point, phase kept.

    :func:`~simcore.sensors.radar.multipath.ghost_sources` merges a sphere's facets at
    their power-weighted centroid, inside the sphere (8.9 mm behind the surface for
    a = 0.2 m at 2.5 m, 60 GHz), and refers the sum's phase to the centroid's range.
    Every ghost of a sphere is drawn at its specular point on the path
    (:func:`sphere_placement`), so the source must be the return of that point: moved to
    ``c − a ĉ`` (the point nearest the radar) with ``2 k r + φ`` unchanged, the same
    monostatic return, ``φ`` now referred to the surface. With the centroid's phase a
    sphere's ghosts came out ``2 k δ`` off (197° for δ = 8.9 mm). Other rows unchanged.
    """
    centre, radius = sphere_centres(scene, scatterers)
    on = np.isfinite(centre[:, 0])
    if not np.any(on):
        return scatterers
    spec = centre[on] - radius[on, None] * _unit(centre[on])
    k = 2.0 * np.pi / scatterers.wavelength_m
    pos = scatterers.positions_m.copy()
    phase = scatterers.phase_rad.copy()
    phase[on] += 2.0 * k * (np.linalg.norm(pos[on], axis=1) - np.linalg.norm(spec, axis=1))
    pos[on] = spec
    return dataclasses.replace(scatterers, positions_m=pos, phase_rad=phase)


def sphere_factor(e_in: NDArray[np.complex128], e_out: NDArray[np.complex128],
                  u_in: NDArray[np.float64], u_out: NDArray[np.float64]
                  ) -> NDArray[np.complex128]:
    """A metal sphere's bistatic co-polar factor relative to its monostatic return (K,).

    ``e_in``: the field arriving over one leg, ``e_out``: the field the receiver would send
    over the other (reciprocity), both at the sphere (K, 3); ``u_in``, ``u_out``: from the
    sphere's centre towards each leg's far end. Geometric optics: the specular point's
    normal ``n`` bisects the legs and a perfect conductor mirrors the whole field there,
    ``e_out · (−M_n e_in)``, over the monostatic ``−1``: ``e_out · M_n e_in``. Where the
    bounces before have rotated the field, the sphere turns it back into the radar's
    polarisation, which the legs' co-polar parts alone (a point target) miss.
    """
    n = _unit(_unit(u_in) + _unit(u_out))
    mirrored = e_in - 2.0 * np.einsum("kd,kd->k", e_in, n)[:, None] * n
    return np.asarray(np.einsum("kd,kd->k", e_out, mirrored), dtype=np.complex128)


def sphere_placement(scene: RadarScene, scatterers: Scatterers) -> Place:
    """Bistatic specular points of the spheres among the ghost sources (``place``).

    A sphere's ghost source (its facets merged, :func:`~simcore.sensors.radar.multipath.
    ghost_sources`, then moved by :func:`sphere_sources`) sits at its monostatic specular
    point; lit from ``src`` and seen from ``rcv`` (an image of the radar on either leg) it
    scatters from the point where its normal bisects the two directions, ``c + a (û_src +
    û_rcv)/|û_src + û_rcv|``: the path is ``a |û_src + û_rcv|`` shorter than through the
    centre (geometric optics, σ = πa² for any bistatic angle but forward scatter). Through
    the monostatic point a ghost over a side wall came out 3 cm long against Sionna RT.
    Other rows keep their positions.
    """
    centre, radius = sphere_centres(scene, scatterers)

    def place(rows: NDArray[np.intp], positions: NDArray[np.float64],
              src: NDArray[np.float64], rcv: NDArray[np.float64]) -> NDArray[np.float64]:
        c = centre[rows]
        on = np.isfinite(c[:, 0])
        if not np.any(on):
            return positions
        out = positions.copy()
        u = _unit(src[on] - c[on]) + _unit(rcv[on] - c[on])
        out[on] = c[on] + radius[rows][on, None] * _unit(u)
        return out

    return place


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)


def _gammas(a: Reflector, b: Reflector, x_a: NDArray[np.float64], x_b: NDArray[np.float64],
            p: NDArray[np.float64], pol: NDArray[np.float64], wavelength_m: float
            ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Co-polar Γ of the two bounces (K,) and the field arriving at ``p`` (K, 3).

    :func:`~simcore.sensors.radar.room.reflect_field` twice, for K paths at once; the
    co-polar part is received across the ray arriving at ``p``.
    """
    field = antenna_fields(pol, x_a).astype(np.complex128)
    field = reflect_many(a, x_a, field, wavelength_m)
    field = reflect_many(b, x_b - x_a, field, wavelength_m)
    return np.asarray(np.einsum("kd,kd->k", field, copolar_fields(pol, p - x_b))), field


def transverse_many(pol: NDArray[np.float64], d: NDArray[np.float64]) -> NDArray[np.float64]:
    """``pol`` made transverse to each direction (K, 3), unit (:func:`room._transverse`).

    A dipole's E; the antennas' is :func:`~simcore.sensors.radar.reflectors.antenna_fields`.
    """
    d = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    out = pol[None] - (d @ pol)[:, None] * d
    norm = np.linalg.norm(out, axis=1)
    pole = norm < 1e-9
    out[pole] = np.array([0.0, 0.0, 1.0]) - d[pole, 2:3] * d[pole]
    return np.asarray(out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300))


def reflect_many(face: Reflector, leg: NDArray[np.float64], field: NDArray[np.complex128],
                  wavelength_m: float) -> NDArray[np.complex128]:
    """:func:`~simcore.sensors.radar.room.reflect_field` for K legs and fields at once."""
    n = face.normal
    d = leg / np.maximum(np.linalg.norm(leg, axis=1, keepdims=True), 1e-300)
    cos_i = np.abs(d @ n)
    g = 4.0 * np.pi * face.height_rms_m * cos_i / wavelength_m
    coherent = np.exp(-0.5 * g * g)[:, None]

    def mirror(v: NDArray[np.complex128]) -> NDArray[np.complex128]:
        return np.asarray(v - 2.0 * (v @ n)[:, None] * n[None])

    if face.band is None:
        return np.asarray(coherent * complex(face.gamma) * mirror(field))
    r_te, r_tm = face.band.oblique_coefficients(face.frequency_hz, cos_i)
    s = np.cross(n, d)
    norm = np.linalg.norm(s, axis=1)
    s[norm <= 1e-9] = transverse_many(np.array([1.0, 0.0, 0.0]), n[None])[0]
    s = s / np.maximum(np.linalg.norm(s, axis=1, keepdims=True), 1e-300)
    e_te = np.einsum("kd,kd->k", field, s)[:, None] * s
    scaled = -r_te[:, None] * e_te + r_tm[:, None] * (field - e_te)
    return np.asarray(-coherent * mirror(scaled))


def one_leg_double_ghosts(scatterers: Scatterers, reflectors: Sequence[Reflector], *,
                          polarization: str, wavelength_m: float,
                          tx_positions_m: NDArray[np.float64],
                          rx_positions_m: NDArray[np.float64],
                          patterns: _Patterns, buffers: RenderBuffers | None,
                          aspect: _Aspect | None = None, place: Place | None = None,
                          centres: NDArray[np.float64] | None = None) -> list[GhostSet]:
    """Ghost sets of the paths radar → A → B → target → radar and their reverse.

    Parameters
    ----------
    scatterers : Scatterers
        The targets that get ghosts (radar frame).
    reflectors : sequence of Reflector
        The frame's planar faces (:func:`~simcore.sensors.radar.multipath.find_reflectors`).
    polarization : str
        The radar's linear polarisation, ``"V"`` or ``"H"``.
    wavelength_m : float
        Wavelength (m).
    tx_positions_m, rx_positions_m : ndarray, shape (N, 3)
        The real antennas (radar frame, m).
    patterns : (ElementPattern, ElementPattern)
        The Tx and Rx element patterns.
    buffers : RenderBuffers or None
        The radar render: A's reflection point must be seen in it (None: no test).
    aspect : callable, optional
        ``aspect(rows, seen_from)``: RCS ratio of the targets ``rows`` lit from the points
        ``seen_from`` (K, 3) and seen from the radar, over their monostatic RCS (a
        trihedral's bistatic lobe); default 1.
    place : callable, optional
        Where each target scatters on the path (:func:`sphere_placement`); default its
        position.
    centres : ndarray, shape (N, 3), optional
        The spheres' centres (:func:`sphere_centres`): their rows take the whole field
        (:func:`sphere_factor`), not its co-polar part.

    Returns
    -------
    list of GhostSet
        Two per ordered pair of faces with a path (order 2), Tx mirrored and Rx mirrored.
    """
    pol = polarization_vector(polarization)
    pos = scatterers.positions_m
    out: list[GhostSet] = []
    origin = np.zeros((len(pos), 3))
    ia_all, ib_all, row_all, xa_all, xb_all = _candidates(reflectors, pos)
    for ia, ib in sorted(set(zip(ia_all.tolist(), ib_all.tolist(), strict=True))):
        sel = np.flatnonzero((ia_all == ia) & (ib_all == ib))
        a = _oriented(reflectors[ia], np.zeros(3))
        assert a is not None
        b = _oriented(reflectors[ib], a.mirror(np.zeros(3)))
        assert b is not None
        rows, x_a, x_b = row_all[sel], xa_all[sel], xb_all[sel]
        if buffers is not None:
            seen = _reflector_seen(buffers, x_a, a.object_index)
            rows, x_a, x_b = rows[seen], x_a[seen], x_b[seen]
        skip = np.zeros(len(reflectors), dtype=bool)
        skip[[ia, ib]] = True
        clear = ~_blocked_many(reflectors, x_a, x_b, skip)
        skip[ia] = False
        clear &= ~_blocked_many(reflectors, x_b, pos[rows], skip)
        rows, x_a, x_b = rows[clear], x_a[clear], x_b[clear]
        gamma, field = _gammas(a, b, x_a, x_b, pos[rows], pol, wavelength_m)
        if centres is not None:
            sph = np.isfinite(centres[rows, 0])
            if np.any(sph):
                c = centres[rows[sph]]
                src = b.mirror(a.mirror(np.zeros(3)))
                gamma[sph] = sphere_factor(field[sph], antenna_fields(pol, pos[rows[sph]])
                                           .astype(np.complex128), src - c, -c)
        strong = np.abs(gamma) >= MIN_PRODUCT
        if not np.any(strong):
            continue
        out += _sets(scatterers, rows[strong], gamma[strong], x_a[strong], a, b,
                     tx_positions_m, rx_positions_m, patterns, aspect, origin[rows[strong]],
                     place)
    return out


def _candidates(reflectors: Sequence[Reflector], pos: NDArray[np.float64]
                ) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp],
                           NDArray[np.float64], NDArray[np.float64]]:
    """Every (face A, face B, target) with the geometry of a path, all pairs at once.

    Returns the faces' and the targets' indices and the reflection points on A and B
    (K, 3), radar frame: the radar and the target on the faces' reflecting sides, the
    unfolded leg crossing B, then A, inside their rectangles.
    """
    empty = (np.zeros(0, np.intp),) * 3 + (np.zeros((0, 3)),) * 2
    if len(reflectors) < 2 or not len(pos):
        return empty
    c = np.array([r.center_m for r in reflectors])
    n = np.array([r.normal for r in reflectors])
    two = np.array([r.two_sided for r in reflectors])
    half = np.array([r.half_size_m for r in reflectors]) + EDGE_TOLERANCE_M
    axes = np.array([r.axes for r in reflectors])
    s0 = -np.einsum("fd,fd->f", c, n)                       # the radar's side of each face
    ok_a = (np.abs(s0) > MIN_DISTANCE_M) & ((s0 > 0) | two)
    n_a = n * np.sign(s0)[:, None]
    src_a = -2.0 * np.abs(s0)[:, None] * n_a                 # the radar mirrored in A
    ia, ib = np.nonzero(ok_a[:, None] & ~np.eye(len(reflectors), dtype=bool))
    s_b = np.einsum("pd,pd->p", src_a[ia] - c[ib], n[ib])
    ok = (np.abs(s_b) > MIN_DISTANCE_M) & ((s_b > 0) | two[ib])
    ia, ib, s_b = ia[ok], ib[ok], s_b[ok]
    n_b = n[ib] * np.sign(s_b)[:, None]
    src_ab = src_a[ia] - 2.0 * np.abs(s_b)[:, None] * n_b    # … then in B
    x_b, hit_b = _cross(pos[None], src_ab[:, None], c[ib], n_b, axes[ib], half[ib])
    x_a, hit_a = _cross(x_b, src_a[ia][:, None], c[ia], n_a[ia], axes[ia], half[ia])
    pair, row = np.nonzero(hit_b & hit_a)
    return ia[pair], ib[pair], row, x_a[pair, row], x_b[pair, row]


def _blocked_many(reflectors: Sequence[Reflector], a: NDArray[np.float64],
                  b: NDArray[np.float64], skip: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Whether each leg a → b (K, 3) crosses a face not in ``skip`` inside its rectangle.

    :func:`~simcore.sensors.radar.room._blocked` for many legs at once.
    """
    faces = [r for r, s in zip(reflectors, skip, strict=True) if not s]
    if not faces or not len(a):
        return np.zeros(len(a), dtype=bool)
    c = np.array([f.center_m for f in faces])
    n = np.array([f.normal for f in faces])
    axes = np.array([f.axes for f in faces])
    half = np.array([f.half_size_m for f in faces]) - EDGE_TOLERANCE_M
    s_a = np.einsum("kfd,fd->kf", a[:, None] - c[None], n)
    s_b = np.einsum("kfd,fd->kf", b[:, None] - c[None], n)
    across = s_a * s_b < 0
    t = np.where(across, s_a / np.where(across, s_a - s_b, 1.0), 0.0)
    x = a[:, None] + t[..., None] * (b - a)[:, None]
    local = np.abs(np.einsum("kfd,fad->kfa", x - c[None], axes))
    return np.asarray(np.any(across & np.all(local < half[None], axis=2), axis=1))


def _cross(p: NDArray[np.float64], img: NDArray[np.float64], c: NDArray[np.float64],
           n: NDArray[np.float64], axes: NDArray[np.float64], half: NDArray[np.float64]
           ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Crossings (P, K, 3) of the segments p → img with the faces (P) and whether inside."""
    s_p = np.einsum("pkd,pd->pk", p - c[:, None], n)
    s_i = np.einsum("pkd,pd->pk", img - c[:, None], n)
    ok = (s_p > MIN_DISTANCE_M) & (s_i < -1e-9)
    t = np.where(ok, s_p / np.where(ok, s_p - s_i, 1.0), 0.0)
    x = p + t[..., None] * (img - p)
    local = np.abs(np.einsum("pkd,pad->pka", x - c[:, None], axes))
    return x, ok & np.all(local <= half[:, None], axis=2)


def _sets(scatterers: Scatterers, rows: NDArray[np.intp], gamma: NDArray[np.complex128],
          x_a: NDArray[np.float64], a: Reflector, b: Reflector,
          tx: NDArray[np.float64], rx: NDArray[np.float64],
          patterns: _Patterns, aspect: _Aspect | None,
          origin: NDArray[np.float64], place: Place | None) -> list[GhostSet]:
    """The Tx-mirrored and the Rx-mirrored ghost set of one pair of faces."""
    src = b.mirror(a.mirror(origin))                       # the radar's image over A, B
    pos = scatterers.positions_m[rows]
    if place is not None:
        pos = place(rows, pos, src, origin)
    lit = np.ones(len(rows)) if aspect is None else aspect(rows, src)
    out = []
    for k, pattern in enumerate(patterns):
        ratio = element_gain(pattern, x_a) / np.maximum(element_gain(pattern, pos), 1e-9)
        amp = gamma * np.sqrt(ratio * lit)
        sc = Scatterers(
            time_s=scatterers.time_s, wavelength_m=scatterers.wavelength_m,
            positions_m=np.ascontiguousarray(pos),
            velocities_mps=scatterers.velocities_mps[rows],
            rcs_m2=scatterers.rcs_m2[rows] * np.abs(amp) ** 2,
            phase_rad=scatterers.phase_rad[rows] + np.angle(amp),
            object_index=scatterers.object_index[rows], kind=scatterers.kind[rows],
            accelerations_mps2=None if scatterers.accelerations_mps2 is None
            else scatterers.accelerations_mps2[rows])
        mirrored = b.mirror(a.mirror(tx if k == 0 else rx))
        out.append(GhostSet(sc, 2, a.object_index,
                            tx_positions_m=mirrored if k == 0 else None,
                            rx_positions_m=mirrored if k == 1 else None))
    return out


__all__ = ["Place", "one_leg_double_ghosts", "reflect_many", "sphere_centres",
           "sphere_factor", "sphere_placement", "sphere_sources", "transverse_many"]
