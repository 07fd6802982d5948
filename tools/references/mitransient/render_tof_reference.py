"""AMCW ToF reference images by transient path tracing (mitransient on Mitsuba 3).

Runs in its own environment (see README.md), not in tofradar's: it reads the scene
descriptions of ``resources/references/tof_scenes.json`` and writes, per scene, the
camera's phasor at its modulation frequency for direct light only, for light bounced once
(one indirect bounce) and for all bounces, each from exact optical path lengths
(mitransient's ``phasor_hdr_film``), to ``resources/references/tof_<scene>.npz``.

The illumination is a projector at the camera's centre filling the camera's rectangular
field of view with uniform radiant intensity (its image-plane irradiance ∝ cos³ of the
ray's angle to the axis, so that intensity per steradian is flat), as tofradar's camera.

With ``--export DIR --name NAME`` it renders instead a scene exported from any tofradar
project by ``tools/references/export_scene.py`` (its meshes as Lambertian surfaces of the
ToF band's albedo, its ToF camera's pose and fields of view at ``--width`` pixels) to
``tof_NAME.npz`` and ``tof_NAME_scene.json`` (see README.md).

Usage::

    tools/references/mitransient/.venv/bin/python \
        tools/references/mitransient/render_tof_reference.py [--spp 4096] [scene ...]
    tools/references/mitransient/.venv/bin/python \
        tools/references/mitransient/render_tof_reference.py --export /tmp/office_scene \
        --name office --spp 65536
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


def camera_and_light(to_world, camera, *, max_depth, spp):
    """Integrator, pinhole camera and projector light of a scene (without its shapes).

    ``camera``: width, height (px), fov_h_deg (horizontal field of view, square pixels),
    modulation_frequency_hz; ``to_world``: the camera's Mitsuba frame (look_at).
    """
    w, h = camera["width"], camera["height"]
    fov = camera["fov_h_deg"]
    tan_x = math.tan(math.radians(fov) / 2)
    tan_y = tan_x * h / w
    tw, th = 8 * w, 8 * h
    xs = ((np.arange(tw) + 0.5) / tw * 2 - 1) * tan_x
    ys = ((np.arange(th) + 0.5) / th * 2 - 1) * tan_y
    profile = (1.0 + xs[None, :] ** 2 + ys[:, None] ** 2) ** -1.5
    bitmap = mi.Bitmap(profile.astype(np.float32)[:, :, None])
    f_opl = camera["modulation_frequency_hz"] / C
    nt = 4
    return {
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


def scene_dict(spec, camera, tmp, *, max_depth, spp):
    """Mitsuba scene of one reference scene of ``tof_scenes.json``."""
    pitch = math.radians(spec.get("camera_pitch_down_deg", 0.0))
    origin = np.asarray(spec["camera_position_m"], float)
    forward = np.array([math.cos(pitch), 0.0, -math.sin(pitch)])
    up = np.array([math.sin(pitch), 0.0, math.cos(pitch)])
    to_world = mi.ScalarTransform4f().look_at(origin=origin.tolist(),
                                              target=(origin + forward).tolist(),
                                              up=up.tolist())
    out = camera_and_light(to_world, camera, max_depth=max_depth, spp=spp)
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


def exported_albedo(tof):
    """Lambertian albedo of an exported object's ToF band: (1 − metallic) × reflectance.

    The albedo tofradar's whole-room multipath model gives a surface
    (``simcore.sensors.tof.sensor.room_from_scene``); specular lobes and retroreflection
    are not traced (tofradar's side of the comparison turns them off).
    """
    return (1.0 - tof["metallic"]) * tof["reflectance"]


def exported_camera(export, *, width, camera_name=None):
    """The render camera of an export: its ToF camera's pose and fields of view at ``width``.

    Returns (to_world, camera) with ``camera`` as :func:`camera_and_light` reads it. The
    height keeps the export's vertical field of view as nearly as square pixels allow
    (Mitsuba's pinhole has square pixels): ``fov_v_deg`` is the one rendered.
    """
    cams = export["tof_cameras"]
    cam = next((c for c in cams if c["name"] == camera_name), None) if camera_name else cams[0]
    if cam is None:
        raise SystemExit(f"render_tof_reference: error: no ToF camera {camera_name!r} "
                         f"in the export (has {[c['name'] for c in cams]})")
    tan_x = math.tan(math.radians(cam["fov_h_deg"]) / 2)
    tan_y = math.tan(math.radians(cam["fov_v_deg"]) / 2)
    height = max(1, round(width * tan_y / tan_x))
    pose = np.asarray(cam["optical_to_world"], float)
    origin, right, down, forward = pose[:3, 3], pose[:3, 0], pose[:3, 1], pose[:3, 2]
    del right                                   # look_at's frame follows from forward, up
    to_world = mi.ScalarTransform4f().look_at(origin=origin.tolist(),
                                              target=(origin + forward).tolist(),
                                              up=(-down).tolist())
    camera = {"name": cam["name"], "width": width, "height": height,
              "fov_h_deg": cam["fov_h_deg"],
              "fov_v_deg": 2 * math.degrees(math.atan(tan_x * height / width)),
              "modulation_frequency_hz": cam["modulation_frequencies_hz"][0],
              "optical_to_world": cam["optical_to_world"]}
    return to_world, camera


def export_scene_dict(export, export_dir, to_world, camera, *, max_depth, spp):
    """Mitsuba scene of an exported tofradar scene (``tools/references/export_scene.py``).

    Every object the ToF band sees (opacity > 0) is a Lambertian mesh of albedo
    :func:`exported_albedo` with the export's vertex normals; closed meshes (outward
    normals) reflect on their outer side only, open ones on both sides (``twosided``), as
    in tofradar's room model. Partly transparent objects are rendered opaque, as the room
    model treats them.
    """
    out = camera_and_light(to_world, camera, max_depth=max_depth, spp=spp)
    for i, obj in enumerate(export["objects"]):
        tof = obj["tof"]
        if tof is None or tof["opacity"] <= 0:
            continue
        diffuse = {"type": "diffuse", "reflectance": exported_albedo(tof)}
        out[f"obj{i:03d}"] = {
            "type": "ply", "filename": str(Path(export_dir) / obj["ply"]),
            "face_normals": False,
            "bsdf": diffuse if obj["closed"] else {"type": "twosided", "material": diffuse}}
    return out


def object_bounds(export, export_dir):
    """Each exported object's world bounding box (2, 3) in m, in the export's order."""
    out = []
    for o in export["objects"]:
        box = mi.load_dict({"type": "ply", "filename": str(Path(export_dir) / o["ply"])}).bbox()
        out.append([list(box.min), list(box.max)])
    return np.array(out, dtype=float)


def render_phasor(scene_description, camera, *, spp, seed=0):
    """Complex phasor image (H, W) at the modulation frequency, tofradar's sign (+i k OPL).

    ``scene_description``: a Mitsuba scene dictionary (its shapes' files must exist).
    """
    scene = mi.load_dict(scene_description)
    steady, phasors = mi.render(scene, spp=spp, seed=seed)
    film = scene.sensors()[0].film()
    freqs = np.array([float(f[0]) for f in film.frequencies])
    ph = np.asarray(phasors)                     # (H, W, F, 2)
    j = int(np.argmin(np.abs(freqs - camera["modulation_frequency_hz"] / C)))
    assert abs(freqs[j] * C / camera["modulation_frequency_hz"] - 1) < 1e-5, freqs
    # mitransient's phase is −2π f OPL; tofradar's phasors are e^{+i 2π f OPL / c}.
    return (ph[:, :, j, 0] - 1j * ph[:, :, j, 1]).astype(np.complex64), np.asarray(steady)[..., 0]


def render_three(name, build, camera, *, spp, max_depth, seed=0):
    """Direct light, one indirect bounce and all bounces of one scene: phasors by label.

    ``build(max_depth)`` makes the Mitsuba scene dictionary at a path depth.
    """
    result = {}
    for label, depth in (("direct", 2), ("one_bounce", 3), ("all", max_depth)):
        t0 = time.perf_counter()
        result[label], _ = render_phasor(build(depth), camera, spp=spp, seed=seed)
        print(f"{name} {label}: {time.perf_counter() - t0:.1f} s", flush=True)
    return result


def render_export(export_dir, *, name, width, spp, max_depth, camera_name=None):
    """Render an exported scene; write ``tof_<name>.npz`` and ``tof_<name>_scene.json``.

    The JSON is the export's ``scene.json`` (objects, materials, cameras) with the
    rendered camera (``reference_camera``) and each object's world bounds (``bounds_m``),
    so that tofradar's side can check that it builds the same scene.
    """
    export_dir = Path(export_dir)
    export = json.loads((export_dir / "scene.json").read_text())
    to_world, camera = exported_camera(export, width=width, camera_name=camera_name)
    result = render_three(
        name, lambda depth: export_scene_dict(export, export_dir, to_world, camera,
                                              max_depth=depth, spp=spp),
        camera, spp=spp, max_depth=max_depth)
    bounds = object_bounds(export, export_dir)
    for obj, box in zip(export["objects"], bounds, strict=True):
        obj["bounds_m"] = np.round(box, 6).tolist()
        obj["albedo"] = None if obj["tof"] is None else exported_albedo(obj["tof"])
    export["reference_camera"] = camera
    export["reference"] = {"spp": spp, "max_depth": max_depth,
                           "mitransient": mitransient.__version__, "mitsuba": mi.__version__}
    refs = ROOT / "resources" / "references"
    (refs / f"tof_{name}_scene.json").write_text(json.dumps(export, indent=1) + "\n")
    out = refs / f"tof_{name}.npz"
    np.savez_compressed(out, spp=spp, max_depth=max_depth,
                        modulation_frequency_hz=camera["modulation_frequency_hz"],
                        mitransient=mitransient.__version__, mitsuba=mi.__version__,
                        **result)
    print("wrote", out)


def main():
    """Render the scenes named (default: all), or an exported scene; write their phasors."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*")
    parser.add_argument("--spp", type=int, default=4096)
    parser.add_argument("--max-depth", type=int, default=24,
                        help="longest path (vertices incl. camera and light) for 'all bounces'")
    parser.add_argument("--export", type=Path,
                        help="folder written by tools/references/export_scene.py: render it")
    parser.add_argument("--name", help="name of the exported scene's results (tof_NAME.npz)")
    parser.add_argument("--width", type=int, default=64,
                        help="exported scene: image width (px); height keeps the field of view")
    parser.add_argument("--camera", help="exported scene: the ToF camera (default: the first)")
    args = parser.parse_args()
    if args.export is not None:
        if not args.name:
            parser.error("--export needs --name")
        render_export(args.export, name=args.name, width=args.width, spp=args.spp,
                      max_depth=args.max_depth, camera_name=args.camera)
        return
    spec = json.loads(SCENES.read_text())
    names = args.scenes or list(spec["scenes"])
    for name in names:
        scene = spec["scenes"][name]
        with tempfile.TemporaryDirectory() as tmp:
            result = render_three(
                name, lambda depth, scene=scene, tmp=tmp: scene_dict(
                    scene, spec["camera"], tmp, max_depth=depth, spp=args.spp),
                spec["camera"], spp=args.spp, max_depth=args.max_depth)
        out = ROOT / "resources" / "references" / f"tof_{name}.npz"
        np.savez_compressed(out, spp=args.spp, max_depth=args.max_depth,
                            modulation_frequency_hz=spec["camera"]["modulation_frequency_hz"],
                            mitransient=mitransient.__version__, mitsuba=mi.__version__,
                            **result)
        print("wrote", out)


if __name__ == "__main__":
    main()
