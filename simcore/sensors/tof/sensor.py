"""The ToF camera as a registered sensor: its render pass and its frame."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers, downsample_labels
from simcore.render.meshes import TriangleMesh, build_mesh
from simcore.render.renderer import RenderRequest
from simcore.scene.geometry import Box, Cylinder, Ellipsoid, Sphere
from simcore.scene.materials import BandMaterial
from simcore.scene.model import Project, Rig
from simcore.scene.people.config import Person
from simcore.scene.people.expand import body_part_table
from simcore.scene.project_io import material_table
from simcore.scene.tof_config import TofCameraConfig
from simcore.sensors.base import DeferredOutput, H5Items, SensorBase, SensorContext, config_key
from simcore.sensors.placement import other_sensors, sensor_state
from simcore.sensors.tof.camera import TofOutput, simulate_tof, slab_transmittance
from simcore.sensors.tof.interference import (
    Illuminator,
    hopped_config,
    light_windows_s,
    overlap_fraction,
)
from simcore.sensors.tof.radiosity import Room, room_from_meshes
from simcore.sensors.tof.schema import SCHEMA
from simcore.sensors.tof.specular import is_mirror, material_columns


class TofSensor(SensorBase):
    """AMCW ToF camera (``rig.tof`` or a named one): the near-infrared band it sees."""

    kind = "tof"
    schema = SCHEMA
    band = "tof"
    on_worker = True

    def render_request(self, project: Project) -> RenderRequest:
        """The supersampled near-infrared pass from the camera."""
        return RenderRequest(self.name, self.band, self.config(project).render_intrinsics())

    def see_through(self, project: Project) -> tuple[bool, ...] | None:
        """The objects that transmit part of the near-IR light (glass panes); None if none."""
        mask = tuple(bool(t > 0) for t in transmittance(tof_bands(project),
                                                         self.config(project)))
        return mask if any(mask) else None

    def sample_offsets_s(self, project: Project) -> tuple[float, ...]:
        """Times of extra renders: motion artefacts, then the previous frame (auto-exposure).

        With motion artefacts, the 2nd to 4th correlation samples' start times; with
        auto-exposure, one of the camera's frame periods earlier (the frame auto-exposure
        looks at).
        """
        cfg = self.config(project)
        offsets: tuple[float, ...] = ()
        if cfg.motion_artifacts and cfg.motion_sampling == "renders":
            offsets += tuple(i * cfg.sample_interval_s for i in (1, 2, 3))
        if cfg.auto_exposure:
            rate = project.timeline.frame_rate_hz
            offsets += (-cfg.frame_divider(rate) / rate,)
        return offsets

    def simulate(self, ctx: SensorContext) -> TofOutput | DeferredOutput:
        """The camera model over the render (and the sample renders, if any).

        Run on the sensor's post thread where there is one (:attr:`SensorContext.defer`):
        its chain goes on to the next frame meanwhile.
        """
        if ctx.defer is not None:
            return ctx.defer(lambda: self._simulate(ctx))
        return self._simulate(ctx)

    def _simulate(self, ctx: SensorContext) -> TofOutput:
        base = self.config(ctx.project)
        rate = ctx.project.timeline.frame_rate_hz
        cfg = hopped_config(base, ctx.index // base.frame_divider(rate))
        lights = illuminators(base, other_cameras(ctx.project, self.name),
                              frame_rate_hz=rate, time_s=ctx.time_s)
        bands = tof_bands(ctx.project)
        extra = list(ctx.sample_buffers)
        previous = extra.pop() if cfg.auto_exposure else None
        samples = (ctx.buffers, *extra) if extra else None
        albedo = None
        if cfg.multipath:
            albedo = ctx.stage("tof_albedo", lambda: diffuse_albedo(bands, ctx.buffers),
                               reads=config_key(*ctx.project.materials,
                                                *ctx.project.objects),
                               inputs=(ctx.buffers,))
        through = ctx.see_through
        trans = None if through is None else transmittance(bands, cfg)
        mirrors = mirror_table(bands) if cfg.specular else None
        room = None
        if cfg.multipath and cfg.multipath_model == "room":
            parts_of = body_part_table(ctx.project)
            room = room_from_scene(object_meshes(ctx.project, ctx.buffers),
                                   [state.transform for state in ctx.snapshot.objects], bands,
                                   closed=[isinstance(o.geometry, CLOSED) for o in
                                           ctx.project.objects],
                                   moving=[not o.motion.is_static or parts_of[i] >= 0
                                           for i, o in enumerate(ctx.project.objects)])
        out: TofOutput = ctx.stage(
            "tof", lambda: simulate_tof(ctx.buffers, cfg, rng=ctx.rng, sample_buffers=samples,
                                        albedo=albedo, exposure_reference=previous,
                                        see_through=through, transmittance=trans,
                                        mirrors=mirrors, illuminators=lights, room=room),
            reads=(config_key(cfg), ctx.seed, ctx.index, self.rng_stream,
                   None if trans is None else trans.tobytes(),
                   b"".join(light.key() for light in lights),
                   None if room is None else room.key()),
            inputs=(ctx.buffers, *ctx.sample_buffers, through))
        parts = body_part_table(ctx.project)
        if np.any(parts >= 0):  # people: per-pixel body part beside the object id
            factor = ctx.buffers.shape[0] // out.gt_object_id.shape[0]
            out = dataclasses.replace(
                out, gt_body_part=downsample_labels(ctx.buffers, parts, factor))
        return out

    def static_items(self, project: Project) -> H5Items:
        """No run-constant datasets."""
        return {}


def tof_bands(project: Project) -> list[BandMaterial | None]:
    """Every object's near-IR (``tof``) band material, in project order.

    The adapter's step from the project to what the ToF physics reads: the material
    table (library overridden by the project's own) looked up by each object's material
    name; None for a name the table lacks.
    """
    table = material_table(project, copy=False)
    return [table[o.material].band("tof") if o.material in table else None
            for o in project.objects]


def transmittance(bands: Sequence[BandMaterial | None], config: TofCameraConfig
                  ) -> NDArray[np.float64]:
    """One-pass near-IR power transmittance of every object (0: opaque), shape (N,).

    From each object's ToF-band material ``bands`` (:func:`tof_bands`; None: opaque) by
    :func:`simcore.sensors.tof.camera.slab_transmittance` at the wavelength of camera
    ``config``.
    """
    wavelength_m = config.wavelength_nm * 1e-9
    return np.array([0.0 if band is None else slab_transmittance(band, wavelength_m)
                     for band in bands], dtype=np.float64)


def mirror_table(bands: Sequence[BandMaterial | None]
                 ) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """Per-object ToF-band mirror columns and flags (:mod:`simcore.sensors.tof.specular`).

    ``bands``: each object's ToF-band material (:func:`tof_bands`).
    """
    columns = material_columns([_known(band) for band in bands])
    return columns, is_mirror(columns)


def diffuse_albedo(bands: Sequence[BandMaterial | None], buffers: RenderBuffers
                   ) -> NDArray[np.float32]:
    """Diffuse albedo ``(1 − metallic) · reflectance`` of the ToF band per render pixel.

    Parameters
    ----------
    bands : sequence of BandMaterial or None, length N
        Each object's ToF-band material (:func:`tof_bands`), indexed like
        ``buffers.object_index``.
    buffers : RenderBuffers
        The ToF render, shape (H, W).

    Returns
    -------
    ndarray, shape (H, W), float32
        0 where no surface is seen.
    """
    values = np.array([(1.0 - b.metallic) * b.reflectance for b in map(_known, bands)]
                      + [0.0], dtype=np.float32)
    return values[buffers.object_index]


def _known(band: BandMaterial | None) -> BandMaterial:
    """``band``; an object whose material the table lacks has none (a KeyError, as before)."""
    if band is None:
        raise KeyError("an object's material is not in the material table")
    return band


def illuminators(own: TofCameraConfig, others: Sequence[tuple[Rig, TofCameraConfig]], *,
                 frame_rate_hz: float, time_s: float) -> list[Illuminator]:
    """The other ToF cameras' frames whose light is on during camera ``own``'s frame.

    Each camera of ``others`` (its rig and configuration) captures its frame ``n`` at
    ``n × period + trigger_offset_s`` on the timeline's clock (``frame_rate_hz``; hopping
    per its own frame count), its illumination on during its four correlation samples'
    exposures (:func:`simcore.sensors.tof.interference.light_windows_s`); the pose is its
    pose at that capture time.
    """
    end = time_s + float(light_windows_s(own)[-1, 1])
    out = []
    for rig, cfg in others:
        period = cfg.frame_divider(frame_rate_hz) / frame_rate_hz
        span = float(light_windows_s(cfg)[-1, 1])
        first = math.floor((time_s - cfg.trigger_offset_s - span) / period)
        last = math.floor((end - cfg.trigger_offset_s) / period)
        for n in range(max(first, 0), last + 1):
            start = n * period + cfg.trigger_offset_s
            frame_cfg = hopped_config(cfg, n)
            if overlap_fraction(own, frame_cfg, start - time_s) <= 0:
                continue
            pose = sensor_state(rig, cfg, start).transform
            out.append(Illuminator(frame_cfg, pose, start - time_s))
    return out


#: Geometries whose meshes are closed, outward normals: their triangles reflect on one side.
CLOSED = (Box, Sphere, Cylinder, Ellipsoid, Person)


def room_from_scene(meshes: Sequence[TriangleMesh | None],
                    transforms: Sequence[NDArray[np.float64]],
                    bands: Sequence[BandMaterial | None], *, closed: Sequence[bool],
                    moving: Sequence[bool] | None = None) -> Room:
    """Every surface the near-IR light can bounce off, in the world frame (:class:`Room`).

    Parameters
    ----------
    meshes : sequence of TriangleMesh or None, length N
        Each object's mesh in its own frame (None: no surface).
    transforms : sequence of ndarray, shape (4, 4), length N
        Each object's local → world transform at the frame's time.
    bands : sequence of BandMaterial or None, length N
        Each object's ToF-band material (:func:`tof_bands`); objects the band does not see
        (opacity 0) are left out.
    closed : sequence of bool, keyword-only
        Objects whose meshes are closed with outward normals (boxes, spheres, …): their
        triangles reflect on their outer side only; the others on both sides.
    moving : sequence of bool, optional, keyword-only
        Objects the project moves (their rigid motion, a person's body).
    """
    parts, albedo, two_sided, movers = [], [], [], []
    flags = [False] * len(closed) if moving is None else list(moving)
    for mesh, t, band, shut, moves in zip(meshes, transforms, bands, closed, flags,
                                          strict=True):
        if mesh is None or band is None or band.opacity <= 0 or len(mesh.triangles) == 0:
            continue
        movers.append(bool(moves))
        points = mesh.points @ t[:3, :3].T + t[:3, 3]
        parts.append((points, mesh.triangles, mesh.normals @ t[:3, :3].T))
        albedo.append((1.0 - band.metallic) * band.reflectance)
        two_sided.append(not shut)
    return room_from_meshes(parts, albedo, two_sided=two_sided,
                            moving=None if moving is None else movers)


def object_meshes(project: Project, buffers: RenderBuffers
                   ) -> tuple[TriangleMesh | None, ...]:
    """Each object's mesh in its frame: the render's, else built here."""
    if len(buffers.meshes) == len(project.objects):
        return buffers.meshes
    out: list[TriangleMesh | None] = []
    for o in project.objects:
        try:
            out.append(build_mesh(o.geometry))
        except (OSError, ValueError):
            out.append(None)
    return tuple(out)


def other_cameras(project: Project, name: str) -> list[tuple[Rig, TofCameraConfig]]:
    """Every ToF camera of the project but ``name``: (rig, configuration)."""
    out = []
    for _, rig, cfg in other_sensors(project, name, TofCameraConfig):
        assert isinstance(cfg, TofCameraConfig)
        out.append((rig, cfg))
    return out
