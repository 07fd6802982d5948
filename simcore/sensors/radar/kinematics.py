"""Motion of points fixed to a rigid body, seen from the (moving, turning) radar.

A world point ``X`` fixed to a body moves with the body's velocity ``v_b`` and angular
velocity ``ω_b`` (world frame, about the body's origin ``o_b``); the radar's optical frame
has origin ``s`` and rotation ``R`` (optical → world) and turns with the rig's angular
velocity ``ω``. With ``D = X − s`` the point in the radar frame is ``x = Rᵀ D`` and, for
velocities and angular velocities that are constant over the frame (constant-velocity
motion, or one segment of a keyframed path),

    ẋ = Rᵀ (Ḋ − ω × D)
    ẍ = Rᵀ (D̈ − 2 ω × Ḋ + ω × (ω × D))

with ``Ḋ = v_b + ω_b × (X − o_b) − ṡ`` and ``D̈ = ω_b × (ω_b × (X − o_b)) − s̈``, where the
radar's origin moves with the rig: ``ṡ = v_rig + ω × (s − o_rig)``,
``s̈ = ω × (ω × (s − o_rig))``. A turning rig therefore gives static points both a
velocity and an acceleration relative to the radar.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from simcore.scene.motion import RigidState
from simcore.scene.snapshot import SensorState


def rigid_point_motion(points_world: NDArray[np.floating], body: RigidState,
                       rig: RigidState, radar: SensorState
                       ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Radar-frame position, velocity and acceleration of world points fixed to a body.

    Parameters
    ----------
    points_world : ndarray, shape (M, 3)
        Points at the snapshot time, world frame (m), rigidly attached to ``body``.
    body : RigidState
        The body's state (``snapshot.objects[i]``).
    rig : RigidState
        The sensor rig's state (``snapshot.rig``).
    radar : SensorState
        The radar's optical frame (``snapshot.radar``).

    Returns
    -------
    positions : ndarray, shape (M, 3)
        Radar optical frame (m).
    velocities : ndarray, shape (M, 3)
        Relative velocities, radar optical frame (m/s).
    accelerations : ndarray, shape (M, 3)
        Relative accelerations, radar optical frame (m/s²).
    """
    x = np.asarray(points_world, dtype=np.float64).reshape(-1, 3)
    w_b = np.asarray(body.angular_velocity_rps, dtype=np.float64)
    w = np.asarray(rig.angular_velocity_rps, dtype=np.float64)
    s = radar.position
    arm_s = s - rig.origin
    s_dot = rig.velocity_mps + np.cross(w, arm_s)
    s_ddot = np.cross(w, np.cross(w, arm_s))
    arm = x - body.origin
    d = x - s
    d_dot = body.velocity_mps + np.cross(w_b, arm) - s_dot
    d_ddot = np.cross(w_b, np.cross(w_b, arm)) - s_ddot
    rot = radar.rotation
    vel = (d_dot - np.cross(w, d)) @ rot
    acc = (d_ddot - 2.0 * np.cross(w, d_dot) + np.cross(w, np.cross(w, d))) @ rot
    return d @ rot, vel, acc


Trajectory = Callable[[NDArray[np.floating]], NDArray[np.float64]]


def radar_frame_trajectory(points_world: NDArray[np.floating],
                           body_at: Callable[[float], RigidState],
                           radar_at: Callable[[float], SensorState]) -> Trajectory:
    """Exact trajectory ``times → positions`` of body-fixed points in the radar frame.

    Parameters
    ----------
    points_world : ndarray, shape (M, 3)
        Points at ``t = 0`` of the callables, world frame (m).
    body_at, radar_at : callable
        ``t → RigidState`` of the body and ``t → SensorState`` of the radar, ``t`` in seconds
        from the frame start (e.g. ``lambda t: take_snapshot(project, t0 + t).objects[i]``).

    Returns
    -------
    callable
        ``times_s (T,) → positions (M, T, 3)`` in the radar optical frame at each time (m);
        the ``trajectory`` argument of the synthesis functions.
    """
    x0 = np.asarray(points_world, dtype=np.float64).reshape(-1, 3)
    body0 = body_at(0.0)
    local = (x0 - body0.origin) @ body0.transform[:3, :3]

    def trajectory(times_s: NDArray[np.floating]) -> NDArray[np.float64]:
        times = np.asarray(times_s, dtype=np.float64).reshape(-1)
        out = np.empty((len(x0), len(times), 3))
        for j, t in enumerate(times):
            b = body_at(float(t))
            r = radar_at(float(t))
            world = local @ b.transform[:3, :3].T + b.origin
            out[:, j] = (world - r.position) @ r.rotation
        return out

    return trajectory


__all__ = ["Trajectory", "radar_frame_trajectory", "rigid_point_motion"]
