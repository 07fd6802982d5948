"""Scenes from 3D assets: glTF 2.0 (``.gltf`` + buffers, ``.glb``) and OBJ with materials.

Every mesh node of an asset becomes one labelled scene object: its node name (made unique),
its world pose (the node hierarchy composed), its triangles stored beside the project as a
binary PLY file (a relative path inside the project folder, the mesh path policy) and a
material mapped from the asset's material name to a material of the dual-band library.

Coordinates: glTF is metres, +Y up; the project is metres, +Z up. A glTF point
``(x, y, z)`` becomes ``(x, -z, y)`` in the project, as Blender's importer converts it. OBJ
files are taken as Y-up too (Blender's OBJ importer default), or as Z-up with ``up="z"``.

Hardening: the file is checked in Python before trimesh sees it. A GLB's header and chunks,
the JSON document, every buffer, buffer view and accessor used by a triangle primitive are
checked against the file's size and the limits below (counts, offsets, strides, data-URI
sizes, URIs outside the asset's folder, node cycles and depth, total triangles); only a
sanitised document with the checked data (no images, textures, extensions or animations)
is handed to trimesh, whose result is checked again (indices, finiteness, coordinate
range). Every problem is an :class:`AssetError` naming the file and what is wrong.
"""

from __future__ import annotations

import base64
import binascii
import io
import json
import math
import re
import struct
import urllib.parse
import warnings
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene.asset_model import (
    NO_MATERIAL,
    Y_UP_TO_Z_UP,
    AssetError,
    AssetMaterial,
    AssetObject,
    AssetScene,
    _fail,
    _make_object,
    _safe_name,
    unique_name,
)
from simcore.scene.limits import (
    MAX_ASSET_BYTES,
    MAX_ASSET_JSON_BYTES,
    MAX_ASSET_NODE_DEPTH,
    MAX_ASSET_NODES,
    MAX_ASSET_OBJECTS,
    MAX_DATA_URI_CHARS,
)
from simcore.scene.mesh_files import (
    MAX_MESH_TRIANGLES,
    MAX_MESH_VERTICES,
    MeshError,
    open_regular_file,
)

#: Largest asset file and external buffer (bytes), ``data:`` URI (characters of base64
#: text), most nodes, deepest node hierarchy, most mesh objects imported, largest JSON part
#: (bytes): :mod:`simcore.scene.limits`.
MAX_NODES = MAX_ASSET_NODES
MAX_NODE_DEPTH = MAX_ASSET_NODE_DEPTH
MAX_JSON_BYTES = MAX_ASSET_JSON_BYTES
#: Most triangles of the whole imported scene (instances counted once each).
MAX_SCENE_TRIANGLES = MAX_MESH_TRIANGLES
#: Prefix of the project materials made for asset materials.
ASSET_MATERIAL_PREFIX = "asset:"
#: Material given to asset materials no rule maps (reported, never silent).
FALLBACK_MATERIAL = "concrete"
ASSET_SUFFIXES = (".gltf", ".glb", ".obj")


_GLB_MAGIC = 0x46546C67
_CHUNK_JSON = 0x4E4F534A
_CHUNK_BIN = 0x004E4942
_COMPONENT_SIZE = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
_TYPE_SIZE = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_TRIANGLES = 4


# --------------------------------------------------------------------------- reading
#: ``read_asset``'s ``allow_outside_paths`` while it reads (the buffer loader is deep).
_ALLOW_OUTSIDE: ContextVar[bool] = ContextVar("allow_outside_paths", default=False)


def read_asset(path: str | Path, *, up: str = "y",
               allow_outside_paths: bool = False) -> AssetScene:
    """Read a glTF, GLB or OBJ asset into objects in project coordinates.

    Parameters
    ----------
    path : str or Path
        The asset file (``.gltf``, ``.glb`` or ``.obj``).
    up : {"y", "z"}
        Up axis of an OBJ file (glTF is always Y up).
    allow_outside_paths : bool
        Accept external buffers outside the asset's folder (``--allow-outside-paths``).

    Returns
    -------
    AssetScene
        The mesh objects, the asset's materials and notes on skipped parts.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in ASSET_SUFFIXES:
        raise _fail(path, f"unsupported asset format {suffix!r} "
                          f"(use {', '.join(ASSET_SUFFIXES)})")
    if up not in ("y", "z"):
        raise _fail(path, f"up axis must be 'y' or 'z', got {up!r}")
    try:
        data = open_regular_file(path, max_bytes=MAX_ASSET_BYTES)
    except MeshError as exc:
        raise AssetError(str(exc)) from None
    if suffix == ".obj":
        from simcore.scene.asset_obj import read_obj
        return read_obj(path, data, up=up)
    if suffix == ".glb":
        doc, bin_chunk = _split_glb(path, data)
    else:
        doc, bin_chunk = _parse_json(path, data), None
    token = _ALLOW_OUTSIDE.set(allow_outside_paths)
    try:
        return _read_gltf(path, doc, bin_chunk)
    finally:
        _ALLOW_OUTSIDE.reset(token)


def _split_glb(path: Path, data: bytes) -> tuple[dict[str, Any], bytes | None]:
    """Header and chunks of a GLB (checked against the file's size)."""
    if len(data) < 20:
        raise _fail(path, f"not a GLB file ({len(data)} bytes; a GLB has a 12-byte header "
                          "and a JSON chunk)")
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != _GLB_MAGIC:
        raise _fail(path, "not a GLB file (no 'glTF' magic)")
    if version != 2:
        raise _fail(path, f"GLB version {version}; only glTF 2.0 is supported")
    if length != len(data):
        raise _fail(path, f"header says {length} bytes but the file has {len(data)} "
                          "(truncated or padded)")
    offset, chunks = 12, []
    while offset < len(data):
        if offset + 8 > len(data):
            raise _fail(path, "file ends inside a chunk header")
        clen, ctype = struct.unpack_from("<II", data, offset)
        if offset + 8 + clen > len(data):
            raise _fail(path, f"chunk of {clen} bytes runs past the end of the file")
        chunks.append((ctype, data[offset + 8:offset + 8 + clen]))
        offset += 8 + clen
    if not chunks or chunks[0][0] != _CHUNK_JSON:
        raise _fail(path, "the first GLB chunk is not JSON")
    doc = _parse_json(path, chunks[0][1])
    bins = [c for t, c in chunks[1:] if t == _CHUNK_BIN]
    return doc, (bins[0] if bins else None)


def _parse_json(path: Path, text: bytes) -> dict[str, Any]:
    if len(text) > MAX_JSON_BYTES:
        raise _fail(path, f"JSON part has {len(text)} bytes; at most {MAX_JSON_BYTES}")
    try:
        doc = json.loads(text.decode("utf-8"), parse_constant=_reject_constant)
    except UnicodeDecodeError:
        raise _fail(path, "not a glTF file (not UTF-8 JSON)") from None
    except json.JSONDecodeError as exc:
        raise _fail(path, f"not a glTF file (invalid JSON: {exc.msg} at line {exc.lineno} "
                          f"column {exc.colno})") from None
    except RecursionError:
        raise _fail(path, "JSON is nested too deeply") from None
    except ValueError as exc:
        raise _fail(path, str(exc)) from None
    if not isinstance(doc, dict):
        raise _fail(path, "not a glTF file (the JSON is not an object)")
    asset = doc.get("asset")
    version = asset.get("version") if isinstance(asset, dict) else None
    if not isinstance(version, str) or not version.startswith("2."):
        raise _fail(path, f"not a glTF 2.0 file (asset.version is {str(version)[:20]!r})")
    return doc


def _reject_constant(name: str) -> float:
    raise ValueError(f"{name} is not a valid JSON number")


# --------------------------------------------------------------------------- glTF checks
def _list(path: Path, doc: dict[str, Any], key: str) -> list[Any]:
    value = doc.get(key, [])
    if not isinstance(value, list):
        raise _fail(path, f"'{key}' is not a list")
    return value


def _index(path: Path, value: Any, length: int, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < length:
        raise _fail(path, f"{what} {str(value)[:30]!r} is not an index in [0, {length})")
    return value


def _uint(path: Path, obj: dict[str, Any], key: str, what: str, *, default: int | None = None,
          maximum: int = 2**40) -> int:
    value = obj.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= maximum:
        raise _fail(path, f"{what}.{key} = {str(value)[:30]!r}; expected an integer in "
                          f"[0, {maximum}]")
    return value


def _numbers(path: Path, value: Any, n: int, what: str, *, limit: float = 1e6
             ) -> NDArray[np.float64]:
    if (not isinstance(value, list) or len(value) != n
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
        raise _fail(path, f"{what} must be a list of {n} numbers")
    arr = np.array(value, dtype=np.float64)
    if not np.isfinite(arr).all() or np.abs(arr).max() > limit:
        raise _fail(path, f"{what} has a non-finite or huge value (at most ±{limit:g})")
    return arr


def _load_buffer(path: Path, buf: Any, i: int, bin_chunk: bytes | None) -> bytes:
    """Bytes of buffer ``i``: the GLB chunk, a data URI or a file beside the asset."""
    if not isinstance(buf, dict):
        raise _fail(path, f"buffers[{i}] is not an object")
    length = _uint(path, buf, "byteLength", f"buffers[{i}]", maximum=MAX_ASSET_BYTES)
    uri = buf.get("uri")
    if uri is None:
        if bin_chunk is None:
            raise _fail(path, f"buffers[{i}] has no uri and the file has no binary chunk")
        data = bin_chunk
    elif not isinstance(uri, str):
        raise _fail(path, f"buffers[{i}].uri is not a string")
    elif uri.startswith("data:"):
        data = _data_uri(path, uri, i)
    else:
        data = _external_buffer(path, uri, i)
    if len(data) < length:
        raise _fail(path, f"buffers[{i}] has {len(data)} bytes, less than its byteLength "
                          f"{length}")
    return data[:length]


def _data_uri(path: Path, uri: str, i: int) -> bytes:
    if len(uri) > MAX_DATA_URI_CHARS:
        raise _fail(path, f"buffers[{i}] data URI has {len(uri)} characters; at most "
                          f"{MAX_DATA_URI_CHARS}")
    head, sep, payload = uri.partition(",")
    if not sep or not head.endswith(";base64"):
        raise _fail(path, f"buffers[{i}] data URI is not base64")
    try:
        return base64.b64decode(payload, validate=True)
    except (binascii.Error, ValueError):
        raise _fail(path, f"buffers[{i}] data URI is not valid base64") from None


def _external_buffer(path: Path, uri: str, i: int) -> bytes:
    """A buffer file, under the path policy of every referenced file.

    Beside the asset unless ``--allow-outside-paths``, then a regular file of at most the
    asset limit.
    """
    rel = urllib.parse.unquote(uri)
    outside_ok = _ALLOW_OUTSIDE.get()
    if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", rel) or "\x00" in rel or (
            rel.startswith(("/", "\\")) and not outside_ok):
        raise _fail(path, f"buffers[{i}].uri {uri[:80]!r} is not a relative path beside the "
                          "asset (absolute paths need --allow-outside-paths; URLs are "
                          "refused)")
    folder = path.resolve().parent
    target = folder / rel
    try:
        inside = target.resolve().is_relative_to(folder)
    except (OSError, RuntimeError):
        inside = False
    if not inside and not outside_ok:
        raise _fail(path, f"buffers[{i}].uri {uri[:80]!r} points outside the asset's folder "
                          "(pass --allow-outside-paths to accept it)")
    try:
        return open_regular_file(target, max_bytes=MAX_ASSET_BYTES)
    except MeshError as exc:
        raise _fail(path, f"buffers[{i}]: {exc}") from None


@dataclass
class _Checked:
    """The checked, remapped pieces of a glTF used by its triangle primitives."""

    path: Path
    doc: dict[str, Any]
    bin_chunk: bytes | None
    buffers: dict[int, bytes] = field(default_factory=dict)
    views: dict[int, int] = field(default_factory=dict)          # old view → new view
    out_views: list[dict[str, Any]] = field(default_factory=list)
    accessors: dict[int, int] = field(default_factory=dict)      # old accessor → new
    out_accessors: list[dict[str, Any]] = field(default_factory=list)
    blob: bytearray = field(default_factory=bytearray)

    def buffer(self, i: int) -> bytes:
        bufs = _list(self.path, self.doc, "buffers")
        i = _index(self.path, i, len(bufs), "bufferView.buffer")    # before it keys a dict
        if i not in self.buffers:
            self.buffers[i] = _load_buffer(self.path, bufs[i], i, self.bin_chunk)
        return self.buffers[i]

    def view(self, i: int) -> tuple[int, int, int | None]:
        """New index, byte length and stride of buffer view ``i`` (copied into the blob)."""
        views = _list(self.path, self.doc, "bufferViews")
        view = views[_index(self.path, i, len(views), "accessor.bufferView")]
        what = f"bufferViews[{i}]"
        if not isinstance(view, dict):
            raise _fail(self.path, f"{what} is not an object")
        data = self.buffer(view.get("buffer", -1))
        offset = _uint(self.path, view, "byteOffset", what, default=0)
        length = _uint(self.path, view, "byteLength", what, maximum=MAX_ASSET_BYTES)
        if offset + length > len(data):
            raise _fail(self.path, f"{what} (bytes {offset}…{offset + length}) runs past the "
                                   f"end of its buffer ({len(data)} bytes)")
        stride = view.get("byteStride")
        if stride is not None and (isinstance(stride, bool) or not isinstance(stride, int)
                                   or not 4 <= stride <= 252 or stride % 4):
            raise _fail(self.path, f"{what}.byteStride {str(stride)[:20]!r} is not a multiple "
                                   "of 4 in [4, 252]")
        if i not in self.views:
            self.blob += b"\0" * (-len(self.blob) % 4)
            out: dict[str, Any] = {"buffer": 0, "byteOffset": len(self.blob),
                                   "byteLength": length}
            if stride is not None:
                out["byteStride"] = stride
            self.blob += data[offset:offset + length]
            self.views[i] = len(self.out_views)
            self.out_views.append(out)
        return self.views[i], length, stride

    def accessor(self, i: int, *, kinds: tuple[str, ...], components: tuple[int, ...],
                 role: str) -> int:
        """Check accessor ``i`` and return its count (remapped on first use)."""
        accessors = _list(self.path, self.doc, "accessors")
        acc = accessors[_index(self.path, i, len(accessors), role)]
        what = f"accessors[{i}]"
        if not isinstance(acc, dict):
            raise _fail(self.path, f"{what} is not an object")
        if "sparse" in acc:
            raise _fail(self.path, f"{what}: sparse accessors are not supported")
        if acc.get("type") not in kinds or acc.get("componentType") not in components:
            raise _fail(self.path, f"{what} ({role}) has type {str(acc.get('type'))[:12]!r} / "
                                   f"componentType {str(acc.get('componentType'))[:12]!r}; "
                                   f"expected {'/'.join(kinds)} of {components}")
        cap = 3 * MAX_MESH_TRIANGLES if kinds == ("SCALAR",) else MAX_MESH_VERTICES
        count = _uint(self.path, acc, "count", what, maximum=cap)
        if count == 0:
            raise _fail(self.path, f"{what}.count is 0")
        if "bufferView" not in acc:
            raise _fail(self.path, f"{what} ({role}) has no bufferView")
        new_view, length, stride = self.view(acc["bufferView"])
        offset = _uint(self.path, acc, "byteOffset", what, default=0)
        elem = _COMPONENT_SIZE[acc["componentType"]] * _TYPE_SIZE[acc["type"]]
        need = offset + (count - 1) * (stride or elem) + elem
        if need > length:
            raise _fail(self.path, f"{what}: {count} elements need {need} bytes but its "
                                   f"bufferView has {length}")
        if i not in self.accessors:
            self.accessors[i] = len(self.out_accessors)
            self.out_accessors.append({"bufferView": new_view, "byteOffset": offset,
                                       "componentType": acc["componentType"],
                                       "count": count, "type": acc["type"]})
        return count


def _check_primitive(chk: _Checked, prim: Any, where: str, n_materials: int
                     ) -> tuple[dict[str, Any] | None, int]:
    """A sanitised triangle primitive and its triangle count (None: not triangles)."""
    path = chk.path
    if not isinstance(prim, dict) or not isinstance(prim.get("attributes"), dict):
        raise _fail(path, f"{where} is not a primitive with attributes")
    mode = prim.get("mode", _TRIANGLES)
    if mode != _TRIANGLES:
        return None, 0
    if "POSITION" not in prim["attributes"]:
        raise _fail(path, f"{where} has no POSITION attribute")
    n_points = chk.accessor(prim["attributes"]["POSITION"], kinds=("VEC3",),
                            components=(5126,), role=f"{where}.POSITION")
    out: dict[str, Any] = {"attributes": {"POSITION": chk.accessors[
        prim["attributes"]["POSITION"]]}, "mode": _TRIANGLES}
    if "indices" in prim:
        n_index = chk.accessor(prim["indices"], kinds=("SCALAR",),
                               components=(5121, 5123, 5125), role=f"{where}.indices")
        out["indices"] = chk.accessors[prim["indices"]]
    else:
        n_index = n_points
    if n_index % 3:
        raise _fail(path, f"{where}: {n_index} indices is not a whole number of triangles")
    if "material" in prim:
        out["material"] = _index(path, prim["material"], n_materials, f"{where}.material")
    return out, n_index // 3


def _node_matrix(path: Path, node: dict[str, Any], i: int) -> dict[str, Any]:
    """The checked transform keys of a node (matrix, or translation/rotation/scale)."""
    out: dict[str, Any] = {}
    if "matrix" in node:
        m = _numbers(path, node["matrix"], 16, f"nodes[{i}].matrix")
        out["matrix"] = m.tolist()
        return out
    if "translation" in node:
        out["translation"] = _numbers(path, node["translation"], 3,
                                      f"nodes[{i}].translation").tolist()
    if "rotation" in node:
        q = _numbers(path, node["rotation"], 4, f"nodes[{i}].rotation", limit=2.0)
        norm = float(np.linalg.norm(q))
        if not 0.5 < norm < 2.0:
            raise _fail(path, f"nodes[{i}].rotation is not a unit quaternion (norm {norm:.3g})")
        out["rotation"] = (q / norm).tolist()
    if "scale" in node:
        out["scale"] = _numbers(path, node["scale"], 3, f"nodes[{i}].scale").tolist()
    return out


def _check_nodes(path: Path, doc: dict[str, Any]) -> tuple[list[dict[str, Any]], list[int]]:
    """Sanitised nodes and scene roots; refuses cycles, shared children and deep trees."""
    nodes = _list(path, doc, "nodes")
    if len(nodes) > MAX_NODES:
        raise _fail(path, f"{len(nodes)} nodes; at most {MAX_NODES}")
    n_meshes = len(_list(path, doc, "meshes"))
    parent: dict[int, int] = {}
    out: list[dict[str, Any]] = []
    taken: set[str] = set()
    for i, node in enumerate(nodes):
        if not isinstance(node, dict):
            raise _fail(path, f"nodes[{i}] is not an object")
        # Unique names here, in file order: trimesh keeps them, and objects sort by them.
        clean: dict[str, Any] = {"name": unique_name(_safe_name(node.get("name"), f"node{i}"),
                                                     taken)}
        clean.update(_node_matrix(path, node, i))
        children = node.get("children", [])
        if not isinstance(children, list):
            raise _fail(path, f"nodes[{i}].children is not a list")
        for c in children:
            _index(path, c, len(nodes), f"nodes[{i}].children entry")
            if c in parent or c == i:
                raise _fail(path, f"node {c} has two parents or is its own child "
                                  "(the node hierarchy must be a tree)")
            parent[c] = i
        if children:
            clean["children"] = list(children)
        if "mesh" in node:
            clean["mesh"] = _index(path, node["mesh"], n_meshes, f"nodes[{i}].mesh")
        out.append(clean)
    roots = _scene_roots(path, doc, len(nodes), parent)
    # Depth and cycles: every node reached from a root at most once, within the depth cap.
    seen: set[int] = set()
    stack = [(r, 1) for r in roots]
    while stack:
        n, depth = stack.pop()
        if n in seen:
            raise _fail(path, f"node {n} is reached twice (cycle in the node hierarchy)")
        if depth > MAX_NODE_DEPTH:
            raise _fail(path, f"node hierarchy deeper than {MAX_NODE_DEPTH}")
        seen.add(n)
        stack.extend((c, depth + 1) for c in out[n].get("children", []))
    return out, roots


def _scene_roots(path: Path, doc: dict[str, Any], n_nodes: int, parent: dict[int, int]
                 ) -> list[int]:
    scenes = _list(path, doc, "scenes")
    if not scenes:
        return [i for i in range(n_nodes) if i not in parent]
    index = doc.get("scene", 0)
    scene = scenes[_index(path, index, len(scenes), "scene")]
    roots = scene.get("nodes", []) if isinstance(scene, dict) else None
    if not isinstance(roots, list):
        raise _fail(path, f"scenes[{index}].nodes is not a list")
    for r in roots:
        _index(path, r, n_nodes, f"scenes[{index}].nodes entry")
        if r in parent:
            raise _fail(path, f"scene root node {r} is also a child of node {parent[r]}")
    if len(set(roots)) != len(roots):
        raise _fail(path, "a scene lists a root node twice")
    return list(roots)


def _check_materials(path: Path, doc: dict[str, Any]
                     ) -> tuple[list[dict[str, Any]], list[AssetMaterial]]:
    out, found = [], []
    for i, mat in enumerate(_list(path, doc, "materials")):
        mat = mat if isinstance(mat, dict) else {}
        name = _safe_name(mat.get("name"), f"material{i}")
        pbr = mat.get("pbrMetallicRoughness")
        pbr = pbr if isinstance(pbr, dict) else {}
        metallic = _factor(pbr.get("metallicFactor"))
        roughness = _factor(pbr.get("roughnessFactor"))
        color = pbr.get("baseColorFactor")
        rgb = None
        if isinstance(color, list) and len(color) == 4 and all(
                isinstance(c, (int, float)) and not isinstance(c, bool) and 0 <= c <= 1
                for c in color):
            rgb = (float(color[0]), float(color[1]), float(color[2]))
        clean_pbr: dict[str, Any] = {}
        if metallic is not None:
            clean_pbr["metallicFactor"] = metallic
        if roughness is not None:
            clean_pbr["roughnessFactor"] = roughness
        out.append({"name": name, "pbrMetallicRoughness": clean_pbr})
        found.append(AssetMaterial(name, metallic, roughness, rgb))
    return out, found


def _factor(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    value = float(value)
    return value if math.isfinite(value) and 0.0 <= value <= 1.0 else None


def _sanitise(path: Path, doc: dict[str, Any], bin_chunk: bytes | None
              ) -> tuple[dict[str, Any], bytes, list[AssetMaterial], list[str]]:
    """A minimal glTF of the checked triangle data, its binary blob, materials, notes."""
    required = doc.get("extensionsRequired", [])
    if required:
        shown = ", ".join(str(e)[:40] for e in required[:3]) if isinstance(required, list) \
            else str(required)[:40]
        raise _fail(path, f"needs glTF extensions that are not supported: {shown} (export "
                          "without compression or quantisation)")
    nodes, roots = _check_nodes(path, doc)
    materials, found = _check_materials(path, doc)
    chk = _Checked(path, doc, bin_chunk)
    meshes, mesh_tris, notes = [], [], []
    used = {n["mesh"] for n in nodes if "mesh" in n}
    for m, mesh in enumerate(_list(path, doc, "meshes")):
        prims = mesh.get("primitives") if isinstance(mesh, dict) else None
        if not isinstance(prims, list) or not prims:
            raise _fail(path, f"meshes[{m}] has no primitives list")
        kept, tris = [], 0
        for p, prim in enumerate(prims if m in used else []):
            clean, n = _check_primitive(chk, prim, f"meshes[{m}].primitives[{p}]",
                                        len(materials))
            if clean is None:
                notes.append(f"meshes[{m}].primitives[{p}]: not triangles (mode "
                             f"{str(prim.get('mode'))[:10]}), skipped")
                continue
            kept.append(clean)
            tris += n
        name = _safe_name(mesh.get("name") if isinstance(mesh, dict) else None, f"mesh{m}")
        meshes.append({"name": name, "primitives": kept})
        mesh_tris.append(tris)
    _check_totals(path, nodes, roots, mesh_tris)
    for node in nodes:        # nodes whose mesh has no triangle primitive carry no mesh
        if "mesh" in node and not meshes[node["mesh"]]["primitives"]:
            del node["mesh"]
    doc_out = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": roots}],
               "nodes": nodes, "meshes": meshes, "materials": materials,
               "accessors": chk.out_accessors, "bufferViews": chk.out_views,
               "buffers": [{"byteLength": len(chk.blob)}]}
    return doc_out, bytes(chk.blob), found, notes


def _check_totals(path: Path, nodes: list[dict[str, Any]], roots: list[int],
                  mesh_tris: list[int]) -> None:
    stack, n_objects, total = list(roots), 0, 0
    while stack:
        n = stack.pop()
        stack.extend(nodes[n].get("children", []))
        if "mesh" in nodes[n] and mesh_tris[nodes[n]["mesh"]]:
            n_objects += 1
            total += mesh_tris[nodes[n]["mesh"]]
    if n_objects > MAX_ASSET_OBJECTS:
        raise _fail(path, f"{n_objects} mesh nodes; at most {MAX_ASSET_OBJECTS}")
    if total > MAX_SCENE_TRIANGLES:
        raise _fail(path, f"{total} triangles in the scene; at most {MAX_SCENE_TRIANGLES}")
    if n_objects == 0:
        raise _fail(path, "the scene has no mesh node with triangles")


def _glb_bytes(doc: dict[str, Any], blob: bytes) -> bytes:
    """A GLB file of a glTF document and one binary buffer."""
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    blob = blob + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(js) + (8 + len(blob) if blob else 0)
    out = struct.pack("<III", _GLB_MAGIC, 2, total) + struct.pack("<II", len(js), _CHUNK_JSON)
    out += js
    if blob:
        out += struct.pack("<II", len(blob), _CHUNK_BIN) + blob
    return out


def _read_gltf(path: Path, doc: dict[str, Any], bin_chunk: bytes | None) -> AssetScene:
    clean, blob, materials, notes = _sanitise(path, doc, bin_chunk)
    import trimesh  # noqa: PLC0415 - heavy, only needed here

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            scene = trimesh.load_scene(io.BytesIO(_glb_bytes(clean, blob)), file_type="glb")
    except Exception as exc:   # trimesh raises many types on data it dislikes
        raise _fail(path, f"trimesh could not read the checked scene: "
                          f"{type(exc).__name__}: {str(exc)[:200]}") from None
    out = AssetScene(source=path, skipped=notes)
    out.materials = {m.name: m for m in materials}
    graph = scene.graph
    taken: set[str] = set()
    order = {n["name"]: i for i, n in enumerate(clean["nodes"])}

    def file_order(node: str) -> tuple[int, str]:
        return order.get(node, order.get(graph.transforms.parents.get(node, ""), -1)), node

    for node in sorted(graph.nodes_geometry, key=file_order):
        matrix, geom_name = graph.get(node)
        geom = scene.geometry[geom_name]
        name = _object_name(graph, node, geom)
        mat = getattr(getattr(geom, "visual", None), "material", None)
        mat_name = _safe_name(getattr(mat, "name", None), NO_MATERIAL) if mat is not None \
            else NO_MATERIAL
        if mat_name == NO_MATERIAL:
            out.materials.setdefault(NO_MATERIAL, AssetMaterial(NO_MATERIAL))
        obj = _make_object(path, unique_name(name, taken), mat_name,
                           np.asarray(matrix, dtype=np.float64),
                           np.asarray(geom.vertices), np.asarray(geom.faces), out.skipped)
        if obj is not None:
            out.objects.append(obj)
    if not out.objects:
        raise _fail(path, "no mesh node with triangles" + (
            f" ({out.skipped[0]})" if out.skipped else ""))
    return out


def _object_name(graph: Any, node: str, geom: Any) -> str:
    """A primitive of a multi-primitive mesh is named ``node.material``."""
    if getattr(geom, "metadata", {}).get("from_gltf_primitive"):
        parent = graph.transforms.parents.get(node, node)
        mat = getattr(getattr(geom, "visual", None), "material", None)
        return f"{parent}.{getattr(mat, 'name', None) or 'part'}"
    return str(node)


__all__ = [
    "ASSET_MATERIAL_PREFIX", "ASSET_SUFFIXES", "FALLBACK_MATERIAL", "MAX_ASSET_BYTES",
    "MAX_ASSET_OBJECTS", "MAX_DATA_URI_CHARS", "MAX_NODES", "MAX_NODE_DEPTH",
    "MAX_SCENE_TRIANGLES", "NO_MATERIAL", "Y_UP_TO_Z_UP", "AssetError", "AssetMaterial",
    "AssetObject", "AssetScene", "read_asset", "unique_name",
]
