"""One frame through the whole chain: snapshot → renders → sensors → DSP → :class:`Frame`.

The :class:`Simulator` is the public entry point; the
:class:`~simcore.engine.FrameEngine` under it decides what runs on which thread and what
is re-used, and every sensor of every rig of the project adds its output to the frame
under its name — in the frames it captures in (its own frame rate and trigger offset:
:mod:`simcore.scene.sensor_timing`).

Examples
--------
>>> from simcore.resources import example_path
>>> from simcore.scene import load_project
>>> project = load_project(example_path("wall"))
>>> with Simulator(project) as sim:
...     frame = sim.frame(0)
>>> sorted(frame.outputs)
['radar', 'tof']
>>> frame.outputs["tof"].depth_m.shape
(171, 224)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.engine import FrameEngine, FrameResult
from simcore.render.buffers import RenderBuffers
from simcore.scene.ground_truth import ObjectTruth, TruthCache, object_ground_truth
from simcore.scene.model import Project
from simcore.scene.people.expand import people_of
from simcore.scene.people.skeleton import SEGMENTS
from simcore.scene.people.truth import (
    PeopleTruth,
    people_radar_items,
    people_static_items,
    people_truth,
)
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors.base import H5Items, rename_items


@dataclass
class Frame:
    """Every output of one frame, all computed from the snapshot at ``time_s``.

    Attributes
    ----------
    index : int
        Frame number.
    time_s : float
        The frame's time (s): the capture time of every sensor with no trigger offset, and
        the time of the poses and object truth.
    rig_pose : ndarray, shape (4, 4)
        The first rig's body frame → world (``snapshot.rigs`` has every rig's).
    object_poses : ndarray, shape (objects, 4, 4)
        Object local frames → world.
    snapshot : SceneSnapshot
        Poses and velocities of everything at ``time_s``.
    outputs : dict of str to sensor output
        The output of each sensor that captured in this frame, by sensor name: ``"tof"``
        (:class:`~simcore.sensors.tof.TofOutput`), ``"radar"``
        (:class:`~simcore.sensors.radar.RadarFrameOutput`: raw ADC cube and its DSP
        products), ``"rgb"`` (:class:`~simcore.sensors.rgb.RgbOutput`) when on, and the
        named sensors of every rig. A sensor that does not capture in this frame (a lower
        frame rate) has no entry.
    buffers : dict of str to RenderBuffers
        Each sensor's render pass.
    see_through : dict of str to RenderBuffers
        The see-through pass of the sensors that have one (the radar, when the scene has
        partially transparent objects: :meth:`RadarSensor.see_through`).
    timings_ms : dict
        Wall time of each stage that ran (ms; the two chains overlap) and ``total``.
    objects : ObjectTruth or None
        Per-object ground truth (velocities, bounding boxes, range/velocity/angles from
        the radar), written to ``/objects/...``; a person's is its torso's.
    people : PeopleTruth or None
        Per-segment and vital-sign truth of the people (``/people/...``); None without
        people. With people, ``snapshot`` holds the segments (the engine's expanded
        objects: :mod:`simcore.scene.people.expand`) and ``object_poses`` the project's
        objects (a person's: its placement on the floor, facing its heading).
    kinds : dict of str to str
        Kind (``"tof"``, ``"radar"``, ``"rgb"``) of every sensor of the project, by name.
    capture_times : dict of str to float
        Every sensor's capture time in this frame (s): the frame's time plus its trigger
        offset (also for a sensor that did not capture: the time its truth is for).
    captured : dict of str to bool
        Whether each sensor captured in this frame (``name in outputs``).
    sensor_truth : dict
        More per-frame items of the truth (``/objects/<radar>/...`` of every radar but the
        built-in one, ``/people/segments/<radar>/...``), path → (array, unit).
    blanks : dict
        For each sensor that did not capture: its items and table rows of a captured
        frame, zeroed (the dataset keeps one frame axis; ``/<name>/captured`` says which).
    timed : bool
        Whether ``/<name>/captured`` and ``/<name>/time`` are written (a project with a
        sensor of its own frame rate or trigger offset).
    """

    index: int
    time_s: float
    rig_pose: NDArray[np.float64]
    object_poses: NDArray[np.float64]
    snapshot: SceneSnapshot
    outputs: dict[str, Any]
    buffers: dict[str, RenderBuffers]
    timings_ms: dict[str, float] = field(default_factory=dict)
    objects: ObjectTruth | None = None
    see_through: dict[str, RenderBuffers] = field(default_factory=dict)
    people: PeopleTruth | None = None
    kinds: dict[str, str] = field(default_factory=dict)
    capture_times: dict[str, float] = field(default_factory=dict)
    sensor_truth: H5Items = field(default_factory=dict)
    blanks: dict[str, tuple[H5Items, dict[str, NDArray[Any]]]] = field(default_factory=dict)
    timed: bool = False

    @property
    def captured(self) -> dict[str, bool]:
        """Whether each sensor of the project captured in this frame."""
        return {name: name in self.outputs for name in self.kinds or self.outputs}

    def sensor_items(self, name: str) -> H5Items:
        """Per-frame datasets of sensor ``name`` under ``/<name>/``.

        Zeros when it did not capture in this frame (:attr:`blanks`).
        """
        if name not in self.outputs:
            return dict(self.blanks[name][0]) if name in self.blanks else {}
        kind = self.kinds.get(name, name)
        return rename_items(self.outputs[name].hdf5_items(), kind, name)

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets of the HDF5 layout: path → (array without frame axis, unit)."""
        items: H5Items = {
            "/time": (np.asarray(self.time_s, dtype=np.float64), "s"),
            "/poses/rig": (self.rig_pose, "m"),
            "/poses/objects": (self.object_poses, "m"),
        }
        if self.objects is not None:
            items.update(self.objects.hdf5_items())
        if self.people is not None:
            items.update(self.people.hdf5_items())
        if self.kinds and self.kinds.get("radar") != "radar":
            # No built-in radar: its truth fields (``/objects/radar_*``) have no sensor.
            items = {p: v for p, v in items.items()
                     if not p.startswith(("/objects/radar_", "/people/segments/radar_"))}
        items.update(self.sensor_truth)
        for name in self.kinds or self.outputs:
            items.update(self.sensor_items(name))
            if self.timed:
                items[f"/{name}/captured"] = (np.asarray(name in self.outputs), "1")
                items[f"/{name}/time"] = (
                    np.asarray(self.capture_times.get(name, self.time_s), dtype=np.float64), "s")
        return items

    def table_rows(self) -> dict[str, NDArray[Any]]:
        """Records this frame adds to growing tables (path → structured array)."""
        rows: dict[str, NDArray[Any]] = {}
        for name in self.kinds or self.outputs:
            if name not in self.outputs:
                rows.update(self.blanks[name][1] if name in self.blanks else {})
                continue
            table_rows = getattr(self.outputs[name], "table_rows", None)
            if table_rows is not None:
                kind = self.kinds.get(name, name)
                rows.update(rename_items(table_rows(self.index), kind, name))
        return rows


class Simulator:
    """Runs frames of a project; keeps renders, caches and threads across frames.

    Parameters
    ----------
    project : Project
        The project; :meth:`set_project` follows edits.
    base_dir : Path, optional
        Folder that relative mesh paths are resolved against.
    seed : int, optional
        Seed of every random stream (default: the project's).
    reuse_static : bool
        Re-use what did not change (the engine's stage cache and still-background
        accelerator; default). Results equal the plain path's (``False``) bit for bit in
        the ToF camera and within the NUFFT tolerance in the radar.
    """

    def __init__(self, project: Project, *, base_dir: Path | None = None,
                 seed: int | None = None, reuse_static: bool = True):
        self.engine = FrameEngine(project, base_dir=base_dir, seed=seed,
                                  accelerate=reuse_static)
        self.seed = self.engine.seed
        # Ground truth of still objects kept between frames (not on the plain path), one
        # per radar (each keeps the nearest ranges from where it is).
        self._reuse = reuse_static
        self._truth_caches: dict[str, TruthCache] = {}
        # Zeroed items and table rows of each sensor, for the frames it does not capture.
        self._blanks: dict[str, tuple[H5Items, dict[str, NDArray[Any]]]] = {}

    @property
    def project(self) -> Project:
        """The project being simulated (as given: people not expanded)."""
        return self.engine.source_project

    def set_project(self, project: Project) -> None:
        """Follow an edited project; keep what its edit does not change."""
        self.engine.set_project(project)
        for cache in self._truth_caches.values():
            cache.clear()
        self._blanks.clear()

    @property
    def n_frames(self) -> int:
        """Number of frames of the project's timeline."""
        return self.project.timeline.n_frames

    def static_items(self) -> H5Items:
        """Run-constant datasets: object names and ids, and each sensor's axes."""
        objects = self.project.objects
        items: H5Items = {
            "/objects/names": (np.array([o.name for o in objects], dtype=str), ""),
            "/objects/ids": (np.array([o.id for o in objects], dtype=np.int32), "1"),
        }
        for sensor in self.engine.sensors:
            items.update(rename_items(sensor.static_items(self.project), sensor.kind,
                                      sensor.name))
        rigs = self.project.all_rigs()
        if len(rigs) > 1:
            items["/poses/rig_names"] = (np.array([r.name for r in rigs], dtype=str), "")
        people = people_of(self.engine.project)
        if people is not None:
            items.update(people_static_items(people))
        return items

    def frame(self, index: int, *, then: int | None = None) -> Frame:
        """Compute frame ``index`` of the timeline: snapshot, renders, every sensor.

        ``then``: the frame likely asked for next (playback), started before this one is
        waited for and adopted by the next call that asks for it
        (:meth:`simcore.engine.FrameEngine.frame`).
        """
        return self._frame(self.engine.frame(index, then=then))

    def frames(self, indices: Iterable[int]) -> Iterator[Frame]:
        """Compute frames ``indices`` in order, overlapping consecutive frames.

        The results equal :meth:`frame`'s, one by one; on two cores a run of frames is
        faster, because frame k+1's renders and ToF camera run while frame k's radar
        chain ends (:meth:`simcore.engine.FrameEngine.frames`). Edits
        (:meth:`set_project`) between frames of one iteration are not allowed.
        """
        for result in self.engine.frames(indices):
            yield self._frame(result)

    def _truth_cache(self, radar: str) -> TruthCache | None:
        if not self._reuse:
            return None
        return self._truth_caches.setdefault(radar, TruthCache())

    def _frame(self, result: FrameResult) -> Frame:
        snap = result.snapshot
        meshes = self.engine.renderer.geometry.meshes
        expanded = self.engine.project
        points = [None if m is None else m.points for m in meshes]
        triangles = [None if m is None else m.triangles for m in meshes]
        kinds = result.kinds or {n: n for n in result.outputs}
        # Every sensor's capture time in this frame (the snapshots of those that did not
        # capture are taken here: their truth is for that time too).
        rate = expanded.timeline.frame_rate_hz
        snaps: dict[str, SceneSnapshot] = dict(result.snapshots)
        by_time = {s.time_s: s for s in snaps.values()}
        by_time.setdefault(snap.time_s, snap)
        timed = False
        for name in kinds:
            cfg = expanded.sensor_config(name)
            offset = float(cfg.trigger_offset_s)  # type: ignore[attr-defined]
            timed = timed or offset > 0 or cfg.frame_divider(rate) > 1  # type: ignore[attr-defined]
            if name not in snaps:
                t = snap.time_s + offset
                if t not in by_time:
                    by_time[t] = take_snapshot(expanded, t)
                snaps[name] = by_time[t]
        radar_snap = snaps.get("radar", snap)
        truth = object_ground_truth(expanded, snap, points, local_triangles=triangles,
                                    cache=self._truth_cache("radar"))
        if radar_snap is not snap:   # the built-in radar's truth at its capture time
            seen = object_ground_truth(expanded, radar_snap, points, local_triangles=triangles,
                                       cache=self._truth_cache("radar"))
            truth = dataclasses.replace(
                truth, **{f: getattr(seen, f) for f in truth.__dataclass_fields__
                          if f.startswith("radar_")})
        others = {name: object_ground_truth(expanded, snaps[name], points,
                                            local_triangles=triangles,
                                            cache=self._truth_cache(name), sensor=name)
                  for name, kind in kinds.items() if kind == "radar" and name != "radar"}
        poses = snap.object_transforms()
        people = people_of(expanded)
        people_gt = None
        sensor_truth: H5Items = {}
        if people is not None:
            segments = truth
            truth = truth.take(people.representative)
            others = {n: t.take(people.representative) for n, t in others.items()}
            poses = poses[people.representative]
            for slot in people.people:
                boxes = segments.aabb_m[slot.first: slot.first + len(SEGMENTS)]
                truth.aabb_m[slot.source_index] = boxes[:, 0].min(0), boxes[:, 1].max(0)
                truth.radar_nearest_range_m[slot.source_index] = (
                    segments.radar_nearest_range_m[slot.first: slot.first + len(SEGMENTS)].min())
                poses[slot.source_index] = slot.body.body_frame(snap.time_s).placement
            people_gt = people_truth(people, snap)
            for name in others:
                sensor_truth.update(people_radar_items(people, snaps[name], name))
        for name, seen_by in others.items():
            sensor_truth.update(seen_by.sensor_items(name))
        if len(snap.rigs) > 1:
            sensor_truth["/poses/rigs"] = (np.stack([r.transform for r in snap.rigs.values()]),
                                           "m")
        blanks = {}
        missing = [n for n in kinds if n not in result.outputs]
        for name, output in result.outputs.items():
            if name not in self._blanks and timed:
                self._blanks[name] = _zeroed(output, kinds[name], name, result.index)
        for name in missing:
            if name not in self._blanks:
                self._blanks[name] = self._blank_of(name, kinds[name], result.index)
            blanks[name] = self._blanks[name]
        return Frame(index=result.index, time_s=snap.time_s, rig_pose=snap.rig.transform,
                     object_poses=poses, snapshot=snap,
                     outputs=result.outputs, buffers=result.buffers,
                     timings_ms=result.timings_ms, objects=truth,
                     see_through=result.see_through, people=people_gt, kinds=kinds,
                     capture_times={n: s.time_s for n, s in snaps.items()},
                     sensor_truth=sensor_truth, blanks=blanks, timed=timed)

    def _blank_of(self, name: str, kind: str, index: int
                  ) -> tuple[H5Items, dict[str, NDArray[Any]]]:
        """Zeroed items of sensor ``name``, from its last capture before frame ``index``.

        Only needed when no frame it captured has been seen yet (a run that starts at a
        frame it does not capture in): that one frame of it is computed.
        """
        rate = self.engine.project.timeline.frame_rate_hz
        n = self.engine.project.sensor_config(name).frame_divider(rate)  # type: ignore[attr-defined]
        last = index - index % n
        result = self.engine.frame(last)
        return _zeroed(result.outputs[name], kind, name, last)

    @property
    def render_count(self) -> int:
        """GPU passes run so far (edits of antennas or DSP settings do not add any)."""
        return self.engine.render_count

    def close(self) -> None:
        """Release rendering resources and the worker thread."""
        self.engine.close()

    def __enter__(self) -> Simulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _zeroed(output: Any, kind: str, name: str, index: int
            ) -> tuple[H5Items, dict[str, NDArray[Any]]]:
    """A sensor output's items and table rows as the zeros of a frame it did not capture."""
    items = {path: (np.zeros_like(np.asarray(a)), unit)
             for path, (a, unit) in rename_items(output.hdf5_items(), kind, name).items()}
    rows: dict[str, NDArray[Any]] = {}
    table_rows = getattr(output, "table_rows", None)
    if table_rows is not None:
        rows = {path: np.zeros(0, dtype=r.dtype)
                for path, r in rename_items(table_rows(index), kind, name).items()}
    return items, rows
