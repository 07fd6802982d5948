"""Hostile inputs for the hardening tests: a small base project and mutations of it."""

from __future__ import annotations

import copy
import json
import random
from pathlib import Path
from typing import Any

from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.project_io import project_to_json

#: Values an attacker puts into numeric or string fields.
HOSTILE_VALUES: list[Any] = [
    0, -1, 1, 2, 3, 7, 0.5, -0.5, 1e308, -1e308, 1e300, 1e-300, 1e-320, 5e-324, 2**31,
    2**63, 2**63 - 1, 2**64, 10**30, 1e12, 65536, 8192, 16384, 1e6, -1e6, 1e9, 1e11,
    "", "x", "\u0000", "a\u0000b", "../../etc/passwd", "/dev/zero", "é" * 300, None, True,
    False, [], {}, [1, 2, 3], {"kind": "box"},
]


def base_project_dict() -> dict[str, Any]:
    """point_targets.json with tiny sensor grids plus a wall: a frame takes ~0.2 s."""
    project = load_project(example_path("point_targets"))
    tof, radar = project.rig.tof, project.rig.radar
    tof.width, tof.height, tof.supersampling = 32, 24, 1
    radar.render_width, radar.render_height = 48, 16
    radar.samples_per_chirp, radar.chirps_per_frame = 128, 8
    data = json.loads(project_to_json(project))
    data["objects"].append({"id": 9, "name": "wall", "geometry": {"kind": "box",
                            "size_m": [0.1, 4.0, 3.0]}, "pose": {"position_m": [5.0, 0.0, 1.0]},
                            "material": "concrete"})
    return data


def leaf_paths(doc: Any, max_depth: int = 12) -> list[tuple[Any, ...]]:
    """Paths (keys and indices) of every leaf and container in ``doc``, up to ``max_depth``."""
    out: list[tuple[Any, ...]] = []
    stack: list[tuple[Any, tuple[Any, ...]]] = [(doc, ())]
    while stack:
        value, prefix = stack.pop()
        if prefix:
            out.append(prefix)
        if len(prefix) >= max_depth:
            continue
        if isinstance(value, dict):
            stack.extend((v, (*prefix, k)) for k, v in value.items())
        elif isinstance(value, list):
            stack.extend((v, (*prefix, i)) for i, v in enumerate(value))
    return out


def set_path(doc: Any, path: tuple[Any, ...], value: Any) -> None:
    """Set ``doc[path[0]][path[1]]… = value``."""
    for key in path[:-1]:
        doc = doc[key]
    doc[path[-1]] = value


def scale_numbers(doc: dict[str, Any], rng: random.Random, n: int) -> dict[str, Any]:
    """``n`` numeric fields of a copy of ``doc`` multiplied by 10^[-4, 4] or negated."""
    doc = copy.deepcopy(doc)
    numeric = [p for p in leaf_paths(doc) if _is_number(_get(doc, p))]
    for path in rng.sample(numeric, min(n, len(numeric))):
        value = _get(doc, path)
        new = value * 10 ** rng.uniform(-4, 4) * rng.choice([1, 1, 1, -1])
        set_path(doc, path, int(new) if isinstance(value, int) else new)
    return doc


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _get(doc: Any, path: tuple[Any, ...]) -> Any:
    for key in path:
        doc = doc[key]
    return doc


def mutate(doc: dict[str, Any], rng: random.Random, n: int) -> dict[str, Any]:
    """``n`` random hostile edits of a copy of ``doc``: values, deletions, blow-ups."""
    doc = copy.deepcopy(doc)
    for _ in range(n):
        paths = leaf_paths(doc)
        path = rng.choice(paths)
        kind = rng.random()
        try:
            if kind < 0.7:
                value = rng.choice(HOSTILE_VALUES)
                if rng.random() < 0.3:
                    value = rng.choice([rng.uniform(-1e6, 1e6), 10 ** rng.uniform(-310, 308),
                                        rng.randint(-2**40, 2**40)])
                set_path(doc, path, copy.deepcopy(value))
            elif kind < 0.8:
                parent = doc
                for key in path[:-1]:
                    parent = parent[key]
                del parent[path[-1]]
            elif kind < 0.9:
                # Multiply a list: many antennas, objects, keyframes.
                parent = doc
                for key in path[:-1]:
                    parent = parent[key]
                if isinstance(parent, list) and parent:
                    parent.extend(copy.deepcopy(parent[-1]) for _ in range(rng.choice(
                        [1, 10, 300])))
            else:
                nested: Any = 0
                for _ in range(rng.choice([5, 80, 2000])):
                    nested = [nested]
                set_path(doc, path, nested)
        except (KeyError, IndexError, TypeError, RecursionError):
            pass
    return doc


def write_project(doc: Any, path: Path) -> Path:
    """Write ``doc`` as JSON (deep nesting written without recursion)."""
    try:
        text = json.dumps(doc)
    except (RecursionError, ValueError):
        text = "[" * 3000 + "]" * 3000
    path.write_text(text, encoding="utf-8")
    return path
