"""Project files: JSON load with validation and migration, atomic save.

Every problem in a project file is reported as a :class:`ProjectError` whose message
names the offending field (as a path like ``objects[2].geometry.size_m[0]``) and value.
"""

from __future__ import annotations

import json
import os
import stat
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from simcore.scene.geometry import MESH_SUFFIXES, Mesh
from simcore.scene.materials import DualBandMaterial, load_material_library
from simcore.scene.model import FORMAT_VERSION, Project
from simcore.scene.people.config import Person

Migration = Callable[[dict[str, Any]], dict[str, Any]]

#: Limits of a project document: file size (bytes), nesting depth, list length, string
#: length. A real project is a few hundred kB, 12 levels deep.
MAX_PROJECT_BYTES = 64 * 2**20
MAX_DEPTH = 64
MAX_LIST_LENGTH = 100_000
MAX_STRING_LENGTH = 1_000_000
MAX_OBJECTS = 4096
#: Longest problem line (characters) and most problems reported.
MAX_PROBLEM_LENGTH = 400
MAX_PROBLEMS = 50


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
def _v2_named_sensors(data: dict[str, Any]) -> dict[str, Any]:
    """Version 3 adds named sensors and rigs; a version-2 rig is the first rig as it was."""
    return data


MIGRATIONS: dict[int, Migration] = {1: _v1_materials_by_band, 2: _v2_named_sensors}


class ProjectError(ValueError):
    """A project file cannot be loaded; ``problems`` lists every issue found."""

    def __init__(self, source: str, problems: list[str]):
        self.source = source
        shown = [cap_line(p) for p in problems[:MAX_PROBLEMS]]
        if len(problems) > MAX_PROBLEMS:
            shown.append(f"... and {len(problems) - MAX_PROBLEMS} more problems")
        self.problems = shown
        lines = "\n".join(f"  - {p}" for p in shown)
        super().__init__(f"{source}: invalid project\n{lines}")


def cap_line(text: str, limit: int = MAX_PROBLEM_LENGTH) -> str:
    """One line of at most ``limit`` characters (newlines folded, the rest elided)."""
    line = " ".join(str(text).split())
    return line if len(line) <= limit else line[: limit - 3] + "..."


def document_limits(data: Any) -> list[str]:
    """Problems with the document's shape: depth, list and string lengths (linear time).

    Objects and materials are capped more tightly (:data:`MAX_OBJECTS`): validating one
    costs about a millisecond, and each is rendered every frame.
    """
    problems: list[str] = []
    if isinstance(data, dict):
        for key in ("objects", "materials"):
            items = data.get(key)
            if isinstance(items, list) and len(items) > MAX_OBJECTS:
                problems.append(f"{key}: {len(items)} entries; allowed at most {MAX_OBJECTS}")
        if problems:
            return problems
    stack: list[tuple[Any, str, int]] = [(data, "", 0)]
    while stack and len(problems) < 10:
        value, where, depth = stack.pop()
        here = where or "(document)"
        if depth > MAX_DEPTH:
            problems.append(f"{here}: nested more than {MAX_DEPTH} levels deep")
            continue
        if isinstance(value, str):
            if len(value) > MAX_STRING_LENGTH:
                problems.append(f"{here}: string of {len(value)} characters; at most "
                                f"{MAX_STRING_LENGTH}")
        elif isinstance(value, list):
            if len(value) > MAX_LIST_LENGTH:
                problems.append(f"{here}: list of {len(value)} items; at most "
                                f"{MAX_LIST_LENGTH}")
                continue
            stack.extend((v, f"{where}[{i}]", depth + 1) for i, v in enumerate(value))
        elif isinstance(value, dict):
            if len(value) > MAX_LIST_LENGTH:
                problems.append(f"{here}: object with {len(value)} keys; at most "
                                f"{MAX_LIST_LENGTH}")
                continue
            stack.extend((v, f"{where}.{k}" if where else str(k), depth + 1)
                         for k, v in value.items())
        elif isinstance(value, int) and not isinstance(value, bool) and abs(value) > 2**63:
            problems.append(f"{here}: integer {value:.3g} is out of range; at most 2**63")
    return problems


def _format_loc(loc: tuple[int | str, ...]) -> str:
    from simcore.scene.model import SENSOR_KINDS

    out = ""
    for i, part in enumerate(loc):
        if isinstance(part, int):
            out += f"[{part}]"
        elif i >= 2 and loc[i - 2] == "sensors" and part in SENSOR_KINDS:
            # pydantic's tag of the sensor's kind, not a key of the file
            out += f"({part})"
        elif isinstance(part, int):
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
        if err["type"] == "union_tag_invalid" and "kind" in str(err.get("ctx", {})):
            ctx = err.get("ctx", {})
            problems.append(f"{loc}.kind: unknown sensor kind {ctx.get('tag')!r} (kinds: "
                            f"{ctx.get('expected_tags')})")
            continue
        if loc == "(document)" and msg.startswith("@") and ": " in msg:
            # A check of the whole document that names its field: "@rigs[0].name: ...".
            loc, msg = msg[1:].split(": ", 1)
        if err["type"] in ("missing", "model_type", "model_attributes_type") or "input" not in err \
                or (err["type"] == "value_error" and isinstance(err["input"], (dict, list))):
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


def material_table(project: Project, *, copy: bool = True) -> dict[str, DualBandMaterial]:
    """Library materials overridden by the project's own materials, keyed by name.

    ``copy=False``: the library's models are the cached ones, not copies (read only).
    """
    table = load_material_library(copy=copy)
    table.update({m.name: m for m in project.materials})
    return table


def check_references(project: Project, base_dir: Path) -> list[str]:
    """Problems with references a schema cannot check: materials and mesh files."""
    problems = []
    materials = material_table(project, copy=False)   # names only: no deep copies
    for asset, name in project.materials_map.items():
        if name not in materials:
            problems.append(f"materials_map[{asset!r}]: unknown material {name!r}")
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
                what = ("is not a regular file (device, FIFO, socket or directory)"
                        if _exists(path) else "mesh file not found")
                problems.append(f"objects[{i}].geometry.path: {what}: {path}")
        if isinstance(geom, Person):
            problems += _person_problems(f"objects[{i}].geometry", geom, materials, base_dir)
    for where, radar in _radars(project):
        front = radar.rig_front_material
        if front not in materials:
            problems.append(f"{where}.rig_front_material: unknown material {front!r} "
                            f"(known: {', '.join(sorted(materials))})")
    return problems


def _radars(project: Project) -> list[tuple[str, Any]]:
    """Every radar configuration of the project with its field path (``rig.radar``, ...)."""
    return [(project.sensor_path(name), cfg)
            for name, cfg in project.sensors_of_kind("radar").items()]


def _person_problems(where: str, person: Person, materials: dict[str, Any],
                     base_dir: Path) -> list[str]:
    """A person's material names and BVH clip (checked and read: one clear line)."""
    from simcore.scene.people.bvh import BvhError, load_bvh, map_joints

    problems = [f"{where}.{field}: unknown material {name!r}"
                for field, name in (("skin", person.skin), ("clothing", person.clothing))
                if name not in materials]
    clip = person.motion.bvh
    # A clip outside the project's folder is read only by the pre-run checks, under the
    # path policy (--allow-outside-paths), never while the project loads.
    if clip is not None and is_inside_folder(resolve_mesh_path(base_dir, clip.path), base_dir):
        try:
            path = resolve_mesh_path(base_dir, clip.path)
            map_joints(load_bvh(path), source=path.name)
        except BvhError as exc:
            problems.append(f"{where}.motion.bvh.path: {exc}")
    return problems


def is_inside_folder(path: Path, folder: Path) -> bool:
    """Whether ``path`` (resolved, symlinks followed) lies inside ``folder``."""
    from simcore.scene.files import is_inside

    try:
        real = path.resolve()
    except (OSError, RuntimeError):
        return False
    return is_inside(real, folder)


def _exists(path: Path) -> bool:
    try:
        return path.exists()
    except OSError:
        return False


def resolve_mesh_path(base_dir: Path, mesh_path: str) -> Path:
    """Resolve a mesh path relative to the project file's directory."""
    path = Path(mesh_path)
    return path if path.is_absolute() else (base_dir / path)


def project_from_dict(data: Any, *, source: str = "project", base_dir: Path | None = None,
                      check_files: bool = True) -> Project:
    """Validate, migrate and check a parsed project document.

    ``check_files`` False skips the check that referenced files (meshes) exist under
    ``base_dir``: for a project stored in a dataset, read for its configuration.
    """
    if not isinstance(data, dict):
        kind = type(data).__name__
        raise ProjectError(source, [f"(document): expected a JSON object, got {kind}"])
    limits = document_limits(data)
    if limits:
        raise ProjectError(source, limits)
    data = migrate(data, source)
    try:
        project = Project.model_validate(data)
    except ValidationError as exc:
        raise ProjectError(source, [_sensor_located(p, data)
                                    for p in format_validation_error(exc)]) from None
    except RecursionError:
        raise ProjectError(source, ["(document): nested too deeply"]) from None
    problems = check_references(project, base_dir or Path.cwd()) if check_files else []
    if problems:
        raise ProjectError(source, problems)
    return project


def _sensor_located(problem: str, data: dict[str, Any]) -> str:
    """A project-wide problem of one sensor, at the sensor's field path in the document.

    ``(document): sensor 'x': field: …`` becomes ``rigs[0].sensors.x.field: …``.
    """
    import re

    match = re.match(r"\(document\): sensor '(\w+)': (\w+)[: ]", problem)
    if match is None:
        return problem
    name, field = match.groups()
    rigs = [data.get("rig"), *(data.get("rigs") or [])]
    for i, rig in enumerate(rigs):
        if not isinstance(rig, dict):
            continue
        where = "rig" if i == 0 else f"rigs[{i - 1}]"
        sensors = rig.get("sensors")
        if isinstance(sensors, dict) and name in sensors:
            where += f".sensors.{name}"
        elif i == 0 and name in ("tof", "radar", "rgb"):
            where += f".{name}"
        else:
            continue
        return f"{where}.{field}: {problem[match.end(2):].lstrip(': ')}"
    return problem


def _reject_constant(name: str) -> float:
    raise ValueError(f"{name} is not a valid number in a project file")


def load_project(path: str | os.PathLike[str]) -> Project:
    """Load and validate a project file; raise :class:`ProjectError` naming any bad field."""
    path = Path(path)
    source = str(path)
    text = _read_text(path, source)
    try:
        data = json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as exc:
        raise ProjectError(
            source, [f"not valid JSON: {exc.msg} at line {exc.lineno}, column {exc.colno}"]
        ) from None
    except ValueError as exc:
        # Also integers of more than 4300 digits (int_max_str_digits).
        raise ProjectError(source, [cap_line(str(exc))]) from None
    except RecursionError:
        raise ProjectError(source, [f"(document): nested more than {MAX_DEPTH} levels deep"]
                           ) from None
    return project_from_dict(data, source=source, base_dir=path.parent)


def _read_text(path: Path, source: str) -> str:
    """The file's text: a regular file of at most :data:`MAX_PROJECT_BYTES`, UTF-8."""
    from simcore.scene.files import InputFileError, read_text_file

    try:
        return read_text_file(path, max_bytes=MAX_PROJECT_BYTES)
    except InputFileError as exc:
        if exc.missing:
            raise ProjectError(source, ["file not found"]) from None
        problem = exc.problem
        if problem.startswith("not a regular file"):
            problem = "not a regular file (a device, FIFO, socket or directory)"
        elif problem.startswith("file has"):
            problem = problem.replace("; at most", "; a project file may have at most")
        elif problem.startswith("not UTF-8"):
            problem = f"cannot read file: {problem}"
        raise ProjectError(source, [cap_line(problem)]) from None


def project_to_json(project: Project) -> str:
    """Serialise a project to its canonical JSON text (stable, so round trips are exact)."""
    data = project.model_dump(mode="json")
    if not data.get("materials_map"):
        # Written only once an asset import fills it: files without imports stay as they were.
        data.pop("materials_map", None)
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


#: Temporary files of interrupted saves older than this are removed by the next save (s).
STALE_TEMP_AGE_S = 60.0


def _clean_stale_temps(folder: Path, name: str) -> None:
    """Remove temporary files that an interrupted save of ``name`` left behind."""
    now = time.time()
    for tmp in folder.glob(f".{name}.*.tmp"):
        try:
            if tmp.is_file() and not tmp.is_symlink() and now - tmp.stat().st_mtime > \
                    STALE_TEMP_AGE_S:
                tmp.unlink()
        except OSError:
            pass


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def save_project(project: Project, path: str | os.PathLike[str]) -> None:
    """Write the project atomically: a temporary file in the same folder, then a rename.

    A symlink is followed (its target is replaced, the link stays); the file keeps its
    permission bits (new files get the usual ``0666 & ~umask``); the folder is fsynced so
    the rename survives a power cut; temporary files of earlier interrupted saves are
    removed.
    """
    path = Path(path)
    if path.is_symlink():
        path = Path(os.path.realpath(path))
    text = project_to_json(project)
    path.parent.mkdir(parents=True, exist_ok=True)
    _clean_stale_temps(path.parent, path.name)
    try:
        mode = stat.S_IMODE(path.stat().st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fchmod(fh.fileno(), mode)
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    _fsync_dir(path.parent)
