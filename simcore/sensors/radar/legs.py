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
    polarization_vector,
)
from simcore.sensors.radar.room import (
    EDGE_TOLERANCE_M,
    _blocked,
    _oriented,
    _transverse,
    reflect_field,
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


def sphere_placement(scene: RadarScene, scatterers: Scatterers) -> Place:
    """Bistatic specular points of the spheres among the ghost sources (``place``).

    A sphere's ghost source (its facets merged, :func:`~simcore.sensors.radar.multipath.
    ghost_sources`) sits at its monostatic specular point; lit from ``src`` and seen from
    ``rcv`` (an image of the radar on either leg) it scatters from the point where its
    normal bisects the two directions, ``c + a (û_src + û_rcv)/|û_src + û_rcv|``: the path
    is ``a |û_src + û_rcv|`` shorter than through the centre (geometric optics, σ = πa²
    for any bistatic angle but forward scatter). Through the monostatic point a ghost over
    a side wall came out 3 cm long against Sionna RT. Other rows keep their positions.
    """
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


def _crossing(face: Reflector, a: NDArray[np.float64], b: NDArray[np.float64]
              ) -> NDArray[np.float64] | None:
    """Where the segments a → b (K, 3) cross the face's plane inside it (NaN rows: not)."""
    s_a = (a - face.center_m) @ face.normal
    s_b = (b - face.center_m) @ face.normal
    ok = (s_a > MIN_DISTANCE_M) & (s_b < -1e-9)
    t = np.where(ok, s_a / np.where(ok, s_a - s_b, 1.0), np.nan)
    x = a + t[:, None] * (b - a)
    local = np.abs((x - face.center_m) @ face.axes.T)
    inside = ok & np.all(local <= face.half_size_m + EDGE_TOLERANCE_M, axis=1)
    if not np.any(inside):
        return None
    x[~inside] = np.nan
    return np.asarray(x)


def _gamma(a: Reflector, b: Reflector, x_a: NDArray[np.float64], x_b: NDArray[np.float64],
           p: NDArray[np.float64], pol: NDArray[np.float64], wavelength_m: float) -> complex:
    """Co-polar Γ of the two bounces, received across the ray arriving at ``p``."""
    field = _transverse(pol.astype(np.complex128), x_a)
    field = reflect_field(a, x_a, field, wavelength_m)
    field = reflect_field(b, x_b - x_a, field, wavelength_m)
    return complex(field @ _transverse(pol.astype(np.complex128), p - x_b))


def one_leg_double_ghosts(scatterers: Scatterers, reflectors: Sequence[Reflector], *,
                          polarization: str, wavelength_m: float,
                          tx_positions_m: NDArray[np.float64],
                          rx_positions_m: NDArray[np.float64],
                          patterns: _Patterns, buffers: RenderBuffers | None,
                          aspect: _Aspect | None = None, place: Place | None = None
                          ) -> list[GhostSet]:
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

    Returns
    -------
    list of GhostSet
        Two per ordered pair of faces with a path (order 2), Tx mirrored and Rx mirrored.
    """
    pol = polarization_vector(polarization)
    pos = scatterers.positions_m
    out: list[GhostSet] = []
    origin = np.zeros((len(pos), 3))
    for ia, face_a in enumerate(reflectors):
        a = _oriented(face_a, np.zeros(3))
        if a is None:
            continue
        src_a = a.mirror(np.zeros(3))
        for ib, face_b in enumerate(reflectors):
            if ib == ia:
                continue
            b = _oriented(face_b, src_a)
            if b is None:
                continue
            src_ab = b.mirror(src_a)
            x_b = _crossing(b, pos, np.broadcast_to(src_ab, pos.shape))
            if x_b is None:
                continue
            x_a = _crossing(a, x_b, np.broadcast_to(src_a, pos.shape))
            if x_a is None:
                continue
            rows = np.flatnonzero(np.isfinite(x_a[:, 0]) & np.isfinite(x_b[:, 0]))
            if buffers is not None and len(rows):
                rows = rows[_reflector_seen(buffers, x_a[rows], a.object_index)]
            keep = [k for k in rows
                    if not _blocked(reflectors, x_a[k], x_b[k], {ia, ib})
                    and not _blocked(reflectors, x_b[k], pos[k], {ib})]
            if not keep:
                continue
            rows = np.array(keep, dtype=np.intp)
            gamma = np.array([_gamma(a, b, x_a[k], x_b[k], pos[k], pol, wavelength_m)
                              for k in rows])
            strong = np.abs(gamma) >= MIN_PRODUCT
            rows, gamma = rows[strong], gamma[strong]
            if not len(rows):
                continue
            out += _sets(scatterers, rows, gamma, x_a[rows], a, b, tx_positions_m,
                         rx_positions_m, patterns, aspect, origin[rows], place)
    return out


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


__all__ = ["Place", "one_leg_double_ghosts", "sphere_placement"]
