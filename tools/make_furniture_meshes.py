"""Build the bundled furniture meshes (``resources/furniture/*.obj``) from boxes and cylinders.

Run from the repository root: ``python tools/make_furniture_meshes.py``. Each piece is
several trimesh primitives concatenated (closed shells that may touch or overlap, as a
modelled piece of furniture often is), in metres: local x is the depth (the front faces
−x), y the width, z up; the footprint is centred on the origin and the lowest point is
z = 0, so a piece placed at floor height stands on the floor. The OBJ text is written
here with 5 decimals, so the files are the same bytes on every machine.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import trimesh

OUT = Path(__file__).resolve().parents[1] / "resources" / "furniture"


def box(sx: float, sy: float, sz: float, x: float, y: float, z: float) -> trimesh.Trimesh:
    """A box of size (sx, sy, sz) centred at (x, y, z)."""
    mesh = trimesh.creation.box(extents=(sx, sy, sz))
    mesh.apply_translation((x, y, z))
    return mesh


def post(r: float, h: float, x: float, y: float, z0: float = 0.0) -> trimesh.Trimesh:
    """A vertical cylinder of radius r and height h standing at (x, y, z0)."""
    mesh = trimesh.creation.cylinder(radius=r, height=h, sections=12)
    mesh.apply_translation((x, y, z0 + h / 2))
    return mesh


def sofa() -> list[trimesh.Trimesh]:
    """A three-seat sofa, 0.9 × 2.0 × 0.85 m, on four feet."""
    d, w, feet = 0.9, 2.0, 0.08
    parts = [box(d, w - 0.3, 0.35, -0.05, 0, feet + 0.175),            # seat block
             box(0.2, w, 0.77, d / 2 - 0.1, 0, feet + 0.385)]           # backrest
    parts += [box(d, 0.15, 0.55, 0, s * (w / 2 - 0.075), feet + 0.275) for s in (-1, 1)]
    parts += [post(0.03, feet, sx * (d / 2 - 0.06), sy * (w / 2 - 0.06))
              for sx in (-1, 1) for sy in (-1, 1)]
    return parts


def armchair() -> list[trimesh.Trimesh]:
    """An armchair, 0.85 × 0.85 × 0.9 m, on four feet."""
    d, w, feet = 0.85, 0.85, 0.08
    parts = [box(d, w - 0.3, 0.35, -0.05, 0, feet + 0.175),
             box(0.2, w, 0.82, d / 2 - 0.1, 0, feet + 0.41)]
    parts += [box(d, 0.15, 0.55, 0, s * (w / 2 - 0.075), feet + 0.275) for s in (-1, 1)]
    parts += [post(0.03, feet, sx * (d / 2 - 0.06), sy * (w / 2 - 0.06))
              for sx in (-1, 1) for sy in (-1, 1)]
    return parts


def bookcase() -> list[trimesh.Trimesh]:
    """A bookcase with a back, 0.35 × 0.9 × 1.8 m, five boards."""
    d, w, h, t = 0.35, 0.9, 1.8, 0.02
    parts = [box(d, t, h, 0, s * (w / 2 - t / 2), h / 2) for s in (-1, 1)]
    parts.append(box(t, w, h, d / 2 - t / 2, 0, h / 2))
    parts += [box(d, w - 2 * t, t, 0, 0, t / 2 + k * (h - t) / 4) for k in range(5)]
    return parts


def dining_table() -> list[trimesh.Trimesh]:
    """A table, 0.9 × 1.6 m, 0.75 m high, on four round legs."""
    d, w, h, t = 0.9, 1.6, 0.75, 0.04
    parts = [box(d, w, t, 0, 0, h - t / 2)]
    parts += [post(0.03, h - t, sx * (d / 2 - 0.08), sy * (w / 2 - 0.08))
              for sx in (-1, 1) for sy in (-1, 1)]
    return parts


PIECES = {"sofa": sofa, "armchair": armchair, "bookcase": bookcase,
          "dining_table": dining_table}


def obj_text(name: str, mesh: trimesh.Trimesh) -> str:
    """The mesh as OBJ text: vertices with 5 decimals, triangles (1-based)."""
    lines = [f"# tofradar furniture: {name} (tools/make_furniture_meshes.py), metres",
             f"o {name}"]
    lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in np.asarray(mesh.vertices)]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(mesh.faces)]
    return "\n".join(lines) + "\n"


def main() -> int:
    """Write every piece's OBJ file and print its size."""
    OUT.mkdir(parents=True, exist_ok=True)
    for name, build in PIECES.items():
        mesh = trimesh.util.concatenate(build())
        lo = mesh.bounds[0]
        centre = (mesh.bounds[0] + mesh.bounds[1]) / 2
        mesh.apply_translation((-centre[0], -centre[1], -lo[2]))   # centred, on the floor
        (OUT / f"{name}.obj").write_text(obj_text(name, mesh), encoding="ascii")
        size = mesh.bounds[1] - mesh.bounds[0]
        print(f"{name}: {len(mesh.vertices)} vertices, {len(mesh.faces)} triangles, "
              f"{size[0]:.2f} × {size[1]:.2f} × {size[2]:.2f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
