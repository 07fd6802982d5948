"""Field paths: one syntax that names a field of a project, used by sweeps and the GUI.

A path is field names joined by dots, with list indices in brackets, exactly as the field
sits in a project file: ``rig.radar.chirps_per_frame``, ``objects[1].pose.position_m[0]``,
``rig.radar.rx[2].position_mm``. It reads a field of a :class:`~simcore.scene.Project` (or
of any pydantic model) or of its ``model_dump()`` document, and sets one in a document.
"""

from __future__ import annotations

import re
from typing import Any, TypeVar

from pydantic import BaseModel

Part = str | int

_PART = re.compile(r"\.?([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]")

M = TypeVar("M", bound=BaseModel)


class FieldPathError(ValueError):
    """A field path is malformed or names a field that does not exist."""


def parse(path: str) -> tuple[Part, ...]:
    """Split a field path into names (str) and list indices (int).

    Parameters
    ----------
    path : str
        E.g. ``"objects[1].pose.position_m[0]"``.

    Returns
    -------
    tuple of str and int
        The parts, in order.

    Raises
    ------
    FieldPathError
        The text is not a field path.

    Examples
    --------
    >>> parse("objects[1].pose.position_m[0]")
    ('objects', 1, 'pose', 'position_m', 0)
    >>> parse("rig.radar.rx[2].position_mm")
    ('rig', 'radar', 'rx', 2, 'position_mm')
    >>> parse("objects.1.pose")
    Traceback (most recent call last):
    ...
    simcore.scene.fieldpath.FieldPathError: cannot parse field path 'objects.1.pose': ...
    """
    parts: list[Part] = []
    pos = 0
    while pos < len(path):
        m = _PART.match(path, pos)
        # A name follows a dot, except at the start; an index never follows a dot.
        if m is None or (m.group(1) is not None and (path[pos] == ".") == (pos == 0)):
            raise FieldPathError(
                f"cannot parse field path {path!r}: expected names joined by '.' and list "
                "indices in brackets, e.g. objects[1].pose.position_m[0]")
        parts.append(m.group(1) if m.group(1) is not None else int(m.group(2)))
        pos = m.end()
    if not parts or not isinstance(parts[0], str):
        raise FieldPathError(f"cannot parse field path {path!r}: it must start with a name")
    return tuple(parts)


def format_path(parts: tuple[Part, ...] | list[Part]) -> str:
    """Join parts into a field path (the inverse of :func:`parse`).

    Examples
    --------
    >>> format_path(("objects", 3, "pose"))
    'objects[3].pose'
    >>> format_path(parse("rig.radar.rx[2].position_mm"))
    'rig.radar.rx[2].position_mm'
    """
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in parts).lstrip(".")


def get(node: Any, path: str) -> Any:
    """The value at ``path`` in a pydantic model or a plain document (dicts and lists).

    Raises
    ------
    FieldPathError
        A part of the path does not exist; the message names the first missing prefix.

    Examples
    --------
    >>> doc = {"rig": {"radar": {"rx": [{"position_mm": [0.0, 0.0]},
    ...                                 {"position_mm": [2.5, 0.0]}]}}}
    >>> get(doc, "rig.radar.rx[1].position_mm[0]")
    2.5
    >>> get(doc, "rig.radar.rx[2]")
    Traceback (most recent call last):
    ...
    simcore.scene.fieldpath.FieldPathError: rig.radar.rx[2] does not exist
    """
    parts = parse(path)
    for depth, part in enumerate(parts):
        node = _child(node, part, parts[: depth + 1])
    return node


def set_in(document: dict[str, Any], path: str, value: Any) -> None:
    """Set the existing field at ``path`` of a plain document in place.

    Tuples on the way (as in ``model_dump()`` output) are replaced by edited copies.

    Raises
    ------
    FieldPathError
        A part of the path does not exist (fields are never created).

    Examples
    --------
    >>> doc = {"objects": [{"pose": {"position_m": (1.0, 2.0, 0.0)}}]}
    >>> set_in(doc, "objects[0].pose.position_m[1]", 5.0)
    >>> doc
    {'objects': [{'pose': {'position_m': (1.0, 5.0, 0.0)}}]}
    >>> set_in(doc, "objects[0].pose.scale", 2.0)
    Traceback (most recent call last):
    ...
    simcore.scene.fieldpath.FieldPathError: objects[0].pose.scale does not exist
    """
    if not isinstance(document, dict):
        raise TypeError("set_in edits a document (dict); use with_value for a model")
    _set(document, parse(path), value, ())


def with_value(model: M, path: str, value: Any) -> M:
    """A validated copy of ``model`` with the field at ``path`` set to ``value``.

    Raises
    ------
    FieldPathError
        The field does not exist.
    pydantic.ValidationError
        The new value makes the model invalid.

    Examples
    --------
    >>> from simcore.scene import Project
    >>> p = with_value(Project(), "rig.radar.chirps_per_frame", 32)
    >>> get(p, "rig.radar.chirps_per_frame"), get(Project(), "rig.radar.chirps_per_frame")
    (32, 16)
    """
    document = model.model_dump()
    set_in(document, path, value)
    return type(model).model_validate(document)


def _child(node: Any, part: Part, where: tuple[Part, ...]) -> Any:
    """``node[part]`` (or the model field ``part``), or FieldPathError naming ``where``."""
    if isinstance(part, int):
        if isinstance(node, (list, tuple)) and part < len(node):
            return node[part]
    elif isinstance(node, BaseModel):
        if part in type(node).model_fields:
            return getattr(node, part)
    elif isinstance(node, dict) and part in node:
        return node[part]
    raise FieldPathError(f"{format_path(where)} does not exist")


def _set(node: Any, parts: tuple[Part, ...], value: Any, done: tuple[Part, ...]) -> Any:
    """Set ``parts`` below ``node`` to ``value``; return ``node`` (or its edited copy)."""
    key = parts[0]
    if isinstance(node, BaseModel):
        raise FieldPathError(f"{format_path(done)} is a model, not a document")
    child = _child(node, key, (*done, key))
    new = value if len(parts) == 1 else _set(child, parts[1:], value, (*done, key))
    if isinstance(node, tuple):
        items = list(node)
        items[key] = new  # type: ignore[index]
        return tuple(items)
    node[key] = new
    return node
