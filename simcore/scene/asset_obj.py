"""OBJ assets: objects (``o``/``g``) split by material (``usemtl``), checked like any mesh.

The project's own hardened OBJ reading (:mod:`simcore.scene.mesh_files`) extended with the
group and material statements; ``mtllib`` files are not opened (their names are all the
import needs, and they come with every ``usemtl``), so nothing outside the file is read.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.assets import (
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


def _parse(path: Path, text: str
           ) -> tuple[NDArray[np.float64], dict[tuple[str, str], list[list[int]]]]:
    """Vertices and the polygons of each (group, material)."""
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
    return np.array(verts, dtype=np.float64).reshape(-1, 3), groups


def read_obj(path: Path, data: bytes, *, up: str = "y") -> AssetScene:
    """Objects of an OBJ file, one per (group, material) with faces, in project axes."""
    points, groups = _parse(path, data.decode("utf-8", errors="replace"))
    out = AssetScene(source=path)
    taken: set[str] = set()
    filled = [key for key, polys in groups.items() if polys]
    if len(filled) > MAX_ASSET_OBJECTS:
        raise AssetError(f"{path.name}: {len(filled)} objects (group × material); at most "
                         f"{MAX_ASSET_OBJECTS}")
    per_group = Counter(g for g, _m in filled)
    several = {g for g, n in per_group.items() if n > 1}
    for (group, material), polys in groups.items():
        if not polys:
            continue
        tris = np.array([(p[0], p[k], p[k + 1]) for p in polys for k in range(1, len(p) - 1)],
                        dtype=np.int64).reshape(-1, 3)
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
