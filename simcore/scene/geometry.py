"""Geometry of scene objects: analytic primitives and imported meshes.

All primitives are centred on the object's local origin. Local axes: a box spans
``±size/2`` on each axis; a cylinder's axis is local z; a plane lies in the local x–y
plane with normal +z; a trihedral corner reflector has its apex at the origin, its three
mutually perpendicular triangular plates with inner edge length ``edge_m``, and its
symmetry axis (direction of maximum return) along local +z; a point target has no surface
(radar only, radiating its given RCS from the origin); an ellipsoid has semi-axes
``radii_m`` along the local axes; a person (:mod:`simcore.scene.people`) stands on the
origin facing local +x and is simulated as rigid ellipsoid segments.
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, field_validator

from simcore.scene.base import Model, Size, Size3, check_name
from simcore.scene.people.config import Person


class Box(Model):
    """Axis-aligned box centred on the origin."""

    kind: Literal["box"] = "box"
    size_m: Size3 = (1.0, 1.0, 1.0)


class Sphere(Model):
    """Sphere centred on the origin."""

    kind: Literal["sphere"] = "sphere"
    radius_m: Size = 0.5


class Cylinder(Model):
    """Closed cylinder along local z, centred on the origin."""

    kind: Literal["cylinder"] = "cylinder"
    radius_m: Size = 0.25
    height_m: Size = 1.0


class Ellipsoid(Model):
    """Ellipsoid centred on the origin with semi-axes along local x, y, z."""

    kind: Literal["ellipsoid"] = "ellipsoid"
    radii_m: Size3 = (0.1, 0.1, 0.1)


class Plane(Model):
    """Rectangle in the local x–y plane, normal +z (seen from both sides)."""

    kind: Literal["plane"] = "plane"
    size_m: tuple[Size, Size] = (1.0, 1.0)


class CornerReflector(Model):
    """Trihedral corner reflector, apex at the origin, opening towards local +z."""

    kind: Literal["corner_reflector"] = "corner_reflector"
    edge_m: Size = 0.1

    def rcs_m2(self, wavelength_m: float) -> float:
        """Peak RCS of a triangular trihedral, 4πa⁴/(3λ²) (m²)."""
        return 4.0 * np.pi * self.edge_m**4 / (3.0 * wavelength_m**2)


class PointTarget(Model):
    """Radar point scatterer of fixed RCS at the origin (invisible to the ToF camera)."""

    kind: Literal["point_target"] = "point_target"
    rcs_m2: float = Field(1.0, ge=1e-12, le=1e6, allow_inf_nan=False)


class Mesh(Model):
    """Triangle mesh read from an STL, OBJ or PLY file (path relative to the project file)."""

    kind: Literal["mesh"] = "mesh"
    path: str = Field(min_length=1, max_length=4096)
    scale: float = Field(1.0, ge=1e-6, le=1e6, allow_inf_nan=False)

    @field_validator("path")
    @classmethod
    def _printable(cls, path: str) -> str:
        return check_name(path, "path")


Geometry = Annotated[
    Union[Box, Sphere, Cylinder, Plane, CornerReflector, PointTarget, Mesh, Ellipsoid, Person],
    Field(discriminator="kind"),
]

MESH_SUFFIXES = (".stl", ".obj", ".ply")


def corner_reflector_axes() -> NDArray[np.float64]:
    """Unit edge directions (rows) of the trihedral, symmetric about local +z.

    Returns
    -------
    ndarray, shape (3, 3)
        Three orthonormal edge directions whose sum points along +z.
    """
    # Rotate the coordinate axes so that (1, 1, 1)/sqrt(3) maps onto +z.
    a = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(a, z)
    s, c = np.linalg.norm(v), float(a @ z)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rot = np.eye(3) + vx + vx @ vx * ((1 - c) / s**2)
    return (rot @ np.eye(3)).T
