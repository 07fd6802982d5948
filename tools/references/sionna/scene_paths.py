r"""Independent reference for tofradar's radar in ANY exported scene: Sionna RT 2.2.

Not part of the package. Same environment as ``room_paths.py`` (see there). First export a
project's scene at one instant with tofradar's own environment, then trace it here::

    .venv/bin/python tools/references/export_scene.py resources/examples/office.json \
        --out /tmp/office_scene --without-people
    tools/references/sionna/.venv/bin/python tools/references/sionna/scene_paths.py \
        /tmp/office_scene --out resources/references/sionna_office_paths.npz

The office is traced without its walking person (``--without-people``): tofradar's
person is a scatterer model (segments with their own RCS and micro-Doppler), not a
surface Sionna's image method could reflect from in the same way, so the two would not
be comparing the same physics.

The scene (``scene.json`` + world-frame PLY meshes, :mod:`export_scene`) becomes a
Mitsuba scene, one shape per object with a radio material built from its radar band, at
the radar's chirp centre frequency ``f`` (``start_frequency_hz + bandwidth_hz / 2``):

* ``metallic`` = 1: ε′ = 1, σ = 10⁷ S/m (ITU-R P.2040 metal; |Γ| > 0.999 at 60 GHz);
* a permittivity: ε′ and ``σ = 2π f ε₀ ε′ tan δ`` (the same complex permittivity
  ``ε′(1 − j tan δ)`` as tofradar's slab model), the slab's ``thickness_m`` where set,
  otherwise 1 m (a lossy half-space: nothing comes back from the back of a 1 m slab);
* left out: objects the radar band does not render (``opacity`` 0) and objects with
  neither a permittivity nor ``metallic`` = 1 (tofradar gives them only a diffuse σ⁰
  return with a random phase, no coherent reflection; e.g. the office's IR retroreflector
  tape), and corner reflectors (below). Roughness is not modelled (smooth faces): the
  comparison makes tofradar's materials smooth too.

How the paths are found, with the settings of ``target_paths.py`` (image method after
shooting-and-bouncing candidates, 10⁶ rays per source, specular reflection, refraction
through slabs (the wave passes a thin paper or wood sheet as it does in tofradar), no
diffuse reflection, no diffraction), for a V- and an H-polarised radar at the radar's Tx:

1. the scene's own monostatic returns: every path radar → faces → radar with up to
   ``--max-depth`` interactions (reflections and slab crossings), Rx 1 cm beside the Tx in
   each of the eight diagonal directions (with the Rx exactly at the Tx the reflection
   points of edges and corners fall on the edges and Sionna drops the paths), the union
   taken one path per image of the radar (the radar mirrored in the planes of the path's
   reflections, each plane from the path's own vertices), its monostatic length the
   image's distance;
2. each corner reflector (an open mesh of three mutually perpendicular triangles sharing
   a vertex, the apex) as geometric optics, exactly as ``target_paths.py``'s trihedral:
   every one-way path radar → faces → apex (Rx at the apex, up to ``--max-depth + 1``
   interactions, a dual-polarised Rx), paired out and back with the trihedral's
   triple-bounce effective area (its bistatic diffraction lobe between different legs).
   Sionna's image method would reflect in each facet's infinite plane and give a 0.2 m
   trihedral the return of an infinite corner.

3. for the record, not for the specular comparison: every single edge diffraction radar →
   edge → radar (Sionna's UTD, ``diffraction`` and ``edge_diffraction`` on, Rx 1 cm off),
   as ``P_diffraction_…`` (with ``point_m``, the diffraction point): a metal plate whose
   specular point lies off the plate returns from its edges, which tofradar's
   physical-optics facets give too.

Paths more than 60 dB (room) or 50 dB (corner) under the scene's strongest are dropped.
Per polarisation ``P`` the file holds ``P_room_…`` and ``P_corner<k>_…``: ``length_m``
(m), ``a`` (Sionna's complex coefficient, co-polar, without the propagation phase),
``bounces`` (reflections), ``crossings`` (slab crossings), ``out`` and ``back`` (unit
directions in which the path leaves and returns to the radar, world frame); and
``radar_m``, ``radar_to_world`` (3 × 3: the radar's optical axes x right, y down,
z forward as columns), ``frequency_hz``, ``traced``, ``left_out`` and ``corners`` (object
names), ``project`` and ``time_s`` (the exported project and instant).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from target_paths import RX_OFFSETS, SAMPLES, _direction, _fields, trihedral_area  # noqa: E402

C = 299_792_458.0
EPS0 = 8.8541878128e-12
METAL_CONDUCTIVITY = 1e7
BULK_THICKNESS_M = 1.0
KEEP_ROOM_DB = 60.0
KEEP_CORNER_DB = 50.0


def radio_material(radar: dict[str, Any] | None, frequency_hz: float
                   ) -> tuple[float, float, float] | None:
    """(ε′, σ (S/m), thickness (m)) of a radar band, or None where it is left out."""
    if radar is None or radar.get("opacity", 1.0) <= 0.0:
        return None
    if radar.get("metallic", 0.0) >= 1.0:
        return 1.0, METAL_CONDUCTIVITY, 0.01
    eps = radar.get("permittivity")
    if eps is None:
        return None
    sigma = 2 * np.pi * frequency_hz * EPS0 * eps * float(radar.get("loss_tangent", 0.0))
    thick = radar.get("thickness_m")
    return float(eps), float(sigma), float(thick) if thick else BULK_THICKNESS_M


def corner_geometry(points: np.ndarray, faces: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, float] | None:
    """(apex, edge unit vectors (3, 3), edge length) of a trihedral mesh, else None.

    A trihedral: three triangles sharing one vertex (the apex), their other vertices
    along three mutually perpendicular edges of equal length.
    """
    if len(faces) != 3:
        return None
    common = set(faces[0]) & set(faces[1]) & set(faces[2])
    if len(common) != 1:
        return None
    apex_i = common.pop()
    tips = sorted({int(v) for f in faces for v in f} - {apex_i})
    if len(tips) != 3:
        return None
    apex = points[apex_i]
    edges = points[tips] - apex
    length = np.linalg.norm(edges, axis=1)
    axes = edges / length[:, None]
    if np.max(np.abs(axes @ axes.T - np.eye(3))) > 1e-3 or np.ptp(length) > 1e-3 * length[0]:
        return None
    return apex, axes, float(length.mean())


def read_ply(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) and triangles (m, 3) of a binary little-endian PLY (export_scene's).

    Vertices at the same position are merged (the exporter may repeat them per triangle).
    """
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    counts = {ln.split()[1]: int(ln.split()[2]) for ln in header if ln.startswith("element")}
    props = [ln.split()[-1] for ln in header if ln.startswith("property float")]
    nv, nf = counts["vertex"], counts["face"]
    verts = np.frombuffer(data, dtype="<f4", count=nv * len(props), offset=end)
    verts = verts.reshape(nv, len(props))[:, :3].astype(float)
    face_t = np.dtype([("n", "u1"), ("i", "<i4", (3,))])
    faces = np.frombuffer(data, dtype=face_t, count=nf, offset=end + nv * len(props) * 4)["i"]
    uniq, inverse = np.unique(np.round(verts, 6), axis=0, return_inverse=True)
    return uniq, inverse.reshape(-1)[faces]


def build_scene(scene_dir: Path, frequency_hz: float
                ) -> tuple[str, list[str], list[str], list[tuple[str, tuple]]]:
    """Mitsuba XML of the scene; names traced, left out; corner reflectors (name, geometry)."""
    scene = json.loads((scene_dir / "scene.json").read_text())
    shapes, traced, left_out, corners = [], [], [], []
    for k, obj in enumerate(scene["objects"]):
        ply = scene_dir / obj["ply"]
        geom = corner_geometry(*read_ply(ply))
        if geom is not None and (obj["radar"] or {}).get("metallic", 0.0) >= 1.0:
            corners.append((obj["name"], geom))
            continue
        mat = radio_material(obj["radar"], frequency_hz)
        if mat is None:
            left_out.append(obj["name"])
            continue
        eps, sigma, thick = mat
        traced.append(obj["name"])
        shapes.append(
            f'  <bsdf type="radio-material" id="m{k}">'
            f'<float name="relative_permittivity" value="{eps!r}"/>'
            f'<float name="conductivity" value="{sigma!r}"/>'
            f'<float name="thickness" value="{thick!r}"/></bsdf>\n'
            f'  <shape type="ply" id="o{k}_{obj["name"]}">'
            f'<string name="filename" value="{ply.resolve()}"/>'
            f'<boolean name="face_normals" value="true"/><ref id="m{k}"/></shape>')
    xml = '<scene version="2.1.0">\n' + "\n".join(shapes) + "\n</scene>\n"
    return xml, traced, left_out, corners


def solve(xml: str, tx: np.ndarray, rx: np.ndarray, *, frequency_hz: float, tx_pol: str,
          rx_pol: str, max_depth: int, diffraction: bool = False) -> dict[str, np.ndarray]:
    """Sionna's paths tx → scene → rx: a [rx_ant, path], length, interactions, vertices."""
    import sionna.rt as rt

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "scene.xml"
        path.write_text(xml)
        scene = rt.load_scene(str(path), merge_shapes=False)
    scene.frequency = frequency_hz
    scene.tx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=tx_pol)
    scene.rx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization=rx_pol)
    scene.add(rt.Transmitter("tx", position=[float(v) for v in tx]))
    scene.add(rt.Receiver("rx", position=[float(v) for v in rx]))
    flags = ({"specular_reflection": False, "refraction": False, "diffraction": True,
              "edge_diffraction": True} if diffraction else
             {"specular_reflection": True, "refraction": True})
    paths = rt.PathSolver()(scene, max_depth=max_depth, los=True, diffuse_reflection=False,
                            synthetic_array=True, samples_per_src=SAMPLES, **flags)
    a_re, a_im = paths.a
    a = (np.asarray(a_re) + 1j * np.asarray(a_im))[0, :, 0, 0, :]       # [rx_ant, path]
    tau = np.asarray(paths.tau).reshape(-1)
    inter = np.asarray(paths.interactions).reshape(max_depth, -1)
    verts = np.asarray(paths.vertices).reshape(max_depth, -1, 3)
    keep = tau > 0
    return {"a": a[:, keep], "length_m": C * tau[keep], "inter": inter[:, keep],
            "verts": verts[:, keep],
            "dep": _direction(np.asarray(paths.theta_t).reshape(-1),
                              np.asarray(paths.phi_t).reshape(-1))[keep],
            "arr": _direction(np.asarray(paths.theta_r).reshape(-1),
                              np.asarray(paths.phi_r).reshape(-1))[keep]}


def _image(radar: np.ndarray, rx: np.ndarray, inter: np.ndarray, verts: np.ndarray
           ) -> np.ndarray:
    """The radar mirrored in the planes of a path's reflections, in turn (m).

    Each plane passes through the reflection point with the normal bisecting the
    reflected and the incident direction; slab crossings do not bend the path.
    """
    pts = [radar] + [verts[i] for i in range(inter.size) if inter[i] != 0] + [rx]
    kinds = [0] + [int(i) for i in inter if i != 0] + [0]
    img = np.array(radar, dtype=float)
    for i in range(1, len(pts) - 1):
        if kinds[i] != 1:                                    # refraction: straight on
            continue
        d_in = pts[i] - pts[i - 1]
        d_out = pts[i + 1] - pts[i]
        n = d_out / np.linalg.norm(d_out) - d_in / np.linalg.norm(d_in)
        n /= np.linalg.norm(n)
        img = img - 2 * float((img - pts[i]) @ n) * n
    return img


def room_returns(xml: str, radar: np.ndarray, *, frequency_hz: float, pol: str,
                 max_depth: int) -> dict[str, np.ndarray]:
    """The scene's monostatic returns: the union over the Rx offsets, one per image."""
    seen: set[tuple[float, ...]] = set()
    rows: dict[str, list] = {k: [] for k in ("length_m", "a", "bounces", "crossings",
                                             "out", "back")}
    for off in RX_OFFSETS:
        rx = radar + np.asarray(off)
        res = solve(xml, radar, rx, frequency_hz=frequency_hz, tx_pol=pol, rx_pol=pol,
                    max_depth=max_depth)
        for i in range(res["length_m"].size):
            inter = res["inter"][:, i]
            bounces = int(np.count_nonzero(inter == 1))
            if bounces == 0:
                continue
            img = _image(radar, rx, inter, res["verts"][:, i])
            key = tuple(np.round(img, 3))
            if key in seen:
                continue
            seen.add(key)
            rows["length_m"].append(float(np.linalg.norm(img - radar)))
            rows["a"].append(res["a"][0, i])
            rows["bounces"].append(bounces)
            rows["crossings"].append(int(np.count_nonzero(inter == 4)))
            rows["out"].append(res["dep"][i])
            rows["back"].append(res["arr"][i])
    out = {k: np.array(v) for k, v in rows.items()}
    strong = np.abs(out["a"]) >= 10 ** (-KEEP_ROOM_DB / 20) * np.max(np.abs(out["a"]))
    return {k: v[strong] for k, v in out.items()}


def diffraction_returns(xml: str, radar: np.ndarray, *, frequency_hz: float, pol: str
                        ) -> dict[str, np.ndarray]:
    """Single edge-diffraction returns radar → edge → radar (UTD, Sionna's), Rx 1 cm off.

    Not part of the specular comparison: they show what tofradar's physical-optics
    facets give at a plate's edges where geometric optics has no path.
    """
    rx = radar + np.asarray(RX_OFFSETS[0])
    res = solve(xml, radar, rx, frequency_hz=frequency_hz, tx_pol=pol, rx_pol=pol,
                max_depth=1, diffraction=True)
    keep = res["inter"][0] == 8                          # InteractionType.DIFFRACTION
    vert = res["verts"][0, keep]
    length = 2 * np.linalg.norm(vert - radar, axis=1)
    out = {"length_m": length, "a": res["a"][0, keep],
           "bounces": np.zeros(length.size, dtype=int),
           "crossings": np.zeros(length.size, dtype=int),
           "out": res["dep"][keep], "back": res["arr"][keep], "point_m": vert}
    if not out["a"].size:
        return out
    strong = np.abs(out["a"]) >= 10 ** (-KEEP_ROOM_DB / 20) * np.max(np.abs(out["a"]))
    return {k: v[strong] for k, v in out.items()}


def corner_returns(xml: str, radar: np.ndarray, geom: tuple, *, frequency_hz: float,
                   pol: str, max_depth: int) -> dict[str, np.ndarray]:
    """Two-way GO paths radar → faces → trihedral → faces → radar (``target_paths.py``)."""
    from scipy.special import j1

    apex, axes, edge = geom
    lam = C / frequency_hz
    k = 2 * np.pi / lam
    one = solve(xml, radar, apex, frequency_hz=frequency_hz, tx_pol=pol, rx_pol="VH",
                max_depth=max_depth)
    u = one["arr"]
    field = _fields(one["a"], u)
    bounces = np.count_nonzero(one["inter"] == 1, axis=0)
    cross = np.count_nonzero(one["inter"] == 4, axis=0)
    area = np.array([trihedral_area(d, edge, axes) for d in u])
    rows: dict[str, list] = {k2: [] for k2 in ("length_m", "a", "bounces", "crossings",
                                               "out", "back")}
    for i in range(u.shape[0]):
        for j in range(u.shape[0]):
            # Three conductor mirrors: −M₃ −M₂ −M₁ = +I (target_paths.py).
            s_ij = complex(field[i] @ field[j])
            a_ij = np.sqrt(area[i] * area[j])
            cosb = float(np.clip(u[i] @ u[j], -1, 1))
            x = k * np.sqrt(a_ij / np.pi) * np.sqrt(max(0.0, 1 - cosb**2))
            lobe = 1.0 if x < 1e-9 else float(2 * j1(x) / x)
            amp = np.sqrt(4 * np.pi) * a_ij / lam * lobe
            rows["length_m"].append(one["length_m"][i] + one["length_m"][j])
            rows["a"].append(s_ij * np.sqrt(4 * np.pi) / lam * amp)
            rows["bounces"].append(int(bounces[i] + bounces[j]))
            rows["crossings"].append(int(cross[i] + cross[j]))
            rows["out"].append(one["dep"][i])
            rows["back"].append(one["dep"][j])
    out = {k2: np.array(v) for k2, v in rows.items()}
    if out["a"].size == 0 or not np.any(out["a"]):
        return out
    strong = np.abs(out["a"]) >= 10 ** (-KEEP_CORNER_DB / 20) * np.max(np.abs(out["a"]))
    return {k2: v[strong] for k2, v in out.items()}


def trace(scene_dir: Path, *, pols: tuple[str, ...] = ("V", "H"), max_depth: int = 3,
          radar_index: int = 0) -> dict[str, np.ndarray]:
    """Every path of one radar of an exported scene, both polarisations (module docstring)."""
    desc = json.loads((scene_dir / "scene.json").read_text())
    radar_cfg = desc["radars"][radar_index]
    pose = np.asarray(radar_cfg["optical_to_world"], dtype=float)
    tx_mm = radar_cfg["tx_mm"][0]
    radar = pose[:3, :3] @ np.array([tx_mm[0] / 1e3, tx_mm[1] / 1e3, 0.0]) + pose[:3, 3]
    freq = radar_cfg["start_frequency_hz"] + radar_cfg["bandwidth_hz"] / 2
    xml, traced, left_out, corners = build_scene(scene_dir, freq)
    out: dict[str, np.ndarray] = {}
    for pol in pols:
        res = room_returns(xml, radar, frequency_hz=freq, pol=pol, max_depth=max_depth)
        for key, v in res.items():
            out[f"{pol}_room_{key}"] = v
        _report(f"{pol} room", res)
        res = diffraction_returns(xml, radar, frequency_hz=freq, pol=pol)
        for key, v in res.items():
            out[f"{pol}_diffraction_{key}"] = v
        _report(f"{pol} diffraction", res)
        for c, (name, geom) in enumerate(corners):
            res = corner_returns(xml, radar, geom, frequency_hz=freq, pol=pol,
                                 max_depth=max_depth + 1)
            for key, v in res.items():
                out[f"{pol}_corner{c}_{key}"] = v
            _report(f"{pol} corner {name}", res)
    out["radar_m"] = radar
    out["radar_to_world"] = pose[:3, :3]
    out["frequency_hz"] = np.array(freq)
    out["traced"] = np.array(traced)
    out["left_out"] = np.array(left_out)
    out["corners"] = np.array([name for name, _ in corners])
    out["project"] = np.array(desc["project"])
    out["time_s"] = np.array(float(desc["time_s"]))
    return out


def _report(what: str, res: dict[str, np.ndarray]) -> None:
    a = np.abs(res["a"])
    order = np.argsort(-a)[:25]
    print(what, a.size, "paths:", ", ".join(
        f"{res['length_m'][i] / 2:.3f} m {20 * np.log10(a[i]):.1f} dB"
        f" ({res['bounces'][i]}r{res['crossings'][i]}t)" for i in order), flush=True)


def main(argv: list[str] | None = None) -> int:
    """Command line: see the module's docstring."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", type=Path, help="folder written by export_scene.py")
    ap.add_argument("--out", type=Path, required=True, help=".npz to write")
    ap.add_argument("--max-depth", type=int, default=3)
    ap.add_argument("--pol", nargs="+", default=["V", "H"], choices=["V", "H"])
    args = ap.parse_args(argv)
    out = trace(args.scene, pols=tuple(args.pol), max_depth=args.max_depth)
    # Single precision (lengths to 1 µm, levels to 1e-7): the file stays small.
    small = {k: v.astype(np.complex64 if np.iscomplexobj(v) else np.float32)
             if v.dtype.kind in "fc" and v.ndim else v for k, v in out.items()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **small)
    print("wrote", args.out, args.out.stat().st_size, "bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
