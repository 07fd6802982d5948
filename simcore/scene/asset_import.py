"""Asset materials mapped to the dual-band library, and an asset turned into a project.

Mapping (:func:`default_mapping`), first rule that applies:

1. an override given by the user (``--map NAME=MATERIAL``, the GUI's mapping dialog);
2. a name rule (:data:`NAME_RULES`): words in the asset material's name such as
   ``metal``/``steel``/``alu`` → ``aluminium``, ``glass``, ``wood``, ``paper``/``cardboard``,
   ``fabric``, ``plastic``, ``concrete``, ``paint``/``plaster``/``wall``, ``skin``;
3. the glTF PBR parameters: an explicit ``metallicFactor`` ≥ 0.9 → ``aluminium``;
4. nothing applies: :data:`FALLBACK_MATERIAL`, and the name is reported as unmapped.

Each asset material becomes one project material ``asset:NAME``: a copy of the mapped
library material whose ToF and visible roughness come from the glTF ``roughnessFactor``
when the file sets one (Beckmann rms slope = perceptual roughness², clipped to the model's
[0.01, 2]). The radar band keeps the library's roughness: a surface rough to light
(micrometres) is smooth at the radar's 5 mm wavelength. The objects use ``asset:NAME``;
the project's ``materials_map`` records ``NAME → library material``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.assets import (
    ASSET_MATERIAL_PREFIX,
    FALLBACK_MATERIAL,
    AssetError,
    AssetMaterial,
    AssetScene,
    unique_name,
)
from simcore.scene.geometry import Mesh
from simcore.scene.materials import DualBandMaterial
from simcore.scene.model import Project, SceneObject
from simcore.scene.motion import Pose
from simcore.scene.project_io import MAX_OBJECTS, material_table

#: Name rules: (regular expression on the lower-case name, library material), in order.
NAME_RULES: tuple[tuple[str, str], ...] = (
    (r"absorb", "radar_absorber"),
    (r"retro", "ir_retroreflector_tape"),
    (r"metal|steel|alumin|\balu|iron|chrome|copper|brass|zinc", "aluminium"),
    (r"glass|window", "glass"),
    (r"wood|oak|pine|birch|beech|walnut|timber|plywood|veneer|\bmdf", "wood"),
    (r"paper|cardboard|carton|\bcard", "paper"),
    (r"fabric|cloth|textile|cotton|linen|wool|carpet|upholster|curtain", "fabric"),
    (r"plastic|rubber|pvc|nylon|acrylic|polymer", "black_plastic"),
    (r"skin|flesh", "skin"),
    (r"concrete|cement|brick|stone|asphalt", "concrete"),
    (r"paint|plaster|drywall|gypsum|wall", "white_paint"),
)
#: Explicit glTF ``metallicFactor`` from which a material maps to a metal.
METALLIC_THRESHOLD = 0.9
METAL_MATERIAL = "aluminium"


@dataclass(frozen=True)
class Mapping:
    """How one asset material was mapped.

    Attributes
    ----------
    asset : str
        Asset material name.
    material : str
        Library material it maps to.
    reason : str
        Why: ``"--map"``, ``"name rule 'metal…'"``, ``"PBR metallic 1"``, or ``"unmapped"``.
    roughness : float or None
        ToF/visible roughness (Beckmann rms slope) from the asset's PBR roughness, if any.
    """

    asset: str
    material: str
    reason: str
    roughness: float | None = None

    @property
    def unmapped(self) -> bool:
        """Whether no rule applied (the fallback material is used)."""
        return self.reason == "unmapped"


def rule_material(name: str, library: set[str]) -> tuple[str, str] | None:
    """(library material, rule) of the first name rule matching ``name``, or None."""
    low = name.lower()
    for pattern, material in NAME_RULES:
        if material in library and re.search(pattern, low):
            return material, f"name rule {pattern.split('|')[0]!r}"
    return None


def default_mapping(materials: dict[str, AssetMaterial], library: set[str], *,
                    overrides: dict[str, str] | None = None) -> dict[str, Mapping]:
    """Map every asset material to a library material (see the module's rules).

    Parameters
    ----------
    materials : dict of str to AssetMaterial
        The asset's materials by name.
    library : set of str
        Names of the materials available (library and project materials).
    overrides : dict of str to str, optional
        Asset material → material chosen by the user; each must be in ``library``.
    """
    overrides = overrides or {}
    for asset, material in overrides.items():
        if material not in library:
            raise AssetError(f"--map {asset}={material}: unknown material {material!r} "
                             f"(known: {', '.join(sorted(library))})")
    out = {}
    for name, mat in materials.items():
        rough = None if mat.roughness is None else min(2.0, max(0.01, mat.roughness ** 2))
        if name in overrides:
            out[name] = Mapping(name, overrides[name], "--map", rough)
            continue
        rule = rule_material(name, library)
        if rule is not None:
            out[name] = Mapping(name, rule[0], rule[1], rough)
        elif (mat.metallic is not None and mat.metallic >= METALLIC_THRESHOLD
              and METAL_MATERIAL in library):
            out[name] = Mapping(name, METAL_MATERIAL, f"PBR metallic {mat.metallic:g}", rough)
        else:
            out[name] = Mapping(name, FALLBACK_MATERIAL, "unmapped", rough)
    return out


def parse_map_options(items: list[str] | None) -> dict[str, str]:
    """``["ASSET=MATERIAL", …]`` → dict; a malformed item is an :class:`AssetError`."""
    out = {}
    for item in items or []:
        asset, sep, material = item.rpartition("=")
        if not sep or not asset.strip() or not material.strip():
            raise AssetError(f"--map {item!r}: expected ASSET_MATERIAL=LIBRARY_MATERIAL")
        out[asset.strip()] = material.strip()
    return out


def project_material(mapping: Mapping, table: dict[str, DualBandMaterial]
                     ) -> DualBandMaterial:
    """The project material ``asset:NAME``: the library material, PBR roughness applied."""
    base = table[mapping.material]
    bands = {b: m.model_copy() for b, m in base.bands.items()}
    if mapping.roughness is not None:
        for band in ("tof", "visible"):
            bands[band] = base.band(band).model_copy(update={"roughness": mapping.roughness})
    note = (f" (ToF/visible roughness {mapping.roughness:.3g} from the asset)"
            if mapping.roughness is not None else "")
    return DualBandMaterial(
        name=ASSET_MATERIAL_PREFIX + mapping.asset,
        description=f"asset material {mapping.asset!r} as {mapping.material}{note}",
        color_rgb=base.color_rgb, bands=bands)


def write_ply(path: Path, points: NDArray[np.float64], triangles: NDArray[np.int64]) -> None:
    """Write a binary little-endian PLY (double vertices, int triangle lists)."""
    header = (f"ply\nformat binary_little_endian 1.0\ncomment tofradar asset import\n"
              f"element vertex {len(points)}\nproperty double x\nproperty double y\n"
              f"property double z\nelement face {len(triangles)}\n"
              f"property list uchar int vertex_indices\nend_header\n").encode("ascii")
    faces = np.empty(len(triangles), dtype=[("k", "u1"), ("i", "<i4", 3)])
    faces["k"] = 3
    faces["i"] = triangles
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "wb") as fh:
        fh.write(header)
        fh.write(np.ascontiguousarray(points, dtype="<f8").tobytes())
        fh.write(faces.tobytes())


def _file_stem(name: str, taken: set[str]) -> str:
    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", name)[:80].strip(".") or "object"
    return unique_name(stem.lower(), taken)


def default_rig_pose(bounds: NDArray[np.float64]) -> Pose:
    """A rig pose that sees the whole scene of ``bounds`` (shape (2, 3), m).

    Room-sized scenes (both horizontal extents ≥ 2 m): inside, 15 % in from the −x side,
    1.5 m above the floor (below the ceiling), looking at the centre. Smaller ones: from
    outside at −x, twice the largest extent plus 1 m away, looking down at the centre.
    """
    lo, hi = bounds
    centre, extent = (lo + hi) / 2, hi - lo
    if extent[0] >= 2.0 and extent[1] >= 2.0:
        eye = np.array([lo[0] + 0.15 * extent[0], centre[1],
                        min(lo[2] + 1.5, hi[2] - 0.1 * extent[2])])
    else:
        eye = centre + np.array([-(2.0 * float(extent.max()) + 1.0), 0.0, 0.5 * extent[2]])
    d = centre - eye
    yaw = math.degrees(math.atan2(d[1], d[0]))
    pitch = math.degrees(math.atan2(-d[2], math.hypot(d[0], d[1])))
    return Pose(position_m=tuple(float(v) for v in eye), rotation_deg=(0.0, pitch, yaw))


@dataclass
class ImportResult:
    """A project built from an asset, and how its materials were mapped."""

    project: Project
    mappings: dict[str, Mapping]
    object_names: list[str]
    n_triangles: int
    skipped: list[str]

    def report_lines(self) -> list[str]:
        """The mapping used, one line per asset material, unmapped names flagged once."""
        counts: dict[str, int] = {}
        for obj in self.project.objects:
            if obj.name in self.object_names:
                key = obj.material.removeprefix(ASSET_MATERIAL_PREFIX)
                counts[key] = counts.get(key, 0) + 1
        lines = []
        for name, m in sorted(self.mappings.items()):
            rough = f", roughness {m.roughness:.3g}" if m.roughness is not None else ""
            why = ("UNMAPPED: no rule matched, using " + m.material
                   + f" (choose with --map '{name}=MATERIAL')") if m.unmapped else m.reason
            lines.append(f"  {name} -> {m.material}  [{why}{rough}; "
                         f"{counts.get(name, 0)} objects]")
        return lines


def build_project(scene: AssetScene, out_path: Path, *, base: Project | None = None,
                  overrides: dict[str, str] | None = None) -> ImportResult:
    """Write the scene's meshes beside ``out_path`` and build the project holding them.

    Parameters
    ----------
    scene : AssetScene
        What :func:`simcore.scene.assets.read_asset` read.
    out_path : Path
        Where the project file will be written; meshes go to ``<stem>.meshes/`` beside it
        (relative paths, inside the project folder).
    base : Project, optional
        Objects, rig and settings the scene is added to; without one, a new project with a
        rig looking at the scene's centre (:func:`default_rig_pose`).
    overrides : dict of str to str, optional
        Asset material → library material chosen by the user.
    """
    base = base or Project(name=scene.source.stem)
    table = material_table(base)
    mappings = default_mapping(scene.materials, set(table), overrides=overrides)
    if len(base.objects) + len(scene.objects) > MAX_OBJECTS:
        raise AssetError(f"{scene.source.name}: {len(scene.objects)} objects added to "
                         f"{len(base.objects)} exceed the project limit of {MAX_OBJECTS}")
    folder = Path(out_path).resolve().parent
    mesh_dir = f"{Path(out_path).stem}.meshes"
    names = {o.name for o in base.objects}
    # Mesh files BASE already uses in the same folder (an earlier import) are kept.
    files = {Path(o.geometry.path).stem for o in base.objects if isinstance(o.geometry, Mesh)
             and Path(o.geometry.path).parent.as_posix() == mesh_dir}
    objects = list(base.objects)
    next_id = max((o.id for o in objects), default=0) + 1
    added = []
    for obj in scene.objects:
        rel = f"{mesh_dir}/{_file_stem(obj.name, files)}.ply"
        write_ply(folder / rel, obj.points, obj.triangles)
        name = unique_name(obj.name, names)
        objects.append(SceneObject(id=next_id, name=name, geometry=Mesh(path=rel),
                                   pose=obj.pose, material=ASSET_MATERIAL_PREFIX + obj.material))
        added.append(name)
        next_id += 1
    made = {ASSET_MATERIAL_PREFIX + m.asset: project_material(m, table)
            for m in mappings.values()}
    materials = [m for m in base.materials if m.name not in made] + list(made.values())
    materials_map = {**base.materials_map, **{m.asset: m.material for m in mappings.values()}}
    data = base.model_dump()
    data["objects"] = [o.model_dump() for o in objects]
    data["materials"] = [m.model_dump() for m in materials]
    data["materials_map"] = materials_map
    if not base.objects and scene.objects:
        data["rig"]["pose"] = default_rig_pose(scene.bounds()).model_dump()
    project = Project.model_validate(data)
    return ImportResult(project, mappings, added, scene.n_triangles, list(scene.skipped))


__all__ = ["METALLIC_THRESHOLD", "NAME_RULES", "ImportResult", "Mapping", "build_project",
           "default_mapping", "default_rig_pose", "parse_map_options", "project_material",
           "rule_material", "write_ply"]
