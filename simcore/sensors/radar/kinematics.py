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
        The radar's optical frame (``snapshot.sensors["radar"]``).

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
    vel_m, vel_c, acc_m, acc_c = motion_maps(body, rig, radar)
    local = (x - radar.position) @ radar.rotation
    return local, local @ vel_m.T + vel_c, local @ acc_m.T + acc_c


def motion_maps(body: RigidState, rig: RigidState, radar: SensorState
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                           NDArray[np.float64]]:
    """Affine maps from radar-frame position to relative velocity and acceleration.

    For points fixed to ``body``, ``ẋ = M_v x + c_v`` and ``ẍ = M_a x + c_a`` with ``x`` in
    the radar optical frame (cross products with the constant angular velocities are 3×3
    matrices; see the module docstring). One body of :func:`motion_maps_batch`.

    Returns
    -------
    m_v : ndarray, shape (3, 3)
        1/s.
    c_v : ndarray, shape (3,)
        m/s.
    m_a : ndarray, shape (3, 3)
        1/s².
    c_a : ndarray, shape (3,)
        m/s².
    """
    m_v, c_v, m_a, c_a = motion_maps_batch(
        np.asarray(body.angular_velocity_rps, dtype=np.float64).reshape(1, 3),
        np.asarray(body.velocity_mps, dtype=np.float64).reshape(1, 3),
        np.asarray(body.origin, dtype=np.float64).reshape(1, 3), rig, radar)
    return m_v[0], c_v[0], m_a[0], c_a[0]


def motion_maps_batch(angular_velocity_rps: NDArray[np.float64],
                      velocity_mps: NDArray[np.float64], origin: NDArray[np.float64],
                      rig: RigidState, radar: SensorState
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                                 NDArray[np.float64]]:
    """:func:`motion_maps` of ``G`` bodies at once (an articulated person's segments).

    Parameters
    ----------
    angular_velocity_rps, velocity_mps, origin : ndarray, shape (G, 3)
        Each body's angular velocity (rad/s) about its origin, the origin's velocity (m/s)
        and the origin (m), world frame.
    rig, radar : RigidState, SensorState
        As for :func:`motion_maps`.

    Returns
    -------
    m_v, c_v, m_a, c_a : ndarray, shapes (G, 3, 3), (G, 3), (G, 3, 3), (G, 3)
        The maps of each body (units as for :func:`motion_maps`).
    """
    w_b = _skew_batch(angular_velocity_rps)                        # (G, 3, 3)
    o_b = origin[..., None]                                        # (G, 3, 1)
    w = _skew(rig.angular_velocity_rps)
    s = radar.position
    arm_s = s - rig.origin
    s_dot = rig.velocity_mps + w @ arm_s
    s_ddot = w @ (w @ arm_s)
    # In world coordinates, as functions of the world point X (D = X − s):
    # Ḋ = W_b (X − o_b) + v_b − ṡ,   D̈ = W_b² (X − o_b) − s̈,
    # ẋ = Rᵀ (Ḋ − W D),   ẍ = Rᵀ (D̈ − 2 W Ḋ + W² D).
    w_b2 = w_b @ w_b
    d_dot_c = velocity_mps - (w_b @ o_b)[..., 0] - s_dot           # (G, 3)
    d_ddot_c = -(w_b2 @ o_b)[..., 0] - s_ddot
    vel_m, vel_c = w_b - w, d_dot_c + w @ s
    acc_m = w_b2 - 2.0 * (w @ w_b) + w @ w
    acc_c = d_ddot_c - 2.0 * (d_dot_c @ w.T) - (w @ w) @ s
    # X = R x + s:  M X + c = (M R) x + (M s + c), then into the radar frame with Rᵀ.
    rot = radar.rotation
    return (rot.T @ vel_m @ rot, (vel_m @ s + vel_c) @ rot,
            rot.T @ acc_m @ rot, (acc_m @ s + acc_c) @ rot)


def _skew_batch(w: NDArray[np.float64]) -> NDArray[np.float64]:
    """Matrices ``[w]×`` of the rows of ``w`` (G, 3), shape (G, 3, 3)."""
    out = np.zeros((len(w), 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -w[:, 2], w[:, 1]
    out[:, 1, 0], out[:, 1, 2] = w[:, 2], -w[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -w[:, 1], w[:, 0]
    return out


def _skew(w: NDArray[np.floating]) -> NDArray[np.float64]:
    """Matrix ``[w]×`` with ``[w]× v = w × v``."""
    wx, wy, wz = (float(c) for c in np.asarray(w, dtype=np.float64))
    return np.array([[0.0, -wz, wy], [wz, 0.0, -wx], [-wy, wx, 0.0]])


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


__all__ = ["Trajectory", "motion_maps", "motion_maps_batch", "radar_frame_trajectory",
           "rigid_point_motion"]
