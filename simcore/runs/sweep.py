"""Parameter sweeps: one dataset per combination of varied project fields.

A field is named by its path in the project (:mod:`simcore.scene.fieldpath`), e.g.
``objects[1].pose.position_m[0]`` or ``rig.radar.chirps_per_frame``. Values are a range
``START:STOP:STEP`` (STOP included when it falls on the grid) or a list ``v1,v2,v3``.
"""

from __future__ import annotations

import copy
import itertools
import json
from dataclasses import dataclass
from typing import Any

import numpy as np

from simcore.scene import fieldpath
from simcore.scene.model import Project
from simcore.scene.project_io import ProjectError, project_from_dict


class SweepError(ValueError):
    """A ``--vary`` specification is malformed or names a field that does not exist."""


@dataclass(frozen=True)
class Variation:
    """One varied field and its values."""

    path: str
    values: tuple[Any, ...]


def _number(text: str) -> int | float:
    try:
        return int(text)
    except ValueError:
        try:
            value = float(text)
        except ValueError:
            raise SweepError(f"{text!r} is not a number") from None
    if not np.isfinite(value):
        raise SweepError(f"{text!r} is not a finite number")
    return value


def parse_vary(spec: str) -> Variation:
    """Parse ``PATH=START:STOP:STEP`` or ``PATH=v1,v2,...``."""
    if "=" not in spec:
        raise SweepError(f"--vary {spec!r}: expected PATH=START:STOP:STEP or PATH=v1,v2")
    path, _, values_text = spec.partition("=")
    try:
        fieldpath.parse(path)
    except fieldpath.FieldPathError as exc:
        raise SweepError(f"--vary {spec!r}: {exc}") from None
    if ":" in values_text:
        parts = values_text.split(":")
        if len(parts) != 3:
            raise SweepError(f"--vary {spec!r}: a range is START:STOP:STEP")
        start, stop, step = (_number(p) for p in parts)
        if step == 0 or (stop - start) / step < 0:
            raise SweepError(f"--vary {spec!r}: STEP must be non-zero and go from START to STOP")
        count = int(np.floor((stop - start) / step + 1e-9)) + 1
        values: tuple[Any, ...] = tuple(
            (start + i * step) if isinstance(start + step, int) else
            round(float(start + i * step), 12) for i in range(count))
    else:
        values = tuple(_number(v) for v in values_text.split(",") if v != "")
    if not values:
        raise SweepError(f"--vary {spec!r}: no values")
    return Variation(path, values)


def expand(project: Project, variations: list[Variation]) -> list[tuple[dict[str, Any], Project]]:
    """All combinations: (parameters, validated project) per variant."""
    base = project.model_dump(mode="json")
    variants = []
    for combo in itertools.product(*(v.values for v in variations)):
        params = {v.path: value for v, value in zip(variations, combo, strict=True)}
        doc = copy.deepcopy(base)
        for path, value in params.items():
            try:
                fieldpath.set_in(doc, path, value)
            except fieldpath.FieldPathError as exc:
                raise SweepError(f"--vary: {exc} in the project") from None
        try:
            variants.append((params, project_from_dict(doc, source=f"variant {params}")))
        except ProjectError as exc:
            raise SweepError(str(exc)) from None
    return variants


def parameters_json(params: dict[str, Any]) -> str:
    """Canonical JSON of a variant's parameters."""
    return json.dumps(params, sort_keys=True)
