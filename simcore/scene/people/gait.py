"""Parametric walk after Boulic, Magnenat-Thalmann & Thalmann (1990).

R. Boulic, N. Magnenat-Thalmann, D. Thalmann, "A global human walking model with
real-time kinematic personification", *The Visual Computer* 6(6), 344–358 (1990). Its
normalised relations, with the relative velocity ``RV = v / H_t`` (``H_t`` = thigh +
shank length, m) and durations in seconds:

- cycle duration ``Dc = 1.346 / sqrt(RV)`` (so the relative cycle length is
  ``RL = 1.346 sqrt(RV)``),
- support (stance) duration ``Ds = 0.752 Dc − 0.143``, swing ``Dsw = 0.248 Dc + 0.143``,
  double support ``Dds = 0.252 Dc − 0.143``,
- valid for ``RV ≤ 2.3``.

The pelvis carries the body at the mean speed with the model's forward surge and
vertical bounce (two per cycle) and lateral sway (one per cycle) (:func:`pelvis_ripple`),
rotation about the vertical and arm swing growing with ``RV``. The legs are placed by
their feet rather than by Boulic's joint-angle curves (which the paper gives as
figures, not tables): each foot is planted during support, so it does not slide, and in
swing it travels one cycle length on a raised-cosine profile (peak speed
``π / (2 (1 − Ds/Dc))`` times ``v``, about 4.3 v at 1.15 m/s), lifted on a half sine;
hip and knee angles follow from the two-link leg reaching the ankle (knee forward), so
they change with speed as the cycle length and timing do.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: Boulic et al. (1990) timing constants.
CYCLE_COEFF = 1.346
SUPPORT_SLOPE, SUPPORT_OFFSET_S = 0.752, 0.143


def cycle_duration_s(relative_speed: float) -> float:
    """Boulic's cycle duration ``1.346 / sqrt(RV)`` (s).

    Examples
    --------
    A 1.8 m person (leg 0.884 m) at 1.15 m/s:

    >>> round(cycle_duration_s(1.15 / 0.884), 2)
    1.18
    """
    return CYCLE_COEFF / float(np.sqrt(relative_speed))


def support_fraction(relative_speed: float) -> float:
    """Support duration over cycle duration, ``(0.752 Dc − 0.143) / Dc``."""
    dc = cycle_duration_s(relative_speed)
    return (SUPPORT_SLOPE * dc - SUPPORT_OFFSET_S) / dc


def raised_cosine(s: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Swing profile ``(1 − cos πs) / 2`` for ``s`` in [0, 1]."""
    return 0.5 * (1.0 - np.cos(np.pi * np.clip(s, 0.0, 1.0)))


def foot_offset(phase: float, speed_mps: float, relative_speed: float, leg_m: float
                ) -> tuple[float, float]:
    """Ankle position of a foot relative to the body's mean position (m): (forward, lift).

    ``phase`` in [0, 1): 0 at this foot's heel strike. In support the foot stays where it
    was put down (relative to the body it moves back at ``v``); in swing it moves one cycle
    length forward (world) on a raised cosine.
    """
    dc = cycle_duration_s(relative_speed)
    beta = support_fraction(relative_speed)
    reach = speed_mps * beta * dc / 2.0  # half the distance the body covers in support
    p = phase % 1.0
    if p < beta:
        return reach - speed_mps * dc * p, 0.0
    s = (p - beta) / (1.0 - beta)
    world = -reach + speed_mps * dc * float(raised_cosine(s))  # from where it lifted off
    body = speed_mps * dc * (p - beta)  # the body's own travel since lift-off
    lift = 0.10 * leg_m * float(np.sin(np.pi * s))
    return world - body, lift


def translation_amplitudes(relative_speed: float) -> tuple[float, float, float]:
    """Boulic's normalised pelvis translation amplitudes (forward, lateral, vertical).

    Multiples of the leg length ``H_t``; as tabulated from Boulic et al. (1990) by
    P. van Dorp and F. C. A. Groen, "Human walking estimation with radar", IEE Proc.
    Radar Sonar Navig. 150(5), 356–365 (2003), Table 1:

    - forward ``A_f = 0.084 RV (1 − RV)`` for ``RV < 0.5``, ``0.021`` above,
    - lateral ``A_l = 0.128 RV (1 − RV)`` for ``RV < 0.5``, ``0.032`` above,
    - vertical ``A_v = 0.015 RV``.

    (The source writes the two constants above ``RV = 0.5`` with a minus sign, which
    makes them jump at 0.5 against the quadratics; here they take the quadratics' sign,
    continuous at 0.5, which is also the sign that slows the body at mid-support and sways
    it over the supporting foot, as an inverted pendulum does.)

    Examples
    --------
    >>> [round(a, 4) for a in translation_amplitudes(1.3)]
    [0.021, 0.032, 0.0195]
    """
    rv = float(relative_speed)
    low = rv * (1.0 - rv) if rv < 0.5 else 0.25
    return 0.084 * low, 0.128 * low, 0.015 * rv


def pelvis_ripple(phase: float, relative_speed: float, leg_m: float
                  ) -> tuple[float, float, float, float]:
    """Pelvis (forward m, lateral m, vertical m, rotation about vertical rad) at ``phase``.

    Boulic's translations about the mean motion, ``phase`` = ``t`` in cycles from the left
    heel strike and ``Ds`` the support's share of the cycle
    (:func:`translation_amplitudes` for the amplitudes):

    - forward surge ``A_f H_t sin 2π(2t + 2φ)`` with ``φ = 0.625 − Ds`` (two per cycle;
      slowest near each mid-support),
    - lateral sway ``A_l H_t sin 2π(t − 0.1)`` towards the left (+y) while the left foot
      supports (one per cycle),
    - vertical ``A_v H_t (sin 2π(2t − 0.35) − 1)``: highest, at the mean hip height of
      :func:`hip_height`, near each mid-support (two per cycle);

    the pelvis turns ``±(2° + 2° RV)`` with the swinging leg.
    """
    a_f, a_l, a_v = (a * leg_m for a in translation_amplitudes(relative_speed))
    phi = 0.625 - support_fraction(relative_speed)
    surge = a_f * np.sin(2 * np.pi * (2 * phase + 2 * phi))
    lateral = a_l * np.sin(2 * np.pi * (phase - 0.1))
    bounce = a_v * (np.sin(2 * np.pi * (2 * phase - 0.35)) - 1.0)
    turn = -np.radians(2.0 + 2.0 * relative_speed) * np.cos(2 * np.pi * phase)
    return float(surge), float(lateral), float(bounce), float(turn)


def hip_height(speed_mps: float, relative_speed: float, leg_m: float, ankle_m: float) -> float:
    """Hip height (m) at the top of the bounce (the leg reaches the foot with a soft knee)."""
    dc = cycle_duration_s(relative_speed)
    reach = speed_mps * support_fraction(relative_speed) * dc / 2.0
    return ankle_m + float(np.sqrt(max((0.97 * leg_m) ** 2 - reach**2, 0.25 * leg_m**2))) \
        + 0.015 * relative_speed * leg_m


def arm_swing_rad(phase: float, relative_speed: float) -> float:
    """Left shoulder flexion (rad; the right arm's is the opposite): against the left leg."""
    amplitude = np.radians(6.0 + 8.0 * relative_speed)
    return float(-amplitude * np.cos(2 * np.pi * phase))


def two_link(hip: NDArray[np.float64], ankle: NDArray[np.float64], thigh: float, shank: float,
             forward: NDArray[np.float64]) -> NDArray[np.float64]:
    """Knee position of a leg from hip to ankle, bending towards ``forward`` (m, shape (3,)).

    An ankle out of reach is pulled in along the hip–ankle line (straight leg).
    """
    d_vec = ankle - hip
    d = float(np.linalg.norm(d_vec))
    u = d_vec / d
    d = min(max(d, abs(thigh - shank) + 1e-6), (thigh + shank) * (1 - 1e-9))
    cos_a = (thigh**2 + d**2 - shank**2) / (2 * thigh * d)
    sin_a = float(np.sqrt(max(0.0, 1.0 - cos_a**2)))
    w = forward - (forward @ u) * u
    w /= np.linalg.norm(w)
    return hip + thigh * (cos_a * u + sin_a * w)


__all__ = ["arm_swing_rad", "cycle_duration_s", "foot_offset", "hip_height", "pelvis_ripple",
           "raised_cosine", "support_fraction", "translation_amplitudes", "two_link"]
