"""``tofradar materials``: the materials and what each does per band."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from simcore.cli.common import (
    _Parser,
)
from simcore.scene.project_io import load_project

if TYPE_CHECKING:
    from simcore.scene.model import Project


def cmd_materials(args: argparse.Namespace) -> int:
    """List the materials (library, or a project's table) with what each does per band."""
    from simcore.scene.materials import load_material_library, summarize_material
    from simcore.scene.project_io import material_table
    from simcore.scene.radar_config import SPEED_OF_LIGHT

    if args.project:
        project = load_project(args.project)
        table = material_table(project)
        f_radar = SPEED_OF_LIGHT / project.radar().wavelength_m
        own = {m.name for m in project.materials}
        users: dict[str, list[str]] = {}
        for o in project.objects:
            users.setdefault(o.material, []).append(o.name)
    else:
        # The library alone: at the default radar's chirp centre frequency.
        from simcore.scene.radar_config import RadarConfig

        f_radar = SPEED_OF_LIGHT / RadarConfig().wavelength_m
        table, own, users = load_material_library(), set(), {}
    for name in sorted(table):
        mat = table[name]
        tag = " (project)" if name in own else ""
        print(f"{name}{tag}: {summarize_material(mat, f_radar)}")
        if mat.description:
            print(f"    {mat.description}")
        if name in users:
            print(f"    used by {', '.join(users[name])}")
    if args.project:
        _print_materials_map(project)
    return 0


def _print_materials_map(project: Project) -> None:
    """The imported asset materials and the library materials they map to."""
    if not project.materials_map:
        return
    print("asset materials (materials_map):")
    for asset, name in sorted(project.materials_map.items()):
        n = sum(1 for o in project.objects if o.material in (f"asset:{asset}",))
        print(f"  {asset} -> {name} ({n} objects)")


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``materials`` subcommand."""
    p = sub.add_parser("materials", help="list the materials and what each does per band",
                       parents=common)
    p.add_argument("project", nargs="?",
                   help="project (its material table and users; default: the library)")
    p.set_defaults(func=cmd_materials)
