"""The asset scene model shared by the glTF and OBJ readers.

:class:`AssetScene` (objects with poses and triangles, materials), :class:`AssetError`,
and the helpers both readers use to name and place objects. :mod:`simcore.scene.assets`
(glTF, and the entry point) and :mod:`simcore.scene.asset_obj` (OBJ) both import this
module and not each other.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from simcore.scene.base import MAX_COORDINATE_M
from simcore.scene.limits import MAX_ASSET_OBJECTS
from simcore.scene.mesh_files import MAX_MESH_COORDINATE, MeshError, check_mesh_arrays
from simcore.scene.motion import Pose

#: Longest object or material name kept from an asset (characters).
MAX_ASSET_NAME = 200
#: Name of the material of primitives that have none.
NO_MATERIAL = "(no material)"
#: glTF (Y up) → project (Z up): (x, y, z) → (x, −z, y).
Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


class AssetError(ValueError):
    """An asset file cannot be imported: unreadable, malformed or over a limit."""


@dataclass(frozen=True)
class AssetMaterial:
    """A material of an asset: its name and the PBR factors the file sets explicitly.

    Attributes
    ----------
    name : str
        Material name in the asset (:data:`NO_MATERIAL` for primitives without one).
    metallic : float or None
        glTF ``metallicFactor`` when the file sets it, else ``None``.
    roughness : float or None
        glTF ``roughnessFactor`` (perceptual roughness, 0…1) when set, else ``None``.
    color_rgb : tuple of float or None
        Linear base colour factor (RGB) when set.
    """

    name: str
    metallic: float | None = None
    roughness: float | None = None
    color_rgb: tuple[float, float, float] | None = None


@dataclass(frozen=True)
class AssetObject:
    """One mesh node of an asset, in project coordinates.

    Attributes
    ----------
    name : str
        Unique object name (the node name, made unique).
    material : str
        Asset material name.
    pose : Pose
        Rigid world pose of the node (m, degrees), z up.
    points : ndarray, shape (points, 3)
        Vertices in the object's local frame (m): the node's scale and shear baked in, so
        that ``pose.matrix() @ [p, 1]`` is the world position.
    triangles : ndarray, shape (triangles, 3), int64
        Vertex indices, counter-clockwise seen from outside.
    """

    name: str
    material: str
    pose: Pose
    points: NDArray[np.float64]
    triangles: NDArray[np.int64]

    def world_points(self) -> NDArray[np.float64]:
        """Vertices in world coordinates, shape (points, 3) (m)."""
        m = self.pose.matrix()
        return np.asarray(self.points @ m[:3, :3].T + m[:3, 3], dtype=np.float64)


@dataclass
class AssetScene:
    """Objects and materials read from one asset file."""

    source: Path
    objects: list[AssetObject] = field(default_factory=list)
    materials: dict[str, AssetMaterial] = field(default_factory=dict)
    skipped: list[str] = field(default_factory=list)

    @property
    def n_triangles(self) -> int:
        """Total triangle count of the objects."""
        return int(sum(len(o.triangles) for o in self.objects))

    def bounds(self) -> NDArray[np.float64]:
        """World bounding box, shape (2, 3): min and max corner (m)."""
        pts = np.concatenate([o.world_points() for o in self.objects]) if self.objects \
            else np.zeros((1, 3))
        return np.stack([pts.min(axis=0), pts.max(axis=0)])


def _fail(path: Path, message: str) -> AssetError:
    return AssetError(f"{path.name}: {message}")


def _safe_name(value: Any, fallback: str) -> str:
    if not isinstance(value, str) or not value.strip():
        return fallback
    name = "".join(c if ord(c) >= 32 and ord(c) != 127 else "_" for c in value).strip()
    return name[:MAX_ASSET_NAME] or fallback


def unique_name(name: str, taken: set[str]) -> str:
    """``name``, or ``name_2``, ``name_3``… the first not in ``taken`` (which gains it)."""
    out, k = name, 2
    while out in taken:
        out, k = f"{name}_{k}", k + 1
    taken.add(out)
    return out


def _make_object(path: Path, name: str, material: str, matrix: NDArray[np.float64],
                 points: NDArray[Any], triangles: NDArray[Any], notes: list[str],
                 *, convert: bool = True) -> AssetObject | None:
    """An object of a node: world matrix (glTF frame) split into a pose and baked scale."""
    try:
        points, triangles = check_mesh_arrays(Path("mesh"), points, triangles)
    except MeshError as exc:
        raise _fail(path, f"node {name!r}: {str(exc).removeprefix('mesh: ')}") from None
    conv = np.eye(4)
    if convert:
        conv[:3, :3] = Y_UP_TO_Z_UP
    world = conv @ matrix
    lin, t = world[:3, :3], world[:3, 3]
    u, s, vt = np.linalg.svd(lin)
    if s.min() <= 1e-9 * max(s.max(), 1e-300):
        notes.append(f"{name}: zero scale (degenerate transform), skipped")
        return None
    rot = u @ vt
    if np.linalg.det(rot) < 0:           # mirrored node: proper rotation, mirror baked in
        rot = u @ np.diag([1.0, 1.0, -1.0]) @ vt
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # gimbal lock: the matrix check below decides
        euler = Rotation.from_matrix(rot).as_euler("xyz", degrees=True)
    if not np.all(np.abs(t) <= MAX_COORDINATE_M):
        raise _fail(path, f"node {name!r}: position {np.abs(t).max():.6g} m from the origin "
                          f"(after the node transforms); a project allows ±{MAX_COORDINATE_M:g} m")
    pose = Pose(position_m=tuple(float(v) for v in t), rotation_deg=tuple(
        float(v) for v in euler))
    back = pose.rotation_matrix()
    if np.abs(back - rot).max() > 1e-12:
        rot = np.eye(3)
        pose = Pose(position_m=pose.position_m)
    local = points @ (rot.T @ lin).T
    if np.linalg.det(lin) < 0:
        triangles = triangles[:, ::-1]
    world_pts = local @ pose.rotation_matrix().T + t
    if not np.isfinite(local).all() or np.abs(world_pts).max() > MAX_MESH_COORDINATE:
        raise _fail(path, f"node {name!r}: world coordinates exceed ±{MAX_MESH_COORDINATE:g} m")
    return AssetObject(name, material, pose, np.ascontiguousarray(local),
                       np.ascontiguousarray(triangles, dtype=np.int64))


__all__ = ["MAX_ASSET_NAME", "MAX_ASSET_OBJECTS", "NO_MATERIAL", "Y_UP_TO_Z_UP", "AssetError",
           "AssetMaterial", "AssetObject", "AssetScene", "unique_name"]
