"""Independent reference for tofradar's radar with targets in a room: Sionna RT + GO targets.

Not part of the package. Same environment as ``room_paths.py`` (see there)::

    tools/references/sionna/.venv/bin/python tools/references/sionna/target_paths.py

Scenes: the 6 × 4 × 3 m concrete room of ``room_paths.py`` (ITU-R P.2040 concrete, smooth,
at 60 GHz), with and without a metal left wall (y = 4 m), the radar at (1.5, 1.6, 1.0) m
facing the front wall (+x, 4.5 m ahead), off the room's symmetry planes; in each room one
target about 2.5 m ahead, off boresight and off the room's symmetry planes:

* ``point``: a point scatterer of σ = 1 m² (isotropic, also bistatically);
* ``sphere``: a metal sphere of radius 0.2 m (GO: σ = π a² = 0.126 m², monostatic and
  bistatic, the return from the specular point);
* ``corner``: a metal triangular trihedral of edge 0.12 m, its symmetry axis towards the
  radar (GO: σ = 4π A² / λ², A the triple-bounce effective area).

How the paths are found. Sionna RT's image-method solver (specular reflections,
polarimetric, the room's faces one-sided) traces, for a V- and for an H-polarised radar,

1. the room's own returns: every path radar → faces → radar up to three bounces (Tx at the
   radar, Rx 1 cm beside it in each of the eight diagonal directions, the union taken one
   path per image of the radar: exactly beside the Tx the reflection points of the room's
   edges and corners fall on the edges and Sionna drops the paths), and
2. every one-way path radar → faces → target (Rx at the target's centre, up to two
   bounces, isotropic Tx, a dual-polarised V/H Rx).

The targets are not meshed in Sionna: its image method reflects a path in a facet's plane as
if the plane were infinite, which gives a faceted sphere the return of an infinite plane
(π D² instead of π a²) and a small trihedral that of an infinite corner (π D²), so a
curved or small metal target's monostatic return is not a ray-tracing result. Instead each
target's two-way returns combine the one-way paths ``i`` (out) and ``j`` (back, by
reciprocity the same channel) with the target's geometric-optics scattering::

    a_ij = (E_j · S E_i) √(4π σ_ij) / λ,     L_ij = L_i + L_j  (a sphere: less, below)

with ``E`` a leg's field at the target as a world vector (Sionna's V and H coefficients on
θ̂ and φ̂ of its direction of arrival ``u``) and ``S``: for the point target tofradar's
convention (its co-polar RCS towards every direction: the co-polar parts of both legs, on
θ̂ for V and φ̂ for H turned to the polarisation's side, :func:`_copolar`), for the sphere
a perfect conductor's mirror at its specular point (``−M``; the point ``P`` on the sphere
whose normal bisects the directions from ``P`` to the radar's images along both legs,
``L_ij`` the exact length through it, :func:`sphere_specular`; σ = πa² with the legs'
distances to the centre, the far-field radar equation), for the trihedral ``+1`` (three
conductor mirrors, ``(−M₃)(−M₂)(−M₁) = +I``: its return has the opposite sign to a
plate's). A direct line ``|E| = λ / (4π d)`` gives the radar equation ``|a| = λ √σ /
((4π)^{3/2} d²)``. The trihedral is a retro-reflector: for ``i = j`` its σ is the GO
effective area in the leg's direction (the entrance triangle projected across the ray and
intersected with its own point reflection through the apex), and between two different legs
the aperture's diffraction lobe ``|2 J₁(x)/x|²``, ``x = k r sin β``, ``r = √(A/π)``, which
is below −30 dB for the bistatic angles of a room's ghosts. What this leaves out: the
target's shadow on the room's returns, paths between target and room faces with the target
reflecting more than once, and the room corners Sionna's solver does not find (the
front–left–ceiling one and those behind the radar). Target paths more than 50 dB under the
direct return are dropped.

Each path is written to ``resources/references/sionna_target_paths.npz`` (keys
``{room}_{room|point|sphere|corner}_…`` for V, ``H_{room}_…`` for H) with its length
(m), coefficient (complex, V → V, without the propagation phase ``e^{-jkL}``: Sionna's
``a``), number of face bounces, and the unit directions in which it leaves and returns to
the radar (world frame), so that the comparison can weigh them by tofradar's element
pattern (Sionna's antennas here are isotropic).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from room_paths import ROOM, room_xml  # noqa: E402

RADAR = (1.5, 1.6, 1.0)
#: Rays shot per source to find the candidate sequences of faces.
SAMPLES = 10**6
FREQUENCY_HZ = 60e9
C = 299_792_458.0
LAMBDA = C / FREQUENCY_HZ
OUT = Path(__file__).resolve().parents[3] / "resources" / "references" / "sionna_target_paths.npz"
#: name: (offset from the radar (m, world), kind, size (m): σ for the point, radius, edge).
TARGETS = {
    "point": ((2.5, 0.45, 0.2), 1.0),
    "sphere": ((2.4, -0.4, 0.3), 0.2),
    "corner": ((2.6, 0.5, -0.25), 0.12),
}
ROOMS = ("concrete", "metal_left")
#: Target paths kept: within 50 dB of the scene's strongest (the direct return).
KEEP = 10 ** (-50 / 20)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _direction(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Unit vector of zenith ``theta`` and azimuth ``phi`` (rad)."""
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)],
                    axis=-1)


def _solve(tx: tuple[float, ...], rx: tuple[float, ...], rx_pol: str, max_depth: int, *,
           metal_left: bool, tx_pol: str = "V") -> dict[str, np.ndarray]:
    """Sionna's specular paths tx → room → rx: a [rx_ant, path], tau, bounces, directions."""
    import sionna.rt as rt

    with tempfile.TemporaryDirectory() as tmp:
        xml = Path(tmp) / "room.xml"
        xml.write_text(room_xml(metal_left=metal_left))
        scene = rt.load_scene(str(xml), merge_shapes=False)
    scene.frequency = FREQUENCY_HZ
    scene.tx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=tx_pol)
    scene.rx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=rx_pol)
    scene.add(rt.Transmitter("tx", position=[float(v) for v in tx]))
    scene.add(rt.Receiver("rx", position=[float(v) for v in rx]))
    paths = rt.PathSolver()(scene, max_depth=max_depth, los=True, specular_reflection=True,
                            diffuse_reflection=False, refraction=False, synthetic_array=True,
                            samples_per_src=SAMPLES)
    names = {obj.object_id: name for name, obj in scene.objects.items()}
    a_re, a_im = paths.a
    a = (np.asarray(a_re) + 1j * np.asarray(a_im))[0, :, 0, 0, :]       # [rx_ant, path]
    tau = np.asarray(paths.tau).reshape(-1)
    inter = np.asarray(paths.interactions).reshape(max_depth, -1)
    keep = tau > 0
    ids = np.asarray(paths.objects).reshape(max_depth, -1)
    faces = [tuple(names.get(int(i), "") for i in col if int(i) in names) for col in ids.T]
    return {"faces": [f for f, k in zip(faces, keep, strict=True) if k],
            "a": a[:, keep], "length_m": C * tau[keep],
            "bounces": np.count_nonzero(inter != 0, axis=0)[keep],
            "dep": _direction(np.asarray(paths.theta_t).reshape(-1),
                              np.asarray(paths.phi_t).reshape(-1))[keep],
            "arr": _direction(np.asarray(paths.theta_r).reshape(-1),
                              np.asarray(paths.phi_r).reshape(-1))[keep]}


#: Rx offsets from the Tx (m) of the room's monostatic traces: with the Rx exactly beside
#: the Tx, the reflection points of a room edge's (corner's) double (triple) bounce lie on
#: the edge, and Sionna's solver drops the path; 1 cm off in every axis it finds most.
RX_OFFSETS = tuple((0.01 * sx, 0.01 * sy, 0.01 * sz) for sx in (1, -1) for sy in (1, -1)
                   for sz in (1, -1))
#: The room's faces: (axis, coordinate) of each plane, by name.
FACES = {"floor": (2, 0.0), "ceiling": (2, ROOM[2]), "front": (0, ROOM[0]), "back": (0, 0.0),
         "left": (1, ROOM[1]), "right": (1, 0.0)}


def _image(faces: tuple[str, ...]) -> np.ndarray:
    """The radar mirrored in ``faces`` in turn (m)."""
    img = np.array(RADAR, dtype=float)
    for name in faces:
        axis, c = FACES[name]
        img[axis] = 2 * c - img[axis]
    return img


def monostatic_length(faces: tuple[str, ...]) -> float:
    """Exact length (m) of the path radar → faces → radar: the radar's image in them."""
    return float(np.linalg.norm(_image(faces) - np.array(RADAR)))


def room_returns(*, metal_left: bool, pol: str = "V") -> dict[str, np.ndarray]:
    """The room's own monostatic returns (up to three bounces, line of sight dropped).

    The union over the Rx offsets :data:`RX_OFFSETS` of Sionna's paths, one per image of
    the radar (its coefficient and directions from the first trace that finds it), with
    the exact monostatic length of its sequence (the radar mirrored in the faces in turn).
    Mirrors in perpendicular faces commute: the orders of one set of faces (an edge's
    two, a corner's six) are one image, of which each bistatic trace realises one order
    (the reflection points of the others fall outside the faces) and the image theory of
    a 90° wedge or corner counts once. So the key is the image (mirrors in parallel faces
    do not commute: front then back wall and back then front are two images).
    """
    seen: dict[tuple[str, ...], int] = {}
    rows: dict[str, list] = {"length_m": [], "a": [], "bounces": [], "out": [], "back": []}
    for off in RX_OFFSETS:
        res = _solve(RADAR, tuple(np.add(RADAR, off)), pol, 3, metal_left=metal_left,
                     tx_pol=pol)
        for i, faces in enumerate(res["faces"]):
            if res["bounces"][i] == 0 or len(faces) != res["bounces"][i]:
                continue
            key = tuple(np.round(_image(faces), 4))
            if key in seen:
                continue
            seen[key] = 1
            rows["length_m"].append(monostatic_length(faces))
            rows["a"].append(res["a"][0, i])
            rows["bounces"].append(res["bounces"][i])
            rows["out"].append(res["dep"][i])
            rows["back"].append(res["arr"][i])
    return {key: np.array(v) for key, v in rows.items()}


def trihedral_area(direction: np.ndarray, edge: float, axes: np.ndarray) -> float:
    """GO triple-bounce effective area (m²) of a triangular trihedral seen along ``direction``.

    ``direction``: unit vector from the apex towards the radar; ``axes``: the three unit
    edge vectors (rows). The entrance triangle (the edges' tips) projected across the ray,
    intersected with its point reflection through the apex (Knott, *Radar Cross Section*
    §5.4); zero outside the octant.
    """
    if np.any(axes @ direction <= 0):
        return 0.0
    e1 = _unit(np.cross(direction, [0.0, 0.0, 1.0] if abs(direction[2]) < 0.9 else [1, 0, 0]))
    e2 = np.cross(direction, e1)
    tips = edge * axes
    tri = np.column_stack([tips @ e1, tips @ e2])
    poly = [tuple(p) for p in tri]
    if _area(tri) < 0:
        tri = tri[::-1]
    for k in range(3):                           # clip by the reflected triangle -tri
        a, b = -tri[k], -tri[(k + 1) % 3]
        poly = _clip(poly, a, b)
        if not poly:
            return 0.0
    return abs(_area(np.array(poly)))


def _area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _clip(poly: list[tuple[float, float]], a: np.ndarray, b: np.ndarray
          ) -> list[tuple[float, float]]:
    """Sutherland–Hodgman: the part of ``poly`` left of the directed edge a → b."""
    def side(p: tuple[float, float]) -> float:
        return float((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]))

    out: list[tuple[float, float]] = []
    for k, p in enumerate(poly):
        q = poly[(k + 1) % len(poly)]
        sp, sq = side(p), side(q)
        if sp >= 0:
            out.append(p)
        if sp * sq < 0:
            t = sp / (sp - sq)
            out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return out


def corner_axes(towards: np.ndarray) -> np.ndarray:
    """Edge unit vectors of a trihedral whose symmetry axis points along ``towards``."""
    s = np.ones(3) / np.sqrt(3)
    t = _unit(towards)
    v, c = np.cross(s, t), float(s @ t)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rot = np.eye(3) + vx + vx @ vx / (1 + c)
    return (rot @ np.eye(3)).T


def sphere_specular(centre: np.ndarray, radius: float, src: np.ndarray, rcv: np.ndarray
                    ) -> tuple[np.ndarray, float]:
    """The specular point of a sphere between two points: its normal and the path's length.

    ``src`` and ``rcv``: the radar's images along the two legs (each leg unfolded through
    its faces, a straight line from the sphere). The point ``P = c + a n`` where the normal
    ``n`` bisects the directions from ``P`` (not from the centre) to both, found by fixed-
    point iteration from the centre's bisector; the length ``|src − P| + |P − rcv|`` is
    stationary there (Fermat). The first-order ``L_i + L_j − a |u_i + u_j|`` (distances to
    the centre) is short by about ``a² sin²(β/2) (1/L_i + 1/L_j) / 2``: 9 mm (≈ 2λ at
    60 GHz) for a = 0.2 m, 2.5 m and 8.4 m legs at β = 132°.
    """
    n = _unit(_unit(src - centre) + _unit(rcv - centre))
    for _ in range(100):
        p = centre + radius * n
        new = _unit(_unit(src - p) + _unit(rcv - p))
        done = float(np.linalg.norm(new - n)) < 1e-13
        n = new
        if done:
            break
    p = centre + radius * n
    return n, float(np.linalg.norm(src - p) + np.linalg.norm(rcv - p))


def _fields(h: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The legs' E at the target as world vectors (K, 3).

    Sionna's V and H coefficients on the receiving antenna's θ̂ and φ̂ of each leg's
    direction of arrival ``u``.
    """
    theta = np.arccos(np.clip(u[:, 2], -1, 1))
    phi = np.arctan2(u[:, 1], u[:, 0])
    t_hat = np.stack([np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi),
                      -np.sin(theta)], axis=1)
    p_hat = np.stack([-np.sin(phi), np.cos(phi), np.zeros_like(phi)], axis=1)
    return h[0][:, None] * t_hat + h[1][:, None] * p_hat


def _copolar(u: np.ndarray, pol: str) -> np.ndarray:
    """The co-polar unit vector at the target of a leg arriving from ``u``: V ∝ θ̂, H ∝ φ̂.

    tofradar's convention (``simcore.sensors.radar.reflectors.copolar_fields``): Ludwig's
    second definition about the vertical, the same as Sionna's ``"V"`` and ``"H"``
    antennas (3GPP TR 38.901 §7.3.2; H horizontal in every direction), turned to the side
    of the radar's polarisation (V: world z, H: world y), the same for ``u`` and ``−u``.
    """
    p = np.array([0.0, 0.0, 1.0]) if pol == "V" else np.array([0.0, 1.0, 0.0])
    if pol == "V":
        e = _unit(p[None] - (u @ p)[:, None] * u)
    else:
        e = _unit(np.cross(np.array([0.0, 0.0, 1.0])[None], u))
    return np.where((e @ p)[:, None] < 0.0, -e, e)


def target_returns(name: str, *, metal_left: bool, pol: str = "V") -> dict[str, np.ndarray]:
    """Two-way paths radar → faces → target → faces → radar (module docstring)."""
    from scipy.special import j1

    offset, size = TARGETS[name]
    centre = np.array(RADAR) + np.array(offset)
    one = _solve(RADAR, tuple(centre), "VH", 2, metal_left=metal_left, tx_pol=pol)
    h, length = one["a"], one["length_m"]                 # h [2, n]
    u = one["arr"]                                        # Sionna: direction of arrival
    k = 2 * np.pi / LAMBDA
    axes = corner_axes(np.array(RADAR) - centre)
    n = length.size
    rows: dict[str, list] = {"length_m": [], "a": [], "bounces": [], "out": [], "back": []}
    field = _fields(h, u)                                  # E at the target per leg (world)
    copol = np.einsum("kd,kd->k", field, _copolar(u, pol))
    for i in range(n):
        for j in range(n):
            cosb = float(np.clip(u[i] @ u[j], -1, 1))
            if name == "point":
                # tofradar's point target: its co-polar RCS towards every direction.
                s_ij = complex(copol[i] * copol[j])
                amp, delta = np.sqrt(size), 0.0
            elif name == "sphere":
                # GO: the specular point's mirror (a perfect conductor: −M) on E.
                nrm, two_way = sphere_specular(centre, size, centre + length[i] * u[i],
                                               centre + length[j] * u[j])
                s_ij = -complex(field[i] @ field[j] - 2 * (field[i] @ nrm) * (field[j] @ nrm))
                amp, delta = np.sqrt(np.pi) * size, length[i] + length[j] - two_way
            else:
                # Three conductor mirrors: −M₃ −M₂ −M₁ = +I (the triple image of a dipole
                # is the dipole itself; a plate's single image is −p: opposite signs).
                s_ij = complex(field[i] @ field[j])
                ai, aj = trihedral_area(u[i], size, axes), trihedral_area(u[j], size, axes)
                area = np.sqrt(ai * aj)
                x = k * np.sqrt(area / np.pi) * np.sqrt(max(0.0, 1 - cosb**2))
                lobe = 1.0 if x < 1e-9 else float(2 * j1(x) / x)
                amp, delta = np.sqrt(4 * np.pi) * area / LAMBDA * lobe, 0.0
            rows["length_m"].append(length[i] + length[j] - delta)
            rows["a"].append(s_ij * np.sqrt(4 * np.pi) / LAMBDA * amp)
            rows["bounces"].append(one["bounces"][i] + one["bounces"][j])
            rows["out"].append(one["dep"][i])
            rows["back"].append(one["dep"][j])
    out = {key: np.array(v) for key, v in rows.items()}
    strong = np.abs(out["a"]) >= KEEP * np.max(np.abs(out["a"]))
    return {key: v[strong] for key, v in out.items()}


def main() -> int:
    """Trace every scene and write the cached arrays."""
    out: dict[str, np.ndarray] = {}
    for pol, plain in (("V", ""), ("H", "H_")):
        for name in ROOMS:
            _scene(out, name, f"{plain}{name}", pol)
    out["radar_m"] = np.array(RADAR)
    out["room_m"] = np.array(ROOM)
    out["frequency_hz"] = np.array(FREQUENCY_HZ)
    for name, (offset, size) in TARGETS.items():
        out[f"target_{name}_m"] = np.array(RADAR) + np.array(offset)
        out[f"target_{name}_size"] = np.array(size)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    # Single precision (lengths to 1 µm, levels to 1e-7): the file stays small.
    small = {k: v.astype(np.complex64 if np.iscomplexobj(v) else np.float32)
             if v.dtype.kind in "fc" and v.ndim else v for k, v in out.items()}
    np.savez_compressed(OUT, **small)
    print("wrote", OUT, OUT.stat().st_size, "bytes")
    return 0


def _scene(out: dict[str, np.ndarray], which: str, room: str, pol: str) -> None:
    """One room at one polarisation: its own returns and each target's, into ``out``."""
    metal = which == "metal_left"
    for key, v in room_returns(metal_left=metal, pol=pol).items():
        out[f"{room}_room_{key}"] = v
    for target in TARGETS:
        res = target_returns(target, metal_left=metal, pol=pol)
        for key, v in res.items():
            out[f"{room}_{target}_{key}"] = v
        a = np.abs(res["a"])
        if target == "point":
            room_a = np.abs(out[f"{room}_room_a"])
            print(room, "room", room_a.size, "paths:", ", ".join(
                f"{out[f'{room}_room_length_m'][i] / 2:.3f} m {20 * np.log10(room_a[i]):.1f}"
                for i in np.argsort(-room_a)[:20]))
        order = np.argsort(-a)[:8]
        print(room, target, res["length_m"].size, "paths; strongest:",
              ", ".join(f"{res['length_m'][i] / 2:.3f} m {20 * np.log10(a[i]):.1f} dB"
                        for i in order))


if __name__ == "__main__":
    sys.exit(main())
