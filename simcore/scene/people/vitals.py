"""Breathing, heartbeat and body sway as small rigid displacements.

Breathing and heartbeat move the chest segment along its outward normal (the chest
frame's +x) by ``d(t) = A_b sin(2π f_b t) + A_h sin(2π f_h t)`` (the abdomen with the
same breathing term); the amplitudes are peak displacements from the mean. Sway is a
slow random drift of the whole body (sum of three sines below 0.1 Hz with phases drawn
from the project seed and the object id), so it stays below the breathing band.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simcore.scene.people.config import VitalSigns

#: Sway frequencies (Hz): below any breathing rate of a person at rest.
SWAY_FREQUENCIES_HZ = (0.031, 0.053, 0.079)


def breathing_m(vitals: VitalSigns | None, t: float) -> float:
    """Breathing part of the chest-wall displacement at ``t`` (m, + outwards)."""
    if vitals is None:
        return 0.0
    return 1e-3 * vitals.breathing_amplitude_mm * float(
        np.sin(2 * np.pi * vitals.breathing_rate_hz * t))


def heartbeat_m(vitals: VitalSigns | None, t: float) -> float:
    """Heartbeat part of the chest-wall displacement at ``t`` (m, + outwards)."""
    if vitals is None:
        return 0.0
    return 1e-3 * vitals.heart_amplitude_mm * float(np.sin(2 * np.pi * vitals.heart_rate_hz * t))


def sway_phases(seed: int, object_id: int) -> NDArray[np.float64]:
    """Random phases (rad) of the sway sines, shape (2, 3): x and y."""
    rng = np.random.default_rng([int(seed), int(object_id), 0x5A7])
    return rng.uniform(0.0, 2 * np.pi, size=(2, len(SWAY_FREQUENCIES_HZ)))


def sway_m(amplitude_mm: float, phases: NDArray[np.float64], t: float) -> NDArray[np.float64]:
    """Horizontal sway offset of the body at ``t`` (m), shape (3,), peak ≤ ``amplitude_mm``."""
    f = np.asarray(SWAY_FREQUENCIES_HZ)
    xy = np.sin(2 * np.pi * f * t + phases).sum(axis=1) / len(f)
    return np.array([xy[0], xy[1], 0.0]) * 1e-3 * amplitude_mm


__all__ = ["SWAY_FREQUENCIES_HZ", "breathing_m", "heartbeat_m", "sway_m", "sway_phases"]
