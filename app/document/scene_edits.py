"""Scene edits used by the menus, the object list and the tests: add, duplicate, delete."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from app.document.document import ProjectDocument
from simcore.scene.snapshot import take_snapshot

#: Geometry and default material of each kind the "Add" menu offers.
NEW_OBJECTS: dict[str, tuple[dict[str, Any], str]] = {
    "box": ({"kind": "box", "size_m": (0.5, 0.5, 0.5)}, "wood"),
    "sphere": ({"kind": "sphere", "radius_m": 0.25}, "aluminium"),
    "cylinder": ({"kind": "cylinder", "radius_m": 0.2, "height_m": 1.0}, "concrete"),
    "plane": ({"kind": "plane", "size_m": (1.0, 1.0)}, "white_paint"),
    "corner_reflector": ({"kind": "corner_reflector", "edge_m": 0.08}, "radar_retroreflector"),
    "point_target": ({"kind": "point_target", "rcs_m2": 1.0}, "aluminium"),
    "person": ({"kind": "person", "height_m": 1.75}, "clothing"),
}

KIND_LABELS = {
    "box": "Box", "sphere": "Sphere", "cylinder": "Cylinder", "plane": "Plane",
    "corner_reflector": "Corner reflector", "point_target": "Point target", "mesh": "Mesh",
    "person": "Person", "ellipsoid": "Ellipsoid",
}


def unique_name(document: ProjectDocument, base: str) -> str:
    """``base``, or ``base_2``, ``base_3``… whichever is not yet an object name."""
    names = {o.name for o in document.project.objects}
    if base not in names:
        return base
    stem = re.sub(r"_\d+$", "", base)
    i = 2
    while f"{stem}_{i}" in names:
        i += 1
    return f"{stem}_{i}"


#: Kinds whose front (local +z) is turned towards the sensors when added.
FACING_KINDS = ("plane", "corner_reflector")


def sensor_boresight(document: ProjectDocument, *, t: float = 0.0
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Mean origin and unit boresight (optical z) of the rig's sensors at time ``t`` (world)."""
    snap = take_snapshot(document.project, t)
    frames = [s.transform for s in snap.sensors.values()] or [snap.rig.transform]
    origin = np.mean([f[:3, 3] for f in frames], axis=0)
    if snap.sensors:
        axis = np.sum([f[:3, 2] for f in frames], axis=0)
    else:
        axis = snap.rig.transform[:3, 0]  # body x: forward
    return origin, axis / np.linalg.norm(axis)


#: A new object keeps this far from existing objects' origins along the boresight (m).
ADD_CLEARANCE_M = 0.4


def point_in_front_of_rig(document: ProjectDocument, distance_m: float = 2.0, *,
                          t: float = 0.0) -> tuple[float, float, float]:
    """World point on the sensors' boresight, ``distance_m`` from their mean origin.

    When an object already sits there (origin closer than :data:`ADD_CLEARANCE_M`), the
    point moves further out along the boresight in steps of that clearance (up to 10 m).
    """
    origin, axis = sensor_boresight(document, t=t)
    snap = take_snapshot(document.project, t)
    taken = np.array([o.origin for o in snap.objects]).reshape(-1, 3)
    d = distance_m
    while d < distance_m + 10.0:
        p = origin + axis * d
        if not len(taken) or np.min(np.linalg.norm(taken - p, axis=1)) >= ADD_CLEARANCE_M:
            break
        d += ADD_CLEARANCE_M
    return (float(round(p[0], 4)), float(round(p[1], 4)), float(round(p[2], 4)))


def facing_rotation_deg(document: ProjectDocument, kind: str, *, t: float = 0.0
                        ) -> tuple[float, float, float]:
    """Rotation (x-y-z extrinsic, degrees) that turns a new object towards the sensors.

    Planes and corner reflectors get their local +z (normal, opening) pointing back along
    the boresight, local x horizontal; other kinds only turn about the vertical to the
    boresight's heading (a box shows the sensors a face, a cylinder stays upright).
    """
    _, b = sensor_boresight(document, t=t)
    if kind in FACING_KINDS:
        z = -b
        x = np.cross((0.0, 0.0, 1.0), z)
        if np.linalg.norm(x) < 1e-6:  # looking straight up or down
            x = np.array([1.0, 0.0, 0.0])
        x /= np.linalg.norm(x)
        matrix = np.column_stack([x, np.cross(z, x), z])
    else:
        yaw = np.arctan2(b[1], b[0]) if np.hypot(b[0], b[1]) > 1e-6 else 0.0
        matrix = Rotation.from_euler("z", yaw).as_matrix()
    euler = Rotation.from_matrix(matrix).as_euler("xyz", degrees=True)
    return (float(round(euler[0], 6)) + 0.0, float(round(euler[1], 6)) + 0.0,
            float(round(euler[2], 6)) + 0.0)


def add_object(document: ProjectDocument, kind: str, *, name: str | None = None,
               position_m: tuple[float, float, float] | None = None,
               geometry: dict[str, Any] | None = None, material: str | None = None) -> int:
    """Add an object of ``kind`` (key of :data:`NEW_OBJECTS` or "mesh"); returns its id."""
    default_geom, default_mat = NEW_OBJECTS.get(kind, ({"kind": kind}, "concrete"))
    geom = dict(geometry if geometry is not None else default_geom)
    oid = document.project.next_object_id()
    pos = position_m if position_m is not None else point_in_front_of_rig(document)
    # Facing the sensors: a plane's normal and a corner reflector's opening point back
    # along the boresight (a rig at the origin looking along +x gives (0, -90, 0)).
    rotation = facing_rotation_deg(document, kind)
    if kind == "person":  # stands on the floor, facing the sensors
        pos = (float(pos[0]), float(pos[1]), 0.0)
        rotation = (0.0, 0.0, float(round((rotation[2] + 360.0) % 360.0 - 180.0, 6)) + 0.0)
    obj = {
        "id": oid,
        "name": unique_name(document, name or kind),
        "geometry": geom,
        "pose": {"position_m": tuple(pos), "rotation_deg": rotation},
        "material": material or default_mat,
    }
    document.edit(f"Add {KIND_LABELS.get(kind, kind).lower()}",
                  lambda d: d["objects"].append(obj))
    document.select(oid)
    return oid


def mesh_path_for_project(document: ProjectDocument, path: Path) -> str:
    """Mesh path as stored in the project: relative to the project folder when possible."""
    path = Path(path).resolve()
    if document.path is not None:
        try:
            return Path(os.path.relpath(path, document.base_dir)).as_posix()
        except ValueError:
            pass
    return str(path)


def import_mesh(document: ProjectDocument, path: Path, *, scale: float = 1.0) -> int:
    """Add a mesh object read from ``path`` (STL, OBJ or PLY)."""
    geom = {"kind": "mesh", "path": mesh_path_for_project(document, path), "scale": scale}
    return add_object(document, "mesh", name=Path(path).stem or "mesh", geometry=geom,
                      material="concrete")


def duplicate_object(document: ProjectDocument, object_id: int) -> int:
    """Copy an object (new id and name, shifted 0.25 m to the side); returns the new id."""
    idx = document.index_of(object_id)
    src = document.project.objects[idx].model_dump()
    new_id = document.project.next_object_id()
    src["id"] = new_id
    src["name"] = unique_name(document, f"{src['name']}_copy")
    p = np.array(src["pose"]["position_m"], dtype=float) + np.array([0.0, 0.25, 0.0])
    src["pose"]["position_m"] = tuple(float(v) for v in p)
    document.edit(f"Duplicate {document.project.objects[idx].name}",
                  lambda d: d["objects"].insert(idx + 1, src))
    document.select(new_id)
    return new_id


def delete_object(document: ProjectDocument, object_id: int) -> None:
    """Remove an object."""
    idx = document.index_of(object_id)
    name = document.project.objects[idx].name
    document.edit(f"Delete {name}", lambda d: d["objects"].pop(idx))


def rename_object(document: ProjectDocument, object_id: int, name: str) -> None:
    """Rename an object (names must be unique and non-empty)."""
    idx = document.index_of(object_id)
    old = document.project.objects[idx].name
    if name != old:
        document.set_value(f"objects[{idx}].name", name, text=f"Rename {old} to {name}")
