"""Locations of the bundled resources (material library, presets, examples, meshes)."""

from __future__ import annotations

from pathlib import Path

RESOURCES_DIR = Path(__file__).resolve().parent.parent / "resources"
EXAMPLES_DIR = RESOURCES_DIR / "examples"
MATERIALS_FILE = RESOURCES_DIR / "materials.json"


def example_path(name: str) -> Path:
    """Return the path of a bundled example project, e.g. ``example_path("office")``."""
    stem = name.removesuffix(".json")
    return EXAMPLES_DIR / f"{stem}.json"
