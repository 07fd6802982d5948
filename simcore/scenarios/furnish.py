"""Furniture and clutter added by count, people on random walks, materials with ranges.

The parts of a scenario spec beyond ``vary`` (``docs/scenarios.md``):

- ``room``: the floor rectangle (``x_m``, ``y_m``, world metres) where pieces and people
  are placed, and the clearance kept free around the rig;
- ``furniture``: pieces of the :data:`PIECES` library (parametric, or bundled meshes at
  their real size) added by count (``count: [lo, hi]``,
  inclusive), each sized within its own ranges, turned by a random yaw and placed so that
  its footprint's axis-aligned bounding box lies inside the room and overlaps no other
  piece, no object of the base project standing in the room, and not the rig's clearance;
- ``people``: people added by count, each starting in a free spot and walking a random
  path of ``waypoints`` (keyframed, inside the room, every leg clear of the furniture),
  with a drawn height, build, speed, gesture and vital signs;
- ``materials``: new named materials, each a copy of a library (or project) material
  whose band parameters are drawn from distributions; they join the project's
  ``materials`` and can be named by the pieces.

Everything is drawn from the scene's own generator after ``vary``, in the spec's order,
so the same spec and seed give the same bytes.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any

import numpy as np
from pydantic import Field, field_validator, model_validator
from scipy.spatial.transform import Rotation

from simcore.preflight import RunError
from simcore.scene.people.config import VitalSigns

from ._dists import Choice, Normal, Strict, Uniform

Dist = Uniform | Normal | Choice
#: Most pieces or people one entry may add, most placement tries per piece or waypoint,
#: most objects the furniture and people of one spec may add.
MAX_PER_ENTRY = 200
MAX_TRIES = 400
MAX_ADDED_OBJECTS = 5000
MAX_WAYPOINTS = 50
#: A person's footprint (m, side of the square kept free of furniture); shortest leg of a
#: walk (m).
PERSON_SIDE_M = 0.6
MIN_LEG_M = 0.2
#: Starts tried per person (each with MAX_TRIES tries per waypoint).
START_TRIES = 20


class FurnishError(RunError):
    """A scene whose pieces or people cannot be placed (one line)."""


def _count_range(v: tuple[int, int]) -> tuple[int, int]:
    if v[0] < 0 or v[0] > v[1] or v[1] > MAX_PER_ENTRY:
        raise ValueError(f"needs 0 <= low <= high <= {MAX_PER_ENTRY}")
    return v


class Room(Strict):
    """The floor rectangle where pieces and people go, and the rig's clearance."""

    x_m: tuple[float, float]
    y_m: tuple[float, float]
    floor_z_m: float = Field(0.0, ge=-1e3, le=1e3, allow_inf_nan=False)
    rig_clearance_m: float = Field(0.5, ge=0.0, le=100.0, allow_inf_nan=False)

    @field_validator("x_m", "y_m")
    @classmethod
    def _span(cls, v: tuple[float, float]) -> tuple[float, float]:
        if not all(math.isfinite(x) and abs(x) <= 1e4 for x in v) or not v[0] < v[1]:
            raise ValueError("needs finite low < high (|value| <= 10000 m)")
        return v


class FurnitureEntry(Strict):
    """``{"piece": "desk", "count": [lo, hi], "materials": {"top": {"choice": [...]}}}``."""

    piece: str
    count: tuple[int, int]
    materials: dict[str, Choice] = Field(default_factory=dict, max_length=16)

    @field_validator("count")
    @classmethod
    def _count(cls, v: tuple[int, int]) -> tuple[int, int]:
        return _count_range(v)

    @model_validator(mode="after")
    def _known(self) -> FurnitureEntry:
        if self.piece not in PIECES:
            raise ValueError(f"piece {self.piece!r} is not one of {', '.join(sorted(PIECES))}")
        roles = PIECES[self.piece].roles
        for role in self.materials:
            if role not in roles:
                raise ValueError(f"piece {self.piece!r} has no part {role!r}; its parts are "
                                 f"{', '.join(roles)}")
        return self


class PeopleEntry(Strict):
    """People added by count, on random walks."""

    count: tuple[int, int]
    waypoints: tuple[int, int] = (2, 4)
    height_m: Dist = Uniform(uniform=(1.55, 1.9))
    build: Dist = Uniform(uniform=(0.85, 1.2))
    speed_mps: Dist = Uniform(uniform=(0.4, 1.2))
    gesture: Choice = Choice(choice=[None])
    vital_signs: dict[str, Dist] | None = None

    @field_validator("count")
    @classmethod
    def _count(cls, v: tuple[int, int]) -> tuple[int, int]:
        return _count_range(v)

    @field_validator("waypoints")
    @classmethod
    def _waypoints(cls, v: tuple[int, int]) -> tuple[int, int]:
        if v[0] < 0 or v[0] > v[1] or v[1] > MAX_WAYPOINTS:
            raise ValueError(f"needs 0 <= low <= high <= {MAX_WAYPOINTS}")
        return v

    @field_validator("vital_signs")
    @classmethod
    def _vitals(cls, v: dict[str, Dist] | None) -> dict[str, Dist] | None:
        for key in v or {}:
            if key not in VitalSigns.model_fields:
                raise ValueError(f"unknown vital sign {key!r}; known: "
                                 f"{', '.join(VitalSigns.model_fields)}")
        return v


class MaterialEntry(Strict):
    """A new material: a copy of ``from`` with band parameters drawn."""

    from_: str = Field(alias="from", min_length=1, max_length=200)
    bands: dict[str, dict[str, Dist]] = Field(default_factory=dict, max_length=8)

    model_config = Strict.model_config | {"populate_by_name": True}


# --- the piece library -------------------------------------------------------------------

Part = tuple[str, dict[str, Any], tuple[float, float, float]]   # role, geometry, local centre


class Piece:
    """A piece of the library: draws its size and returns its parts and footprint.

    ``mesh``: the bundled mesh file (``furniture/<name>.obj``) of a mesh piece, else None.
    """

    def __init__(self, roles: tuple[str, ...], defaults: dict[str, str],
                 build: Callable[[np.random.Generator], tuple[list[Part], float, float]],
                 doc: str, mesh: str | None = None) -> None:
        self.roles, self.defaults, self.build, self.doc = roles, defaults, build, doc
        self.mesh = mesh


#: Folder of the bundled furniture meshes under the resources, and the folder (next to the
#: generated projects) that holds their copies: a generated project names
#: ``furniture/<piece>.obj``, relative to its own folder.
FURNITURE_DIR = "furniture"


@functools.cache
def mesh_bounds(name: str) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(lowest, highest) corner (m) of the bundled furniture mesh ``name``."""
    from simcore.resources import RESOURCES_DIR
    from simcore.scene.mesh_files import read_mesh_arrays

    points, _ = read_mesh_arrays(RESOURCES_DIR / FURNITURE_DIR / f"{name}.obj")
    lo, hi = points.min(axis=0), points.max(axis=0)
    return (float(lo[0]), float(lo[1]), float(lo[2])), (float(hi[0]), float(hi[1]),
                                                        float(hi[2]))


def _mesh_build(name: str) -> Callable[[np.random.Generator], tuple[list[Part], float, float]]:
    """The build of a mesh piece: one part at its real size, standing on the floor.

    The part's local centre puts the mesh's footprint centre on the piece's position and
    its lowest point at floor height; nothing is drawn.
    """
    def build(rng: np.random.Generator) -> tuple[list[Part], float, float]:
        lo, hi = mesh_bounds(name)
        geometry = {"kind": "mesh", "path": f"{FURNITURE_DIR}/{name}.obj", "scale": 1.0}
        centre = (-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2])
        return [("body", geometry, centre)], hi[0] - lo[0], hi[1] - lo[1]

    return build


def _box(role: str, sx: float, sy: float, sz: float, x: float, y: float, z: float) -> Part:
    return role, {"kind": "box", "size_m": [sx, sy, sz]}, (x, y, z)


def _desk(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    w, d, h = rng.uniform(1.0, 1.6), rng.uniform(0.6, 0.8), rng.uniform(0.70, 0.76)
    t, leg = 0.03, 0.04
    parts = [_box("top", d, w, t, 0.0, 0.0, h - t / 2)]
    for sx in (-1, 1):
        for sy in (-1, 1):
            parts.append(_box("legs", leg, leg, h - t, sx * (d / 2 - leg), sy * (w / 2 - leg),
                              (h - t) / 2))
    return parts, d, w


def _table(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    r, h = rng.uniform(0.35, 0.6), rng.uniform(0.70, 0.76)
    return [("top", {"kind": "cylinder", "radius_m": r, "height_m": 0.03}, (0.0, 0.0, h - 0.015)),
            ("legs", {"kind": "cylinder", "radius_m": 0.03, "height_m": h - 0.03},
             (0.0, 0.0, (h - 0.03) / 2))], 2 * r, 2 * r


def _chair(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    s, h = rng.uniform(0.4, 0.5), rng.uniform(0.42, 0.5)
    back = rng.uniform(0.35, 0.5)
    return [_box("seat", s, s, 0.06, 0.0, 0.0, h),
            _box("back", 0.04, s, back, s / 2 - 0.02, 0.0, h + 0.03 + back / 2),
            ("post", {"kind": "cylinder", "radius_m": 0.025, "height_m": h - 0.03},
             (0.0, 0.0, (h - 0.03) / 2))], s, s


def _shelf(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    w, d, h = rng.uniform(0.6, 1.2), rng.uniform(0.28, 0.4), rng.uniform(1.0, 2.0)
    n = int(rng.integers(3, 6))
    t = 0.02
    parts = [_box("frame", d, t, h, 0.0, sy * (w / 2 - t / 2), h / 2) for sy in (-1, 1)]
    for k in range(n):
        z = t / 2 + k * (h - t) / (n - 1)
        parts.append(_box("boards", d, w - 2 * t, t, 0.0, 0.0, z))
    return parts, d, w


def _cabinet(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    w, d, h = rng.uniform(0.4, 1.0), rng.uniform(0.4, 0.6), rng.uniform(0.6, 1.3)
    return [_box("body", d, w, h, 0.0, 0.0, h / 2)], d, w


def _box_clutter(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    sx, sy, sz = rng.uniform(0.15, 0.6), rng.uniform(0.15, 0.6), rng.uniform(0.1, 0.5)
    return [_box("body", sx, sy, sz, 0.0, 0.0, sz / 2)], sx, sy


def _bin(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    r, h = rng.uniform(0.12, 0.2), rng.uniform(0.3, 0.5)
    return [("body", {"kind": "cylinder", "radius_m": r, "height_m": h}, (0.0, 0.0, h / 2))
            ], 2 * r, 2 * r


def _plant(rng: np.random.Generator) -> tuple[list[Part], float, float]:
    r, h = rng.uniform(0.1, 0.18), rng.uniform(0.25, 0.4)
    crown = rng.uniform(0.2, 0.4)
    return [("pot", {"kind": "cylinder", "radius_m": r, "height_m": h}, (0.0, 0.0, h / 2)),
            ("leaves", {"kind": "sphere", "radius_m": crown}, (0.0, 0.0, h + crown * 0.8))
            ], 2 * max(r, crown), 2 * max(r, crown)


#: The pieces a spec adds by name; sizes (m) drawn within the ranges of ``docs/scenarios.md``.
PIECES: dict[str, Piece] = {
    "desk": Piece(("top", "legs"), {"top": "wood", "legs": "aluminium"}, _desk,
                  "top 1.0–1.6 × 0.6–0.8 m at 0.70–0.76 m, four legs"),
    "table": Piece(("top", "legs"), {"top": "wood", "legs": "aluminium"}, _table,
                   "round top of radius 0.35–0.6 m at 0.70–0.76 m on a post"),
    "chair": Piece(("seat", "back", "post"),
                   {"seat": "fabric", "back": "black_plastic", "post": "aluminium"}, _chair,
                   "seat 0.4–0.5 m at 0.42–0.5 m, backrest 0.35–0.5 m, a post"),
    "shelf": Piece(("frame", "boards"), {"frame": "wood", "boards": "wood"}, _shelf,
                   "0.6–1.2 m wide, 0.28–0.4 m deep, 1–2 m high, 3–5 boards"),
    "cabinet": Piece(("body",), {"body": "aluminium"}, _cabinet,
                     "a block 0.4–1.0 × 0.4–0.6 × 0.6–1.3 m"),
    "box": Piece(("body",), {"body": "paper"}, _box_clutter,
                 "a carton 0.15–0.6 × 0.15–0.6 × 0.1–0.5 m on the floor"),
    "bin": Piece(("body",), {"body": "black_plastic"}, _bin,
                 "a cylinder of radius 0.12–0.2 m, 0.3–0.5 m high"),
    "plant": Piece(("pot", "leaves"), {"pot": "black_plastic", "leaves": "fabric"}, _plant,
                   "a pot and a round crown of radius 0.2–0.4 m"),
    # Bundled meshes (resources/furniture, built by tools/make_furniture_meshes.py).
    "sofa": Piece(("body",), {"body": "fabric"}, _mesh_build("sofa"),
                  "three-seat sofa mesh, 0.95 × 2.0 × 0.85 m", mesh="sofa"),
    "armchair": Piece(("body",), {"body": "fabric"}, _mesh_build("armchair"),
                      "armchair mesh, 0.9 × 0.85 × 0.9 m", mesh="armchair"),
    "bookcase": Piece(("body",), {"body": "wood"}, _mesh_build("bookcase"),
                      "bookcase mesh with a back and five boards, 0.35 × 0.9 × 1.8 m",
                      mesh="bookcase"),
    "dining_table": Piece(("body",), {"body": "wood"}, _mesh_build("dining_table"),
                          "table mesh on four round legs, 0.9 × 1.6 × 0.75 m",
                          mesh="dining_table"),
}


# --- geometry helpers --------------------------------------------------------------------

Rect = tuple[float, float, float, float]     # x0, y0, x1, y1


def _overlap(a: Rect, b: Rect) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _footprint(x: float, y: float, yaw_deg: float, d: float, w: float) -> Rect:
    """Axis-aligned box of a d (local x) × w (local y) rectangle turned by ``yaw_deg``."""
    c, s = abs(math.cos(math.radians(yaw_deg))), abs(math.sin(math.radians(yaw_deg)))
    hx, hy = (c * d + s * w) / 2, (s * d + c * w) / 2
    return x - hx, y - hy, x + hx, y + hy


def object_footprint(obj: dict[str, Any]) -> Rect | None:
    """Floor-plane bounding box of a parametric object of a project document (None: other)."""
    g = obj.get("geometry", {})
    kind = g.get("kind")
    if kind == "box":
        half = np.asarray(g["size_m"], dtype=float) / 2
    elif kind == "cylinder":
        half = np.array([g["radius_m"], g["radius_m"], g["height_m"] / 2], dtype=float)
    elif kind == "sphere":
        half = np.full(3, float(g["radius_m"]))
    elif kind == "ellipsoid":
        half = np.asarray(g["radii_m"], dtype=float)
    elif kind == "corner_reflector":
        half = np.full(3, float(g["edge_m"]))
    elif kind == "person":
        half = np.array([PERSON_SIDE_M / 2, PERSON_SIDE_M / 2, 1.0])
    else:
        return None
    pose = obj.get("pose", {})
    rot = Rotation.from_euler("xyz", pose.get("rotation_deg", [0, 0, 0]),
                              degrees=True).as_matrix()
    ext = np.abs(rot) @ half
    p = np.asarray(pose.get("position_m", [0, 0, 0]), dtype=float)
    return p[0] - ext[0], p[1] - ext[1], p[0] + ext[0], p[1] + ext[1]


def _segment_hits(p: np.ndarray, q: np.ndarray, r: Rect) -> bool:
    """Whether the segment p→q meets the rectangle (slab test)."""
    t0, t1 = 0.0, 1.0
    for axis, (lo, hi) in enumerate(((r[0], r[2]), (r[1], r[3]))):
        dv = q[axis] - p[axis]
        if abs(dv) < 1e-12:
            if not lo < p[axis] < hi:
                return False
            continue
        a, b = (lo - p[axis]) / dv, (hi - p[axis]) / dv
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
        if t0 >= t1:
            return False
    return True


def _r(v: float) -> float:
    return round(float(v), 6)


# --- the drawing -------------------------------------------------------------------------

def draw_materials(entries: dict[str, MaterialEntry], library: dict[str, dict[str, Any]],
                   rng: np.random.Generator) -> list[dict[str, Any]]:
    """The drawn materials (documents), in the spec's order."""
    out = []
    for name, entry in entries.items():
        if entry.from_ not in library:
            raise FurnishError(f"materials.{name}.from: {entry.from_!r} is not a material of "
                               "the library or the base project")
        doc = dict(library[entry.from_])
        doc = {**doc, "name": name, "bands": {k: dict(v) for k, v in doc["bands"].items()}}
        doc["description"] = f"{entry.from_} with drawn parameters (scenario)"
        for band, params in entry.bands.items():
            if band not in doc["bands"]:
                raise FurnishError(f"materials.{name}.bands.{band}: {entry.from_!r} has no band "
                                   f"{band!r}; it has {', '.join(doc['bands'])}")
            for key, dist in params.items():
                doc["bands"][band][key] = dist.draw(rng)
        out.append(doc)
    return out


def _empty_motion() -> dict[str, Any]:
    return {"velocity_mps": [0.0, 0.0, 0.0], "angular_velocity_dps": [0.0, 0.0, 0.0],
            "keyframes": [], "repeat": "hold"}


def _base_footprints(doc: dict[str, Any], area: Rect, room: Room) -> list[Rect]:
    """Floor areas already taken before any piece is placed.

    The base project's objects standing in the room (not the floor or the ceiling) and the
    rig's clearance.
    """
    ax, ay = area[2] - area[0], area[3] - area[1]
    taken: list[Rect] = []
    for obj in doc.get("objects", []):
        fp = object_footprint(obj)
        if fp is None or not _overlap(fp, area):
            continue
        if fp[2] - fp[0] >= 0.5 * ax and fp[3] - fp[1] >= 0.5 * ay:
            continue        # the floor or the ceiling
        taken.append(fp)
    rig = doc.get("rig", {}).get("pose", {}).get("position_m", [0.0, 0.0, 0.0])
    c = room.rig_clearance_m
    if c > 0:
        taken.append((rig[0] - c, rig[1] - c, rig[0] + c, rig[1] + c))
    return taken


def _rounded(geometry: dict[str, Any]) -> dict[str, Any]:
    """A part's geometry with its floats rounded to the micrometre (stable JSON)."""
    return {key: ([_r(v) for v in val] if isinstance(val, list)
                  else _r(val) if isinstance(val, float) else val)
            for key, val in geometry.items()}


class _Placer:
    """Adds pieces and people to one project document, keeping their footprints apart.

    Holds the room, the footprints taken so far, the names in use and the next object id;
    every draw comes from ``rng`` in the order of the calls.
    """

    def __init__(self, doc: dict[str, Any], room: Room, rng: np.random.Generator,
                 index: int) -> None:
        self.room, self.rng, self.index = room, rng, index
        self.area: Rect = (room.x_m[0], room.y_m[0], room.x_m[1], room.y_m[1])
        self.taken = _base_footprints(doc, self.area, room)
        self.objects: list[dict[str, Any]] = doc.setdefault("objects", [])
        self.next_id = max((int(o.get("id", 0)) for o in self.objects), default=0) + 1
        self.names = {o.get("name") for o in self.objects}
        self.bundled: list[int] = []     # objects that name a bundled furniture mesh

    def fresh(self, stem: str) -> str:
        """``stem`` + the first number no object's name (or name prefix) uses."""
        k = 1
        while f"{stem}{k}" in self.names or any(n and str(n).startswith(f"{stem}{k}_")
                                                for n in self.names):
            k += 1
        self.names.add(f"{stem}{k}")
        return f"{stem}{k}"

    def free_spot(self, d: float, w: float, what: str) -> tuple[float, float, float, Rect]:
        """A position and yaw where a d × w footprint lies in the room, clear of the rest."""
        area, rng = self.area, self.rng
        ax, ay = area[2] - area[0], area[3] - area[1]
        for _ in range(MAX_TRIES):
            yaw = float(rng.uniform(-180.0, 180.0))
            c_, s_ = abs(math.cos(math.radians(yaw))), abs(math.sin(math.radians(yaw)))
            hx, hy = (c_ * d + s_ * w) / 2, (s_ * d + c_ * w) / 2
            if 2 * hx >= ax or 2 * hy >= ay:
                continue
            x = float(rng.uniform(area[0] + hx, area[2] - hx))
            y = float(rng.uniform(area[1] + hy, area[3] - hy))
            fp = _footprint(x, y, yaw, d, w)
            if not any(_overlap(fp, t) for t in self.taken):
                return x, y, yaw, fp
        raise FurnishError(f"scene {self.index}: no free place for {what} in the room after "
                           f"{MAX_TRIES} tries; lower the counts or enlarge room.x_m/y_m")

    def add_piece(self, entry: FurnitureEntry) -> None:
        """One piece of ``entry``: its parts sized, materials drawn, placed and turned."""
        rng, piece = self.rng, PIECES[entry.piece]
        parts, d, w = piece.build(rng)
        mats = {role: (str(entry.materials[role].draw(rng)) if role in entry.materials
                       else piece.defaults[role]) for role in piece.roles}
        stem = self.fresh(entry.piece)
        x, y, yaw, fp = self.free_spot(d, w, f"a {entry.piece}")
        self.taken.append(fp)
        cy, sy = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
        for k, (role, geometry, (lx, ly, lz)) in enumerate(parts):
            if piece.mesh is not None:
                self.bundled.append(len(self.objects))
            self.objects.append({
                "id": self.next_id, "name": f"{stem}_{role}{k + 1}",
                "geometry": _rounded(geometry),
                "pose": {"position_m": [_r(x + cy * lx - sy * ly), _r(y + sy * lx + cy * ly),
                                        _r(self.room.floor_z_m + lz)],
                         "rotation_deg": [0.0, 0.0, _r(yaw)]},
                "material": mats[role], "motion": _empty_motion()})
            self.next_id += 1

    def _walk(self, n_way: int, name: str) -> tuple[list[np.ndarray], Rect]:
        """A start clear of the furniture and ``n_way`` legs that cross none of it."""
        area, rng, half = self.area, self.rng, PERSON_SIDE_M / 2
        grown = [(t[0] - half, t[1] - half, t[2] + half, t[3] + half) for t in self.taken]
        for _start in range(START_TRIES):   # a start boxed in by furniture: another one
            x, y, _yaw, fp = self.free_spot(PERSON_SIDE_M, PERSON_SIDE_M, f"person {name}")
            points = [np.array([x, y])]
            for _w in range(n_way):
                for _t in range(MAX_TRIES):
                    q = np.array([rng.uniform(area[0] + half, area[2] - half),
                                  rng.uniform(area[1] + half, area[3] - half)])
                    if float(np.hypot(*(q - points[-1]))) >= MIN_LEG_M and not any(
                            _segment_hits(points[-1], q, t) for t in grown):
                        points.append(q)
                        break
                else:
                    break
            if len(points) == n_way + 1:
                return points, fp
        raise FurnishError(f"scene {self.index}: no clear walk of {n_way} legs for person "
                           f"{name} from {START_TRIES} starts; fewer pieces or waypoints")

    @staticmethod
    def _keyframes(points: list[np.ndarray], speed: float
                   ) -> tuple[dict[str, Any], dict[str, Any] | None, float]:
        """The motion (keyframes relative to the start), walk and heading of a path."""
        motion = _empty_motion()
        if len(points) < 2 or speed <= 0:
            return motion, None, 0.0
        step = points[1] - points[0]
        yaw = math.degrees(math.atan2(step[1], step[0]))
        x, y = points[0]
        t = 0.0
        for k, p in enumerate(points):
            if k:
                t += float(np.hypot(*(p - points[k - 1]))) / speed
            motion["keyframes"].append({"time_s": _r(t), "position_m": [
                _r(p[0] - x), _r(p[1] - y), 0.0], "rotation_deg": [0.0, 0.0, 0.0]})
        motion["repeat"] = "back_and_forth"
        return motion, {"speed_mps": _r(speed), "path": "keyframes"}, yaw

    def add_person(self, group: PeopleEntry) -> None:
        """One person of ``group``: a clear random walk, drawn body, gesture and vitals."""
        rng = self.rng
        name = self.fresh("walker")
        n_way = int(rng.integers(group.waypoints[0], group.waypoints[1] + 1))
        points, fp = self._walk(n_way, name)
        speed = max(float(group.speed_mps.draw(rng)), 0.0)
        self.taken.append(fp)
        motion, walk, yaw = self._keyframes(points, speed)
        vitals = None
        if group.vital_signs is not None:
            vitals = {key: _r(dist.draw(rng)) for key, dist in group.vital_signs.items()}
        x, y = points[0]
        self.objects.append({
            "id": self.next_id, "name": name,
            "geometry": {"kind": "person", "height_m": _r(group.height_m.draw(rng)),
                         "build": _r(group.build.draw(rng)), "skin": "skin",
                         "clothing": "clothing",
                         "motion": {"posture": "standing", "walk": walk,
                                    "gesture": group.gesture.draw(rng),
                                    "vital_signs": vitals, "bvh": None, "sway_mm": 2.0}},
            "pose": {"position_m": [_r(x), _r(y), _r(self.room.floor_z_m)],
                     "rotation_deg": [0.0, 0.0, _r(yaw)]},
            "material": "clothing", "motion": motion})
        self.next_id += 1


def furnish(doc: dict[str, Any], room: Room, furniture: list[FurnitureEntry],
            people: list[PeopleEntry], rng: np.random.Generator, *, index: int) -> list[int]:
    """Add the pieces and people to the project document ``doc`` (in place).

    Each entry draws its count, then its pieces (or people) one by one, in the spec's
    order; each lands in a free spot of the room (:class:`_Placer`). Returns the indices
    of the objects that name a bundled furniture mesh (``furniture/<piece>.obj``,
    relative to the generated project's folder, where :func:`simcore.scenarios.generate`
    copies it).
    """
    placer = _Placer(doc, room, rng, index)
    for entry in furniture:
        count = int(rng.integers(entry.count[0], entry.count[1] + 1))
        for _ in range(count):
            placer.add_piece(entry)
    for group in people:
        count = int(rng.integers(group.count[0], group.count[1] + 1))
        for _ in range(count):
            placer.add_person(group)
    return placer.bundled
