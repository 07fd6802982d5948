"""The FMCW radar as a registered sensor: render → scatterers → IF → receiver → DSP.

Each step runs through the engine's stage cache (:meth:`SensorContext.stage`) with the
configuration slice it reads, so an antenna or waveform edit re-uses the render and the
scatterers, a DSP edit re-uses the ADC cube, and a ToF edit re-uses the whole radar frame.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.dsp import RadarProducts, process_frame, static_axes_items
from simcore.render.renderer import RenderRequest
from simcore.scene.model import Project, Rig
from simcore.scene.people.expand import body_part_table
from simcore.scene.project_io import material_table
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.base import (
    DeferredOutput,
    H5Items,
    SensorBase,
    SensorContext,
    config_key,
    rename_items,
)
from simcore.sensors.placement import other_sensors
from simcore.sensors.radar.background import (
    BackgroundFacets,
    cell_pixels,
    changed_cells,
)
from simcore.sensors.radar.frontend import RadarOutput, radar_output, radar_scatterers
from simcore.sensors.radar.interference_frame import FrameInterference, frame_interference
from simcore.sensors.radar.labels import (
    DetectionLabels,
    LabelScatterers,
    label_detections,
    prepare_scatterer_sets,
    prepare_scatterers,
)
from simcore.sensors.radar.multipath import ghost_scatterers, synthesize_ghosts
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.schema import SCHEMA
from simcore.sensors.radar.surfaces import transmissive_objects
from simcore.sensors.radar.synthesis import ComplexCube, prepare, synthesize_if
from simcore.sensors.radar.transmit import frame_transmit_config


@dataclass(frozen=True)
class RadarFrameOutput:
    """One frame of the radar: the raw ADC data and its processing.

    Attributes
    ----------
    raw : RadarOutput
        ADC cube (chirps, tx*rx, samples) and chirp times.
    dsp : RadarProducts
        Range/Doppler/angle maps, CFAR detections and point cloud of ``raw``.
    labels : DetectionLabels or None
        Ground truth of each detection of ``dsp.detections`` (object id, power fraction,
        ghost flag); None = unlabelled.
    body_parts : ndarray, shape (objects,), int32, or None
        Body-part id of each (engine) object, −1 for non-segments; None without people.
        A detection's ``body_part`` is that of its dominant object.
    """

    raw: RadarOutput
    dsp: RadarProducts
    labels: DetectionLabels | None = None
    body_parts: NDArray[np.int32] | None = None
    #: Dataset group of the sensor (its name).
    group: str = "radar"

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets of the raw data and the maps (under ``/<group>/``)."""
        return {**rename_items(self.raw.hdf5_items(), "radar", self.group),
                **self.dsp.hdf5_items(group=self.group)}

    def table_rows(self, index: int) -> dict[str, NDArray[np.void]]:
        """Rows this frame adds to the detections table (with their labels)."""
        rows = self.dsp.detection_records(index)
        if self.labels is not None and len(self.labels) == len(rows):
            rows["object_id"] = self.labels.object_id
            rows["power_fraction"] = self.labels.power_fraction
            rows["ghost"] = self.labels.ghost
            if self.body_parts is not None and self.labels.object_index is not None:
                table = np.append(self.body_parts, np.int32(-1))
                rows["body_part"] = table[self.labels.object_index]
        return {f"/{self.group}/detections": rows}


#: Prepared scatterer sets and their signs whose sum is a frame's scatterers (labels).
_LabelParts = list[tuple[LabelScatterers, float]]


class RadarSensor(SensorBase):
    """FMCW radar (``rig.radar`` or a named one): the 60 GHz band seen from its board.

    The adapter between the project and the radar physics: it takes the radar's slice of
    each frame (:meth:`RadarScene.from_project`: the objects, the material table, the
    snapshot and this radar's own state, by its name) and its configuration, and hands
    those to the physics, which never reads the project.
    """

    kind = "radar"
    schema = SCHEMA
    band = "radar"
    on_worker = True

    def render_request(self, project: Project) -> RenderRequest:
        """The radar pass (visibility only): facet grid × render supersampling, square pixels."""
        return RenderRequest(self.name, self.band, self.config(project).render_intrinsics(),
                             geometry_only=True)

    def sample_offsets_s(self, project: Project) -> tuple[float, ...]:
        """No extra renders: motion within the frame is the scatterers' velocities."""
        return ()

    def see_through(self, project: Project) -> tuple[bool, ...] | None:
        """The objects that transmit part of the radar wave (slabs: glass, paper, wood)."""
        return transmissive_objects(project.objects, material_table(project, copy=False),
                                    self.config(project).wavelength_m)

    def simulate(self, ctx: SensorContext) -> RadarFrameOutput | DeferredOutput:
        """Scatterers, IF synthesis, receiver and DSP of one frame.

        Receiver, DSP and labels run on the engine's post thread when it has one
        (``ctx.defer``).
        """
        # The frame's hopping channel and chirp jitter (none by default): the same draw as
        # other radars receive as interference (simcore.sensors.radar.transmit).
        base = self.config(ctx.project)
        cfg = frame_transmit_config(
            base, ctx.index // base.frame_divider(ctx.project.timeline.frame_rate_hz))
        scene = RadarScene.from_project(ctx.project, ctx.snapshot, self.name)
        found = _ideal_over_background(ctx, scene, cfg)
        scatterers: Scatterers | None
        if found is None:
            plain = ctx.stage(
                "radar_scatterers",
                lambda: radar_scatterers(scene, ctx.buffers, seed=ctx.seed,
                                         see_through=ctx.see_through, config=cfg),
                reads=_scatterer_reads(ctx, cfg), inputs=(ctx.buffers, ctx.see_through))
            # Per-scatterer arrays that do not depend on antennas or waveform: an antenna
            # edit re-uses them with the scatterers.
            prepared = ctx.stage("radar_prepare", lambda: prepare(plain), reads=(),
                                 inputs=(plain,))
            ideal = ctx.stage("radar_synthesis",
                              lambda: synthesize_if(plain, cfg, prepared=prepared),
                              reads=config_key(cfg), inputs=(plain, prepared))
            n_scatterers = transformed = len(plain)
            scatterers = plain
            parts = None
        else:
            ideal, n_scatterers, transformed, parts, scatterers = found
        ghosts: list[LabelScatterers] = []
        if cfg.multipath_order > 0:
            ideal, ghosts = _with_multipath(ctx, scene, cfg, ideal, scatterers)
        inr_db = None
        interference = _interference(ctx, scene, self.name, cfg, scatterers)
        if interference is not None:
            ideal = ideal + interference.cube
            inr_db = interference.inr_db
        rest = functools.partial(self._finish, ctx, cfg, ideal, n_scatterers, transformed,
                                 scatterers, parts, ghosts, inr_db)
        # Receiver, DSP and labels on the engine's post thread: the chain goes on to the
        # next frame's scatterers and synthesis meanwhile.
        return ctx.defer(rest) if ctx.defer is not None else rest()

    def _finish(self, ctx: SensorContext, cfg: RadarConfig, ideal: ComplexCube,
                n_scatterers: int, transformed: int, scatterers: Scatterers | None,
                parts: _LabelParts | None, ghosts: list[LabelScatterers],
                inr_db: float | None = None) -> RadarFrameOutput:
        """The frame's last steps: label terms, receiver, DSP, detection labels."""
        if parts is None:
            assert scatterers is not None
            sc = scatterers
            parts = [(ctx.stage("radar_label_scatterers", lambda: prepare_scatterers(sc, cfg),
                                reads=config_key(cfg), inputs=(sc,)), 1.0)]
        raw = ctx.stage(
            "radar_receiver",
            lambda: radar_output(ideal, cfg, rng=ctx.rng, time_s=ctx.time_s,
                                 n_scatterers=n_scatterers, transformed=transformed,
                                 inr_db=inr_db),
            reads=(config_key(cfg), ctx.seed, ctx.index, ctx.time_s, self.rng_stream),
            inputs=(ideal,))
        to_world = ctx.snapshot.sensor(self.name).transform
        dsp = ctx.stage(
            "dsp", lambda: process_frame(raw.adc, cfg, ctx.project.dsp, radar_to_world=to_world),
            reads=(config_key(cfg, ctx.project.dsp), to_world.tobytes()), inputs=(raw,))
        ids = np.array([o.id for o in ctx.project.objects], dtype=np.int32)
        labels = ctx.stage(
            "radar_labels",
            lambda: label_detections(dsp.detections, parts, ids, cfg, ctx.project.dsp, dsp.axes,
                                     ghosts=ghosts),
            reads=(config_key(cfg, ctx.project.dsp), ids.tobytes()),
            inputs=(dsp, *(p for p, _ in parts), *ghosts))
        parts_table = body_part_table(ctx.project)
        return RadarFrameOutput(raw=raw, dsp=dsp, labels=labels,
                                body_parts=parts_table if np.any(parts_table >= 0) else None,
                                group=self.name)

    def static_items(self, project: Project) -> H5Items:
        """The axes of the radar maps."""
        return static_axes_items(self.config(project), project.dsp, group=self.name)


def _with_multipath(ctx: SensorContext, scene: RadarScene, cfg: RadarConfig,
                    ideal: ComplexCube,
                    scatterers: Scatterers | None
                    ) -> tuple[ComplexCube, list[LabelScatterers]]:
    """``ideal`` plus the IF of the frame's multipath ghosts, and the ghosts for the labels.

    Stage ``radar_multipath``. The ghosts are prepared for the detection labels with each
    path's antennas, so with its bistatic ranges (:func:`prepare_scatterer_sets`: the sets
    with the real antennas as one, those with mirrored ones as another), and a detection
    of a ghost is labelled ``ghost`` with the id of the object it is a ghost of.

    The ghosts come from all the frame's scatterers (over the still background: the
    background's facets outside the changed cells and the frame's own in them), so both
    paths add the same ghosts; computed here only when the caller has none.
    """
    def run() -> tuple[ComplexCube, list[LabelScatterers]]:
        sc = scatterers
        if sc is None:
            sc = radar_scatterers(scene, ctx.buffers, seed=ctx.seed,
                                  see_through=ctx.see_through, config=cfg)
        sets = ghost_scatterers(scene, sc, cfg, buffers=ctx.buffers)
        labels = prepare_scatterer_sets(
            [(g.scatterers, g.tx_positions_m, g.rx_positions_m) for g in sets], cfg)
        return ideal + synthesize_ghosts(sets, cfg), labels

    to_world = scene.radar.transform
    return ctx.stage("radar_multipath", run,
                     reads=(_scatterer_reads(ctx, cfg), config_key(cfg), ctx.time_s,
                            to_world.tobytes()),
                     inputs=(ideal, ctx.buffers, ctx.see_through))


def aggressors(project: Project, victim: str) -> list[tuple[str, Rig, RadarConfig]]:
    """Every radar of the project but ``victim``: (name, rig, configuration).

    What :func:`~simcore.sensors.radar.interference_frame.frame_interference` reads.
    """
    return [(n, r, c) for n, r, c in other_sensors(project, victim, RadarConfig)
            if isinstance(c, RadarConfig)]


def _interference(ctx: SensorContext, scene: RadarScene, name: str, cfg: RadarConfig,
                  scatterers: Scatterers | None) -> FrameInterference | None:
    """The other radars' signals in this frame (stage ``radar_interference``), or None.

    Over the direct paths, and with ``multipath_order`` ≥ 1 also over the frame's
    scatterers (over the still background: those :func:`_ideal_over_background` gives;
    computed here only when the caller has none).
    """
    others = aggressors(ctx.project, name)
    if not others:
        return None
    reflect = cfg.multipath_order > 0

    def run() -> FrameInterference | None:
        sc = scatterers
        if reflect and sc is None:
            sc = radar_scatterers(scene, ctx.buffers, config=cfg, seed=ctx.seed,
                                  see_through=ctx.see_through)
        return frame_interference(others, ctx.project.sensor_rig(name), cfg, ctx.time_s,
                                  frame_rate_hz=ctx.project.timeline.frame_rate_hz,
                                  scatterers=sc if reflect else None)

    rigs = ctx.project.all_rigs()
    return ctx.stage("radar_interference", run,
                     reads=(config_key(cfg, *rigs), ctx.time_s,
                            ctx.project.timeline.frame_rate_hz,
                            _scatterer_reads(ctx, cfg) if reflect else None),
                     inputs=(ctx.buffers, ctx.see_through) if reflect else ())


def _scatterer_reads(ctx: SensorContext, cfg: RadarConfig) -> object:
    """What the scatterers depend on besides the render: λ, speckle, grid, materials."""
    return (cfg.wavelength_m, cfg.speckle, cfg.polarization, ctx.seed, cfg.render_width,
            cfg.render_height,
            cfg.render_fov_h_deg, cfg.render_supersampling,
            config_key(*ctx.project.materials), config_key(*ctx.project.objects))


def _ideal_over_background(ctx: SensorContext, scene: RadarScene, cfg: RadarConfig
                           ) -> tuple[ComplexCube, int, int, _LabelParts,
                                      Scatterers | None] | None:
    """The frame's IF as background IF − changed background facets + the frame's there.

    Returns (IF, scatterers in the frame, scatterers transformed, the same sum for the
    detection labels: the background's prepared scatterers (kept across frames) with sign
    +1, the hidden facets' with −1 and the frame's own there with +1; and, when the radar
    has multipath, all the frame's scatterers: the background's facets outside the changed
    cells and the frame's own in them, for the ghosts), or None when the engine gave no
    background or too much of the render changed.
    """
    bg = ctx.background
    if bg is None or bg.buffers.shape != ctx.buffers.shape:
        return None
    if (ctx.see_through is None) != (bg.see_through is None):
        return None
    facets = cfg.facet_intrinsics()
    cells = changed_cells(bg.changed, ctx.buffers.intrinsics, facets)
    if cells is None:
        return None
    reads = _scatterer_reads(ctx, cfg)
    background = ctx.stage(
        "radar_background_scatterers",
        lambda: BackgroundFacets.of(
            radar_scatterers(scene, bg.buffers, seed=ctx.seed,
                             see_through=bg.see_through, config=cfg),
            len(ctx.project.objects)),
        reads=reads, inputs=(bg.buffers, bg.see_through))
    background_prepared = ctx.stage("radar_background_prepare",
                                    lambda: prepare(background.scatterers), reads=(),
                                    inputs=(background,))
    background_if = ctx.stage(
        "radar_background_synthesis",
        lambda: synthesize_if(background.scatterers, cfg, prepared=background_prepared),
        reads=config_key(cfg), inputs=(background, background_prepared))
    background_labels = ctx.stage("radar_background_label_scatterers",
                                  lambda: prepare_scatterers(background.scatterers, cfg),
                                  reads=config_key(cfg), inputs=(background,))

    def frame_if() -> tuple[ComplexCube, int, int, _LabelParts, Scatterers | None]:
        pixels = cell_pixels(cells, ctx.buffers.intrinsics, facets)
        others = radar_scatterers(scene, ctx.buffers, seed=ctx.seed,
                                  pixels=pixels, see_through=ctx.see_through, config=cfg)
        inside = background.cell_mask(cells)
        hidden = background.scatterers.subset(np.flatnonzero(inside))
        # One synthesis of the change: the hidden facets negated (phase + π) with the
        # frame's own, so their static rows share one transform per pair and the call's
        # fixed costs are paid once.
        change = Scatterers.concatenate([hidden.negated(), others])
        out = background_if + synthesize_if(change, cfg) if len(change) else background_if.copy()
        n = len(background.scatterers) - len(hidden) + len(others)
        parts = [(background_labels, 1.0), (prepare_scatterers(hidden, cfg), -1.0),
                 (prepare_scatterers(others, cfg), 1.0)]
        # Multipath ghosts need every scatterer of the frame: the background's where the
        # frame did not change, the frame's own where it did (as the IF above).
        full = (Scatterers.concatenate([background.scatterers.subset(np.flatnonzero(~inside)),
                                        others]) if cfg.multipath_order > 0 else None)
        return out, n, len(hidden) + len(others), parts, full

    return ctx.stage("radar_synthesis", frame_if, reads=(reads, config_key(cfg)),
                     inputs=(ctx.buffers, bg.buffers, ctx.see_through))

