"""Validation report, "ToF multipath against mitransient": MPI bias against a path tracer.

The scenes of ``resources/references/tof_scenes.json`` — a concave corner of two white
Lambertian panels and a furnished room with surfaces outside the camera's view — were
rendered by mitransient (transient path tracing on Mitsuba 3; its own environment, see
``tools/references/mitransient``) as AMCW phasors at the camera's modulation frequency from
exact optical path lengths: direct light only, one indirect bounce, and all bounces. The
phasors are committed as small arrays (``resources/references/tof_<scene>.npz``), so this
comparison runs without the path tracer.

:func:`reference_project` builds the same scene as a tofradar project (same geometry,
albedo, camera and illumination: uniform radiant intensity over the camera's rectangular
field of view) and :func:`compare` simulates its ideal ToF camera with multipath off and
on, and measures the MPI bias (depth with multipath − depth without) next to the
reference's (depth of all bounces − depth of direct light), near creases (within
:data:`CREASE_PX` pixels of a place where two surfaces meet at an angle) and beyond.
"""

from __future__ import annotations

import json
import math
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import binary_dilation
from scipy.spatial.transform import Rotation

from simcore.render import RenderRequest, render_once
from simcore.resources import RESOURCES_DIR
from simcore.scene.materials import BandMaterial, DualBandMaterial
from simcore.scene.model import Project
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig

REFERENCES = RESOURCES_DIR / "references"
#: Pixels within this many pixels of a crease count as "near the crease".
CREASE_PX = 10
#: Sub-pixels per axis of the tofradar render (the reference averages over the pixel).
SUPERSAMPLING = 4


@cache
def scenes() -> dict[str, Any]:
    """The reference scenes' description (``resources/references/tof_scenes.json``)."""
    return json.loads((REFERENCES / "tof_scenes.json").read_text())


def reference_phasors(name: str) -> dict[str, NDArray[np.complex64]]:
    """The reference's phasors of scene ``name``: ``direct``, ``one_bounce``, ``all`` (H, W)."""
    with np.load(REFERENCES / f"tof_{name}.npz") as data:
        return {k: data[k] for k in ("direct", "one_bounce", "all")}


def camera_config(*, multipath: bool, bounces: int = 0, surfel_m: float = 0.25
                  ) -> TofCameraConfig:
    """The reference camera: ideal (no noise, no quantisation), multipath ``room`` on/off."""
    cam = scenes()["camera"]
    w, h = cam["width"], cam["height"]
    fov_v = 2 * math.degrees(math.atan(math.tan(math.radians(cam["fov_h_deg"]) / 2) * h / w))
    return TofCameraConfig(width=w, height=h, fov_h_deg=cam["fov_h_deg"], fov_v_deg=fov_v,
                           supersampling=SUPERSAMPLING,
                           modulation_frequencies_hz=[cam["modulation_frequency_hz"]],
                           ideal=True, crosstalk_sigma_px=0.0, min_amplitude_dn=0.0,
                           multipath=multipath, multipath_model="room",
                           multipath_bounces=bounces, multipath_surfel_m=surfel_m)


def reference_project(name: str, tof: TofCameraConfig) -> Project:
    """Scene ``name`` as a tofradar project with camera ``tof`` (Lambertian materials)."""
    spec = scenes()["scenes"][name]
    objects: list[dict[str, Any]] = []
    materials: dict[str, DualBandMaterial] = {}
    for i, panel in enumerate(spec["panels"]):
        objects.append(_panel(f"panel{i}", panel, _material(materials, panel["reflectance"])))
    for box in spec["boxes"]:
        objects.append({"name": box["name"], "geometry": {"kind": "box", "size_m": box["size"]},
                        "pose": {"position_m": box["centre"]},
                        "material": _material(materials, box["reflectance"])})
    for i, o in enumerate(objects):
        o["id"] = i + 1
    rig = {"name": "rig", "pose": {"position_m": spec["camera_position_m"],
                                   "rotation_deg": [0.0, spec["camera_pitch_down_deg"], 0.0]},
           "tof": tof.model_dump()}
    return Project.model_validate({
        "name": f"mitransient_{name}", "objects": objects, "rig": rig,
        "materials": [m.model_dump() for m in materials.values()],
        "timeline": {"frame_rate_hz": 10.0, "duration_s": 0.1}})


def _material(table: dict[str, DualBandMaterial], reflectance: float) -> str:
    """Name of a Lambertian ToF material of ``reflectance`` (added to ``table``)."""
    name = f"lambert_{reflectance:.3f}"
    band = BandMaterial(reflectance=reflectance, specular=0.0)
    table[name] = DualBandMaterial(name=name, bands={"tof": band, "radar": band})
    return name


def _panel(name: str, panel: dict[str, Any], material: str) -> dict[str, Any]:
    """A two-sided rectangle (corner, edge_u, edge_v) as a Plane object."""
    u, v = np.asarray(panel["edge_u"], float), np.asarray(panel["edge_v"], float)
    centre = np.asarray(panel["corner"], float) + (u + v) / 2
    rot = np.column_stack([u / np.linalg.norm(u), v / np.linalg.norm(v),
                           np.cross(u, v) / np.linalg.norm(np.cross(u, v))])
    euler = Rotation.from_matrix(rot).as_euler("xyz", degrees=True)
    return {"name": name, "material": material,
            "geometry": {"kind": "plane",
                         "size_m": [float(np.linalg.norm(u)), float(np.linalg.norm(v))]},
            "pose": {"position_m": centre.tolist(), "rotation_deg": euler.tolist()}}


#: Scenes exported from a tofradar project (``tools/references/export_scene.py``) and
#: rendered by the path tracer (``tof_<name>.npz`` beside ``tof_<name>_scene.json``), with
#: the reach (px) of "near a crease" in each: in a furnished room seen from 3–6 m nearly
#: every pixel lies within :data:`CREASE_PX` of some crease (the office: 2 243 of 2 269
#: compared pixels at 64 × 44), so the office's regions are split at 3 px (≈ 3°, 15–30 cm
#: at its walls), which halves them.
EXPORTED: dict[str, int] = {"office": 3}

#: What makes a project's ToF camera like the path tracer's: an ideal sensor (no noise,
#: no quantisation, no cross-talk, no amplitude threshold) with none of the optics and
#: electronics effects (the path tracer has a pinhole, a uniform sensor and exact phases),
#: a still exposure (the path tracer renders one instant), and no glossy or mirror paths
#: (it traces Lambertian surfaces only).
LIKE_FOR_LIKE_CAMERA: dict[str, Any] = {
    "ideal": True, "crosstalk_sigma_px": 0.0, "min_amplitude_dn": 0.0,
    "motion_artifacts": False, "auto_exposure": False, "ambient_light": False,
    "background_suppression": False, "wiggling": False, "distortion": False,
    "vignetting": False, "stray_light": False, "specular": False, "hop_channels": 1}


@cache
def exported_scene(name: str) -> dict[str, Any]:
    """The exported scene ``name`` as the path tracer rendered it (``tof_<name>_scene.json``).

    The export's ``scene.json`` with ``reference_camera`` (the rendered camera: width,
    height, fields of view, modulation frequency) and each object's world ``bounds_m``.
    """
    return json.loads((REFERENCES / f"tof_{name}_scene.json").read_text())


def exported_project_path(name: str) -> Path:
    """The project file the scene ``name`` was exported from (a shipped resource)."""
    rel = Path(exported_scene(name)["project"])
    return RESOURCES_DIR.joinpath(*rel.parts[1:]) if rel.parts[0] == "resources" else rel


def lambertian_materials(project: Project) -> list[DualBandMaterial]:
    """The project's materials in use, their ToF band made Lambertian.

    What the path tracer renders: albedo ``(1 − metallic) · reflectance`` (the albedo of
    tofradar's diffuse term and of its room model, kept as it is) and nothing else — the
    glossy lobe (``specular``) and retroreflection (``retroreflector``, ``retro_gain``)
    set to 0. The radar band is left as it is.
    """
    from simcore.scene.people.expand import expand_people
    from simcore.scene.project_io import material_table

    table = material_table(project)
    used = {o.material for o in expand_people(project).objects}
    out = []
    for name in sorted(used & table.keys()):
        material = table[name]
        tof = material.band("tof").model_copy(update={
            "specular": 0.0, "retroreflector": False, "retro_gain": 0.0})
        out.append(material.model_copy(update={"bands": {**material.bands, "tof": tof}}))
    return out


def exported_camera_config(name: str, **multipath: Any) -> TofCameraConfig:
    """The exported scene's ToF camera as the path tracer saw it, with ``multipath`` set.

    The project's own camera configuration with :data:`LIKE_FOR_LIKE_CAMERA`, the
    reference's resolution and fields of view (square pixels), :data:`SUPERSAMPLING`,
    one modulation frequency (the reference's), and the ``multipath_*`` fields given
    (``multipath``, ``multipath_model``, ``multipath_surfel_m``, …; the rest the
    project's).
    """
    from simcore.scene.project_io import load_project

    ref = exported_scene(name)["reference_camera"]
    project = load_project(exported_project_path(name))
    cfg = project.sensor_config(ref["name"])
    assert isinstance(cfg, TofCameraConfig)
    data = cfg.model_dump() | LIKE_FOR_LIKE_CAMERA | {
        "width": ref["width"], "height": ref["height"], "fov_h_deg": ref["fov_h_deg"],
        "fov_v_deg": ref["fov_v_deg"], "supersampling": SUPERSAMPLING,
        "modulation_frequencies_hz": [ref["modulation_frequency_hz"]]} | multipath
    return TofCameraConfig.model_validate(data)


def exported_project(name: str, tof: TofCameraConfig) -> Project:
    """The project scene ``name`` was exported from, as the path tracer saw it.

    Its ToF camera replaced by ``tof`` (:func:`exported_camera_config`), its other
    sensors removed, its materials made Lambertian (:func:`lambertian_materials`). Raises
    ValueError when the project's objects at the export's time no longer lie where the
    reference saw them (the project was edited since: export and render it again).
    """
    from simcore.scene.project_io import load_project

    scene = exported_scene(name)
    cam = scene["reference_camera"]["name"]
    project = load_project(exported_project_path(name))
    rig = project.sensor_rig(cam)
    rigs = [r.model_copy(update={"sensors": {}}) for r in project.rigs]
    if rig is project.rig:
        new_rig = rig.model_copy(update={
            **{field: None for field in project.rig.sensor_configs() if field != cam},
            "sensors": {}, cam: tof})
    else:
        raise ValueError(f"{name}: the compared camera {cam!r} is not on the first rig")
    project = project.model_copy(update={
        "rig": new_rig, "rigs": rigs, "materials": lambertian_materials(project)})
    _check_scene(name, project)
    return project


def _check_scene(name: str, project: Project) -> None:
    """The project is the scene the path tracer rendered (else ValueError).

    Each object's world bounds within 1 mm, its ToF albedo ``(1 − metallic) ·
    reflectance`` within 1e-6 and the camera's pose within 1 mm / 1e-6, at the export's
    time.
    """
    from simcore.render.meshes import build_mesh
    from simcore.scene.people.expand import expand_people
    from simcore.sensors.tof.sensor import tof_bands

    scene = exported_scene(name)
    expanded = expand_people(project, base_dir=exported_project_path(name).parent)
    snap = take_snapshot(expanded, scene["time_s"])
    ours = []
    for obj, state, band in zip(expanded.objects, snap.objects, tof_bands(expanded),
                                strict=True):
        mesh = build_mesh(obj.geometry)
        if mesh is None or len(mesh.triangles) == 0:
            continue
        t = state.transform
        world = mesh.points @ t[:3, :3].T + t[:3, 3]
        albedo = None if band is None else (1.0 - band.metallic) * band.reflectance
        ours.append((obj.name, np.array([world.min(axis=0), world.max(axis=0)]), albedo))
    theirs = [(o["name"], np.asarray(o["bounds_m"]), o["albedo"]) for o in scene["objects"]]
    same = len(ours) == len(theirs) and all(
        a == b and np.allclose(x, y, atol=1e-3)
        and (p is None) == (q is None) and (p is None or abs(p - q) < 1e-6)
        for (a, x, p), (b, y, q) in zip(ours, theirs, strict=True))
    cam = scene["reference_camera"]
    pose = snap.sensor(cam["name"]).transform
    same = same and np.allclose(pose, np.asarray(cam["optical_to_world"]), atol=1e-6)
    if not same:
        raise ValueError(f"{exported_project_path(name)} is not the scene the path tracer "
                         f"rendered (tof_{name}_scene.json): export and render it again "
                         f"(tools/references/mitransient/README.md)")


def simulate_exported(name: str, *, multipath: bool, **settings: Any
                      ) -> dict[str, NDArray[Any]]:
    """The like-for-like camera on exported scene ``name`` (:func:`simulate_project`).

    ``settings``: ``multipath_*`` fields of the camera (default: the project's, with
    ``multipath_model = "room"``).
    """
    cfg = exported_camera_config(name, multipath=multipath,
                                 **({"multipath_model": "room"} | settings))
    project = exported_project(name, cfg)
    return simulate_project(project, cfg, sensor=exported_scene(name)["reference_camera"]
                            ["name"], base_dir=exported_project_path(name).parent,
                            moving=True)


def compare_exported(name: str, *, reference_key: str = "all", **settings: Any
                     ) -> dict[str, Any]:
    """:func:`compare` on exported scene ``name``, with ``multipath_*`` ``settings``.

    ``reference_key``: the reference's phasor with multipath (``all``; ``one_bounce``
    against ``multipath_bounces = 1``).

    "Near a crease" reaches :data:`EXPORTED` pixels. Besides :func:`compare`'s regions:
    ``moving``, the pixels whose sub-pixels all see objects the project moves (a person:
    curved, so not "pure", but not mixed with the room behind), and ``still``, the pure
    pixels on the others.
    """
    freq = exported_scene(name)["reference_camera"]["modulation_frequency_hz"]
    off = simulate_exported(name, multipath=False, **settings)
    on = simulate_exported(name, multipath=True, **settings)
    result = measure(reference_phasors(name), off, on, freq, reach_px=EXPORTED[name],
                     reference_key=reference_key)
    maps = result["maps"]
    mover = maps["lit"] & off["moving"]
    maps["moving"] = mover
    for label, mask in (("moving", mover), ("still", maps["valid"] & ~off["moving"])):
        result[label] = _bias_stats(maps["tofradar"][mask], maps["reference"][mask])
    return result


def simulate(name: str, *, multipath: bool, bounces: int = 0, surfel_m: float = 0.25
             ) -> dict[str, NDArray[Any]]:
    """The ideal tofradar camera on scene ``name``: depth (m), normals, points, object id."""
    cfg = camera_config(multipath=multipath, bounces=bounces, surfel_m=surfel_m)
    return simulate_project(reference_project(name, cfg), cfg)


def simulate_project(project: Project, cfg: TofCameraConfig, *, sensor: str = "tof",
                     base_dir: Path | None = None, moving: bool = False
                     ) -> dict[str, NDArray[Any]]:
    """Camera ``cfg`` (sensor ``sensor`` of ``project``) at t = 0, as the engine's ToF sensor.

    People are expanded into their segments; the room of ``multipath_model = "room"`` is
    built from the snapshot and the render's meshes, with the objects the project moves
    flagged as moving where ``moving`` (as the engine does; otherwise every object counts
    as still and ``multipath_moving`` plays no part).

    Returns
    -------
    dict
        ``depth`` (H, W) m, ``valid``, ``object`` (ground-truth id), ``normals`` and
        ``points`` (H, W, 3; sub-pixel means), ``pure`` (:func:`pure_pixels`),
        ``amplitude`` (DN), ``moving`` (H, W) bool: pixels whose sub-pixels all see
        objects the project moves.
    """
    from simcore.scene.people.expand import body_part_table, expand_people
    from simcore.sensors.tof.camera import simulate_tof
    from simcore.sensors.tof.sensor import (
        CLOSED,
        diffuse_albedo,
        object_meshes,
        room_from_scene,
        tof_bands,
    )

    project = expand_people(project, base_dir=base_dir)
    buf = render_once(project, RenderRequest(sensor, "tof", cfg.render_intrinsics()),
                      base_dir=base_dir)
    bands = tof_bands(project)
    snap = take_snapshot(project, 0.0)
    parts = body_part_table(project)
    movers = [not o.motion.is_static or parts[i] >= 0 for i, o in enumerate(project.objects)]
    room = room_from_scene(object_meshes(project, buf), [s.transform for s in snap.objects],
                           bands, closed=[isinstance(o.geometry, CLOSED)
                                          for o in project.objects],
                           moving=movers if moving else None)
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0),
                       albedo=diffuse_albedo(bands, buf), room=room)
    k = cfg.supersampling
    h, w = cfg.height, cfg.width
    normals = buf.normals.reshape(h, k, w, k, 3).mean(axis=(1, 3))
    points = buf.points_m.reshape(h, k, w, k, 3).mean(axis=(1, 3))
    flags = np.array([*movers, False])
    on_mover = flags[buf.object_index].reshape(h, k, w, k).all(axis=(1, 3))
    return {"depth": out.depth_m, "valid": out.valid, "object": out.gt_object_id,
            "amplitude": out.amplitude,
            "normals": normals, "points": points,
            "pure": pure_pixels(buf.object_index, buf.normals, k), "moving": on_mover}


def phasor_depth(phasor: NDArray[np.complexfloating], frequency_hz: float
                 ) -> NDArray[np.float64]:
    """Depth (m) of phasors ``e^{i 2π f L / c}``: ``L / 2`` wrapped to ``c / (2 f)``."""
    return np.mod(np.angle(phasor), 2 * np.pi) * SPEED_OF_LIGHT / (4 * np.pi * frequency_hz)


def crease_mask(normals: NDArray[np.floating], points: NDArray[np.floating],
                valid: NDArray[np.bool_], *, seen: NDArray[np.bool_],
                reach_px: int = CREASE_PX) -> NDArray[np.bool_]:
    """Pixels within ``reach_px`` of a crease: neighbours whose surfaces meet at an angle.

    Two neighbouring pixels straddle a crease when their normals differ by more than 30°
    while their surface points lie close (within 3 cm plus 3 % of the range: not a depth
    edge); ``seen``: pixels that see a surface (a crease is found among them, the result
    is limited to ``valid``).
    """
    crease = np.zeros(valid.shape, dtype=bool)
    for axis in (0, 1):
        a = [slice(None), slice(None)]
        b = [slice(None), slice(None)]
        a[axis], b[axis] = slice(0, -1), slice(1, None)
        na, nb = normals[tuple(a)], normals[tuple(b)]
        pa, pb = points[tuple(a)], points[tuple(b)]
        cos = np.einsum("...i,...i->...", na, nb) / np.maximum(
            np.linalg.norm(na, axis=-1) * np.linalg.norm(nb, axis=-1), 1e-12)
        near = np.linalg.norm(pa - pb, axis=-1) < 0.03 + 0.03 * np.linalg.norm(pa, axis=-1)
        hit = (cos < math.cos(math.radians(30))) & near
        crease[tuple(a)] |= hit
        crease[tuple(b)] |= hit
    return binary_dilation(crease & seen, iterations=reach_px) & valid


def pure_pixels(object_index: NDArray[np.integer], normals: NDArray[np.floating], k: int
                ) -> NDArray[np.bool_]:
    """Sensor pixels whose ``k × k`` sub-pixels all see one flat surface (not mixed pixels).

    A pixel across a depth edge or a crease mixes two surfaces' phasors (flying pixels),
    whose weights depend on how each renderer samples the pixel: such pixels are left out
    of the comparison.
    """
    h, w = object_index.shape[0] // k, object_index.shape[1] // k
    ids = object_index.reshape(h, k, w, k)
    same = (ids == ids[:, :1, :, :1]).all(axis=(1, 3)) & (ids[:, 0, :, 0] >= 0)
    n = normals.reshape(h, k, w, k, 3)
    flat = (np.einsum("ykxlc,yxc->ykxl", n, n[:, 0, :, 0]) > 0.999).all(axis=(1, 3))
    return same & flat


def compare(name: str, *, bounces: int = 0, surfel_m: float = 0.25) -> dict[str, Any]:
    """The MPI bias and direct depth of tofradar against mitransient's on scene ``name``.

    Returns
    -------
    dict
        ``direct_error_mm`` (median and 95th percentile of |tofradar − reference| direct
        depth), and per region (``near``: within :data:`CREASE_PX` px of a crease,
        ``beyond``) the median MPI bias of both (mm), their ratio and the pixel count; and
        ``maps``: the per-pixel bias images (m) and the region masks.
    """
    freq = scenes()["camera"]["modulation_frequency_hz"]
    off = simulate(name, multipath=False)
    on = simulate(name, multipath=True, bounces=bounces, surfel_m=surfel_m)
    return measure(reference_phasors(name), off, on, freq)


def measure(ref: dict[str, NDArray[np.complex64]], off: dict[str, NDArray[Any]],
            on: dict[str, NDArray[Any]], frequency_hz: float, *,
            reference_key: str = "all", reach_px: int = CREASE_PX) -> dict[str, Any]:
    """MPI bias and direct depth of tofradar's ``off``/``on`` runs against phasors ``ref``.

    ``off``, ``on``: :func:`simulate_project`'s results with multipath off and on;
    ``reference_key``: the reference's phasor with multipath (``all`` or ``one_bounce``);
    ``reach_px``: "near a crease" (:func:`crease_mask`). Pixels compared: valid in both
    runs, lit directly in both (a black surface, e.g. a metal's diffuse albedo 0, has no
    direct depth) and not mixed (:func:`pure_pixels`). Returns :func:`compare`'s
    dictionary.
    """
    lit = (np.abs(ref["direct"]) > 0) & (off["amplitude"] > 0)
    valid = off["valid"] & on["valid"] & lit & off["pure"]
    ref_direct = phasor_depth(ref["direct"], frequency_hz)
    with np.errstate(divide="ignore", invalid="ignore"):     # unlit pixels: left out
        ref_bias = phasor_depth(ref[reference_key] / ref["direct"], frequency_hz)
    ref_bias = np.where(ref_bias > SPEED_OF_LIGHT / (4 * frequency_hz), ref_bias
                        - SPEED_OF_LIGHT / (2 * frequency_hz), ref_bias)
    ours = on["depth"].astype(np.float64) - off["depth"]
    near = crease_mask(off["normals"], off["points"], valid,
                       seen=np.isfinite(off["points"]).all(axis=-1), reach_px=reach_px)
    result: dict[str, Any] = {}
    direct_err = np.abs(off["depth"] - ref_direct)[valid] * 1e3
    result["direct_error_mm"] = {"median": float(np.median(direct_err)),
                                 "p95": float(np.percentile(direct_err, 95))}
    for label, mask in (("near", near), ("beyond", valid & ~near)):
        result[label] = _bias_stats(ours[mask], ref_bias[mask])
    result["maps"] = {"tofradar": ours, "reference": ref_bias, "near": near, "valid": valid,
                      "lit": off["valid"] & on["valid"] & lit}
    return result


def _bias_stats(ours: NDArray[np.floating], ref: NDArray[np.floating]) -> dict[str, Any]:
    """Median MPI bias (mm) of both over some pixels, their ratio and the pixel count."""
    if ours.size == 0:
        return {"tofradar_mm": math.nan, "reference_mm": math.nan, "ratio": math.nan,
                "pixels": 0}
    t, r = float(np.median(ours) * 1e3), float(np.median(ref) * 1e3)
    return {"tofradar_mm": t, "reference_mm": r, "ratio": t / r, "pixels": int(ours.size)}


def tof_reference_section(out_dir: str | Path) -> tuple[list[tuple[str, str, str]],
                                                         dict[str, Any]]:
    """Figures and numbers of the section: bias maps of both, per scene."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figures, numbers = [], {}
    for name in scenes()["scenes"]:
        res = compare(name)
        maps = res.pop("maps")
        numbers[name] = res
        fig, axes = plt.subplots(1, 2, figsize=(9, 3.2))
        vmax = float(np.percentile(np.abs(maps["reference"][maps["valid"]]), 99) * 1e3)
        for ax, key in zip(axes, ("tofradar", "reference"), strict=True):
            img = np.where(maps["valid"], maps[key] * 1e3, np.nan)
            im = ax.imshow(img, vmin=0, vmax=vmax, cmap="viridis")
            ax.contour(maps["near"], levels=[0.5], colors="w", linewidths=0.6)
            ax.set_title(f"{name}: {'tofradar' if key == 'tofradar' else 'mitransient'}")
            ax.set_axis_off()
        fig.colorbar(im, ax=axes, label="MPI bias (mm)")
        file = f"tof_mitransient_{name}.png"
        fig.savefig(out / file, dpi=110)
        plt.close(fig)
        text = (f"MPI bias (depth with multipath − without), median: near creases "
                f"{res['near']['tofradar_mm']:.1f} mm (mitransient "
                f"{res['near']['reference_mm']:.1f} mm), beyond "
                f"{res['beyond']['tofradar_mm']:.1f} mm (mitransient "
                f"{res['beyond']['reference_mm']:.1f} mm); direct depth |error| median "
                f"{res['direct_error_mm']['median']:.3f} mm. White line: {CREASE_PX} px "
                f"from a crease.")
        figures.append((file, f"ToF multipath against mitransient: {name}", text))
    for name in EXPORTED:
        figure, numbers[name] = _exported_figure(name, out, plt)
        figures.append(figure)
    return figures, numbers


#: The office's runs of the report: label → camera settings (the screen model's (§8)
#: patch scaled to the reference's resolution: 8 px of 224 → 2 px of 64).
OFFICE_RUNS: dict[str, dict[str, Any]] = {
    "room_first_order": {},
    "room_exact": {"multipath_moving": "exact"},
    "room_one_bounce": {"multipath_bounces": 1, "reference_key": "one_bounce"},
    "screen": {"multipath_model": "screen", "multipath_patch_px": 2},
}


def _exported_figure(name: str, out: Path, plt: Any) -> tuple[tuple[str, str, str],
                                                              dict[str, Any]]:
    """The bias maps of an exported scene (room model, reference, screen model), numbers."""
    numbers: dict[str, Any] = {}
    maps: dict[str, Any] = {}
    for label, settings in OFFICE_RUNS.items():
        res = compare_exported(name, **settings)
        maps[label] = res.pop("maps")
        numbers[label] = res
    ref = maps["room_first_order"]
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.0), layout="constrained")
    vmax = float(np.percentile(np.abs(ref["reference"][ref["valid"]]), 99) * 1e3)
    panels = (("room_first_order", "tofradar", "tofradar, room model"),
              ("room_first_order", "reference", "mitransient, all bounces"),
              ("screen", "tofradar", "tofradar, screen model (§8)"))
    for ax, (label, key, title) in zip(axes, panels, strict=True):
        m = maps[label]
        shown = m["valid"] | m.get("moving", np.zeros_like(m["valid"]))
        im = ax.imshow(np.where(shown, m[key] * 1e3, np.nan), vmin=0, vmax=vmax,
                       cmap="viridis")
        ax.contour(m["near"], levels=[0.5], colors="w", linewidths=0.6)
        ax.set_title(f"{name}: {title}", fontsize=9)
        ax.set_xlabel("image column (px)")
    axes[0].set_ylabel("image row (px)")
    fig.colorbar(im, ax=axes, label="MPI bias (mm)")
    file = f"tof_mitransient_{name}.png"
    fig.savefig(out / file, dpi=110)
    plt.close(fig)
    room, scr = numbers["room_first_order"], numbers["screen"]
    text = (f"The {name} example at t = 0 (its walker included), like-for-like materials "
            f"(Lambertian, albedo (1 − metallic) × reflectance), ideal camera at "
            f"{ref['valid'].shape[1]} × {ref['valid'].shape[0]}. MPI bias, median: near "
            f"creases (within {EXPORTED[name]} px, white line) room model "
            f"{room['near']['tofradar_mm']:.1f} mm, mitransient "
            f"{room['near']['reference_mm']:.1f} mm, screen model "
            f"{scr['near']['tofradar_mm']:.1f} mm; beyond "
            f"{room['beyond']['tofradar_mm']:.1f} / {room['beyond']['reference_mm']:.1f} / "
            f"{scr['beyond']['tofradar_mm']:.1f} mm; direct depth |error| median "
            f"{room['direct_error_mm']['median']:.3f} mm. Mixed pixels (depth edges, "
            f"creases) are left out; the walker's pixels are shown but not in the medians.")
    return (file, f"ToF multipath against mitransient: {name}", text), numbers


__all__ = ["EXPORTED", "LIKE_FOR_LIKE_CAMERA", "OFFICE_RUNS", "compare", "compare_exported",
           "crease_mask", "exported_camera_config", "exported_project", "exported_scene",
           "lambertian_materials", "measure", "phasor_depth", "pure_pixels",
           "reference_phasors", "reference_project", "scenes", "simulate",
           "simulate_exported", "simulate_project", "tof_reference_section"]
