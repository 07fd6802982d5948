"""Locations of the bundled resources (material library, examples, meshes).

The files live in the repository's top-level ``resources/`` folder. The package reaches
them as ``simcore/_resources`` (a link to that folder in a source checkout, a copy inside
the installed wheel), so they are found through :mod:`importlib.resources` the same way
in a checkout, an editable install and an installed wheel, from any working directory.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def _resources_dir() -> Path:
    """The bundled resources folder as a file-system path."""
    root = files("simcore").joinpath("_resources")
    if not isinstance(root, Path) or not root.is_dir():
        raise RuntimeError(
            f"tofradar's bundled resources are missing ({root}); reinstall the package")
    return root


RESOURCES_DIR = _resources_dir()
EXAMPLES_DIR = RESOURCES_DIR / "examples"
MATERIALS_FILE = RESOURCES_DIR / "materials.json"


def example_path(name: str) -> Path:
    """Return the path of a bundled example project.

    Parameters
    ----------
    name : str
        Example name with or without ``.json``, e.g. ``"office"``.

    Returns
    -------
    Path
        The project file (it may not exist: see :func:`simcore.examples.list_examples`).

    Examples
    --------
    >>> example_path("office").name
    'office.json'
    >>> example_path("wall.json").parent == EXAMPLES_DIR
    True
    """
    stem = name.removesuffix(".json")
    return EXAMPLES_DIR / f"{stem}.json"
