"""Project files: JSON load with validation and migration, atomic save.

Every problem in a project file is reported as a :class:`ProjectError` whose message
names the offending field (as a path like ``objects[2].geometry.size_m[0]``) and value.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from simcore.scene.geometry import MESH_SUFFIXES, Mesh
from simcore.scene.materials import DualBandMaterial, load_material_library
from simcore.scene.model import FORMAT_VERSION, Project

Migration = Callable[[dict[str, Any]], dict[str, Any]]



def _v1_materials_by_band(data: dict[str, Any]) -> dict[str, Any]:
    """Version 1 → 2: a material's ``tof`` and ``radar`` parameters move into ``bands``."""
    materials = data.get("materials")
    if isinstance(materials, list):
        upgraded = []
        for material in materials:
            if isinstance(material, dict):
                material = dict(material)
                bands = {band: material.pop(band) for band in ("tof", "radar")
                         if band in material}
                if bands:
                    material["bands"] = {**bands, **material.get("bands", {})}
            upgraded.append(material)
        data["materials"] = upgraded
    return data


#: ``MIGRATIONS[n]`` upgrades a version-``n`` document to version ``n + 1``.
MIGRATIONS: dict[int, Migration] = {1: _v1_materials_by_band}


class ProjectError(ValueError):
    """A project file cannot be loaded; ``problems`` lists every issue found."""

    def __init__(self, source: str, problems: list[str]):
        self.source = source
        self.problems = problems
        lines = "\n".join(f"  - {p}" for p in problems)
        super().__init__(f"{source}: invalid project\n{lines}")


def _format_loc(loc: tuple[int | str, ...]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in ("box", "sphere", "cylinder", "plane", "corner_reflector", "point_target",
                      "mesh"):
            out += f"({part})"
        else:
            out += f".{part}" if out else str(part)
    return out or "(document)"


def _short(value: Any) -> str:
    text = json.dumps(value, default=str) if not isinstance(value, str) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def format_validation_error(exc: ValidationError) -> list[str]:
    """Turn a pydantic error into one line per problem: ``field: message (got value)``."""
    problems = []
    for err in exc.errors():
        loc = _format_loc(tuple(err["loc"]))
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] in ("missing", "model_type", "model_attributes_type") or "input" not in err:
            problems.append(f"{loc}: {msg}")
        else:
            problems.append(f"{loc}: {msg} (got {_short(err['input'])})")
    return problems


def migrate(data: dict[str, Any], source: str = "project", *,
            migrations: dict[int, Migration] | None = None,
            current: int = FORMAT_VERSION) -> dict[str, Any]:
    """Upgrade a project document to version ``current`` through ``migrations``.

    ``migrations`` defaults to :data:`MIGRATIONS`; ``migrations[n]`` turns a version-``n``
    document into a version-``n + 1`` one.
    """
    migrations = MIGRATIONS if migrations is None else migrations
    version = data.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool):
        raise ProjectError(source, [f"format_version: must be an integer (got {_short(version)})"])
    if version > current:
        raise ProjectError(
            source,
            [f"format_version: {version} is newer than this tofradar supports "
             f"({current}); upgrade tofradar to open it"],
        )
    while version < current:
        if version not in migrations:
            raise ProjectError(source, [f"format_version: {version} is not a known version"])
        data = migrations[version](dict(data))
        version += 1
        data["format_version"] = version
    return data


def material_table(project: Project) -> dict[str, DualBandMaterial]:
    """Library materials overridden by the project's own materials, keyed by name."""
    table = load_material_library()
    table.update({m.name: m for m in project.materials})
    return table


def check_references(project: Project, base_dir: Path) -> list[str]:
    """Problems with references a schema cannot check: materials and mesh files."""
    problems = []
    materials = material_table(project)
    for i, obj in enumerate(project.objects):
        if obj.material not in materials:
            problems.append(
                f"objects[{i}].material: unknown material {obj.material!r} "
                f"(known: {', '.join(sorted(materials))})"
            )
        geom = obj.geometry
        if isinstance(geom, Mesh):
            path = resolve_mesh_path(base_dir, geom.path)
            if path.suffix.lower() not in MESH_SUFFIXES:
                problems.append(
                    f"objects[{i}].geometry.path: unsupported mesh format {path.suffix!r} "
                    f"(use {', '.join(MESH_SUFFIXES)})"
                )
            elif not path.is_file():
                problems.append(f"objects[{i}].geometry.path: mesh file not found: {path}")
    return problems


def resolve_mesh_path(base_dir: Path, mesh_path: str) -> Path:
    """Resolve a mesh path relative to the project file's directory."""
    path = Path(mesh_path)
    return path if path.is_absolute() else (base_dir / path)


def project_from_dict(data: Any, *, source: str = "project", base_dir: Path | None = None
                      ) -> Project:
    """Validate, migrate and check a parsed project document."""
    if not isinstance(data, dict):
        kind = type(data).__name__
        raise ProjectError(source, [f"(document): expected a JSON object, got {kind}"])
    data = migrate(data, source)
    try:
        project = Project.model_validate(data)
    except ValidationError as exc:
        raise ProjectError(source, format_validation_error(exc)) from None
    problems = check_references(project, base_dir or Path.cwd())
    if problems:
        raise ProjectError(source, problems)
    return project


def _reject_constant(name: str) -> float:
    raise ValueError(f"{name} is not a valid number in a project file")


def load_project(path: str | os.PathLike[str]) -> Project:
    """Load and validate a project file; raise :class:`ProjectError` naming any bad field."""
    path = Path(path)
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ProjectError(source, ["file not found"]) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ProjectError(source, [f"cannot read file: {exc}"]) from None
    try:
        data = json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as exc:
        raise ProjectError(
            source, [f"not valid JSON: {exc.msg} at line {exc.lineno}, column {exc.colno}"]
        ) from None
    except ValueError as exc:
        raise ProjectError(source, [str(exc)]) from None
    return project_from_dict(data, source=source, base_dir=path.parent)


def project_to_json(project: Project) -> str:
    """Serialise a project to its canonical JSON text (stable, so round trips are exact)."""
    return json.dumps(project.model_dump(mode="json"), indent=2, ensure_ascii=False) + "\n"


def save_project(project: Project, path: str | os.PathLike[str]) -> None:
    """Write the project atomically: a temporary file in the same folder, then a rename."""
    path = Path(path)
    text = project_to_json(project)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
