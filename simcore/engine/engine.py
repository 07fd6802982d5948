"""The frame engine: which step runs where, and what is re-used.

One frame is: snapshot → a render pass per sensor (GPU, on the calling thread, which owns
the VTK windows) → shading and the sensor's simulation. Sensors that ask for it
(``on_worker``: the ToF camera and the radar) run their shading and simulation each on its
own worker thread, while the calling thread renders the next frame and simulates the others;
numpy, finufft and the compiled kernels release the GIL, so on two cores the chains overlap
and no chain waits for the calling thread's renders of another sensor.

Every step goes through the engine's one :class:`~simcore.engine.cache.StageCache`. A
render is keyed by the scene's version, the pass and the poses and velocities of the
objects and the sensor (not the time), so a scene where nothing moves is rendered once,
and an edit of antennas or DSP settings re-uses every render. The optional
:class:`StillBackground` accelerator renders the still objects alone once, so that each
frame shades only the pixels a moving object changes and sensors may use it
(:class:`simcore.sensors.base.Background`).
"""

from __future__ import annotations

import ctypes
import dataclasses
import functools
import time
from collections.abc import Callable, Hashable, Iterable, Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from simcore.engine.cache import StageCache
from simcore.render.buffers import RenderBuffers
from simcore.render.renderer import Raster, RenderRequest, SceneRenderer, changed_pixels
from simcore.scene.model import Project
from simcore.scene.people.expand import body_part_table, expand_people, people_of
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors import Sensor, SensorContext, SensorOutput, active_sensors, frame_rng
from simcore.sensors.base import Background, DeferredOutput

T = TypeVar("T")
#: A background pass, its shading and the flat indices of the pixels that differ from it.
_Changed = tuple[Raster, RenderBuffers, NDArray[np.intp]]


@dataclass
class FrameResult:
    """What the engine computed for one frame (the pipeline wraps it in a ``Frame``)."""

    index: int
    snapshot: SceneSnapshot
    outputs: dict[str, Any]
    buffers: dict[str, RenderBuffers]
    timings_ms: dict[str, float] = field(default_factory=dict)
    see_through: dict[str, RenderBuffers] = field(default_factory=dict)
    #: Kind of every sensor of the project (also those that did not capture), by name.
    kinds: dict[str, str] = field(default_factory=dict)
    #: The snapshot each capturing sensor saw (at its capture time), by name.
    snapshots: dict[str, SceneSnapshot] = field(default_factory=dict)

    @property
    def capture_times(self) -> dict[str, float]:
        """Capture time (s) of every sensor that captured in this frame."""
        return {n: s.time_s for n, s in self.snapshots.items()}


def _single_threaded_blas() -> None:
    """Make OpenBLAS run single-threaded on the calling thread (no-op without OpenBLAS).

    The worker chain already runs beside the calling thread's on a 2-core machine;
    OpenBLAS's own threads only spin there (the DSP's angle search doubled its CPU time
    for a 10 % shorter wall time). Uses ``openblas_set_num_threads_local`` (OpenBLAS ≥
    0.3.27), which leaves other threads alone.
    """
    try:
        with open("/proc/self/maps", encoding="ascii", errors="replace") as maps:
            paths = {line.split()[-1] for line in maps
                     if "openblas" in line.lower() and line.rstrip().endswith(".so")}
    except OSError:
        return
    for path in sorted(paths):
        try:
            setter = ctypes.CDLL(path).openblas_set_num_threads_local
        except (OSError, AttributeError):
            continue
        setter.argtypes = [ctypes.c_int]
        setter.restype = ctypes.c_int
        setter(1)


def _state_key(snapshot: SceneSnapshot, sensor: str) -> bytes:
    """Poses and velocities a render depends on (not the time)."""
    parts = [snapshot.sensor(sensor).transform, snapshot.sensor(sensor).velocity_mps,
             snapshot.sensor(sensor).angular_velocity_rps, snapshot.object_transforms()]
    if snapshot.objects:     # stacked: no bytes object per object (assets have many)
        parts += [np.array([s.velocity_mps for s in snapshot.objects], dtype=np.float64),
                  np.array([s.angular_velocity_rps for s in snapshot.objects],
                           dtype=np.float64)]
    return b"".join(np.ascontiguousarray(p, dtype=np.float64).tobytes() for p in parts)


@dataclass
class _InFlight:
    """A frame whose worker chains may still run (:meth:`FrameEngine._start`)."""

    index: int
    snapshot: SceneSnapshot
    sensors: list[Sensor]
    timings: dict[str, float]
    start: float
    snapshots: dict[str, SceneSnapshot] = field(default_factory=dict)
    futures: dict[str, Future[tuple[RenderBuffers, SensorOutput]]] = field(default_factory=dict)
    results: dict[str, tuple[RenderBuffers, SensorOutput]] = field(default_factory=dict)
    through: dict[str, RenderBuffers] = field(default_factory=dict)


class StillBackground:
    """Accelerator: the still objects rendered alone, once, for the sensors of still rigs.

    Applies when some (not all) objects never move, to the sensors whose rig never moves
    (every rig's motion counts: a sensor on a moving rig renders every frame in full).
    Then every frame's render
    differs from the background only where moving objects are: shading copies the other
    pixels (the same values as shading them), and sensors get the changed pixels
    (:class:`~simcore.sensors.base.Background`) to re-use work done on the background.
    """

    def __init__(self) -> None:
        self.hide: tuple[bool, ...] | None = None
        self.still_rigs: frozenset[str] = frozenset()

    def applies_to(self, rig: str) -> bool:
        """Whether the background serves the sensors of rig ``rig``."""
        return self.hide is not None and rig in self.still_rigs

    def follow(self, project: Project) -> None:
        """Decide from the project's motions whether (and what) to hide."""
        # A person's segments move (gait, gestures, breathing, sway) whatever the object's
        # rigid motion says.
        parts = body_part_table(project)
        still = [o.motion.is_static and parts[i] < 0 for i, o in enumerate(project.objects)]
        self.still_rigs = frozenset(r.name for r in project.all_rigs() if r.motion.is_static)
        applies = bool(self.still_rigs) and any(still) and not all(still)
        self.hide = tuple(not s for s in still) if applies else None


class FrameEngine:
    """Runs frames of a project through the registered sensors, re-using what it can.

    Parameters
    ----------
    project : Project
        The project (:meth:`set_project` follows edits).
    base_dir : Path, optional
        Folder that relative mesh paths are resolved against.
    seed : int, optional
        Seed of every random stream (default: the project's).
    accelerate : bool
        Use the stage cache and the still-background accelerator (default). False runs
        every step of every frame: the plain path the accelerated one is tested against.
    threads : bool
        Run each ``on_worker`` sensor on its own worker thread (default).
    """

    def __init__(self, project: Project, *, base_dir: Path | None = None,
                 seed: int | None = None, accelerate: bool = True, threads: bool = True):
        self.seed = project.seed if seed is None else seed
        self.base_dir = base_dir
        self.source_project = project
        project = expand_people(project, base_dir=base_dir)
        self.renderer = SceneRenderer(project, base_dir=base_dir)
        # Six results per stage: a frame, its ToF sample renders (motion artefacts, the
        # previous frame for auto-exposure) and an edit's re-run stay cached together.
        self.cache = StageCache(keep=6, enabled=accelerate)
        self.background = StillBackground() if accelerate else None
        self.threads = threads
        self._workers: dict[str, ThreadPoolExecutor] = {}
        self._posts: dict[str, ThreadPoolExecutor] = {}
        self._scene_json = ""
        self._scene_version = 0
        self._ahead: _InFlight | None = None
        self._edited = False
        #: Rasters of the frame being started, by what makes two passes alike.
        self._shared: dict[Hashable, Raster] = {}
        self.set_project(project)

    # ------------------------------------------------------------------ project
    def set_project(self, project: Project) -> None:
        """Follow an edited project: renders stay valid while the scene is unchanged.

        People are expanded into their segments here (:func:`expand_people`): the engine's
        ``project`` is the expanded one, ``source_project`` the one given.
        """
        if people_of(project) is None:
            self.source_project = project
            project = expand_people(project, base_dir=self.base_dir)
        scene_json = "\n".join(
            [o.model_dump_json() for o in project.objects]
            + [m.model_dump_json() for m in project.materials])
        if self._ahead is not None:  # started for the previous project
            _drain(self._ahead)
            self._ahead = None
        if scene_json != self._scene_json:
            self.renderer.set_project(project)
            # After an edit of the scene (not for the first project), the next frame runs
            # without the still background: building it again costs about one more frame,
            # which an edit — often one of a drag's many — should not wait for.
            self._edited = bool(self._scene_json)
            self._scene_json = scene_json
            self._scene_version += 1
        self.project = project
        self.sensors = active_sensors(project)
        # Results kept per stage: six per sensor of the most numerous kind (the sensors of
        # a kind share their stages' names; a still scene is then rendered and
        # synthesised once however many sensors there are).
        per_kind: dict[str, int] = {}
        for sensor in self.sensors:
            per_kind[sensor.kind] = per_kind.get(sensor.kind, 0) + 1
        self.cache.keep = 6 * max(per_kind.values(), default=1)
        if self.background is not None:
            self.background.follow(project)

    # ------------------------------------------------------------------ one frame
    def frame(self, index: int, *, then: int | None = None) -> FrameResult:
        """Compute frame ``index`` of the timeline.

        ``then``: the frame that will most likely be asked for next (playback). It is
        started before this one is waited for, as in :meth:`frames`, and adopted by the
        next call if that asks for it with the project unchanged; otherwise it is waited
        for and dropped.
        """
        flight, self._ahead = self._ahead, None
        if flight is not None and flight.index != index:
            _drain(flight)
            flight = None
        if flight is None:
            flight = self._start(index)
        if then is not None:
            try:
                self._ahead = self._start(then)
            except BaseException:
                _drain(flight)
                raise
        return self._finish(flight)

    def frames(self, indices: Iterable[int]) -> Iterator[FrameResult]:
        """Compute frames ``indices`` in order, two at a time (the results of :meth:`frame`).

        While the worker thread finishes frame k's worker chains (the radar), the calling
        thread already renders frame k+1 and runs its own chains (the ToF camera): on two
        cores neither thread waits for the other's chain of the same frame. Each chain
        still runs its frames in order on its one thread, so every result equals
        :meth:`frame`'s. Stopping the iteration early waits for the frame in flight.
        """
        pending: _InFlight | None = None
        try:
            for index in indices:
                done, pending = pending, self._start(index)
                if done is not None:
                    yield self._finish(done)
            if pending is not None:
                done, pending = pending, None
                yield self._finish(done)
        finally:
            if pending is not None:
                _drain(pending)

    def _start(self, index: int) -> _InFlight:
        """Snapshot and renders of frame ``index``; worker chains submitted, the others run."""
        start = time.perf_counter()
        timings: dict[str, float] = {}
        project = self.project
        t0 = time.perf_counter()
        frame_time = project.timeline.frame_time(index)
        snap = take_snapshot(project, frame_time)
        # Each sensor that captures in this frame sees the scene at the frame's time plus
        # its trigger offset: one snapshot per distinct capture time.
        rate = project.timeline.frame_rate_hz
        capturing = []
        by_offset: dict[float, SceneSnapshot] = {0.0: snap}
        snapshots: dict[str, SceneSnapshot] = {}
        for sensor in self.sensors:
            cfg = project.sensor_config(sensor.name)
            if not cfg.captures(index, rate):  # type: ignore[attr-defined]
                continue
            offset = float(cfg.trigger_offset_s)  # type: ignore[attr-defined]
            if offset not in by_offset:
                by_offset[offset] = take_snapshot(project, frame_time + offset)
            snapshots[sensor.name] = by_offset[offset]
            capturing.append(sensor)
        timings["snapshot"] = (time.perf_counter() - t0) * 1e3
        # GPU passes on this thread; worker sensors' rasters first so their chain starts.
        order = sorted(capturing, key=lambda s: not (s.on_worker and self.threads))
        flight = _InFlight(index=index, snapshot=snap, sensors=capturing,
                           timings=timings, start=start, snapshots=snapshots)
        plain, self._edited = self._edited, False
        self._shared.clear()
        try:
            for sensor in order:
                chain = self._sensor_chain(sensor, snapshots[sensor.name], index, timings,
                                           flight.through, plain=plain)
                if sensor.on_worker and self.threads:
                    flight.futures[sensor.name] = self._pool(sensor.name).submit(chain)
                else:
                    flight.results[sensor.name] = chain()
        except BaseException:
            _drain(flight)
            raise
        return flight

    def _finish(self, flight: _InFlight) -> FrameResult:
        """Wait for a frame's worker chains; its result."""
        results = flight.results
        error: BaseException | None = None
        for name, future in flight.futures.items():
            try:
                results[name] = future.result()
            except BaseException as exc:  # the first error, after every chain has ended
                error = error or exc
        for name, (buffers, output) in list(results.items()):
            if isinstance(output, DeferredOutput):
                try:
                    results[name] = (buffers, output.result())
                except BaseException as exc:
                    error = error or exc
        if error is not None:
            raise error
        flight.timings["total"] = (time.perf_counter() - flight.start) * 1e3
        names = [s.name for s in flight.sensors]
        snaps = flight.snapshots
        return FrameResult(
            index=flight.index, snapshot=flight.snapshot,
            outputs={n: results[n][1] for n in names},
            buffers={n: _stamped(results[n][0], snaps[n], n) for n in names},
            timings_ms=flight.timings,
            see_through={n: _stamped(b, snaps[n], n) for n, b in flight.through.items()},
            kinds={s.name: s.kind for s in self.sensors},
            snapshots=dict(snaps))

    def _sensor_chain(self, sensor: Sensor, snap: SceneSnapshot, index: int,
                      timings: dict[str, float], through_out: dict[str, RenderBuffers], *,
                      plain: bool = False
                      ) -> Callable[[], tuple[RenderBuffers, SensorOutput]]:
        """Rasterise the sensor's passes now; return the rest (shading, physics) to run.

        ``plain``: without the still background (the first frame after a scene edit).
        """
        project = self.project
        request = sensor.render_request(project)
        label = f"render_{sensor.name}"
        raster = self._raster(snap, request, timings, label)
        samples = [self._raster(take_snapshot(project, snap.time_s + dt), request, timings,
                                f"render_{sensor.name}_samples")
                   for dt in sensor.sample_offsets_s(project)]
        hide = _see_through(sensor, project)
        # A raster shared with an alike sensor (named after that one) shares its
        # see-through pass too: the same stage, request and input.
        owner = dataclasses.replace(request, sensor=raster.sensor)
        through = (None if hide is None else
                   self.cache.run(f"raster:{raster.sensor}:see_through",
                                  lambda: self.renderer.rasterize_see_through(raster, owner,
                                                                              hide),
                                  reads=(self._scene_version, owner, hide), inputs=(raster,),
                                  timings=timings, label=f"render_{sensor.name}_see_through"))
        bg_raster = (None if plain or not self._background_for(sensor.name)
                     else self._background_raster(snap, request, timings))
        bg_through = (None if bg_raster is None or hide is None
                      else self._background_see_through(snap, request, hide, timings))

        def chain() -> tuple[RenderBuffers, SensorOutput]:
            background = None
            if bg_raster is not None:
                bg = self._shade(bg_raster, None, timings, "render_background")
                changed = changed_pixels(raster, (bg_raster, bg))
                if changed is not None:
                    background = (bg_raster, bg, changed)
            bg_pair = None if background is None else background[:2]
            buffers = self._shade(raster, bg_pair, timings, label)
            see_through = bg_see_through = None
            if through is not None:
                see_through, bg_see_through, background = self._shade_see_through(
                    sensor.name, (raster, buffers), through, bg_through, background, timings)
                through_out[sensor.name] = see_through
            sample_buffers = tuple(self._shade(r, bg_pair, timings, label) for r in samples)

            def stage(name: str, fn: Callable[[], T], *, reads: Hashable,
                      inputs: Sequence[object] = ()) -> T:
                return self.cache.run(name, fn, reads=reads, inputs=inputs, timings=timings)

            ctx = SensorContext(
                project=project, snapshot=snap, index=index, seed=self.seed,
                buffers=buffers, sample_buffers=sample_buffers,
                rng=frame_rng(self.seed, index, sensor.rng_stream), stage=stage,
                background=(None if background is None
                            else Background(background[1], background[2], bg_see_through)),
                see_through=see_through,
                defer=functools.partial(self._defer, sensor.name) if self.threads else None,
                name=sensor.name)
            return buffers, sensor.simulate(ctx)

        return chain

    def _background_see_through(self, snap: SceneSnapshot, request: RenderRequest,
                                hide: tuple[bool, ...], timings: dict[str, float]) -> Raster:
        """The still background's pass with the sensor's see-through objects hidden too."""
        assert self.background is not None and self.background.hide is not None
        both = tuple(a or b for a, b in zip(self.background.hide, hide, strict=True))
        return self._raster(snap, request, timings, "render_background",
                            hide=both, kind="background_see_through")

    def _shade_see_through(self, name: str, frame: tuple[Raster, RenderBuffers],
                           through: Raster, bg_through: Raster | None,
                           background: _Changed | None, timings: dict[str, float]
                           ) -> tuple[RenderBuffers, RenderBuffers | None, _Changed | None]:
        """Shade sensor ``name``'s see-through pass.

        It is shaded over the background's see-through pass where that applies, else over
        the frame's own pass (``frame``): it differs from that only where it shows a
        hidden object (same instant, same labels). Returns the see-through buffers, the
        background's see-through buffers (None where unused) and the background with the
        pixels that differ from either.
        """
        through_pair = frame
        bg_see_through = None
        if bg_through is not None and background is not None:
            bg_see_through = self._shade(bg_through, None, timings, "render_background",
                                         kind="background_see_through")
            more = changed_pixels(through, (bg_through, bg_see_through))
            if more is None:
                background = bg_see_through = None
            else:
                through_pair = (bg_through, bg_see_through)
                background = (background[0], background[1], np.union1d(background[2], more))
        see_through = self._shade(through, through_pair, timings, f"render_{name}_see_through",
                                  kind="see_through")
        return see_through, bg_see_through, background

    def _raster(self, snap: SceneSnapshot, request: RenderRequest, timings: dict[str, float],
                label: str, hide: tuple[bool, ...] | None = None,
                kind: str | None = None) -> Raster:
        # One name per pass kind (frame, background, see-through): a sample render at
        # another time is the same pass, so the previous frame's render serves
        # auto-exposure. The background is still: its render does not read the poses.
        kind = kind or ("background" if hide is not None else "frame")
        state = _state_key(snap, request.sensor)
        reads = (self._scene_version, request, hide,
                 None if kind.startswith("background") else state)
        # Sensors whose passes are alike (band, pixel grid, pose and velocities, instant)
        # share one raster: a second camera where the first is renders nothing.
        alike = (kind, hide, snap.time_s, request.band, request.intrinsics,
                 request.geometry_only, state)
        shared = self._shared.get(alike)
        if shared is not None:
            return shared
        raster = self.cache.run(f"raster:{request.sensor}:{kind}",
                                lambda: self.renderer.rasterize(snap, request, hide=hide),
                                reads=reads, timings=timings, label=label)
        self._shared[alike] = raster
        return raster

    def _background_for(self, sensor: str) -> bool:
        """Whether the still background serves ``sensor`` (its rig never moves)."""
        return (self.background is not None
                and self.background.applies_to(self.project.sensor_rig(sensor).name))

    def _background_raster(self, snap: SceneSnapshot, request: RenderRequest,
                           timings: dict[str, float]) -> Raster | None:
        if self.background is None or self.background.hide is None:
            return None
        return self._raster(snap, request, timings, "render_background",
                            hide=self.background.hide)

    def _shade(self, raster: Raster, background: tuple[Raster, RenderBuffers] | None,
               timings: dict[str, float], label: str, kind: str | None = None
               ) -> RenderBuffers:
        kind = kind or ("background" if label == "render_background" else "frame")
        return self.cache.run(f"shade:{raster.sensor}:{kind}",
                              lambda: self.renderer.shade(raster, background=background),
                              reads=(), inputs=(raster,), timings=timings, label=label)

    # ------------------------------------------------------------------ resources
    @property
    def render_count(self) -> int:
        """GPU passes run so far (edits of antennas or DSP settings do not add any)."""
        return self.renderer.render_count

    def _pool(self, sensor: str) -> ThreadPoolExecutor:
        """The sensor's own worker thread: its frames run in order, beside other sensors'."""
        if sensor not in self._workers:
            self._workers[sensor] = ThreadPoolExecutor(
                max_workers=1, thread_name_prefix=f"sensor-chain-{sensor}",
                initializer=_single_threaded_blas)
        return self._workers[sensor]

    def _defer(self, sensor: str, rest: Callable[[], SensorOutput]) -> DeferredOutput:
        """Run a sensor's last steps on its post thread (its frames in order).

        Each sensor has its own: one sensor's deferred steps do not queue behind another's.
        """
        if sensor not in self._posts:
            self._posts[sensor] = ThreadPoolExecutor(
                max_workers=1, thread_name_prefix=f"sensor-post-{sensor}",
                initializer=_single_threaded_blas)
        return DeferredOutput(self._posts[sensor].submit(rest))

    def close(self) -> None:
        """Release the rendering resources and the worker thread."""
        if self._ahead is not None:
            _drain(self._ahead)
            self._ahead = None
        for worker in self._workers.values():
            worker.shutdown(wait=True)
        self._workers.clear()
        for post in self._posts.values():
            post.shutdown(wait=True)
        self._posts.clear()
        self.renderer.close()


def _drain(flight: _InFlight) -> None:
    """Let a frame's worker chains end (or never start) and drop their results."""
    outputs = [output for _, output in flight.results.values()]
    for future in flight.futures.values():
        if not future.cancel() and future.exception() is None:
            outputs.append(future.result()[1])
    for output in outputs:
        if isinstance(output, DeferredOutput):
            output.future.exception()


def _see_through(sensor: Sensor, project: Project) -> tuple[bool, ...] | None:
    """The sensor's see-through mask, or None when it has none or hides nothing."""
    method = getattr(sensor, "see_through", None)
    hide = None if method is None else method(project)
    return tuple(hide) if hide is not None and any(hide) else None


def _stamped(buffers: RenderBuffers, snap: SceneSnapshot, sensor: str) -> RenderBuffers:
    """A re-used render with this frame's time and sensor state (same pixel arrays)."""
    if buffers.time_s == snap.time_s:
        return buffers
    return dataclasses.replace(buffers, time_s=snap.time_s, sensor=snap.sensor(sensor))
