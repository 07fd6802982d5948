"""Build the bundled glTF room and the example project made from it.

    .venv/bin/python tools/make_gltf_room.py

Writes ``resources/examples/office_gltf_room.glb`` (a 6 × 5 × 3 m room in glTF's Y-up
metres: painted walls, floor and ceiling, a metal cabinet, a glass panel, a wooden desk
whose top and legs are child nodes, a cardboard box on the desk, each with a named
material) and then imports it as ``tofradar import`` does into
``resources/examples/office_gltf.json`` with its meshes in ``office_gltf.meshes/``, the
sensors of the office example on a rig placed by the importer.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np

from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.asset_import import build_project
from simcore.scene.assets import read_asset
from simcore.scene.model import Project, Timeline
from simcore.scene.project_io import save_project

EXAMPLES = Path(__file__).resolve().parents[1] / "resources" / "examples"
CUBE = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)],
                dtype=np.float32)
CUBE_TRIS = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]],
                     dtype=np.uint32)


class Room:
    """A glTF document with one buffer, built node by node."""

    def __init__(self) -> None:
        self.doc: dict = {"asset": {"version": "2.0", "generator": "tools/make_gltf_room.py"},
                          "nodes": [], "meshes": [], "materials": [], "accessors": [],
                          "bufferViews": []}
        self.blob = bytearray()

    def _accessor(self, array: np.ndarray, kind: str, component: int) -> int:
        self.blob += b"\0" * (-len(self.blob) % 4)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob),
                                        "byteLength": array.nbytes})
        self.blob += array.tobytes()
        acc = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": component,
               "count": len(array), "type": kind}
        if kind == "VEC3":
            acc["min"], acc["max"] = array.min(0).tolist(), array.max(0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def material(self, name: str, **pbr: float) -> int:
        """Add a named PBR material; returns its index."""
        self.doc["materials"].append({"name": name, "pbrMetallicRoughness": pbr})
        return len(self.doc["materials"]) - 1

    def box_mesh(self, size: tuple[float, float, float], material: int) -> int:
        """Add a box mesh of edge lengths ``size``; returns its index."""
        prim = {"attributes": {"POSITION": self._accessor(CUBE * np.float32(size), "VEC3",
                                                          5126)},
                "indices": self._accessor(CUBE_TRIS.ravel(), "SCALAR", 5125),
                "material": material}
        self.doc["meshes"].append({"primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, name: str, **fields: object) -> int:
        """Add a node; returns its index."""
        self.doc["nodes"].append({"name": name, **fields})
        return len(self.doc["nodes"]) - 1

    def box(self, name: str, size: tuple[float, float, float], at: tuple[float, float, float],
            material: int, **fields: object) -> int:
        """Add a node holding a box at ``at``; returns its index."""
        return self.node(name, mesh=self.box_mesh(size, material), translation=list(at),
                         **fields)

    def glb(self) -> bytes:
        """The GLB file: JSON chunk and one binary chunk."""
        children = {c for n in self.doc["nodes"] for c in n.get("children", [])}
        doc = {**self.doc, "scene": 0, "buffers": [{"byteLength": len(self.blob)}],
               "scenes": [{"nodes": [i for i in range(len(self.doc["nodes"]))
                                     if i not in children]}]}
        js = json.dumps(doc, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        blob = bytes(self.blob) + b"\0" * (-len(self.blob) % 4)
        return (struct.pack("<III", 0x46546C67, 2, 28 + len(js) + len(blob))
                + struct.pack("<II", len(js), 0x4E4F534A) + js
                + struct.pack("<II", len(blob), 0x004E4942) + blob)


def room() -> Room:
    """The room in glTF axes (x right, y up, z towards the viewer), metres."""
    r = Room()
    walls = r.material("Painted walls", metallicFactor=0.0, roughnessFactor=0.9)
    metal = r.material("Metal cabinet", metallicFactor=1.0, roughnessFactor=0.4)
    glass = r.material("Glass panel", metallicFactor=0.0, roughnessFactor=0.05)
    wood = r.material("Wooden desk", metallicFactor=0.0, roughnessFactor=0.6)
    card = r.material("Cardboard box", metallicFactor=0.0, roughnessFactor=0.8)
    lx, ly, lz, t = 6.0, 3.0, 5.0, 0.1            # room 6 (x) × 3 (up) × 5 (z) m
    r.box("floor", (lx, t, lz), (0, -t / 2, 0), walls)
    r.box("ceiling", (lx, t, lz), (0, ly + t / 2, 0), walls)
    r.box("wall_back", (t, ly, lz), (lx / 2 + t / 2, ly / 2, 0), walls)     # +x: ahead
    r.box("wall_front", (t, ly, lz), (-lx / 2 - t / 2, ly / 2, 0), walls)
    r.box("wall_left", (lx, ly, t), (0, ly / 2, -lz / 2 - t / 2), walls)   # −z: project +y
    r.box("wall_right", (lx, ly, t), (0, ly / 2, lz / 2 + t / 2), walls)
    r.box("cabinet", (0.5, 1.8, 0.9), (2.6, 0.9, -1.4), metal)
    r.box("glass_panel", (0.01, 1.2, 1.6), (0.8, 1.0, 1.3), glass,
          rotation=[0.0, float(np.sin(np.radians(10))), 0.0, float(np.cos(np.radians(10)))])
    legs = [r.box(f"desk_leg_{i}", (0.05, 0.72, 0.05), (sx * 0.55, -0.37, sz * 0.3), wood)
            for i, (sx, sz) in enumerate(((-1, -1), (-1, 1), (1, -1), (1, 1)))]
    top = r.box("desk_top", (1.2, 0.03, 0.7), (0, 0, 0), wood)
    carton = r.box("cardboard_box", (0.4, 0.3, 0.3), (0.2, 0.165, 0.0), card)
    r.node("desk", translation=[1.8, 0.735, 0.6],
           rotation=[0.0, float(np.sin(np.radians(-15))), 0.0, float(np.cos(np.radians(-15)))],
           children=[top, *legs, carton])
    return r


def main() -> None:
    """Write the GLB, then import it into the example project."""
    glb = EXAMPLES / "office_gltf_room.glb"
    glb.write_bytes(room().glb())
    office = load_project(example_path("office"))
    base = Project(
        name="office_gltf",
        description="A room imported from a glTF asset (tools/make_gltf_room.py): metal "
                    "cabinet, glass panel, wooden desk with a cardboard box, painted walls.",
        timeline=Timeline(frame_rate_hz=10, duration_s=0.5),
        rig=office.rig, dsp=office.dsp)
    out = EXAMPLES / "office_gltf.json"
    result = build_project(read_asset(glb), out, base=base)
    project = result.project.model_copy(update={"rig": result.project.rig.model_copy(
        update={"pose": _rig_pose(result.project)})})
    save_project(project, out)
    print(f"wrote {glb.name} and {out.name} ({len(result.object_names)} objects)")
    for line in result.report_lines():
        print(line)


def _rig_pose(project: Project):  # noqa: ANN202 - a Pose
    """The importer's pose for a new project (the base had no objects but is not new)."""
    from simcore.scene.asset_import import default_rig_pose
    from simcore.scene.assets import read_asset as _read

    scene = _read(EXAMPLES / "office_gltf_room.glb")
    return default_rig_pose(scene.bounds())


if __name__ == "__main__":
    main()
