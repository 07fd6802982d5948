"""The bundled example projects: list them, copy them (with their meshes) into a folder."""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any

from simcore.resources import EXAMPLES_DIR


class ExamplesError(Exception):
    """Copying the examples would overwrite a file, or a bundled example is unreadable."""


@dataclass(frozen=True)
class Example:
    """One bundled example project."""

    name: str
    path: Path
    description: str

    @property
    def summary(self) -> str:
        """First sentence of the description (one line)."""
        first = self.description.split(". ")[0].split("; ")[0].strip()
        return first.rstrip(".")


def list_examples() -> list[Example]:
    """The bundled example projects, sorted by name.

    Examples
    --------
    >>> {"office", "point_targets", "wall"} <= {e.name for e in list_examples()}
    True
    >>> [e for e in list_examples() if e.name == "wall"][0].summary
    'A flat concrete wall 2.0 m in front of the rig, normal to the boresight, larger than both fields of view'
    """  # noqa: E501 - doctest output is one line
    examples = []
    for path in sorted(EXAMPLES_DIR.glob("*.json")):
        document = _read(path)
        examples.append(Example(path.stem, path, str(document.get("description", ""))))
    return examples


def mesh_files(project_file: Path) -> list[PurePosixPath]:
    """Relative paths of the mesh files a project file refers to, in project order.

    Mesh paths in a project are relative to the project file; absolute paths and paths
    that leave the project's folder are not bundled and so are not returned.

    Examples
    --------
    >>> mesh_files(EXAMPLES_DIR / "wall.json")
    []
    """
    found: list[PurePosixPath] = []
    for obj in _read(project_file).get("objects", []):
        geometry = obj.get("geometry", {}) if isinstance(obj, dict) else {}
        if geometry.get("kind") != "mesh" or not isinstance(geometry.get("path"), str):
            continue
        rel = PurePosixPath(geometry["path"])
        if not rel.is_absolute() and ".." not in rel.parts and rel not in found:
            found.append(rel)
    return found


def copy_examples(target: Path) -> list[Path]:
    """Copy every bundled example project and its meshes into ``target``.

    The folder is created if needed. Nothing is copied if any destination file exists
    already (:class:`ExamplesError` names it), so a copy never overwrites a user's file.

    Returns
    -------
    list of Path
        The files written, project files first.
    """
    target = Path(target)
    if target.exists() and not target.is_dir():
        raise ExamplesError(f"{target} exists and is not a folder")
    examples = list_examples()
    pairs = [(example.path, target / example.path.name) for example in examples]
    for example in examples:
        for rel in mesh_files(example.path):
            source = example.path.parent / rel
            if not source.is_file():
                raise ExamplesError(f"bundled example {example.name} lacks its mesh {rel}")
            pair = (source, target / rel)
            if pair not in pairs:
                pairs.append(pair)
    existing = [dest for _, dest in pairs if dest.exists()]
    if existing:
        more = f" (and {len(existing) - 1} more)" if len(existing) > 1 else ""
        raise ExamplesError(f"{existing[0]} exists already{more}; not overwriting, "
                            "choose an empty folder")
    for source, dest in pairs:
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, dest)
    return [dest for _, dest in pairs]


def _read(path: Path) -> dict[str, Any]:
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ExamplesError(f"cannot read bundled example {path.name}: {exc}") from None
    return document if isinstance(document, dict) else {}
