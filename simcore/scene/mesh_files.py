"""Mesh files (STL, OBJ, PLY) parsed and checked in Python before any native code sees them.

VTK's readers trust the file: face indices out of range crash them and a PLY header that
claims 2·10⁹ vertices aborts the process with ``std::bad_alloc``. Here every count is
checked against the file's size and the caps below before anything is allocated, every
index against the vertex count and every coordinate for finiteness; VTK only receives the
checked arrays. Every problem is a :class:`MeshError` naming the file and what is wrong.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simcore.scene.files import InputFileError, read_regular_file

#: Largest mesh file read (bytes), most vertices and most triangles of one mesh.
MAX_MESH_FILE_BYTES = 256 * 2**20
MAX_MESH_VERTICES = 4_000_000
MAX_MESH_TRIANGLES = 4_000_000
#: Largest vertex coordinate magnitude in the file's own units.
MAX_MESH_COORDINATE = 1e6
MESH_SUFFIXES = (".stl", ".obj", ".ply")


class MeshError(ValueError):
    """A mesh file could not be read, breaks a limit or has no triangles."""


def _fail(path: Path, message: str) -> MeshError:
    return MeshError(f"{path.name}: {message}")


def open_regular_file(path: Path, *, max_bytes: int = MAX_MESH_FILE_BYTES) -> bytes:
    """Read a regular file of at most ``max_bytes``; refuse devices, FIFOs, loops, dirs.

    :func:`simcore.scene.files.read_regular_file` with its problem as a :class:`MeshError`.
    """
    try:
        return read_regular_file(path, max_bytes=max_bytes)
    except InputFileError as exc:
        raise _fail(path, exc.problem) from None


def read_mesh_arrays(path: Path) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Parse and check a mesh file.

    Returns
    -------
    points : ndarray, shape (points, 3), float64
        Vertex positions in the file's units, all finite.
    triangles : ndarray, shape (triangles, 3), int64
        Vertex indices, each in ``[0, points)``; polygons are fan-triangulated.
    """
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise _fail(path, f"unsupported mesh format {suffix!r} (use {', '.join(MESH_SUFFIXES)})")
    data = open_regular_file(path)
    if suffix == ".stl":
        points, tris = _parse_stl(path, data)
    elif suffix == ".obj":
        points, tris = _parse_obj(path, data)
    else:
        points, tris = _parse_ply(path, data)
    return check_mesh_arrays(path, points, tris)


def check_mesh_arrays(path: Path, points: NDArray[np.floating], tris: NDArray[np.integer]
                      ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Counts, finiteness, coordinate range and index range of a parsed mesh."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    tris = np.asarray(tris, dtype=np.int64).reshape(-1, 3)
    if len(points) > MAX_MESH_VERTICES:
        raise _fail(path, f"{len(points)} vertices; at most {MAX_MESH_VERTICES}")
    if len(tris) > MAX_MESH_TRIANGLES:
        raise _fail(path, f"{len(tris)} triangles; at most {MAX_MESH_TRIANGLES}")
    if len(tris) == 0:
        raise _fail(path, "no triangles in the file")
    if not np.isfinite(points).all():
        raise _fail(path, "vertex coordinates include NaN or infinity")
    if len(points) and np.abs(points).max() > MAX_MESH_COORDINATE:
        raise _fail(path, f"vertex coordinate {np.abs(points).max():.3g} exceeds "
                          f"±{MAX_MESH_COORDINATE:g}")
    if tris.min() < 0 or tris.max() >= len(points):
        bad = int(tris.min()) if tris.min() < 0 else int(tris.max())
        raise _fail(path, f"face index {bad} out of range [0, {len(points)})")
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    keep = area2 > 0
    if not keep.any():
        raise _fail(path, "every triangle has zero area")
    return points, tris[keep]


def _fan(polys: list[list[int]]) -> list[tuple[int, int, int]]:
    out = []
    for poly in polys:
        for k in range(1, len(poly) - 1):
            out.append((poly[0], poly[k], poly[k + 1]))
    return out


# --------------------------------------------------------------------------- STL
def _parse_stl(path: Path, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    if len(data) >= 84:
        n = int.from_bytes(data[80:84], "little")
        if len(data) == 84 + 50 * n:
            if n > MAX_MESH_TRIANGLES:
                raise _fail(path, f"{n} triangles; at most {MAX_MESH_TRIANGLES}")
            rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
            verts = np.frombuffer(data, dtype=rec, count=n, offset=84)["v"].reshape(-1, 3)
            return _merge(verts.astype(np.float64))
    if not data.lstrip()[:5].lower() == b"solid":
        raise _fail(path, "neither a binary STL (size does not match its triangle count) "
                          "nor an ASCII STL ('solid' header)")
    text = data.decode("ascii", errors="replace")
    number = r"([-+0-9.eEinfINFaA]+)"
    found = re.findall(rf"vertex\s+{number}\s+{number}\s+{number}", text)
    if len(found) % 3:
        raise _fail(path, f"{len(found)} vertices is not a whole number of triangles")
    if len(found) // 3 > MAX_MESH_TRIANGLES:
        raise _fail(path, f"{len(found) // 3} triangles; at most {MAX_MESH_TRIANGLES}")
    try:
        verts = np.array(found, dtype=np.float64).reshape(-1, 3)
    except ValueError:
        raise _fail(path, "a vertex coordinate is not a number") from None
    return _merge(verts)


def _merge(verts: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Shared vertices from a triangle soup (as VTK's STL reader merges them)."""
    if not np.isfinite(verts).all():
        return verts, np.arange(len(verts)).reshape(-1, 3)   # reported by the checks
    points, inverse = np.unique(verts, axis=0, return_inverse=True)
    return points, np.asarray(inverse, dtype=np.int64).reshape(-1, 3)


# --------------------------------------------------------------------------- OBJ
def _parse_obj(path: Path, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    text = data.decode("utf-8", errors="replace")
    verts: list[list[float]] = []
    polys: list[list[int]] = []
    for lineno, line in enumerate(text.splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        try:
            if parts[0] == "v":
                if len(parts) < 4:
                    raise ValueError("a vertex needs three coordinates")
                verts.append([float(p) for p in parts[1:4]])
                if len(verts) > MAX_MESH_VERTICES:
                    raise _fail(path, f"more than {MAX_MESH_VERTICES} vertices")
            elif parts[0] == "f":
                if len(parts) < 4:
                    raise ValueError("a face needs at least three vertices")
                idx = []
                for p in parts[1:]:
                    i = int(p.split("/")[0])
                    if i == 0:
                        raise ValueError("face index 0 (OBJ indices start at 1)")
                    # Negative indices count back from the latest vertex.
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                polys.append(idx)
                if len(polys) > MAX_MESH_TRIANGLES:
                    raise _fail(path, f"more than {MAX_MESH_TRIANGLES} faces")
        except ValueError as exc:
            if isinstance(exc, MeshError):
                raise
            raise _fail(path, f"line {lineno}: {exc}") from None
    tris = _fan(polys)
    return (np.array(verts, dtype=np.float64).reshape(-1, 3),
            np.array(tris, dtype=np.int64).reshape(-1, 3))


# --------------------------------------------------------------------------- PLY
_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
    "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def _ply_header(path: Path, data: bytes
                ) -> tuple[str, list[tuple[str, int, list[tuple[str, str, str | None]]]], int]:
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise _fail(path, "not a PLY file (no 'ply' magic or no 'end_header')")
    body = data.index(b"\n", end) + 1 if b"\n" in data[end:] else len(data)
    fmt = ""
    elements: list[tuple[str, int, list[tuple[str, str, str | None]]]] = []
    for line in data[:end].decode("ascii", errors="replace").splitlines()[1:]:
        parts = line.split()
        if not parts or parts[0] in ("comment", "obj_info"):
            continue
        if parts[0] == "format" and len(parts) >= 2:
            fmt = parts[1]
        elif parts[0] == "element" and len(parts) == 3:
            try:
                count = int(parts[2])
            except ValueError:
                raise _fail(path, f"element count {parts[2]!r} is not an integer") from None
            if count < 0:
                raise _fail(path, f"negative element count {count}")
            elements.append((parts[1], count, []))
        elif parts[0] == "property" and elements:
            if parts[1] == "list" and len(parts) == 5:
                count_t, item_t = _PLY_TYPES.get(parts[2]), _PLY_TYPES.get(parts[3])
                if count_t is None or item_t is None:
                    raise _fail(path, f"unknown PLY type in {line.strip()!r}")
                elements[-1][2].append((parts[4], item_t, count_t))
            elif len(parts) == 3 and parts[1] in _PLY_TYPES:
                elements[-1][2].append((parts[2], _PLY_TYPES[parts[1]], None))
            else:
                raise _fail(path, f"unsupported property line {line.strip()!r}")
        else:
            raise _fail(path, f"unexpected header line {line.strip()[:60]!r}")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise _fail(path, f"unknown PLY format {fmt!r}")
    return fmt, elements, body


def _parse_ply(path: Path, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    fmt, elements, offset = _ply_header(path, data)
    remaining = len(data) - offset
    for name, count, _props in elements:
        # Every element takes at least one byte (binary) or two characters (ASCII): a
        # count the file cannot hold is refused before anything is allocated.
        if count > remaining:
            raise _fail(path, f"header claims {count} {name} elements but the file has "
                              f"only {remaining} bytes of data")
        cap = MAX_MESH_VERTICES if name == "vertex" else MAX_MESH_TRIANGLES
        if count > cap:
            raise _fail(path, f"{count} {name} elements; at most {cap}")
    if fmt == "ascii":
        return _ply_ascii(path, data[offset:], elements)
    return _ply_binary(path, data, offset, elements, "<" if "little" in fmt else ">")


def _vertices_and_faces(path: Path, found: dict[str, object]
                        ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    if "vertex" not in found or "face" not in found:
        raise _fail(path, "a PLY mesh needs 'vertex' and 'face' elements")
    verts = found["vertex"]
    faces = found["face"]
    assert isinstance(verts, np.ndarray) and isinstance(faces, np.ndarray)
    return verts, faces


def _ply_ascii(path: Path, body: bytes,
               elements: list[tuple[str, int, list[tuple[str, str, str | None]]]]
               ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    tokens = body.split()
    pos = 0
    found: dict[str, object] = {}

    def take(n: int) -> list[bytes]:
        nonlocal pos
        if pos + n > len(tokens):
            raise _fail(path, "file ends before the elements its header declares")
        out = tokens[pos:pos + n]
        pos += n
        return out

    try:
        for name, count, props in elements:
            names = [p[0] for p in props]
            if all(p[2] is None for p in props):
                values = np.array(take(count * len(props)), dtype=np.float64).reshape(
                    count, len(props))
                if name == "vertex":
                    if not {"x", "y", "z"} <= set(names):
                        raise _fail(path, "vertex element lacks x, y or z")
                    found["vertex"] = values[:, [names.index(a) for a in "xyz"]]
                continue
            polys: list[list[int]] = []
            for _ in range(count):
                row: list[int] = []
                for pname, _t, count_t in props:
                    if count_t is None:
                        take(1)
                        continue
                    k = int(take(1)[0])
                    if k < 0 or k > 1_000_000:
                        raise _fail(path, f"list length {k} out of range")
                    items = [int(float(t)) for t in take(k)]
                    if pname in ("vertex_indices", "vertex_index"):
                        row = items
                polys.append(row)
            if name == "face":
                found["face"] = np.array(_fan(polys), dtype=np.int64).reshape(-1, 3)
    except ValueError as exc:
        if isinstance(exc, MeshError):
            raise
        raise _fail(path, f"a value is not a number ({exc})") from None
    return _vertices_and_faces(path, found)


def _ply_binary(path: Path, data: bytes, offset: int,
                elements: list[tuple[str, int, list[tuple[str, str, str | None]]]],
                order: str) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    found: dict[str, object] = {}
    for name, count, props in elements:
        names = [p[0] for p in props]
        if all(p[2] is None for p in props):
            dtype = np.dtype([(p[0], order + p[1]) for p in props])
            if offset + count * dtype.itemsize > len(data):
                raise _fail(path, f"file ends inside the {count} {name} elements")
            rec = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            offset += count * dtype.itemsize
            if name == "vertex":
                if not {"x", "y", "z"} <= set(names):
                    raise _fail(path, "vertex element lacks x, y or z")
                found["vertex"] = np.stack([rec[a].astype(np.float64) for a in "xyz"], axis=1)
            continue
        if name == "face" and len(props) == 1 and props[0][2] is not None:
            # Fast path: every face a triangle (checked), read as fixed records.
            tri_t = np.dtype([("k", order + props[0][2]), ("i", order + props[0][1], 3)])
            if offset + count * tri_t.itemsize <= len(data):
                rec = np.frombuffer(data, dtype=tri_t, count=count, offset=offset)
                if (rec["k"] == 3).all():
                    found["face"] = rec["i"].astype(np.int64)
                    offset += count * tri_t.itemsize
                    continue
        polys: list[list[int]] = []
        for _ in range(count):
            row: list[int] = []
            for pname, item_t, count_t in props:
                if count_t is None:
                    size = np.dtype(item_t).itemsize
                    if offset + size > len(data):
                        raise _fail(path, f"file ends inside the {name} elements")
                    offset += size
                    continue
                ct = np.dtype(order + count_t)
                if offset + ct.itemsize > len(data):
                    raise _fail(path, f"file ends inside the {name} elements")
                k = int(np.frombuffer(data, dtype=ct, count=1, offset=offset)[0])
                offset += ct.itemsize
                it = np.dtype(order + item_t)
                if k < 0 or offset + k * it.itemsize > len(data):
                    raise _fail(path, f"list of {k} items runs past the end of the file")
                items = np.frombuffer(data, dtype=it, count=k, offset=offset).astype(np.int64)
                offset += k * it.itemsize
                if pname in ("vertex_indices", "vertex_index"):
                    row = items.tolist()
            polys.append(row)
        if name == "face":
            found["face"] = np.array(_fan(polys), dtype=np.int64).reshape(-1, 3)
    return _vertices_and_faces(path, found)
