"""Hand gestures as arm joint-angle curves.

Each gesture is one repetition's curve of the arm's angles over a phase ``u`` in [0, 1):
shoulder flexion (forward raise), abduction (sideways raise), horizontal rotation (about
the vertical, positive towards the body's left) and elbow flexion (forward bend) and
elbow side bend (towards the body's outside), all in degrees. The arm blends in from and
back to the posture's arm over ``RAMP_S`` at the start and end of the gesture.
"""

from __future__ import annotations

import numpy as np

from simcore.scene.people.config import Gesture

#: Blend time into and out of a gesture (s).
RAMP_S = 0.3

ArmAngles = tuple[float, float, float, float, float]  # flex, abd, horiz, elbow, elbow_side


def _sweep(u: float) -> float:
    """0 → 1 over u ∈ [0, 0.6) (the stroke), 1 → 0 over [0.6, 1) (the return)."""
    if u < 0.6:
        return 0.5 * (1 - np.cos(np.pi * u / 0.6))
    return 0.5 * (1 + np.cos(np.pi * (u - 0.6) / 0.4))


def gesture_angles(kind: str, u: float, side: float) -> ArmAngles:
    """Arm angles (deg) of gesture ``kind`` at phase ``u``; ``side`` +1 left arm, −1 right.

    Horizontal rotation is returned for the body (positive = towards the left).
    """
    if kind == "wave":  # upper arm out sideways, forearm up, swinging side to side
        return 10.0, 80.0, 0.0, 0.0, 90.0 + 25.0 * np.sin(2 * np.pi * u)
    if kind in ("swipe_left", "swipe_right"):
        direction = 1.0 if kind == "swipe_left" else -1.0
        horiz = direction * (-35.0 + 70.0 * _sweep(u))
        return 80.0, 0.0, horiz, 20.0, 0.0
    if kind in ("push", "pull"):
        s = _sweep(u)
        elbow = 100.0 - 90.0 * s if kind == "push" else 10.0 + 90.0 * s
        return 75.0, 0.0, -side * 10.0, elbow, 0.0
    if kind == "circle":
        return (70.0 + 20.0 * np.sin(2 * np.pi * u), 20.0 + 20.0 * np.cos(2 * np.pi * u),
                -side * 10.0, 15.0, 0.0)
    raise ValueError(f"unknown gesture {kind!r}")


def gesture_weight_phase(gesture: Gesture, t: float) -> tuple[float, float]:
    """(blend weight 0…1, phase within the current repetition) of a gesture at ``t`` (s)."""
    local = t - gesture.start_s
    if local < 0 or local > gesture.duration_s:
        return 0.0, 0.0
    ramp = min(RAMP_S, gesture.duration_s / 4)
    w = min(1.0, local / ramp, (gesture.duration_s - local) / ramp)
    w = 0.5 * (1 - np.cos(np.pi * w))
    rep = gesture.duration_s / gesture.repetitions
    return float(w), (local % rep) / rep


__all__ = ["RAMP_S", "gesture_angles", "gesture_weight_phase"]
