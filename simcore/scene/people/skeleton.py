"""Skeleton of a person: rigid segments with anthropometric proportions.

Segment lengths and joint heights are fractions of the standing height ``H`` from the
Drillis & Contini (1966) body-segment table as reproduced in D. A. Winter, *Biomechanics
and Motor Control of Human Movement*, 4th ed. (Wiley, 2009), Fig. 4.1:

======================  ==========  =========================================
landmark / length       fraction H  used for
======================  ==========  =========================================
top of head             1.000       head
chin                    0.870       head / neck boundary
shoulder (acromion)     0.818       neck base, shoulder joints
chest (nipple)          0.720       chest / abdomen boundary
hip (greater trochanter) 0.530      hip joints, pelvis frame
knee                    0.285       knee joints
ankle                   0.039       ankle joints
upper arm               0.186       shoulder → elbow
forearm                 0.146       elbow → wrist
hand                    0.108       wrist → fingertip
thigh                   0.245       hip → knee
shank                   0.246       knee → ankle
foot length             0.152       foot
shoulder width          0.259       shoulder joints at ± 0.259 H / 2 (less the arm radius)
hip width               0.191       hip joints at ± 0.191 H / 4
======================  ==========  =========================================

Girths (ellipsoid semi-axes across a segment) are not in that table; they are fractions
of ``H`` chosen for an average adult and scaled by ``build`` (1 = average, 0.8 slim,
1.3 heavy). Each segment is an ellipsoid; its frame has the origin at the proximal joint,
axes parallel to the body frame (x forward, y left, z up) in the rest pose (standing,
arms hanging), and the ellipsoid's centre at ``center`` in that frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: Winter (2009) Fig. 4.1 (Drillis & Contini 1966): fractions of the standing height.
WINTER_FRACTIONS: dict[str, float] = {
    "head_top": 1.000, "chin": 0.870, "shoulder": 0.818, "chest": 0.720, "hip": 0.530,
    "knee": 0.285, "ankle": 0.039, "upper_arm": 0.186, "forearm": 0.146, "hand": 0.108,
    "thigh": 0.245, "shank": 0.246, "foot": 0.152, "shoulder_width": 0.259,
    "hip_width": 0.191,
}

#: Segment names, in the order of the snapshot's segment objects (body-part id = index).
SEGMENTS: tuple[str, ...] = (
    "pelvis", "abdomen", "chest", "neck", "head",
    "upper_arm_l", "forearm_l", "hand_l", "upper_arm_r", "forearm_r", "hand_r",
    "thigh_l", "shin_l", "foot_l", "thigh_r", "shin_r", "foot_r",
)
#: Parent of each segment (index into SEGMENTS; −1 for the root).
PARENTS: tuple[int, ...] = (-1, 0, 1, 2, 3, 2, 5, 6, 2, 8, 9, 0, 11, 12, 0, 14, 15)
SEGMENT_INDEX = {name: i for i, name in enumerate(SEGMENTS)}
#: Segments worn with the clothing material (the rest are skin).
CLOTHED: frozenset[str] = frozenset({
    "pelvis", "abdomen", "chest", "upper_arm_l", "upper_arm_r", "forearm_l", "forearm_r",
    "thigh_l", "thigh_r", "shin_l", "shin_r", "foot_l", "foot_r"})


@dataclass(frozen=True)
class Skeleton:
    """Rest-pose geometry of one person.

    Attributes
    ----------
    height_m : float
        Standing height (m).
    joints : ndarray, shape (S, 3)
        Offset of each segment's proximal joint from its parent's joint, rest pose, body
        frame (m); the root's offset is its joint's height above the feet's soles.
    centers : ndarray, shape (S, 3)
        Ellipsoid centre in the segment frame (m).
    radii : ndarray, shape (S, 3)
        Ellipsoid semi-axes along the segment frame's x, y, z (m).
    lengths : dict of str to float
        Named segment lengths (m): ``upper_arm``, ``forearm``, ``hand``, ``thigh``,
        ``shank``, ``foot``, ``leg`` (thigh + shank).
    """

    height_m: float
    joints: NDArray[np.float64]
    centers: NDArray[np.float64]
    radii: NDArray[np.float64]
    lengths: dict[str, float]

    @property
    def leg_length_m(self) -> float:
        """Thigh + shank length (m), Boulic's normalising height ``H_t``."""
        return self.lengths["leg"]


def build_skeleton(height_m: float, build: float = 1.0) -> Skeleton:
    """Segments of a person of ``height_m`` (m) and ``build`` (girth scale, 1 = average).

    Examples
    --------
    >>> s = build_skeleton(1.8)
    >>> round(s.lengths["thigh"], 3), round(s.leg_length_m, 3)
    (0.441, 0.884)
    """
    h, f, b = float(height_m), WINTER_FRACTIONS, float(build)
    lengths = {k: f[k] * h for k in ("upper_arm", "forearm", "hand", "thigh", "shank", "foot")}
    lengths["leg"] = lengths["thigh"] + lengths["shank"]
    arm_r = 0.024 * h * b
    # Trunk split at fixed landmarks: pelvis [hip, 0.60], abdomen [0.60, chest], chest
    # [chest, shoulder], neck [shoulder, chin], head [chin, top].
    z_abd, z_chest = 0.600 * h, f["chest"] * h
    z_sh, z_chin = f["shoulder"] * h, f["chin"] * h
    z_hip = f["hip"] * h
    sh_y = f["shoulder_width"] * h / 2 - arm_r
    hip_y = f["hip_width"] * h / 4
    joints = np.zeros((len(SEGMENTS), 3))
    centers = np.zeros_like(joints)
    radii = np.zeros_like(joints)

    def seg(name: str, joint: tuple[float, float, float], center: tuple[float, float, float],
            radius: tuple[float, float, float]) -> None:
        i = SEGMENT_INDEX[name]
        joints[i], centers[i], radii[i] = joint, center, radius

    seg("pelvis", (0, 0, z_hip), (0, 0, 0.02 * h), (0.060 * h * b, 0.095 * h * b, 0.055 * h))
    seg("abdomen", (0, 0, z_abd - z_hip), (0, 0, (z_chest - z_abd) / 2),
        (0.060 * h * b, 0.085 * h * b, (z_chest - z_abd) / 2 + 0.03 * h))
    seg("chest", (0, 0, z_chest - z_abd), (0, 0, (z_sh - z_chest) / 2 - 0.005 * h),
        (0.062 * h * b, 0.095 * h * b, (z_sh - z_chest) / 2 + 0.03 * h))
    seg("neck", (0, 0, z_sh - z_chest), (0, 0, (z_chin - z_sh) / 2),
        (0.030 * h * b, 0.030 * h * b, (z_chin - z_sh) / 2 + 0.01 * h))
    head = (1.0 - f["chin"]) * h
    seg("head", (0, 0, z_chin - z_sh), (0.005 * h, 0, 0.45 * head),
        (0.056 * h, 0.045 * h, 0.55 * head))
    for side, sy in (("l", 1.0), ("r", -1.0)):
        ua, fa, hd = lengths["upper_arm"], lengths["forearm"], lengths["hand"]
        seg(f"upper_arm_{side}", (0, sy * sh_y, z_sh - 0.02 * h - z_chest), (0, 0, -ua / 2),
            (arm_r, arm_r, ua / 2))
        seg(f"forearm_{side}", (0, 0, -ua), (0, 0, -fa / 2),
            (0.8 * arm_r, 0.8 * arm_r, fa / 2))
        seg(f"hand_{side}", (0, 0, -fa), (0, 0, -hd / 2), (0.010 * h, 0.026 * h, hd / 2))
        th, sk, ft = lengths["thigh"], lengths["shank"], lengths["foot"]
        seg(f"thigh_{side}", (0, sy * hip_y, 0), (0, 0, -th / 2),
            (0.040 * h * b, 0.040 * h * b, th / 2))
        seg(f"shin_{side}", (0, 0, -th), (0, 0, -sk / 2), (0.028 * h * b, 0.028 * h * b, sk / 2))
        ankle = f["ankle"] * h
        seg(f"foot_{side}", (0, 0, -sk), (0.25 * ft, 0, -0.45 * ankle),
            (ft / 2, 0.028 * h, 0.55 * ankle))
    return Skeleton(height_m=h, joints=joints, centers=centers, radii=radii, lengths=lengths)


__all__ = ["CLOTHED", "PARENTS", "SEGMENTS", "SEGMENT_INDEX", "WINTER_FRACTIONS", "Skeleton",
           "build_skeleton"]
