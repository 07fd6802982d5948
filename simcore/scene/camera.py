"""Pinhole intrinsics and per-pixel ray geometry (optical frame: x right, y down, z forward)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class PinholeIntrinsics:
    """Pinhole camera with square or non-square pixels.

    Pixel ``(row, col)`` has its centre at image coordinates ``u = col + 0.5``,
    ``v = row + 0.5``; a point ``(x, y, z)`` in the optical frame projects to
    ``u = fx x / z + cx``, ``v = fy y / z + cy``.
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @classmethod
    def from_fov(cls, width: int, height: int, fov_h_deg: float, fov_v_deg: float | None = None
                 ) -> PinholeIntrinsics:
        """Intrinsics spanning the given full fields of view (square pixels if no ``fov_v``).

        Examples
        --------
        A 90° horizontal field of view over 4 pixels puts the focal length at 2 pixels:

        >>> k = PinholeIntrinsics.from_fov(4, 2, 90.0)
        >>> round(k.fx, 9), round(k.fy, 9), k.cx, k.cy
        (2.0, 2.0, 2.0, 1.0)
        >>> round(k.fov_v_deg, 3)
        53.13
        """
        fx = 0.5 * width / np.tan(np.deg2rad(fov_h_deg) / 2)
        fy = fx if fov_v_deg is None else 0.5 * height / np.tan(np.deg2rad(fov_v_deg) / 2)
        return cls(width, height, float(fx), float(fy), width / 2.0, height / 2.0)

    @property
    def fov_h_deg(self) -> float:
        """Full horizontal field of view (degrees)."""
        return float(np.rad2deg(2 * np.arctan(0.5 * self.width / self.fx)))

    @property
    def fov_v_deg(self) -> float:
        """Full vertical field of view (degrees)."""
        return float(np.rad2deg(2 * np.arctan(0.5 * self.height / self.fy)))

    def scaled(self, factor: int) -> PinholeIntrinsics:
        """Intrinsics of the same field of view with ``factor``× more pixels per axis.

        Examples
        --------
        >>> k = PinholeIntrinsics.from_fov(4, 2, 90.0).scaled(3)
        >>> k.width, k.height, round(k.fx, 9), k.cx, k.cy, round(k.fov_h_deg, 9)
        (12, 6, 6.0, 6.0, 3.0, 90.0)
        """
        return PinholeIntrinsics(self.width * factor, self.height * factor, self.fx * factor,
                                 self.fy * factor, self.cx * factor, self.cy * factor)

    def ray_directions(self) -> NDArray[np.float64]:
        """Un-normalised ray directions ``(x/z, y/z, 1)`` per pixel, shape (H, W, 3).

        Examples
        --------
        >>> PinholeIntrinsics.from_fov(4, 2, 90.0).ray_directions()[0]
        array([[-0.75, -0.25,  1.  ],
               [-0.25, -0.25,  1.  ],
               [ 0.25, -0.25,  1.  ],
               [ 0.75, -0.25,  1.  ]])
        """
        u = (np.arange(self.width) + 0.5 - self.cx) / self.fx
        v = (np.arange(self.height) + 0.5 - self.cy) / self.fy
        rays = np.empty((self.height, self.width, 3))
        rays[..., 0] = u[None, :]
        rays[..., 1] = v[:, None]
        rays[..., 2] = 1.0
        return rays

    def pixel_solid_angle(self) -> NDArray[np.float64]:
        """Solid angle of each pixel (sr), shape (H, W): ``cos³(off-axis) / (fx fy)``.

        Examples
        --------
        The pixels of a 90° × 90° view add up to its solid angle, 2π/3 sr:

        >>> omega = PinholeIntrinsics.from_fov(400, 400, 90.0).pixel_solid_angle()
        >>> round(float(omega.sum()), 3), round(2 * np.pi / 3, 3)
        (2.094, 2.094)
        """
        rays = self.ray_directions()
        cos_axis = 1.0 / np.linalg.norm(rays, axis=-1)
        return cos_axis**3 / (self.fx * self.fy)

    def project(self, points: NDArray[np.floating]) -> NDArray[np.float64]:
        """Project optical-frame points, shape (..., 3), to image coordinates (..., 2).

        Examples
        --------
        >>> k = PinholeIntrinsics.from_fov(4, 2, 90.0)
        >>> k.project(np.array([[0.0, 0.0, 2.0], [1.0, 0.5, 2.0]]))
        array([[2. , 1. ],
               [3. , 1.5]])
        """
        p = np.asarray(points, dtype=np.float64)
        return np.stack(
            [self.fx * p[..., 0] / p[..., 2] + self.cx, self.fy * p[..., 1] / p[..., 2] + self.cy],
            axis=-1,
        )
