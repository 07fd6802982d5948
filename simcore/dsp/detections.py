"""Detections of one frame as a point cloud, and the record layout of ``/radar/detections``.

A detection at range ``R``, azimuth ``az`` (positive right) and elevation ``el`` (positive
up) lies at ``R * (sin az cos el, -sin el, cos az cos el)`` in the radar's optical frame
(x right, y down, z boresight). Radial velocity is positive for targets moving away.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.angle import direction_vectors

#: Record layout of the ``/radar/detections`` table (radar optical frame, m, m/s, deg, dB),
#: with the ground-truth label of each detection: the id of the object contributing most
#: power to its cell (−1 = noise), that power fraction, whether it is a multipath ghost, and
#: for a person the body part (segment index, :data:`simcore.scene.people.SEGMENTS`; −1
#: for other objects and noise).
DETECTION_DTYPE = np.dtype([
    ("frame", "<i8"),
    ("range", "<f4"),
    ("velocity", "<f4"),
    ("azimuth_deg", "<f4"),
    ("elevation_deg", "<f4"),
    ("x", "<f4"),
    ("y", "<f4"),
    ("z", "<f4"),
    ("snr_db", "<f4"),
    ("object_id", "<i4"),
    ("power_fraction", "<f4"),
    ("ghost", "?"),
    ("body_part", "<i4"),
])

#: Units of the fields of :data:`DETECTION_DTYPE`, in field order.
DETECTION_UNITS = {
    "frame": "1", "range": "m", "velocity": "m/s", "azimuth_deg": "deg",
    "elevation_deg": "deg", "x": "m", "y": "m", "z": "m", "snr_db": "dB",
    "object_id": "1", "power_fraction": "1", "ghost": "", "body_part": "1",
}


def spherical_to_radar_xyz(
    range_m: ArrayLike, azimuth_rad: ArrayLike, elevation_rad: ArrayLike
) -> NDArray[np.float64]:
    """Points in the radar optical frame from range and angles.

    Parameters
    ----------
    range_m, azimuth_rad, elevation_rad : array_like, shape (n,)
        Range (m) and angles (rad).

    Returns
    -------
    xyz : ndarray, shape (n, 3), float64
        ``R * (sin az cos el, -sin el, cos az cos el)`` (m).
    """
    r = np.asarray(range_m, dtype=np.float64)
    return r[..., None] * direction_vectors(azimuth_rad, elevation_rad)


def transform_points(points: ArrayLike, matrix: ArrayLike) -> NDArray[np.float64]:
    """Apply a 4×4 homogeneous transform to points.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        Points (m).
    matrix : array_like, shape (4, 4)
        Source frame → target frame.

    Returns
    -------
    ndarray, shape (n, 3), float64
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    m = np.asarray(matrix, dtype=np.float64)
    if m.shape != (4, 4):
        raise ValueError(f"transform must be 4x4, got {m.shape}")
    return p @ m[:3, :3].T + m[:3, 3]


@dataclass(frozen=True)
class Detections:
    """Point cloud of one frame; every array has length ``n`` (strongest first).

    Attributes
    ----------
    doppler_index, range_index : ndarray, shape (n,), int64
        Cell of the range–Doppler map.
    range_m : ndarray, shape (n,), float64
        Range (m), sub-bin interpolated when enabled.
    velocity_mps : ndarray, shape (n,), float64
        Radial velocity (m/s), positive = moving away.
    azimuth_deg, elevation_deg : ndarray, shape (n,), float64
        Angles (deg): azimuth positive right, elevation positive up.
    snr_db : ndarray, shape (n,), float64
        Cell power over the CFAR noise estimate (dB).
    power_db : ndarray, shape (n,), float64
        Cell power of the range–Doppler map (dB).
    xyz_radar_m : ndarray, shape (n, 3), float64
        Position in the radar optical frame (x right, y down, z boresight; m).
    xyz_world_m : ndarray, shape (n, 3), float64, or None
        Position in the world frame, when a radar → world transform was given.
    """

    doppler_index: NDArray[np.int64]
    range_index: NDArray[np.int64]
    range_m: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    azimuth_deg: NDArray[np.float64]
    elevation_deg: NDArray[np.float64]
    snr_db: NDArray[np.float64]
    power_db: NDArray[np.float64]
    xyz_radar_m: NDArray[np.float64]
    xyz_world_m: NDArray[np.float64] | None = None

    def __len__(self) -> int:
        return int(self.range_m.size)

    @classmethod
    def empty(cls, *, with_world: bool = False) -> Detections:
        """A point cloud with no points."""
        z = np.zeros(0)
        i = np.zeros(0, dtype=np.int64)
        return cls(i, i.copy(), z, z.copy(), z.copy(), z.copy(), z.copy(), z.copy(),
                   np.zeros((0, 3)), np.zeros((0, 3)) if with_world else None)

    def records(self, frame: int) -> NDArray[np.void]:
        """The detections as rows of the ``/radar/detections`` table.

        Parameters
        ----------
        frame : int
            Frame index written into the ``frame`` field.

        Returns
        -------
        ndarray, shape (n,), dtype :data:`DETECTION_DTYPE`
            Radar-frame coordinates; the label fields hold "unlabelled" (``object_id`` −1,
        ``power_fraction`` 0, ``ghost`` False, ``body_part`` −1) until the radar sensor
        fills them in.
        """
        out = np.zeros(len(self), dtype=DETECTION_DTYPE)
        out["frame"] = frame
        out["body_part"] = -1
        out["range"] = self.range_m
        out["velocity"] = self.velocity_mps
        out["azimuth_deg"] = self.azimuth_deg
        out["elevation_deg"] = self.elevation_deg
        out["x"] = self.xyz_radar_m[:, 0]
        out["y"] = self.xyz_radar_m[:, 1]
        out["z"] = self.xyz_radar_m[:, 2]
        out["snr_db"] = self.snr_db
        out["object_id"] = -1
        return out
