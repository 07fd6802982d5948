r"""Export a tofradar project's scene at one instant for the independent reference tracers.

Runs in tofradar's own environment. It writes what mitransient (ToF) and Sionna RT (radar)
need to trace the same scene as tofradar, for any project (not only the bundled examples):

- ``DIR/meshes/NNN_<name>.ply``: each object's triangles in the world frame at ``--time``
  (people as their posed segments), with vertex normals (outward for closed meshes);
- ``DIR/scene.json``: per object its mesh file, whether the mesh is closed (one-sided
  reflection), whether the project moves it, its material name and both bands' parameters
  (``tof``: reflectance, metallic, specular, opacity, retroreflector; ``radar``:
  permittivity, loss tangent, thickness, metallic, rms height, σ⁰ reflectance), and every
  ToF camera and radar with its optical-frame pose (x right, y down, z forward → world,
  4 × 4) and the settings a tracer needs (field of view, resolution, modulation
  frequencies; carrier, bandwidth, polarisation, antenna offsets).

Usage (from the repository root)::

    .venv/bin/python tools/references/export_scene.py resources/examples/office.json \
        --out /tmp/office_scene [--time 0] [--without-people] [--still-only]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import trimesh

from simcore.render.meshes import build_mesh
from simcore.scene.people.config import Person
from simcore.scene.people.expand import body_part_table, expand_people
from simcore.scene.project_io import load_project, material_table
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.tof.sensor import CLOSED

_TOF_FIELDS = ("reflectance", "metallic", "specular", "roughness", "opacity",
               "retroreflector", "retro_gain")
_RADAR_FIELDS = ("reflectance", "metallic", "opacity", "permittivity", "loss_tangent",
                 "thickness_m", "height_rms_m")


def _band(material: Any, band: str, fields: tuple[str, ...]) -> dict[str, Any] | None:
    if material is None:
        return None
    b = material.band(band)
    return {name: getattr(b, name) for name in fields}


def _sensors(project: Any, snap: Any) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    cameras, radars = [], []
    for rig in project.all_rigs():
        for name, cfg in rig.sensor_configs().items():
            pose = snap.sensor(name).transform.tolist()
            kind = type(cfg).__name__
            if kind == "TofCameraConfig":
                cameras.append({"name": name, "rig": rig.name, "optical_to_world": pose,
                                "width": cfg.width, "height": cfg.height,
                                "fov_h_deg": cfg.fov_h_deg, "fov_v_deg": cfg.fov_v_deg,
                                "modulation_frequencies_hz": list(
                                    cfg.modulation_frequencies_hz)})
            elif kind == "RadarConfig":
                radars.append({"name": name, "rig": rig.name, "optical_to_world": pose,
                               "start_frequency_hz": cfg.start_frequency_hz,
                               "bandwidth_hz": cfg.bandwidth_hz,
                               "polarization": cfg.polarization,
                               "tx_mm": [list(a.position_mm) for a in cfg.tx],
                               "rx_mm": [list(a.position_mm) for a in cfg.rx]})
    return cameras, radars


def export_scene(project_path: Path, out: Path, *, time_s: float = 0.0,
                 people: bool = True, still_only: bool = False) -> dict[str, Any]:
    """Write the scene of ``project_path`` at ``time_s`` to ``out``; return its description.

    Parameters
    ----------
    project_path : Path
        A tofradar project file.
    out : Path
        Folder to write (created; its ``meshes/`` replaced).
    time_s : float, keyword-only
        Instant of the scene (s).
    people : bool, keyword-only
        Include people (their segments posed at ``time_s``).
    still_only : bool, keyword-only
        Leave out every object the project moves.
    """
    project = load_project(project_path)
    base = project_path.resolve().parent
    if not people:
        project = project.model_copy(update={"objects": [
            o for o in project.objects if not isinstance(o.geometry, Person)]})
    expanded = expand_people(project, base_dir=base)
    snap = take_snapshot(expanded, time_s)
    parts = body_part_table(expanded)
    table = material_table(expanded, copy=False)
    mesh_dir = out / "meshes"
    mesh_dir.mkdir(parents=True, exist_ok=True)
    for old in mesh_dir.glob("*.ply"):
        old.unlink()
    objects = []
    for i, (obj, state) in enumerate(zip(expanded.objects, snap.objects, strict=True)):
        moving = (not obj.motion.is_static) or parts[i] >= 0
        if still_only and moving:
            continue
        mesh = build_mesh(obj.geometry, base_dir=base)
        if mesh is None or len(mesh.triangles) == 0:
            continue
        t = state.transform
        points = mesh.points @ t[:3, :3].T + t[:3, 3]
        normals = mesh.normals @ t[:3, :3].T
        safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in obj.name)
        name = f"{i:03d}_{safe}.ply"
        trimesh.Trimesh(points, mesh.triangles, vertex_normals=normals,
                        process=False).export(mesh_dir / name)
        material = table.get(obj.material)
        objects.append({"name": obj.name, "ply": f"meshes/{name}",
                        "closed": isinstance(obj.geometry, CLOSED), "moving": bool(moving),
                        "material": obj.material,
                        "tof": _band(material, "tof", _TOF_FIELDS),
                        "radar": _band(material, "radar", _RADAR_FIELDS)})
    cameras, radars = _sensors(expanded, snap)
    scene = {"_doc": __doc__.split("\n\n")[0], "project": str(project_path),
             "time_s": time_s, "objects": objects, "tof_cameras": cameras, "radars": radars}
    (out / "scene.json").write_text(json.dumps(scene, indent=1), encoding="utf-8")
    return scene


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module's docstring."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("project", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--time", type=float, default=0.0, help="instant of the scene (s)")
    ap.add_argument("--without-people", action="store_true")
    ap.add_argument("--still-only", action="store_true",
                    help="leave out every object the project moves")
    args = ap.parse_args(argv)
    try:
        scene = export_scene(args.project, args.out, time_s=args.time,
                             people=not args.without_people, still_only=args.still_only)
    except (OSError, ValueError) as exc:
        print(f"export_scene: error: {exc}", file=sys.stderr)
        return 2
    print(f"{len(scene['objects'])} objects, {len(scene['tof_cameras'])} ToF cameras, "
          f"{len(scene['radars'])} radars -> {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
