"""What a sensor kind writes: its outputs, declared once, in its own package.

Each sensor kind's package holds a ``schema.py`` with one :class:`SensorSchema`: every
dataset the kind writes under a sensor's group (``/<sensor name>/<output>``), with its
dimensions, unit, dtype, whether it is per frame or static, whether NaN is a legal value,
how it is previewed and which ROS 2 message / Foxglove topic carries it. The writers, the
reader (:func:`simcore.io.reader.open_dataset`), the PNG previews, MCAP and the live
stream, ``tofradar products``, the pre-run checks and the GUI's panels all work from these
declarations and a sensor's *name*, never from a built-in group path: a new sensor kind
adds its outputs in its own package, and a sensor of any name is written like the
built-in one.

Examples
--------
>>> import simcore.sensors  # registers the built-in kinds and their schemas
>>> from simcore.sensors.schema import schema_of
>>> out = schema_of("tof").output("depth")
>>> out.dims, out.unit, out.per_frame
(('row', 'col'), 'm', True)
>>> schema_of("radar").dataset_path("front", "range_doppler")
'/front/range_doppler'
"""

from __future__ import annotations

from collections.abc import Mapping

from simcore.scene.layout import (
    COMMON_DIMS,
    Output,
    Preview,
    PreviewFrame,
    SensorSchema,
    reserved_names,
)

#: Schemas by kind (filled by :func:`declare`, from each kind's package).
_SCHEMAS: dict[str, SensorSchema] = {}


def declare(schema: SensorSchema) -> SensorSchema:
    """Register a sensor kind's schema (once per kind)."""
    if schema.kind in _SCHEMAS and _SCHEMAS[schema.kind] is not schema:
        raise ValueError(f"sensor kind {schema.kind!r} declared its outputs twice")
    _SCHEMAS[schema.kind] = schema
    return schema


def schema_of(kind: str) -> SensorSchema:
    """The output schema of sensor kind ``kind``.

    The kinds declare theirs when ``simcore.sensors`` registers them; this module does not
    import that package (it sits below it), so a caller imports it first (``simcore.io``
    does).
    """
    try:
        return _SCHEMAS[kind]
    except KeyError:
        known = ", ".join(_SCHEMAS) or "none: import simcore.sensors to register the kinds"
        raise KeyError(f"unknown sensor kind {kind!r} (kinds: {known})") from None


def schemas() -> dict[str, SensorSchema]:
    """Every declared schema, by kind."""
    if not _SCHEMAS:
        raise LookupError("no sensor kind is registered: import simcore.sensors first")
    return dict(_SCHEMAS)


def split_path(path: str, kinds: Mapping[str, str]) -> tuple[str, str, Output] | None:
    """``(sensor name, kind, output)`` of a dataset path, None when no sensor's output.

    ``kinds`` maps each sensor's name to its kind (the project's sensors).
    """
    head, sep, rest = path.strip("/").partition("/")
    kind = kinds.get(head)
    if not sep or kind is None or kind not in schemas():
        return None
    out = schema_of(kind).find(rest)
    return None if out is None else (head, kind, out)


def nan_allowed(path: str, kinds: Mapping[str, str]) -> bool:
    """Whether dataset ``path`` may hold NaN (its output declares so)."""
    found = split_path(path, kinds)
    return found is not None and found[2].nan


def must_be_finite(path: str, kinds: Mapping[str, str]) -> bool:
    """Whether every value of ``path`` must be finite (raw sensor data)."""
    found = split_path(path, kinds)
    return found is not None and found[2].finite


__all__ = ["COMMON_DIMS", "Output", "Preview", "PreviewFrame", "SensorSchema", "declare",
           "must_be_finite", "nan_allowed", "reserved_names", "schema_of", "schemas",
           "split_path"]
