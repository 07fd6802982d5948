"""Planar reflectors and ghost sets: what the image method and the room's paths share.

A :class:`Reflector` is one planar face that reflects specularly (its rectangle, normal,
material and motion, in the radar optical frame); a :class:`GhostSet` is the ghost
scatterers of one kind of path with the antenna positions to synthesise them.
:mod:`simcore.sensors.radar.multipath` (targets' ghosts) and
:mod:`simcore.sensors.radar.room` (the room's own multiple bounces) both build on this
module and not on each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.materials import BandMaterial
from simcore.sensors.radar.scatterers import Scatterers

#: A target nearer to the plane than this (m), or behind it, has no image path.
MIN_DISTANCE_M = 1e-3


@dataclass(frozen=True)
class Reflector:
    """One planar specular reflector (a rectangle), in the radar optical frame.

    Attributes
    ----------
    object_index : int
        Index of its object in the scene's objects.
    center_m : ndarray, shape (3,)
        Rectangle centre (m).
    axes : ndarray, shape (2, 3)
        Unit in-plane edge directions.
    half_size_m : ndarray, shape (2,)
        Half extents along ``axes`` (m).
    normal : ndarray, shape (3,)
        Unit normal of the reflecting side (outward for a box face).
    two_sided : bool
        Reflects on both sides (a ``Plane``).
    gamma : complex
        Normal-incidence reflection coefficient of the material (metal −1).
    height_rms_m : float
        Rms surface height of the material (m).
    normal_speed_mps : float
        Speed of the plane along ``normal`` relative to the radar (m/s).
    band : BandMaterial or None
        The material's radar band (Fresnel TE/TM at the path's angle,
        :func:`polarised_reflection`); None: ``gamma`` at every angle.
    frequency_hz : float
        Carrier frequency the coefficients are evaluated at (Hz).
    """

    object_index: int
    center_m: NDArray[np.float64]
    axes: NDArray[np.float64]
    half_size_m: NDArray[np.float64]
    normal: NDArray[np.float64]
    two_sided: bool
    gamma: complex
    height_rms_m: float
    normal_speed_mps: float
    band: BandMaterial | None = None
    frequency_hz: float = 0.0

    def mirror(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Mirror images of ``points`` (..., 3) in the reflector's plane."""
        s = (points - self.center_m) @ self.normal
        return np.asarray(points - 2.0 * s[..., None] * self.normal)

    def mirror_vectors(self, vectors: NDArray[np.float64]) -> NDArray[np.float64]:
        """Mirror free vectors (..., 3) (velocities, accelerations) in the plane."""
        return np.asarray(vectors - 2.0 * (vectors @ self.normal)[..., None] * self.normal)


def polarization_vector(polarization: str) -> NDArray[np.float64]:
    """The antennas' E-field direction on boresight, radar optical frame (V: board y, H: x)."""
    return np.array([0.0, 1.0, 0.0]) if polarization == "V" else np.array([1.0, 0.0, 0.0])


def antenna_fields(polarization: NDArray[np.float64], directions: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """The antennas' unit E towards each direction (K, 3), radar optical frame.

    ``polarization``: the E direction on boresight (:func:`polarization_vector`), in the
    board plane. Ludwig's second definition about the board's y axis, the polarised
    element of 3GPP TR 38.901 §7.3.2 (model 2; Sionna RT's ``"V"`` and ``"H"``): V is
    ``θ̂`` about board y, ``v̂ = (ŷ − (ŷ·d̂) d̂)/|…|`` (a y dipole's E), H is ``φ̂`` about it,
    ``ĥ = ŷ × d̂/|…| = v̂ × d̂`` (E ⊥ board y in every direction, not an x dipole's E); a
    slant polarisation ``p`` is ``p_y v̂ + p_x ĥ``. V and H are orthogonal in every
    direction (an x dipole's E is not orthogonal to V off the principal planes, and tilts
    39° out of the board's horizontal towards 65° right, 22° down). Along ±y (the pole)
    ``v̂`` is boresight made transverse.
    """
    d = directions / np.maximum(np.linalg.norm(directions, axis=1, keepdims=True), 1e-300)
    v = -d[:, 1:2] * d
    v[:, 1] += 1.0
    norm = np.linalg.norm(v, axis=1)
    pole = norm < 1e-9
    v[pole] = np.array([0.0, 0.0, 1.0]) - d[pole, 2:3] * d[pole]
    v /= np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)
    h = np.cross(v, d)
    out = float(polarization[1]) * v + float(polarization[0]) * h
    return np.asarray(out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300))


def antenna_field(polarization: NDArray[np.float64], direction: NDArray[np.float64]
                  ) -> NDArray[np.float64]:
    """:func:`antenna_fields` for one direction (3,), without array overhead (a room path)."""
    norm = math.sqrt(float(direction[0]) ** 2 + float(direction[1]) ** 2
                     + float(direction[2]) ** 2)
    dx, dy, dz = (float(direction[0]) / norm, float(direction[1]) / norm,
                  float(direction[2]) / norm)
    vx, vy, vz = -dy * dx, 1.0 - dy * dy, -dy * dz
    size = math.sqrt(vx * vx + vy * vy + vz * vz)
    if size < 1e-9:                                      # along ±y: boresight transverse
        vx, vy, vz = -dz * dx, -dz * dy, 1.0 - dz * dz
        size = math.sqrt(vx * vx + vy * vy + vz * vz)
    vx, vy, vz = vx / size, vy / size, vz / size
    hx, hy, hz = vy * dz - vz * dy, vz * dx - vx * dz, vx * dy - vy * dx
    p_v, p_h = float(polarization[1]), float(polarization[0])
    ex, ey, ez = p_v * vx + p_h * hx, p_v * vy + p_h * hy, p_v * vz + p_h * hz
    size = max(math.sqrt(ex * ex + ey * ey + ez * ez), 1e-300)
    return np.array([ex / size, ey / size, ez / size])


def copolar_fields(polarization: NDArray[np.float64], directions: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """The co-polar unit vector of a wave along each direction (K, 3), at a target.

    :func:`antenna_fields` turned to the side of ``polarization`` (``ê · p ≥ 0``), so the
    same for a wave and for one in the opposite direction: ``φ̂`` reverses with the
    direction, and a point target's co-polar part taken on it would flip the sign of a
    wave coming back towards the radar (H off a front wall near normal incidence came out
    ``−Γ`` where V gives ``Γ``; at normal incidence the two are the same wave). V's ``θ̂``
    needs no turn. On the direction from the radar to a target ahead it is the antennas' E.
    """
    e = antenna_fields(polarization, directions)
    return np.asarray(np.where((e @ polarization)[:, None] < 0.0, -e, e))


def _reflector_seen(buffers: RenderBuffers, points: NDArray[np.float64], object_index: int
                    ) -> NDArray[np.bool_]:
    """Whether the render shows the reflector at each point (outside the render: True)."""
    intr = buffers.intrinsics
    out = np.ones(len(points), dtype=bool)
    front = points[:, 2] > 0
    if not np.any(front):
        return out
    uv = intr.project(points[front])
    col = np.floor(uv[:, 0]).astype(np.int64)
    row = np.floor(uv[:, 1]).astype(np.int64)
    within = (col >= 0) & (col < intr.width) & (row >= 0) & (row < intr.height)
    seen = np.ones(len(uv), dtype=bool)
    seen[within] = buffers.object_index[row[within], col[within]] == object_index
    out[front] = seen
    return out


@dataclass(frozen=True)
class GhostSet:
    """Ghost scatterers of one kind of path, with the antenna positions to synthesise them.

    ``tx_positions_m`` / ``rx_positions_m`` None = the configuration's (real) antennas.
    ``order`` is 1 or 2, ``reflector`` the object index of the reflector.
    """

    scatterers: Scatterers
    order: int
    reflector: int
    tx_positions_m: NDArray[np.float64] | None = None
    rx_positions_m: NDArray[np.float64] | None = None
