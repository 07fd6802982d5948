"""Randomized scenarios: a spec of distributions over project fields → N valid projects.

A scenario spec (JSON or YAML, ``docs/scenarios.md``) names a base project (a bundled
example or a project file) and, for any field of the project document (the paths of
``tofradar sweep --vary``), a distribution: ``{"uniform": [low, high]}``,
``{"normal": {"mean": m, "std": s, "min": a, "max": b}}`` (clipped) or
``{"choice": [v1, v2, ...]}``. Project ``i`` of a run with seed ``K`` draws its values from
``numpy.random.default_rng([K, i])`` in the spec's field order, so the same spec and seed
give byte-identical projects on any machine; each project records the spec's name, the
seed and its index in its ``description`` and gets its own noise seed.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import Field, ValidationError, field_validator, model_validator

from simcore.preflight import MAX_SEED, RunError
from simcore.resources import RESOURCES_DIR
from simcore.scene import fieldpath
from simcore.scene.geometry import Mesh
from simcore.scene.limits import (
    MAX_SCENARIO_COUNT,
    MAX_SPEC_BYTES,
    MAX_SPEC_DEPTH,
    MAX_SPEC_FIELDS,
    MAX_SPEC_VALUES,
)
from simcore.scene.project_io import ProjectError, project_from_dict, project_to_json

from ._dists import MAX_CHOICES, Choice, Normal, Strict, Uniform
from .furnish import (
    FURNITURE_DIR,
    MAX_ADDED_OBJECTS,
    PIECES,
    FurnishError,
    FurnitureEntry,
    MaterialEntry,
    PeopleEntry,
    Room,
    draw_materials,
    furnish,
)

#: Most projects of one ``generate`` run, fields varied by one spec, values of a choice;
#: largest spec file (bytes) and nesting depth (:mod:`simcore.scene.limits`).
MAX_COUNT = MAX_SCENARIO_COUNT
MAX_FIELDS = MAX_SPEC_FIELDS
MAX_DEPTH = MAX_SPEC_DEPTH
SPEC_FORMAT = "tofradar-scenario/1"


class ScenarioError(RunError):
    """A scenario spec that cannot be used (one line, naming the field)."""


#: Most parts of one piece of each kind (sized by drawing many).
_MOST_PARTS = {name: max(len(p.build(np.random.default_rng(k))[0]) for k in range(32))
               for name, p in PIECES.items()}


class ScenarioSpec(Strict):
    """A scenario: a base project and distributions over its fields."""

    format: str = SPEC_FORMAT
    name: str = Field(min_length=1, max_length=200)
    base: str = Field(min_length=1, max_length=4096)
    vary: dict[str, Uniform | Normal | Choice] = Field(default_factory=dict,
                                                       max_length=MAX_FIELDS)
    materials: dict[str, MaterialEntry] = Field(default_factory=dict, max_length=MAX_FIELDS)
    room: Room | None = None
    furniture: list[FurnitureEntry] = Field(default_factory=list, max_length=MAX_FIELDS)
    people: list[PeopleEntry] = Field(default_factory=list, max_length=MAX_FIELDS)

    @model_validator(mode="after")
    def _furnishable(self) -> ScenarioSpec:
        if (self.furniture or self.people) and self.room is None:
            raise ValueError("furniture and people need a 'room' ({\"x_m\": [x0, x1], "
                             "\"y_m\": [y0, y1]}) to be placed in")
        most = sum(e.count[1] * _MOST_PARTS[e.piece] for e in self.furniture) + sum(
            e.count[1] for e in self.people)
        if most > MAX_ADDED_OBJECTS:
            raise ValueError(f"furniture and people may add up to {most} objects; at most "
                             f"{MAX_ADDED_OBJECTS}")
        return self

    @field_validator("format")
    @classmethod
    def _format(cls, v: str) -> str:
        if v != SPEC_FORMAT:
            raise ValueError(f"unknown format {v!r}; expected {SPEC_FORMAT!r}")
        return v


#: Most values (numbers, strings, lists, objects) of one spec, aliases counted as often as
#: they are used (a YAML "billion laughs" of nested aliases stops here).
MAX_VALUES = MAX_SPEC_VALUES


def _depth(doc: Any, limit: int = MAX_DEPTH) -> int:
    """Nesting depth of ``doc`` (stops past ``limit``); raises ValueError past MAX_VALUES."""
    stack, deepest, seen = [(doc, 1)], 0, 0
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        seen += 1
        if seen > MAX_VALUES:
            raise ValueError(f"more than {MAX_VALUES} values")
        if d > limit:
            break
        if isinstance(node, dict):
            stack.extend((v, d + 1) for v in node.values())
        elif isinstance(node, list):
            stack.extend((v, d + 1) for v in node)
    return deepest


def load_spec(path: str | Path) -> tuple[ScenarioSpec, Path]:
    """Read and validate a spec (JSON, or YAML for ``.yaml``/``.yml``); its base project.

    Raises :class:`ScenarioError` with one line naming what is wrong.
    """
    from simcore.scene.files import InputFileError, read_text_file

    path = Path(path)
    try:
        text = read_text_file(path, max_bytes=MAX_SPEC_BYTES, label=str(path))
    except InputFileError as exc:
        if exc.missing:
            raise ScenarioError(f"{path}: no such spec file") from None
        raise ScenarioError(str(exc)) from None
    try:
        if path.suffix.lower() in (".yaml", ".yml"):
            import yaml

            doc = yaml.safe_load(text)
        else:
            doc = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise ScenarioError(f"{path}: not valid {path.suffix.lstrip('.') or 'JSON'}: "
                            f"{str(exc)[:200]}") from None
    except Exception as exc:  # noqa: BLE001 — yaml's errors
        raise ScenarioError(f"{path}: not valid YAML: {str(exc)[:200]}") from None
    try:
        too_deep = _depth(doc) > MAX_DEPTH
    except ValueError as exc:
        raise ScenarioError(f"{path}: {exc} (YAML aliases count each time they are used)"
                            ) from None
    if too_deep:
        raise ScenarioError(f"{path}: nested deeper than {MAX_DEPTH} levels")
    if not isinstance(doc, dict):
        raise ScenarioError(f"{path}: a spec is an object with 'name', 'base' and 'vary'")
    vary = doc.get("vary", {})
    for field, dist in (vary.items() if isinstance(vary, dict) else ()):
        kinds = list(dist) if isinstance(dist, dict) else []
        if len(kinds) != 1 or kinds[0] not in ("uniform", "normal", "choice"):
            raise ScenarioError(f"{path}: vary.{field}: a distribution is one of "
                                '{"uniform": [low, high]}, {"normal": {"mean": m, "std": s}}, '
                                f'{{"choice": [...]}}; got {json.dumps(dist)[:80]}')
    try:
        spec = ScenarioSpec.model_validate(doc)
    except ValidationError as exc:
        raise ScenarioError(f"{path}: {_first_error(exc, vary)}") from None
    return spec, _base_path(spec, path)


def _first_error(exc: ValidationError, vary: Any) -> str:
    """The error of the distribution kind the spec names (not of the union's other kinds)."""
    names = {"uniform": "Uniform", "normal": "Normal", "choice": "Choice"}
    errors = exc.errors()
    for err in errors:
        loc = err["loc"]
        if len(loc) >= 3 and loc[0] == "vary" and isinstance(vary, dict):
            kind = next(iter(vary.get(loc[1]) or {"": 0}))
            if loc[2] != names.get(kind):
                continue
            loc = (loc[0], loc[1], *loc[3:])
        return f"{'.'.join(str(p) for p in loc) or '(spec)'}: {_message(err)}"
    err = errors[0]
    return f"{'.'.join(str(p) for p in err['loc']) or '(spec)'}: {_message(err)}"


def _message(err: Any) -> str:
    """A pydantic error's message and the value it refused, without pydantic's prefixes."""
    msg = str(err["msg"]).removeprefix("Value error, ")
    value = err.get("input")
    if isinstance(value, (int, float, str, bool)) or value is None:
        shown = repr(value)
        msg += f" (got {shown[:60]})"
    return msg


def _base_path(spec: ScenarioSpec, spec_path: Path) -> Path:
    from simcore.resources import example_path

    candidate = (spec_path.parent / spec.base)
    if candidate.is_file():
        return candidate
    if candidate.exists() or candidate.is_symlink():
        raise ScenarioError(f"{spec_path}: base {spec.base!r} is not a regular file (device, "
                            "FIFO, socket, directory or dangling symlink)")
    bundled = example_path(spec.base)
    if bundled.is_file():
        return bundled
    raise ScenarioError(f"{spec_path}: base {spec.base!r} is neither a project file next to "
                        "the spec nor a bundled example")


def scene(spec: ScenarioSpec, base_doc: dict[str, Any], *, seed: int, index: int,
          base_dir: Path) -> str:
    """Project ``index`` of the scenario as canonical JSON (validated)."""
    rng = np.random.default_rng([seed, index])
    doc = json.loads(json.dumps(base_doc))
    values: dict[str, Any] = {}
    for path, dist in spec.vary.items():
        values[path] = dist.draw(rng)
        try:
            fieldpath.set_in(doc, path, values[path])
        except fieldpath.FieldPathError as exc:
            raise ScenarioError(f"vary {path!r}: {exc} in the base project") from None
    doc["seed"] = int(rng.integers(0, min(MAX_SEED, 2**31 - 1)))
    try:
        if spec.materials:
            doc["materials"] = list(doc.get("materials") or []) + draw_materials(
                spec.materials, _material_library(doc), rng)
        bundled: list[int] = []
        if spec.room is not None:
            bundled = furnish(doc, spec.room, spec.furniture, spec.people, rng, index=index)
    except FurnishError as exc:
        raise ScenarioError(str(exc)) from None
    record = spec.model_dump(mode="json", by_alias=True)
    for key in ("materials", "room", "furniture", "people"):    # a spec of 'vary' alone is
        if not record[key]:                                      # recorded as it was before
            del record[key]
    doc["description"] = json.dumps({"scenario": spec.name, "seed": seed, "index": index,
                                     "spec": record}, sort_keys=True)
    doc["name"] = f"{spec.name} #{index}"
    # Bundled furniture meshes are checked where they are; the project names the copy next
    # to it (generate() writes it), so a folder of scenes is complete and the same bytes
    # on every machine.
    checked = json.loads(json.dumps(doc))
    for i in bundled:
        checked["objects"][i]["geometry"]["path"] = str(RESOURCES_DIR / doc["objects"][i][
            "geometry"]["path"])
    try:
        project = project_from_dict(checked, base_dir=base_dir, source=f"scene {index}")
    except ProjectError as exc:
        raise ScenarioError(f"scene {index} is not a valid project: {str(exc)[:300]}") from None
    for i in bundled:
        geometry = project.objects[i].geometry
        assert isinstance(geometry, Mesh)
        geometry.path = doc["objects"][i]["geometry"]["path"]
    return project_to_json(project)


def copy_furniture_meshes(spec: ScenarioSpec, out: Path) -> list[Path]:
    """Copy the bundled meshes of the spec's mesh pieces into ``out/furniture``."""
    names = sorted({PIECES[e.piece].mesh for e in spec.furniture
                    if PIECES[e.piece].mesh is not None}, key=str)
    copied = []
    for name in names:
        target = out / FURNITURE_DIR / f"{name}.obj"
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(RESOURCES_DIR / FURNITURE_DIR / f"{name}.obj", target)
        copied.append(target)
    return copied


def _material_library(doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """The library's materials and the project's own (which override), by name."""
    from simcore.scene.materials import load_material_library

    out = {m.name: m.model_dump(mode="json") for m in load_material_library().values()}
    for m in doc.get("materials") or []:
        if isinstance(m, dict) and "name" in m:
            out[m["name"]] = m
    return out


def generate(spec_path: str | Path, out: str | Path, *, count: int, seed: int = 0,
             overwrite: bool = False,
             on_project: Callable[[int, int], None] | None = None,
             n_frames: int | None = None, allow_outside_paths: bool = False,
             memory_budget_bytes: int | None = None) -> list[Path]:
    """Write ``count`` projects of the spec into ``out`` (``scene_00000.json``, …).

    All or nothing: every scene is validated and passes the pre-run checks of
    :func:`simcore.preflight.check` (positions, speeds, rates, frame counts, mesh and clip
    files in ``out``, memory) as ``tofradar validate`` would run them there, each written
    to a hidden temporary file; only when all have passed do they replace the folder's
    scenes. A failure removes what this call wrote and leaves the folder as it was.
    ``on_project(done, count)`` is called after each project (progress).

    Parameters
    ----------
    n_frames : int, optional
        Frames each scene will run (``--frames`` of ``generate --run``); default: the
        scene's timeline.
    allow_outside_paths : bool
        Accept mesh and clip files outside ``out``.
    memory_budget_bytes : int, optional
        Memory budget of a frame (default: as ``tofradar run``).

    Returns the files written. Raises :class:`ScenarioError` for a bad spec, a count out
    of 1..MAX_COUNT, a negative seed, existing scene files without ``overwrite``, or a
    scene that is not valid or does not pass the pre-run checks.
    """
    if not 1 <= count <= MAX_COUNT:
        raise ScenarioError(f"--count {count}: allowed 1..{MAX_COUNT}")
    if not 0 <= seed <= MAX_SEED:
        raise ScenarioError(f"--seed {seed}: allowed 0..{MAX_SEED}")
    spec, base = load_spec(spec_path)
    base_doc = _read_base(base)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ScenarioError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.glob("scene_*.json")) and not overwrite:
        raise ScenarioError(f"--out {out} already holds scenes; use --overwrite")
    made_out = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ScenarioError(f"--out {out}: cannot create the folder ({exc.strerror})") from None
    furniture = out / FURNITURE_DIR
    made_furniture = not furniture.exists()
    staged: list[Path] = []
    try:
        copy_furniture_meshes(spec, out)
        for i in range(count):
            text = scene(spec, base_doc, seed=seed, index=i, base_dir=base.parent)
            _preflight_scene(text, out, index=i, n_frames=n_frames,
                             allow_outside_paths=allow_outside_paths,
                             memory_budget_bytes=memory_budget_bytes)
            tmp = out / f".scene_{i:05d}.json.tmp"
            staged.append(tmp)
            tmp.write_text(text, encoding="utf-8")
            if on_project is not None:
                on_project(i + 1, count)
    except BaseException as exc:
        for tmp in staged:
            tmp.unlink(missing_ok=True)
        if made_furniture:
            shutil.rmtree(furniture, ignore_errors=True)
        if made_out:
            shutil.rmtree(out, ignore_errors=True)
        if isinstance(exc, OSError):
            raise ScenarioError(f"--out {out}: cannot write the scenes ({exc})") from None
        raise
    for old in out.glob("scene_*.json"):       # --overwrite: no stale scene of a larger run
        old.unlink()
    written = []
    for i, tmp in enumerate(staged):
        target = out / f"scene_{i:05d}.json"
        os.replace(tmp, target)
        written.append(target)
    return written


def _read_base(base: Path) -> dict[str, Any]:
    """The base project's document (a regular file of at most a project's size)."""
    from simcore.scene.files import InputFileError, read_json_file
    from simcore.scene.project_io import MAX_PROJECT_BYTES

    try:
        doc = read_json_file(base, max_bytes=MAX_PROJECT_BYTES, label=f"base {base}")
    except InputFileError as exc:
        raise ScenarioError(str(exc)) from None
    if not isinstance(doc, dict):
        raise ScenarioError(f"base {base}: a project file holds a JSON object")
    return doc


def _preflight_scene(text: str, folder: Path, *, index: int, n_frames: int | None,
                     allow_outside_paths: bool, memory_budget_bytes: int | None) -> None:
    """Scene ``index`` as ``tofradar validate`` would check it in ``folder``."""
    from simcore.preflight import check

    try:
        project = project_from_dict(json.loads(text), base_dir=folder,
                                    source=f"scene {index}")
    except ProjectError as exc:
        hint = ("; the scenes refer to files relative to --out: put the base project's "
                "mesh and clip files there" if any("not found" in p for p in exc.problems)
                else "")
        raise ScenarioError(f"scene {index} is not a valid project in {folder}: "
                            f"{'; '.join(exc.problems)[:300]}{hint}") from None
    problems = check(project, base_dir=folder, n_frames=n_frames,
                     allow_outside_paths=allow_outside_paths,
                     memory_budget_bytes=memory_budget_bytes)
    if problems:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise ScenarioError(f"scene {index} would not run: {problems[0]}{more}; nothing "
                            "was written")


#: Objects larger than this (m, any side) are the room's structure: a spec made from a
#: scene keeps them where they are.
STRUCTURE_SIZE_M = 1.5


def _largest_side(geometry: dict[str, Any]) -> float | None:
    """Largest side (m) of a parametric geometry; None for meshes and unknown kinds."""
    sides: list[float] = []
    for key, value in geometry.items():
        if key == "size_m" and isinstance(value, list):
            sides.extend(float(v) for v in value)
        elif key in ("radius_m",):
            sides.append(2.0 * float(value))
        elif key in ("height_m", "edge_m", "length_m", "width_m", "side_m"):
            sides.append(float(value))
    return max(sides) if sides else None


def spec_from_project(project_doc: dict[str, Any], *, name: str, base: str,
                      move_m: float = 0.1, turn_deg: float = 15.0) -> dict[str, Any]:
    """A starting scenario spec for a scene: what can move without breaking the scene.

    Varies the rig's x and y (uniform within ±``move_m`` of where it is) and yaw (within
    ±``turn_deg``), and the same of every object that stands alone: an object stands alone
    when it is not the room's structure (every side under :data:`STRUCTURE_SIZE_M`, not a
    mesh), has no keyframed path, and shares the stem of its name (``desk1`` of
    ``desk1_leg2``) with no other object, so furniture built of several parts keeps its
    parts together. A person's height varies by ±5 % and its walking speed by ±20 %. The
    result is a spec document to edit and :func:`load_spec`; ``base`` is the project file
    it refers to (relative to the spec's folder).
    """
    half_m, half_deg = move_m, turn_deg

    def around(value: float, half: float) -> dict[str, list[float]]:
        return {"uniform": [round(value - half, 6), round(value + half, 6)]}

    vary: dict[str, Any] = {}
    rig = project_doc.get("rig", {}).get("pose", {})
    pos, rot = rig.get("position_m", [0.0, 0.0, 0.0]), rig.get("rotation_deg", [0.0, 0.0, 0.0])
    vary["rig.pose.position_m[0]"] = around(pos[0], half_m)
    vary["rig.pose.position_m[1]"] = around(pos[1], half_m)
    vary["rig.pose.rotation_deg[2]"] = around(rot[2], half_deg)
    objects = project_doc.get("objects", [])
    stems: dict[str, int] = {}
    for obj in objects:
        stem = obj["name"].rsplit("_", 1)[0] if "_" in obj["name"] else obj["name"]
        stems[stem] = stems.get(stem, 0) + 1
    for i, obj in enumerate(objects):
        geometry = obj.get("geometry", {})
        if geometry.get("kind") == "person":
            height = float(geometry.get("height_m", 1.7))
            vary[f"objects[{i}].geometry.height_m"] = {
                "uniform": [round(0.95 * height, 4), round(1.05 * height, 4)]}
            walk = (geometry.get("motion") or {}).get("walk")
            if walk and walk.get("speed_mps"):
                speed = float(walk["speed_mps"])
                vary[f"objects[{i}].geometry.motion.walk.speed_mps"] = {
                    "uniform": [round(0.8 * speed, 4), round(1.2 * speed, 4)]}
            continue
        side = _largest_side(geometry)
        stem = obj["name"].rsplit("_", 1)[0] if "_" in obj["name"] else obj["name"]
        if side is None or side >= STRUCTURE_SIZE_M or stems[stem] > 1 \
                or (obj.get("motion") or {}).get("keyframes"):
            continue
        opos = obj.get("pose", {}).get("position_m", [0.0, 0.0, 0.0])
        orot = obj.get("pose", {}).get("rotation_deg", [0.0, 0.0, 0.0])
        vary[f"objects[{i}].pose.position_m[0]"] = around(opos[0], half_m)
        vary[f"objects[{i}].pose.position_m[1]"] = around(opos[1], half_m)
        vary[f"objects[{i}].pose.rotation_deg[2]"] = around(orot[2], half_deg)
    return {"format": SPEC_FORMAT, "name": name, "base": base, "vary": vary}


def export_spec(project_path: str | Path, spec_path: str | Path, *,
                name: str | None = None) -> ScenarioSpec:
    """Write the starting spec of a saved project (:func:`spec_from_project`) and check it.

    The spec refers to the project file by its path relative to the spec's folder; it is
    validated (:func:`load_spec`) and its first scene generated before it is kept.
    """
    import os
    import tempfile

    project_path, spec_path = Path(project_path).resolve(), Path(spec_path)
    doc = json.loads(project_path.read_text(encoding="utf-8"))
    base = os.path.relpath(project_path, spec_path.resolve().parent)
    spec_doc = spec_from_project(doc, name=name or spec_path.stem, base=base)
    spec_path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=spec_path.parent, prefix=f".{spec_path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(json.dumps(spec_doc, indent=2) + "\n")
        spec, base_file = load_spec(tmp)
        scene(spec, json.loads(base_file.read_text(encoding="utf-8")), seed=0, index=0,
              base_dir=base_file.parent)
        os.replace(tmp, spec_path)
    finally:
        Path(tmp).unlink(missing_ok=True)
    return spec


__all__ = ["MAX_CHOICES", "PIECES", "Choice", "Normal", "ScenarioError", "ScenarioSpec",
           "Uniform", "copy_furniture_meshes", "export_spec", "generate", "load_spec", "scene",
           "spec_from_project"]
