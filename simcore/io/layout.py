"""Dimensions and coordinates of every dataset of the layout, for the readers and writers.

The common groups' dimensions come from :mod:`simcore.scene.layout`; each sensor's from its
kind's schema (:mod:`simcore.sensors.schema`), for the sensor's *name*: a sensor not named
after its kind (``/front/range_doppler``) gets the kind's dimensions with its name before
each that is not common (``front_velocity``, ``front_range``), so sensors with other axes do
not clash. This module is below the reader and the writers (HDF5, Zarr) that all use it.
"""

from __future__ import annotations

import json
from collections.abc import Mapping

from simcore.scene.layout import (
    COMMON_COORDS,
    COMMON_DATASETS,
    OBJECT_DATASETS,
    PEOPLE_DATASETS,
)
from simcore.sensors.schema import schema_of, schemas, split_path


def _builtin_tables() -> tuple[dict[str, tuple[str, ...]], dict[str, tuple[str, ...]],
                               dict[str, str]]:
    """Dims of the built-in sensors' outputs (sensor named after its kind), and coords."""
    dims: dict[str, tuple[str, ...]] = {}
    products: dict[str, tuple[str, ...]] = {}
    coords: dict[str, str] = {}
    for kind, schema in schemas().items():
        for out in schema.outputs:
            if out.optional or out.dtype == "record":
                continue
            path = schema.dataset_path(kind, out.name)
            (products if out.product else dims)[path] = out.dims
            if out.coord is not None:
                coords[path] = out.coord
    return dims, products, coords


_SENSOR_DIMS, PRODUCT_DIMS, _SENSOR_COORDS = _builtin_tables()

#: Dimension names of each dataset a run of the built-in sensors writes, without the
#: leading ``frame`` axis of per-frame arrays (sensors' datasets from their schemas).
DIMS: dict[str, tuple[str, ...]] = {
    **COMMON_DATASETS,
    **{f"/objects/{name}": dims for name, dims in OBJECT_DATASETS.items()},
    **_SENSOR_DIMS,
}

#: Dimension names of the datasets that only projects with several rigs write.
RIGS_DIMS: dict[str, tuple[str, ...]] = {
    "/poses/rigs": ("rig", "pose_row", "pose_col"),
    "/poses/rig_names": ("rig",),
}

#: Dimension names of the datasets that only projects with people write (docs/people.md).
PEOPLE_DIMS: dict[str, tuple[str, ...]] = {
    f"/people/{name}": dims for name, dims in PEOPLE_DATASETS.items()}

#: Dimension names of the datasets that only runs over several scenes write.
SCENE_DIMS: dict[str, tuple[str, ...]] = {
    "/scene_index": (),
    "/scenes/names": ("scene",),
    "/scenes/seeds": ("scene",),
    "/scenes/projects": ("scene",),
}

#: Dimensions whose length is a scene's count of things, and the group of each: in a run
#: over scenes whose counts differ, arrays along them are padded to the largest scene's
#: count, with ``<group>/count`` and ``<group>/valid`` per frame (docs/dataset.md).
ENTITY_GROUPS: dict[str, str] = {"object": "/objects", "person": "/people",
                                 "segment": "/people/segments"}


def _entity_scene_dims() -> dict[str, tuple[str, ...]]:
    """``/objects/count``, ``/objects/valid``, ``/scenes/objects/names`` … of each entity."""
    out: dict[str, tuple[str, ...]] = {}
    for entity, group in ENTITY_GROUPS.items():
        out[f"{group}/count"] = ()
        out[f"{group}/valid"] = (entity,)
        out[f"/scenes{group}/count"] = ("scene",)
    for table in (DIMS, PEOPLE_DIMS):
        for path, dims in table.items():
            if dims and dims[0] in ENTITY_GROUPS:
                out[f"/scenes{path}"] = ("scene", *dims)
    return out


SCENE_DIMS.update(_entity_scene_dims())

#: Axis datasets that become coordinates: path → coordinate name.
COORDS = {**_SENSOR_COORDS, **COMMON_COORDS}


def inner_dims(path: str) -> tuple[str, ...] | None:
    """Dimension names of a dataset of the layout, without a per-frame leading ``frame``."""
    for table in (DIMS, RIGS_DIMS, PEOPLE_DIMS, SCENE_DIMS, PRODUCT_DIMS):
        if path in table:
            return table[path]
    return None


def entity_of(path: str) -> str | None:
    """The entity dimension (``object``, ``person``, ``segment``) of ``path``'s first axis."""
    dims = inner_dims(path)
    return dims[0] if dims and dims[0] in ENTITY_GROUPS else None


def sensor_kinds(project_json: str) -> dict[str, str]:
    """Kind of every sensor of a stored project document, by name (``{}`` if unreadable).

    Read from the document as stored (any format version: the first rig's ``tof`` and
    ``radar`` are there unless set to null, ``rgb`` when set).
    """
    try:
        doc = json.loads(project_json)
        rig = doc.get("rig") or {}
        kinds = {k: k for k in ("tof", "radar")
                 if ("rig" in doc and k not in rig) or rig.get(k) is not None}
        if rig.get("rgb") is not None:
            kinds["rgb"] = "rgb"
        for r in [rig, *(doc.get("rigs") or [])]:
            for name, cfg in (r.get("sensors") or {}).items():
                kinds[str(name)] = str(cfg.get("kind", ""))
        return kinds
    except (ValueError, AttributeError, TypeError):
        return {}


def _with_builtins(kinds: Mapping[str, str] | None) -> dict[str, str]:
    """``kinds`` plus each kind's built-in name when no sensor takes it (older files)."""
    out = {k: k for k in schemas()}
    out.update(kinds or {})
    return out


def dims_of(path: str, kinds: Mapping[str, str] | None = None) -> tuple[str, ...] | None:
    """Dimension names of dataset ``path`` (without the frame axis), None when unknown.

    A sensor's datasets have the dimensions its kind declares (prefixed with its name
    unless it is named after its kind); a radar's object truth (``/objects/<name>/range``)
    is along ``object``, its people truth (``/people/segments/<name>/range``) along
    ``segment``.
    """
    found = (COMMON_DATASETS.get(path) or RIGS_DIMS.get(path) or PEOPLE_DIMS.get(path)
             or SCENE_DIMS.get(path))
    if found is None and path.startswith("/objects/"):
        found = OBJECT_DATASETS.get(path.removeprefix("/objects/"))
    if found is not None:
        return found
    every = _with_builtins(kinds)
    sensor = split_path(path, every)
    if sensor is not None:
        name, kind, out = sensor
        return schema_of(kind).dims(name, out)
    parts = path.strip("/").split("/")
    if len(parts) == 3 and parts[0] == "objects" and every.get(parts[1]) == "radar":
        return ("object",)
    if len(parts) == 4 and parts[:2] == ["people", "segments"] and parts[2] in every:
        return ("segment",)
    return None


def coord_of(path: str, kinds: Mapping[str, str] | None = None) -> str | None:
    """The coordinate that dataset ``path`` becomes, None for a plain variable.

    ``/radar/range_axis`` → ``range``; a named radar's ``/<name>/range_axis`` →
    ``<name>_range``.
    """
    if path in COMMON_COORDS:
        return COMMON_COORDS[path]
    sensor = split_path(path, _with_builtins(kinds))
    if sensor is None:
        return None
    name, kind, out = sensor
    return schema_of(kind).coord(name, out)


def table_dims(path: str, kinds: Mapping[str, str] | None = None) -> tuple[str, str]:
    """Row dimension of a detections table and slot dimension of its per-frame form.

    ``detection`` and ``slot`` for the built-in radar's; ``<name>_detection`` and
    ``<name>_slot`` for a named radar's (its variables ``<name>_detection_<field>``).
    """
    sensor = split_path(path.removesuffix("_by_frame"), _with_builtins(kinds))
    if sensor is None or sensor[0] == sensor[1]:
        return "detection", "slot"
    return f"{sensor[0]}_detection", f"{sensor[0]}_slot"
