"""OBJ assets: objects (``o``/``g``) split by material (``usemtl``), checked like any mesh.

The project's own hardened OBJ reading (:mod:`simcore.scene.mesh_files`) extended with the
group and material statements; ``mtllib`` files are not opened (their names are all the
import needs, and they come with every ``usemtl``), so nothing outside the file is read.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.asset_model import (
    MAX_ASSET_OBJECTS,
    NO_MATERIAL,
    AssetError,
    AssetMaterial,
    AssetScene,
    _make_object,
    _safe_name,
    unique_name,
)
from simcore.scene.mesh_files import MAX_MESH_TRIANGLES, MAX_MESH_VERTICES

Groups = dict[tuple[str, str], list[NDArray[np.int64]]]

_STATEMENT = re.compile(rb"^(o|g|usemtl)(?=[ \t\r\n]|$)(?:[ \t]+([^\r\n]*))?", re.M)
_VERTEX = re.compile(rb"^v[ \t]+(\S+)[ \t]+(\S+)[ \t]+(\S+)", re.M)
_FACE = re.compile(rb"^f[ \t]+([^\r\n]*)", re.M)


def _count_lines(data: bytes, key: bytes) -> int:
    """Lines starting with ``key`` and a blank (an upper bound before anything is parsed)."""
    n = sum(data.count(b"\n" + key + sep) for sep in (b" ", b"\t"))
    return n + int(data.startswith((key + b" ", key + b"\t")))


def _fan_arrays(counts: NDArray[np.int64], idx: NDArray[np.int64]) -> NDArray[np.int64]:
    """Fan triangles of polygons of ``counts`` vertices whose indices follow in ``idx``."""
    starts = np.cumsum(counts) - counts
    n_tri = counts - 2
    face = np.repeat(np.arange(len(counts)), n_tri)
    k = np.arange(int(n_tri.sum())) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri) + 1
    first = starts[face]
    return np.stack([idx[first], idx[first + k], idx[first + k + 1]], axis=1)


def _parse_fast(path: Path, data: bytes) -> tuple[NDArray[np.float64], Groups] | None:
    """Vectorised parsing of a plain OBJ; None where the exact line parser must decide.

    Plain means: no indented lines, no negative (relative) indices, no line continuations,
    every vertex with three numbers and every face with at least three positive indices;
    anything else goes to :func:`_parse`, which names the offending line.
    """
    if b"\n " in data or b"\n\t" in data or data[:1] in (b" ", b"\t") or b"\\\n" in data:
        return None
    n_v, n_f = _count_lines(data, b"v"), _count_lines(data, b"f")
    if n_v > MAX_MESH_VERTICES or n_f > MAX_MESH_TRIANGLES:
        raise AssetError(f"{path.name}: {n_v} vertices, {n_f} faces; at most "
                         f"{MAX_MESH_VERTICES} and {MAX_MESH_TRIANGLES}")
    found = _VERTEX.findall(data)
    try:
        points = np.array(found, dtype=bytes).astype(np.float64).reshape(-1, 3)
    except ValueError:
        return None
    if len(points) != n_v:
        return None
    groups: Groups = {}
    key = (path.stem, NO_MATERIAL)
    group, material, pos, n_tris = path.stem, NO_MATERIAL, 0, 0
    for match in [*_STATEMENT.finditer(data), None]:
        end = match.start() if match is not None else len(data)
        lines = _FACE.findall(data, pos, end)
        if lines:
            counts = np.array([len(line.split()) for line in lines], dtype=np.int64)
            text = b" ".join(lines)
            if b"-" in text:          # relative indices count from the line's position
                return None
            tokens = re.sub(rb"/\S*", b"", text).split()
            try:
                idx = np.array(tokens, dtype=bytes).astype(np.int64) - 1
            except ValueError:
                return None
            if (counts < 3).any() or len(idx) != counts.sum() or (idx < 0).any():
                return None
            n_tris += int((counts - 2).sum())
            if n_tris > MAX_MESH_TRIANGLES:
                raise AssetError(f"{path.name}: more than {MAX_MESH_TRIANGLES} triangles")
            groups.setdefault(key, []).append(_fan_arrays(counts, idx))
        if match is None:
            break
        value = _safe_name(match.group(2).decode("utf-8", "replace") if match.group(2) else "",
                           NO_MATERIAL if match.group(1) == b"usemtl" else path.stem)
        if match.group(1) == b"usemtl":
            material = value
        else:
            group = value
        key, pos = (group, material), match.end()
    return points, groups


def _parse(path: Path, text: str) -> tuple[NDArray[np.float64], Groups]:
    """Vertices and the triangles of each (group, material), line by line."""
    verts: list[list[float]] = []
    groups: dict[tuple[str, str], list[list[int]]] = {}
    group, material, n_faces = path.stem, NO_MATERIAL, 0
    current = groups.setdefault((group, material), [])
    for lineno, line in enumerate(text.splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        key = parts[0]
        try:
            if key == "v":
                if len(parts) < 4:
                    raise ValueError("a vertex needs three coordinates")
                verts.append([float(p) for p in parts[1:4]])
                if len(verts) > MAX_MESH_VERTICES:
                    raise AssetError(f"{path.name}: more than {MAX_MESH_VERTICES} vertices")
            elif key == "f":
                if len(parts) < 4:
                    raise ValueError("a face needs at least three vertices")
                idx = []
                for p in parts[1:]:
                    i = int(p.split("/")[0])
                    if i == 0:
                        raise ValueError("face index 0 (OBJ indices start at 1)")
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                current.append(idx)
                n_faces += len(idx) - 2
                if n_faces > MAX_MESH_TRIANGLES:
                    raise AssetError(f"{path.name}: more than {MAX_MESH_TRIANGLES} triangles")
            elif key in ("o", "g", "usemtl"):
                value = _safe_name(line.split(None, 1)[1] if len(parts) > 1 else "",
                                   NO_MATERIAL if key == "usemtl" else path.stem)
                if key == "usemtl":
                    material = value
                else:
                    group = value
                current = groups.setdefault((group, material), [])
        except ValueError as exc:
            if isinstance(exc, AssetError):
                raise
            raise AssetError(f"{path.name}: line {lineno}: {exc}") from None
    out: Groups = {k: [np.array(_fan_polys(v), dtype=np.int64).reshape(-1, 3)]
                   for k, v in groups.items() if v}
    return np.array(verts, dtype=np.float64).reshape(-1, 3), out


def _fan_polys(polys: list[list[int]]) -> list[tuple[int, int, int]]:
    return [(p[0], p[k], p[k + 1]) for p in polys for k in range(1, len(p) - 1)]


def read_obj(path: Path, data: bytes, *, up: str = "y") -> AssetScene:
    """Objects of an OBJ file, one per (group, material) with faces, in project axes."""
    fast = _parse_fast(path, data)
    points, groups = fast if fast is not None else _parse(
        path, data.decode("utf-8", errors="replace"))
    out = AssetScene(source=path)
    taken: set[str] = set()
    filled = [key for key, polys in groups.items() if polys]
    if len(filled) > MAX_ASSET_OBJECTS:
        raise AssetError(f"{path.name}: {len(filled)} objects (group × material); at most "
                         f"{MAX_ASSET_OBJECTS}")
    per_group = Counter(g for g, _m in filled)
    several = {g for g, n in per_group.items() if n > 1}
    for (group, material), parts in groups.items():
        if not parts:
            continue
        tris = np.concatenate(parts)
        if tris.min() < 0 or tris.max() >= len(points):
            bad = int(tris.min()) if tris.min() < 0 else int(tris.max())
            raise AssetError(f"{path.name}: face index {bad + 1} out of range "
                             f"[1, {len(points)}]")
        used, inverse = np.unique(tris, return_inverse=True)
        local = points[used]
        centre = (local.min(axis=0) + local.max(axis=0)) / 2 if np.isfinite(local).all() \
            else np.zeros(3)
        matrix = np.eye(4)
        matrix[:3, 3] = centre
        name = f"{group}.{material}" if group in several else group
        obj = _make_object(path, unique_name(name, taken), material, matrix, local - centre,
                           inverse.reshape(-1, 3), out.skipped, convert=up == "y")
        out.materials.setdefault(material, AssetMaterial(material))
        if obj is not None:
            out.objects.append(obj)
    if not out.objects:
        raise AssetError(f"{path.name}: no faces in the file")
    return out


__all__ = ["read_obj"]
