"""The room's own multiple bounces: edges, corners and echoes between its planar faces.

Every sequence of two or three planar faces (:func:`~simcore.sensors.radar.multipath.
find_reflectors`: walls, floor, ceiling, furniture) that the wave can follow from the radar
back to it is a specular path of the image method (Allen & Berkley, *J. Acoust. Soc. Am.*
65, 1979; for radio, Geng & Wiesbeck, *Planungsmethoden für die Mobilkommunikation*, 1998):
the radar's image is mirrored in each face of the sequence in turn, and the path exists
when the straight line from the last image back to the radar, traced back through the
faces in reverse order, crosses each face inside its rectangle, with the first and the last
leg seen in the radar render (nothing in front of the faces) and the legs between faces
clear of the scene's other planar objects. Two faces meeting at an edge (floor and wall)
give the room's dihedral edges, three faces its trihedral corners, two facing walls its
echoes (front wall, back wall, then the radar).

Each path's return is that of the radar's image at the path's length ``2D``: an infinite
plane's ``√σ = √π D`` times the faces' Fresnel coefficients at the path's angles and the
radar's polarisation (the E vector followed through the bounces, :func:`reflect_field`),
limited by the faces' geometric-optics aperture: the area ``A`` of the beam that follows
the whole sequence (the faces unfolded along the path and projected across it, their
intersection), ``√σ = 2√π A / λ`` (Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd
ed., §5.4: a dihedral's 8πa²b²/λ², a square trihedral's 12πa⁴/λ² summed over its
orders). Each order of faces is its own path (a sequence and its reverse are both
counted: they have equal lengths and add coherently). Near an edge or a corner the orders
of its faces share one image (mirrors in perpendicular faces commute; image theory of a
90° wedge or corner), so each order's ``√π D`` is that image's share: half at an edge, a
sixth at a corner (:func:`_same_image_orders`; checked against Sionna RT in
``tests/test_radar_sionna_targets.py``).

Single-face returns are the faces' own surface facets (:mod:`~simcore.sensors.radar.
surfaces`), not repeated here. Limits: edge diffraction (UTD) and the transition of a
path's return when its reflection point nears a face's border are not modelled (a path
is all there or not); the faces are taken still relative to the radar (no Doppler).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.materials import BandMaterial
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.radar.equation import element_gain
from simcore.sensors.radar.reflectors import (
    MIN_DISTANCE_M,
    GhostSet,
    Reflector,
    polarization_vector,
)
from simcore.sensors.radar.room_kernel import room_candidates
from simcore.sensors.radar.scatterers import KIND_POINT_TARGET, Scatterers
from simcore.sensors.radar.scene import RadarScene

#: A reflection point may lie this far outside its face's rectangle (m): two faces that
#: meet at an edge put the dihedral's reflection points on their common border.
EDGE_TOLERANCE_M = 0.02
#: Longest sequence of faces followed (3: trihedral corners).
MAX_FACES = 3


def room_returns(scene: RadarScene | None, config: RadarConfig, reflectors: Sequence[Reflector], *,
                 buffers: RenderBuffers | None, order: int, time_s: float) -> list[GhostSet]:
    """The room's multiple-bounce returns (module docstring) as ghost sets of order ≥ 2.

    Parameters
    ----------
    scene : RadarScene or None
        The radar's slice of the frame (not read: the faces are ``reflectors``; kept for
        symmetry with the other path functions).
    config : RadarConfig
        Wavelength and polarisation.
    reflectors : sequence of Reflector
        The frame's planar faces, radar frame (:func:`~simcore.sensors.radar.multipath.
        find_reflectors`).
    buffers : RenderBuffers or None
        The radar render: the first and last reflection points must be seen in it.
    order : int
        The radar's ``multipath_order``: 1 follows pairs of faces, 2 also triples.
    time_s : float
        The frame's time (for the scatterers).

    Returns
    -------
    list of GhostSet
        One set of point scatterers (real antennas) per face sequence with a path,
        attributed to the sequence's first face.
    """
    del scene
    if order <= 0 or len(reflectors) < 2:
        return []
    lam = config.wavelength_m
    paths = _room_paths(_key(reflectors), lam, config.polarization, min(order + 1, MAX_FACES))
    out: list[GhostSet] = []
    seen = (np.ones(len(paths), dtype=bool) if buffers is None
            else _paths_seen(buffers, paths, reflectors))
    for (seq, first, last, position, amplitude), ok in zip(paths, seen, strict=True):
        if not ok:
            continue
        # The scatterer sits towards the last reflection point, where the wave comes back
        # from, so the synthesis weighs both legs by the pattern there; the wave left
        # towards the first: that leg's gain ratio goes into the RCS (an echo between
        # facing walls leaves forwards and comes back from behind).
        gains = element_gain(config.element_pattern, np.array([first, last]))
        if gains[1] <= 1e-12:
            continue
        out.append(GhostSet(Scatterers(
            time_s=time_s, wavelength_m=lam, positions_m=position[None],
            velocities_mps=np.zeros((1, 3)),
            rcs_m2=np.array([abs(amplitude) ** 2 * gains[0] / gains[1]]),
            phase_rad=np.array([float(np.angle(amplitude))]),
            object_index=np.array([reflectors[seq[0]].object_index], dtype=np.int32),
            kind=np.array([KIND_POINT_TARGET], dtype=np.int8)), len(seq),
            reflectors[seq[0]].object_index))
    return out


_Path = tuple[tuple[int, ...], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
              complex]


def _paths_seen(buffers: RenderBuffers, paths: Sequence[_Path],
                reflectors: Sequence[Reflector]) -> NDArray[np.bool_]:
    """Whether each path's first and last reflection points are seen in the render.

    Seen as one of the path's faces (at an edge or a corner the points are on every face's
    border); a point behind the radar or outside the render counts as seen, as in
    :func:`~simcore.sensors.radar.reflectors._reflector_seen` (one projection of every
    path's two points instead of one call per point and face).
    """
    if not paths:
        return np.zeros(0, dtype=bool)
    points = np.array([[first, last] for _, first, last, _, _ in paths]).reshape(-1, 3)
    label = np.zeros(len(points), dtype=np.int64)
    shown = np.zeros(len(points), dtype=bool)          # in front and inside the render
    front = points[:, 2] > 0
    if np.any(front):
        intr = buffers.intrinsics
        uv = intr.project(points[front])
        col = np.floor(uv[:, 0]).astype(np.int64)
        row = np.floor(uv[:, 1]).astype(np.int64)
        within = (col >= 0) & (col < intr.width) & (row >= 0) & (row < intr.height)
        inside = np.flatnonzero(front)[within]
        shown[inside] = True
        label[inside] = buffers.object_index[row[within], col[within]]
    label2, shown2 = label.reshape(-1, 2), shown.reshape(-1, 2)
    out = np.empty(len(paths), dtype=bool)
    for k, (seq, _, _, _, _) in enumerate(paths):
        objects = {reflectors[i].object_index for i in seq}
        out[k] = all(not shown2[k, j] or int(label2[k, j]) in objects for j in range(2))
    return out


def _key(reflectors: Sequence[Reflector]) -> tuple[object, ...]:
    """A hashable description of the faces (their geometry and material), for the cache."""
    bands: dict[int, str] = {}          # the faces of one material share its band
    for r in reflectors:
        if r.band is not None and id(r.band) not in bands:
            bands[id(r.band)] = r.band.model_dump_json()
    return tuple((r.center_m.tobytes(), r.axes.tobytes(), r.half_size_m.tobytes(),
                  r.normal.tobytes(), r.two_sided, complex(r.gamma), r.height_rms_m,
                  None if r.band is None else bands[id(r.band)], r.frequency_hz,
                  r.object_index) for r in reflectors)


@lru_cache(maxsize=32)
def _room_paths(key: tuple[object, ...], wavelength_m: float, polarization: str,
                max_faces: int) -> list[_Path]:
    """Every face sequence with a geometric path, by face geometry (a still room: once).

    Returns (face indices, first and last reflection point, the equivalent scatterer's
    position, its amplitude √σ with phase) per path.
    """
    faces = [_face_of(k) for k in key]
    pol = polarization_vector(polarization)
    out: list[_Path] = []
    # Which face can follow which: the next reflection point lies in front of the face
    # just left, so some corner of the next face must, and the point just left lies in
    # front of the next face, so some corner of it must (necessary conditions; they prune
    # the faces of furniture behind one another). Strictly in front, beyond the edge
    # tolerance: two faces of one convex box meet at an edge with every corner of each on
    # or behind the other's plane, and the tolerance put reflection points on that edge
    # (a box on a desk made "corners" with its own faces, 16 dB over the desk's return).
    corners = np.array([[f.center_m + sa * f.half_size_m[0] * f.axes[0]
                         + sb * f.half_size_m[1] * f.axes[1]
                         for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1))] for f in faces])
    signed = np.einsum("jcd,id->ijc", corners, np.array([f.normal for f in faces])) \
        - np.einsum("id,id->i", np.array([f.center_m for f in faces]),
                    np.array([f.normal for f in faces]))[:, None, None]
    front = np.any(signed > EDGE_TOLERANCE_M, axis=2)       # corner of j before plane i
    back = np.any(signed < -EDGE_TOLERANCE_M, axis=2)       # … or behind (two-sided)
    reach = front | (np.array([f.two_sided for f in faces])[:, None] & back)
    follows = reach & reach.T

    # The sequences in depth-first order (each first face, each second, the pair then its
    # triples); a compiled pass drops those that certainly have no path, the trace decides.
    for row in room_candidates(
            np.array([f.center_m for f in faces]).reshape(-1, 3),
            np.array([f.normal for f in faces]).reshape(-1, 3),
            np.array([f.axes for f in faces]).reshape(-1, 2, 3),
            np.array([f.half_size_m for f in faces]).reshape(-1, 2),
            np.array([f.two_sided for f in faces], dtype=bool), follows, max_faces,
            EDGE_TOLERANCE_M, MIN_DISTANCE_M):
        path = _trace(faces, tuple(int(i) for i in row[:3] if i >= 0), wavelength_m, pol,
                      legs_clear=bool(row[3] == 1))
        if path is not None:
            out.append(path)
    return out


def _search(faces: Sequence[Reflector], follows: NDArray[np.bool_], max_faces: int,
            wavelength_m: float, pol: NDArray[np.float64]) -> list[_Path]:
    """Every sequence traced in Python, in the same order: the reference of the filter."""
    out: list[_Path] = []

    def extend(seq: tuple[int, ...], image: NDArray[np.float64]) -> None:
        for i, face in enumerate(faces):
            if seq and (i == seq[-1] or not follows[seq[-1], i]):
                continue
            oriented = _oriented(face, image)
            if oriented is None:
                continue
            longer = (*seq, i)
            if len(longer) >= 2:
                path = _trace(faces, longer, wavelength_m, pol)
                if path is not None:
                    out.append(path)
            if len(longer) < max_faces:
                extend(longer, oriented.mirror(image))

    extend((), np.zeros(3))
    return out


def _face_of(k: Any) -> Reflector:
    c, ax, half, n, two, gamma, h, band, freq, obj = k
    return Reflector(object_index=int(obj), center_m=np.frombuffer(c),
                     axes=np.frombuffer(ax).reshape(2, 3), half_size_m=np.frombuffer(half),
                     normal=np.frombuffer(n), two_sided=bool(two), gamma=complex(gamma),
                     height_rms_m=float(h), normal_speed_mps=0.0,
                     band=None if band is None else BandMaterial.model_validate_json(band),
                     frequency_hz=float(freq))


def _oriented(face: Reflector, point: NDArray[np.float64]) -> Reflector | None:
    """The face with its normal towards ``point``, or None (behind a one-sided face)."""
    s = float((point - face.center_m) @ face.normal)
    if abs(s) < MIN_DISTANCE_M:
        return None
    if s > 0:
        return face
    if not face.two_sided:
        return None
    return Reflector(face.object_index, face.center_m, face.axes, face.half_size_m,
                     -face.normal, True, face.gamma, face.height_rms_m, 0.0, face.band,
                     face.frequency_hz)


def _trace(faces: Sequence[Reflector], seq: tuple[int, ...], wavelength_m: float,
           pol: NDArray[np.float64], *, legs_clear: bool = False) -> _Path | None:
    """The path radar → faces ``seq`` → radar by the image method, or None.

    ``legs_clear``: no other face can block a leg between the reflection points (the
    compiled filter, :func:`~simcore.sensors.radar.room_kernel.room_candidates`, found it
    with a margin), so that test is skipped.
    """
    images = [np.zeros(3)]
    oriented: list[Reflector] = []
    for i in seq:
        face = _oriented(faces[i], images[-1])
        if face is None:
            return None
        oriented.append(face)
        images.append(face.mirror(images[-1]))
    # Back-trace from the radar towards the last image, through the faces in reverse.
    points: list[NDArray[np.float64]] = []
    target = np.zeros(3)
    for face, image in zip(reversed(oriented), reversed(images[1:]), strict=True):
        s_a = float((target - face.center_m) @ face.normal)
        s_b = float((image - face.center_m) @ face.normal)
        if not (s_a > -1e-9 and s_b < -1e-9):     # the radar's side → behind (an edge: on it)
            return None
        x = target + s_a / (s_a - s_b) * (image - target)
        local = (x - face.center_m) @ face.axes.T
        if np.any(np.abs(local) > face.half_size_m + EDGE_TOLERANCE_M):
            return None
        points.append(x)
        target = x
    points.reverse()                                     # reflection points in path order
    if min(np.linalg.norm(points[0]), np.linalg.norm(points[-1])) < MIN_DISTANCE_M:
        return None
    for k in range(len(points) - 1 if not legs_clear else 0):
        if _blocked(faces, points[k], points[k + 1], {seq[k], seq[k + 1]}):
            return None
    # The wave's E vector through the bounces (each face mirrors it, scaling its TE and TM
    # parts by Fresnel), received by the antenna's polarisation. The ray's direction on
    # each face is the unfolded path's, mirrored in the faces before it (defined also where
    # two reflection points meet at an edge).
    unfolded = images[-1] / float(np.linalg.norm(images[-1]))
    direction = unfolded
    field = _transverse(pol.astype(np.complex128), direction)
    for face in oriented:
        field = reflect_field(face, direction, field, wavelength_m)
        direction = face.mirror_vectors(direction)
    amplitude = complex(field @ _transverse(pol.astype(np.complex128), direction))
    half = 0.5 * float(np.linalg.norm(images[-1]))
    near = math.sqrt(math.pi) * half
    if float(np.linalg.norm(direction + unfolded)) < 1e-6:
        # A wedge or corner returns the wave only if it is concave: every face in front of
        # every other face (an echo between facing walls meets one of them twice). Convex
        # ones (two faces of one box, or a box's side and front faces with the floor) put
        # their reflection points on the common edge too, within the edge tolerance, but
        # no wave goes from one face to the other there.
        if not all(_facing(oriented[k], oriented[m]) for k in range(len(seq))
                   for m in range(k + 1, len(seq)) if seq[k] != seq[m]):
            return None
        # A retro-directive sequence (a plane wave comes back on itself: dihedral across its
        # edge, trihedral): its far-field return is the GO aperture's.
        # Near it, the radar's image: one image for all the orders of the same faces
        # (mirrors in perpendicular faces commute), each order a share of it.
        size = min(near / _same_image_orders(faces, seq, images[-1]),
                   2.0 * math.sqrt(math.pi) * _aperture(oriented, images[-1]) / wavelength_m)
    else:
        # Otherwise only the image exists (no far-field return): full where the first
        # Fresnel zone around each reflection point lies on its face.
        size = near * _fresnel_fit(oriented, points, math.sqrt(wavelength_m * half / 2.0))
    last = points[-1]
    position = half * last / max(float(np.linalg.norm(last)), 1e-300)
    return seq, points[0], last, position, amplitude * size


def _facing(a: Reflector, b: Reflector) -> bool:
    """Whether some corner of each face lies in front of the other face.

    Beyond the edge tolerance: the two faces of a concave edge, not of a convex one.
    """
    def ahead(f: Reflector, g: Reflector) -> bool:
        corners = g.center_m + np.array([sa * g.half_size_m[0] * g.axes[0]
                                         + sb * g.half_size_m[1] * g.axes[1]
                                         for sa in (-1, 1) for sb in (-1, 1)])
        return bool(np.any((corners - f.center_m) @ f.normal > EDGE_TOLERANCE_M))

    return ahead(a, b) and ahead(b, a)


def _same_image_orders(faces: Sequence[Reflector], seq: tuple[int, ...],
                       image: NDArray[np.float64]) -> int:
    """How many orders of the faces ``seq`` give the radar the same image ``image`` (m).

    Orders with a face twice in a row do not count: a 90° edge has two, a corner six, an
    echo between facing walls one.

    Image theory of a right-angled wedge or corner (exact for perfect conductors): the
    radar's double (triple) image in its faces is one image, whichever face it is
    mirrored in first; at its edge (corner) every order's reflection points meet, each
    order carrying a share of that one image's return.
    """
    count = 0
    for order in set(itertools.permutations(seq)):
        if any(a == b for a, b in itertools.pairwise(order)):
            continue
        point = np.zeros(3)
        for i in order:
            face = _oriented(faces[i], point)
            if face is None:
                break
            point = face.mirror(point)
        else:
            count += int(np.linalg.norm(point - image) < 1e-6)
    return max(count, 1)


def _fresnel_fit(faces: Sequence[Reflector], points: Sequence[NDArray[np.float64]],
                 radius_m: float) -> float:
    """Product over the reflection points of min(1, distance to the face's border / radius)."""
    out = 1.0
    for face, x in zip(faces, points, strict=True):
        local = np.abs((x - face.center_m) @ face.axes.T)
        border = float(np.min(face.half_size_m - local))
        out *= min(1.0, max(border, 0.0) / radius_m)
    return out


def _transverse(vector: NDArray[np.complex128], direction: NDArray[np.float64]
                ) -> NDArray[np.complex128]:
    """``vector`` without its part along ``direction``, normalised (a wave's E).

    Along the polarisation itself (a V antenna's leg straight down) the antenna's
    spherical unit vector θ̂ at the pole is taken, as ray tracers' isotropic antennas do:
    the boresight direction made transverse (the element pattern, not this, decides
    whether anything is sent there).
    """
    d = direction / max(float(np.linalg.norm(direction)), 1e-300)
    out = vector - (vector @ d) * d
    norm = float(np.linalg.norm(out))
    if norm < 1e-9:
        out = np.array([0.0, 0.0, 1.0]) - d[2] * d
        norm = float(np.linalg.norm(out))
    return np.asarray(out / max(norm, 1e-300))


def reflect_field(face: Reflector, leg: NDArray[np.float64], field: NDArray[np.complex128],
                  wavelength_m: float) -> NDArray[np.complex128]:
    """The E vector of a wave along ``leg`` after its specular reflection on ``face``.

    E splits into its TE part (along ``ŝ = n × d̂``, parallel to the surface) and its TM
    part; the reflected E is ``−M (ρ_TE E_TE + ρ_TM E_TM)`` with M the face's mirror,
    ``ρ_TE = −Γ_TE`` and ``ρ_TM = Γ_TM`` (Born & Wolf signs,
    :meth:`~simcore.scene.materials.BandMaterial.oblique_coefficients`): a perfect
    conductor's image of a dipole ``p`` is ``−M p``. Times the Kirchhoff coherent factor
    of the face's rms height at the angle. A face without a band scales E by −Γ before
    the mirror (its ``gamma`` at every angle and polarisation).
    """
    d = leg / max(float(np.linalg.norm(leg)), 1e-300)
    cos_i = abs(float(d @ face.normal))
    g = 4.0 * math.pi * face.height_rms_m * cos_i / wavelength_m
    coherent = math.exp(-0.5 * g * g)
    if face.band is None:
        return coherent * complex(face.gamma) * _mirror(face, field)
    r_te, r_tm = face.band.oblique_coefficients(face.frequency_hz, np.array([cos_i]))
    s = _cross3(face.normal, d)
    norm = float(np.linalg.norm(s))
    s = s / norm if norm > 1e-9 else _transverse(np.array([1.0, 0.0, 0.0]), face.normal).real
    e_te = (field @ s) * s
    e_tm = field - e_te
    scaled = -complex(r_te[0]) * e_te + complex(r_tm[0]) * e_tm
    return -coherent * _mirror(face, scaled)


def _cross3(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.cross`` of two 3-vectors, in its order of operations (without its overhead)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _mirror(face: Reflector, vector: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """A complex vector mirrored in the face's plane."""
    out: NDArray[np.complex128] = vector - 2.0 * (vector @ face.normal) * face.normal
    return out


def _blocked(faces: Sequence[Reflector], a: NDArray[np.float64], b: NDArray[np.float64],
             skip: set[int]) -> bool:
    """Whether the leg a → b crosses any other face inside its rectangle (an obstruction)."""
    for i, face in enumerate(faces):
        if i in skip:
            continue
        s_a = float((a - face.center_m) @ face.normal)
        s_b = float((b - face.center_m) @ face.normal)
        if s_a * s_b >= 0:
            continue
        x = a + s_a / (s_a - s_b) * (b - a)
        local = (x - face.center_m) @ face.axes.T
        if np.all(np.abs(local) < face.half_size_m - EDGE_TOLERANCE_M):
            return True
    return False


def _aperture(faces: Sequence[Reflector], image: NDArray[np.float64]) -> float:
    """Geometric-optics aperture (m²) of the beam that follows ``faces`` towards ``image``.

    The faces unfolded along the path (each later face mirrored in the earlier ones),
    projected on the plane across the unfolded direction; the area of their intersection.
    """
    u = image / max(float(np.linalg.norm(image)), 1e-300)
    e1 = _cross3(u, np.array([1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0]))
    e1 /= np.linalg.norm(e1)
    e2 = _cross3(u, e1)
    polygon: NDArray[np.float64] | None = None
    mirrors: list[Reflector] = []
    for face in faces:
        corners = np.array([face.center_m + sa * face.half_size_m[0] * face.axes[0]
                            + sb * face.half_size_m[1] * face.axes[1]
                            for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
        for m in reversed(mirrors):
            corners = m.mirror(corners)
        flat = np.stack([corners @ e1, corners @ e2], axis=1)
        flat = _convex(flat)
        polygon = flat if polygon is None else _clip(polygon, flat)
        if len(polygon) < 3:
            return 0.0
        mirrors.append(face)
    assert polygon is not None
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _convex(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The four projected corners in counter-clockwise order (a parallelogram's)."""
    c = points.mean(axis=0)
    order = np.argsort(np.arctan2(points[:, 1] - c[1], points[:, 0] - c[0]))
    return points[order]


def _clip(subject: NDArray[np.float64], clip: NDArray[np.float64]) -> NDArray[np.float64]:
    """Sutherland–Hodgman: ``subject`` ∩ the convex counter-clockwise polygon ``clip``.

    On Python floats (the same IEEE operations as on numpy scalars, without their cost).
    """
    out = [(float(p[0]), float(p[1])) for p in subject]
    corners = [(float(p[0]), float(p[1])) for p in clip]
    for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
        if not out:
            break
        e0, e1 = b[0] - a[0], b[1] - a[1]
        inside = [e0 * (p[1] - a[1]) - e1 * (p[0] - a[0]) >= 0 for p in out]
        new = []
        for i, p in enumerate(out):
            q = out[i - 1]
            if inside[i]:
                if not inside[i - 1]:
                    new.append(_cross_point(q, p, a, b))
                new.append(p)
            elif inside[i - 1]:
                new.append(_cross_point(q, p, a, b))
        out = new
    return np.array(out, dtype=np.float64).reshape(-1, 2)


def _cross_point(p: tuple[float, float], q: tuple[float, float], a: tuple[float, float],
                 b: tuple[float, float]) -> tuple[float, float]:
    """Where segment p → q crosses the line through a and b."""
    d0, d1 = q[0] - p[0], q[1] - p[1]
    e0, e1 = b[0] - a[0], b[1] - a[1]
    den = d0 * e1 - d1 * e0
    if abs(den) < 1e-300:
        return p
    t = ((a[0] - p[0]) * e1 - (a[1] - p[1]) * e0) / den
    return p[0] + t * d0, p[1] + t * d1


__all__ = ["EDGE_TOLERANCE_M", "MAX_FACES", "reflect_field", "room_returns"]
