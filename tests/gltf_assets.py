"""glTF 2.0 files written by hand (JSON + one binary buffer) for the asset-import tests."""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

import numpy as np

#: The 8 corners and 12 outward (counter-clockwise) triangles of a unit cube at the origin.
CUBE_POINTS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5)
                        for z in (-0.5, 0.5)], dtype=np.float32)
CUBE_TRIANGLES = np.array([
    [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
    [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.uint32)


def box(size: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Points and triangles of a box of edge lengths ``size`` (glTF axes), centred."""
    return (CUBE_POINTS * np.asarray(size, dtype=np.float32)).astype(np.float32), CUBE_TRIANGLES


class Gltf:
    """A glTF document under construction: meshes, materials and nodes, one buffer."""

    def __init__(self) -> None:
        self.doc: dict[str, Any] = {"asset": {"version": "2.0"}, "nodes": [], "meshes": [],
                                    "materials": [], "accessors": [], "bufferViews": []}
        self.blob = bytearray()

    def _view(self, data: bytes) -> int:
        self.blob += b"\0" * (-len(self.blob) % 4)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob),
                                        "byteLength": len(data)})
        self.blob += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, array: np.ndarray, kind: str, component: int) -> int:
        acc = {"bufferView": self._view(array.tobytes()), "componentType": component,
               "count": int(len(array)), "type": kind}
        if kind == "VEC3":
            acc["min"], acc["max"] = array.min(0).tolist(), array.max(0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def material(self, name: str, **pbr: float) -> int:
        self.doc["materials"].append({"name": name, "pbrMetallicRoughness": pbr})
        return len(self.doc["materials"]) - 1

    def mesh(self, parts: list[tuple[np.ndarray, np.ndarray, int | None]],
             name: str | None = None) -> int:
        prims = []
        for points, tris, material in parts:
            prim: dict[str, Any] = {"attributes": {"POSITION": self.accessor(
                np.asarray(points, np.float32), "VEC3", 5126)},
                "indices": self.accessor(np.asarray(tris, np.uint32).ravel(), "SCALAR", 5125)}
            if material is not None:
                prim["material"] = material
            prims.append(prim)
        self.doc["meshes"].append({"primitives": prims, **({"name": name} if name else {})})
        return len(self.doc["meshes"]) - 1

    def node(self, name: str | None = None, **fields: Any) -> int:
        node = {k: v for k, v in fields.items() if v is not None}
        if name is not None:
            node["name"] = name
        self.doc["nodes"].append(node)
        return len(self.doc["nodes"]) - 1

    def finish(self) -> dict[str, Any]:
        children = {c for n in self.doc["nodes"] for c in n.get("children", [])}
        doc = dict(self.doc)
        doc["scene"] = 0
        doc["scenes"] = [{"nodes": [i for i in range(len(doc["nodes"])) if i not in children]}]
        doc["buffers"] = [{"byteLength": len(self.blob)}]
        return doc

    def glb(self) -> bytes:
        return glb_bytes(self.finish(), bytes(self.blob))

    def write_glb(self, path: Path) -> Path:
        path.write_bytes(self.glb())
        return path

    def write_gltf(self, path: Path, buffer_name: str = "scene.bin") -> Path:
        doc = self.finish()
        doc["buffers"][0]["uri"] = buffer_name
        (path.parent / buffer_name).write_bytes(bytes(self.blob))
        path.write_text(json.dumps(doc))
        return path


def glb_bytes(doc: dict[str, Any], blob: bytes) -> bytes:
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob = blob + b"\0" * (-len(blob) % 4)
    out = struct.pack("<III", 0x46546C67, 2, 28 + len(js) + len(blob))
    return out + struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack(
        "<II", len(blob), 0x004E4942) + blob
