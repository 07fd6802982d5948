"""AMCW ToF reference images by transient path tracing (mitransient on Mitsuba 3).

Runs in its own environment (see README.md), not in tofradar's: it reads the scene
descriptions of ``resources/references/tof_scenes.json`` and writes, per scene, the
camera's phasor at its modulation frequency for direct light only, for light bounced once
(one indirect bounce) and for all bounces, each from exact optical path lengths
(mitransient's ``phasor_hdr_film``), to ``resources/references/tof_<scene>.npz``.

The illumination is a projector at the camera's centre filling the camera's rectangular
field of view with uniform radiant intensity (its image-plane irradiance ∝ cos³ of the
ray's angle to the axis, so that intensity per steradian is flat), as tofradar's camera.

Usage::

    tools/references/mitransient/.venv/bin/python \
        tools/references/mitransient/render_tof_reference.py [--spp 4096] [scene ...]
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_mono")
import mitransient  # noqa: E402,F401  (registers the transient plug-ins)

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "resources" / "references" / "tof_scenes.json"
C = 299_792_458.0


def box_quads(centre, size):
    """The six outward faces of an axis-aligned box as (corner, edge_u, edge_v), u×v outward."""
    c, h = np.asarray(centre, float), np.asarray(size, float) / 2
    quads = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            a, b = (axis + 1) % 3, (axis + 2) % 3
            eu, ev = np.zeros(3), np.zeros(3)
            eu[a], ev[b] = 2 * h[a], 2 * h[b]
            corner = c.copy()
            corner[axis] += sign * h[axis]
            corner[a] -= h[a]
            corner[b] -= h[b]
            if sign < 0:            # u × v must point along −axis: swap the edges
                eu, ev = ev, eu
            quads.append((corner, eu, ev))
    return quads


def write_obj(path, quads):
    """An OBJ of quads (two triangles each, counter-clockwise about u × v)."""
    lines = []
    for i, (c, u, v) in enumerate(quads):
        for p in (c, c + u, c + u + v, c + v):
            lines.append(f"v {p[0]:.9f} {p[1]:.9f} {p[2]:.9f}")
        b = 4 * i + 1
        lines.append(f"f {b} {b + 1} {b + 2}")
        lines.append(f"f {b} {b + 2} {b + 3}")
    path.write_text("\n".join(lines) + "\n")


def scene_dict(spec, camera, tmp, *, max_depth, spp):
    """Mitsuba scene of one reference scene."""
    w, h = camera["width"], camera["height"]
    fov = camera["fov_h_deg"]
    pitch = math.radians(spec.get("camera_pitch_down_deg", 0.0))
    origin = np.asarray(spec["camera_position_m"], float)
    forward = np.array([math.cos(pitch), 0.0, -math.sin(pitch)])
    up = np.array([math.sin(pitch), 0.0, math.cos(pitch)])
    to_world = mi.ScalarTransform4f().look_at(origin=origin.tolist(),
                                              target=(origin + forward).tolist(),
                                              up=up.tolist())
    tan_x = math.tan(math.radians(fov) / 2)
    tan_y = tan_x * h / w
    tw, th = 8 * w, 8 * h
    xs = ((np.arange(tw) + 0.5) / tw * 2 - 1) * tan_x
    ys = ((np.arange(th) + 0.5) / th * 2 - 1) * tan_y
    profile = (1.0 + xs[None, :] ** 2 + ys[:, None] ** 2) ** -1.5
    bitmap = mi.Bitmap(profile.astype(np.float32)[:, :, None])
    f_opl = camera["modulation_frequency_hz"] / C
    nt = 4
    out = {
        "type": "scene",
        "integrator": {"type": "transient_path", "max_depth": max_depth,
                       "camera_unwarp": False},
        "sensor": {
            "type": "perspective", "fov": fov, "fov_axis": "x", "to_world": to_world,
            # Paths are measured from the near-clip plane: put it at the pinhole.
            "near_clip": 1e-6,
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "phasor_hdr_film", "width": w, "height": h,
                     "temporal_bins": nt, "bin_width_opl": 1.0 / (nt * f_opl),
                     "start_opl": 0.0, "wl_mean": 1.0 / f_opl, "wl_sigma": 1e9,
                     "rfilter": {"type": "box"}},
        },
        "light": {"type": "projector", "to_world": to_world, "fov": fov,
                  "irradiance": {"type": "bitmap", "bitmap": bitmap, "filter_type": "nearest",
                                 "raw": True}},
    }
    for i, panel in enumerate(spec["panels"]):
        path = Path(tmp) / f"panel{i}.obj"
        write_obj(path, [(np.asarray(panel["corner"], float), np.asarray(panel["edge_u"], float),
                          np.asarray(panel["edge_v"], float))])
        out[f"panel{i}"] = {"type": "obj", "filename": str(path), "face_normals": True,
                            "bsdf": {"type": "twosided", "material": {
                                "type": "diffuse", "reflectance": panel["reflectance"]}}}
    for box in spec["boxes"]:
        path = Path(tmp) / f"{box['name']}.obj"
        write_obj(path, box_quads(box["centre"], box["size"]))
        out[box["name"]] = {"type": "obj", "filename": str(path), "face_normals": True,
                            "bsdf": {"type": "diffuse", "reflectance": box["reflectance"]}}
    return out


def render_phasor(spec, camera, *, max_depth, spp, seed=0):
    """Complex phasor image (H, W) at the modulation frequency, tofradar's sign (+i k OPL)."""
    with tempfile.TemporaryDirectory() as tmp:
        scene = mi.load_dict(scene_dict(spec, camera, tmp, max_depth=max_depth, spp=spp))
        steady, phasors = mi.render(scene, spp=spp, seed=seed)
        film = scene.sensors()[0].film()
        freqs = np.array([float(f[0]) for f in film.frequencies])
    ph = np.asarray(phasors)                     # (H, W, F, 2)
    j = int(np.argmin(np.abs(freqs - camera["modulation_frequency_hz"] / C)))
    assert abs(freqs[j] * C / camera["modulation_frequency_hz"] - 1) < 1e-5, freqs
    # mitransient's phase is −2π f OPL; tofradar's phasors are e^{+i 2π f OPL / c}.
    return (ph[:, :, j, 0] - 1j * ph[:, :, j, 1]).astype(np.complex64), np.asarray(steady)[..., 0]


def main():
    """Render the scenes named (default: all) and write their phasors."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*")
    parser.add_argument("--spp", type=int, default=4096)
    parser.add_argument("--max-depth", type=int, default=24,
                        help="longest path (vertices incl. camera and light) for 'all bounces'")
    args = parser.parse_args()
    spec = json.loads(SCENES.read_text())
    names = args.scenes or list(spec["scenes"])
    for name in names:
        scene = spec["scenes"][name]
        result = {}
        for label, depth in (("direct", 2), ("one_bounce", 3), ("all", args.max_depth)):
            t0 = time.perf_counter()
            phasor, steady = render_phasor(scene, spec["camera"], max_depth=depth, spp=args.spp)
            result[label] = phasor
            print(f"{name} {label}: {time.perf_counter() - t0:.1f} s", flush=True)
        out = ROOT / "resources" / "references" / f"tof_{name}.npz"
        np.savez_compressed(out, spp=args.spp, max_depth=args.max_depth,
                            modulation_frequency_hz=spec["camera"]["modulation_frequency_hz"],
                            mitransient=mitransient.__version__, mitsuba=mi.__version__,
                            **result)
        print("wrote", out)


if __name__ == "__main__":
    main()
