"""``tofradar import``: a glTF/GLB/OBJ scene as a project's objects."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    CliError,
    _Parser,
)
from simcore.scene.project_io import load_project


def cmd_import(args: argparse.Namespace) -> int:
    """Import a glTF/GLB/OBJ scene into a new project (or into a copy of BASE)."""
    from simcore.scene.asset_import import build_project, parse_map_options
    from simcore.scene.assets import AssetError, read_asset
    from simcore.scene.project_io import save_project

    out = Path(args.out)
    if out.suffix.lower() != ".json":
        raise CliError(f"--out {out}: the project file must end in .json")
    base = load_project(args.into) if args.into else None
    if base is not None and Path(args.into).resolve().parent != out.resolve().parent and any(
            o.geometry.kind == "mesh" for o in base.objects):
        raise CliError(f"--into {args.into}: its mesh paths are relative to its folder; "
                       "write --out into the same folder")
    try:
        overrides = parse_map_options(args.map)
        scene = read_asset(Path(args.scene), up=args.up,
                           allow_outside_paths=args.allow_outside_paths)
        result = build_project(scene, out, base=base, overrides=overrides)
    except AssetError as exc:
        raise CliError(str(exc)) from None
    save_project(result.project, out)
    print(f"wrote {out}: {len(result.object_names)} objects, {result.n_triangles} triangles "
          f"from {Path(args.scene).name} (meshes in {out.stem}.meshes/)")
    print("material mapping:")
    for line in result.report_lines():
        print(line)
    for note in result.skipped:
        print(f"  skipped: {note}")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``import`` subcommand."""
    p = sub.add_parser("import", help="import a glTF/GLB/OBJ scene as a project's objects",
                       parents=common)
    p.add_argument("scene", help="asset file (.gltf with its buffers, .glb or .obj)")
    p.add_argument("--out", required=True, help="project file to write (.json)")
    p.add_argument("--into", metavar="BASE", help="add the objects to this project's "
                                                  "objects and rig (default: a new project)")
    p.add_argument("--map", action="append", metavar="ASSET_MATERIAL=LIBRARY_MATERIAL",
                   help="map an asset material to a library material (repeatable)")
    p.add_argument("--up", choices=("y", "z"), default="y",
                   help="up axis of an OBJ file (default y, as Blender exports; glTF is "
                        "always y up)")
    p.set_defaults(func=cmd_import)
