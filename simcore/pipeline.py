"""One frame through the whole chain: snapshot → renders → sensors → DSP → :class:`Frame`.

The :class:`Simulator` is the public entry point; the
:class:`~simcore.engine.FrameEngine` under it decides what runs on which thread and what
is re-used, and every sensor registered in :mod:`simcore.sensors` that the project's rig
carries adds its output to the frame under its name.

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
from simcore.scene.people.truth import PeopleTruth, people_static_items, people_truth
from simcore.scene.snapshot import SceneSnapshot
from simcore.sensors.base import H5Items


@dataclass
class Frame:
    """Every output of one frame, all computed from the snapshot at ``time_s``.

    Attributes
    ----------
    index : int
        Frame number.
    time_s : float
        Timestamp shared by all sensor outputs (s).
    rig_pose : ndarray, shape (4, 4)
        Rig body frame → world.
    object_poses : ndarray, shape (objects, 4, 4)
        Object local frames → world.
    snapshot : SceneSnapshot
        Poses and velocities of everything at ``time_s``.
    outputs : dict of str to sensor output
        Each sensor's output by sensor name: ``"tof"`` (:class:`~simcore.sensors.tof.TofOutput`),
        ``"radar"`` (:class:`~simcore.sensors.radar.RadarFrameOutput`: raw ADC cube and
        its DSP products), ``"rgb"`` (:class:`~simcore.sensors.rgb.RgbOutput`) when on.
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
        for output in self.outputs.values():
            items.update(output.hdf5_items())
        return items

    def table_rows(self) -> dict[str, NDArray[Any]]:
        """Records this frame adds to growing tables (path → structured array)."""
        rows: dict[str, NDArray[Any]] = {}
        for output in self.outputs.values():
            table_rows = getattr(output, "table_rows", None)
            if table_rows is not None:
                rows.update(table_rows(self.index))
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
        # Ground truth of still objects kept between frames (not on the plain path).
        self._truth_cache = TruthCache() if reuse_static else None

    @property
    def project(self) -> Project:
        """The project being simulated (as given: people not expanded)."""
        return self.engine.source_project

    def set_project(self, project: Project) -> None:
        """Follow an edited project; keep what its edit does not change."""
        self.engine.set_project(project)
        if self._truth_cache is not None:
            self._truth_cache.clear()

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
            items.update(sensor.static_items(self.project))
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

    def _frame(self, result: FrameResult) -> Frame:
        snap = result.snapshot
        meshes = self.engine.renderer.geometry.meshes
        expanded = self.engine.project
        truth = object_ground_truth(expanded, snap,
                                    [None if m is None else m.points for m in meshes],
                                    local_triangles=[None if m is None else m.triangles
                                                     for m in meshes],
                                    cache=self._truth_cache)
        poses = snap.object_transforms()
        people = people_of(expanded)
        people_gt = None
        if people is not None:
            segments = truth
            truth = truth.take(people.representative)
            poses = poses[people.representative]
            for slot in people.people:
                boxes = segments.aabb_m[slot.first: slot.first + len(SEGMENTS)]
                truth.aabb_m[slot.source_index] = boxes[:, 0].min(0), boxes[:, 1].max(0)
                truth.radar_nearest_range_m[slot.source_index] = (
                    segments.radar_nearest_range_m[slot.first: slot.first + len(SEGMENTS)].min())
                poses[slot.source_index] = slot.body.body_frame(snap.time_s).placement
            people_gt = people_truth(people, snap)
        return Frame(index=result.index, time_s=snap.time_s, rig_pose=snap.rig.transform,
                     object_poses=poses, snapshot=snap,
                     outputs=result.outputs, buffers=result.buffers,
                     timings_ms=result.timings_ms, objects=truth,
                     see_through=result.see_through, people=people_gt)

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
