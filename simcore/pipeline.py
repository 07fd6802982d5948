"""One frame through the whole chain: snapshot → render → sensors → DSP → :class:`Frame`.

Each stage is a plain function or small class over arrays and dataclasses; the
:class:`Simulator` only sequences them, times them and keeps what can be cached between
frames (the renderer's windows and meshes).
"""

from __future__ import annotations

import ctypes
import dataclasses
import json
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.dsp import RadarProducts, process_frame, static_axes_items
from simcore.render import PinholeIntrinsics, RenderBuffers, SceneRenderer
from simcore.render.renderer import Raster, changed_pixels
from simcore.scene.model import Project
from simcore.scene.motion import Motion
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors.radar.frontend import RadarFrontEnd, RadarOutput
from simcore.sensors.tof.camera import TofOutput, simulate_tof

H5Items = dict[str, tuple[NDArray[np.generic], str]]


def tof_render_intrinsics(project: Project) -> PinholeIntrinsics:
    """Supersampled render grid of the ToF camera (sub-pixels tile sensor pixels)."""
    return project.rig.tof.render_intrinsics()


def radar_render_intrinsics(project: Project) -> PinholeIntrinsics:
    """Render grid of the radar pass (scatterer grid × render supersampling, square pixels)."""
    return project.rig.radar.render_intrinsics()


def render_key(project: Project) -> str:
    """Everything a render pass depends on, as text: equal keys → renders can be re-used.

    Radar waveform, antennas, noise and DSP settings are not part of it, so editing them
    re-runs only the stages after rendering.
    """
    radar = project.rig.radar
    return json.dumps({
        "objects": [o.model_dump(mode="json") for o in project.objects],
        "materials": [m.model_dump(mode="json") for m in project.materials],
        "rig_pose": project.rig.pose.model_dump(mode="json"),
        "rig_motion": project.rig.motion.model_dump(mode="json"),
        "tof": project.rig.tof.model_dump(mode="json"),
        "radar_pose": radar.pose_on_rig.model_dump(mode="json"),
        "radar_grid": [radar.render_width, radar.render_height, radar.render_fov_h_deg,
                       radar.render_supersampling],
        "timeline": project.timeline.model_dump(mode="json"),
    }, sort_keys=True)


#: Independent random streams of a frame, so that changing one sensor leaves the others'
#: noise untouched.
RNG_STREAMS = {"tof": 0, "radar": 1}


def frame_rng(seed: int, index: int, stream: str) -> np.random.Generator:
    """Random generator of one sensor in frame ``index``, whatever order frames run in."""
    return np.random.default_rng([seed, index, RNG_STREAMS[stream]])


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
    tof : TofOutput
        ToF camera outputs at sensor resolution, ground truth included.
    radar : RadarOutput
        Raw ADC cube (chirps, tx*rx, samples) and chirp times.
    dsp : RadarProducts
        Range/Doppler/angle maps, CFAR detections and point cloud of ``radar``.
    timings_ms : dict
        Wall time of each stage (ms).
    """

    index: int
    time_s: float
    rig_pose: NDArray[np.float64]
    object_poses: NDArray[np.float64]
    tof: TofOutput
    radar: RadarOutput
    dsp: RadarProducts
    snapshot: SceneSnapshot
    tof_buffers: RenderBuffers
    radar_buffers: RenderBuffers
    timings_ms: dict[str, float] = field(default_factory=dict)

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets of the HDF5 layout: path → (array without frame axis, unit)."""
        return {
            "/time": (np.asarray(self.time_s, dtype=np.float64), "s"),
            "/poses/rig": (self.rig_pose, "m"),
            "/poses/objects": (self.object_poses, "m"),
            **self.tof.hdf5_items(),
            **self.radar.hdf5_items(),
            **self.dsp.hdf5_items(),
        }

    def table_rows(self) -> dict[str, NDArray[Any]]:
        """Records this frame adds to growing tables (path → structured array)."""
        return {"/radar/detections": self.dsp.detection_records(self.index)}


def _single_threaded_blas() -> None:
    """Make OpenBLAS run single-threaded on the calling thread (no-op without OpenBLAS).

    The radar chain already runs beside the ToF chain on a 2-core machine; OpenBLAS's own
    threads only spin there (the DSP's angle search doubled its CPU time for a 10 %
    shorter wall time). Uses ``openblas_set_num_threads_local`` (OpenBLAS ≥ 0.3.27),
    which leaves other threads alone.
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


def is_still(motion: Motion) -> bool:
    """Whether a motion leaves its object (or the rig) at its base pose at all times."""
    return (not motion.keyframes and not any(motion.velocity_mps)
            and not any(motion.angular_velocity_dps))


class Simulator:
    """Runs frames of a project; keeps the renderer (windows, meshes) across frames.

    With ``reuse_static`` (default) and a rig that does not move, what does not change
    between frames is computed once: a scene whose objects do not move either is rendered
    once (later frames re-use the render with their own timestamp), and the radar IF of
    the static objects comes from one render of them alone
    (:meth:`RadarFrontEnd.set_background`), so each frame transforms only the scatterers
    that differ from it. Results are identical in every run and whatever order frames are
    computed in; they differ from ``reuse_static=False`` only within the NUFFT tolerance.
    """

    def __init__(self, project: Project, *, base_dir: Path | None = None, seed: int | None = None,
                 reuse_static: bool = True):
        self.seed = project.seed if seed is None else seed
        self.reuse_static = reuse_static
        self.renderer = SceneRenderer(project, base_dir=base_dir)
        self._render_key = ""
        # Frame index → (snapshot, ToF render, radar render, radar pixels that differ from
        # the radar background or None).
        self._render_cache: dict[int, tuple[SceneSnapshot, RenderBuffers, RenderBuffers,
                                            NDArray[np.intp] | None]] = {}
        self._static_renders: tuple[RenderBuffers, RenderBuffers] | None = None
        self._background_key: str | None = None
        self._bg_radar: tuple[Raster, RenderBuffers] | None = None
        self._bg_tof: tuple[Raster, RenderBuffers] | None = None
        self._tof_cache: tuple[RenderBuffers, tuple[str, int, int], TofOutput] | None = None
        self.radar = RadarFrontEnd(project, speckle_seed=self.seed)
        self._worker: ThreadPoolExecutor | None = None
        self.set_project(project)

    def set_project(self, project: Project) -> None:
        """Follow an edited project; keep cached renders when nothing they depend on changed."""
        key = render_key(project)
        if key != self._render_key:
            self.renderer.set_project(project)
            self._render_cache.clear()
            self._static_renders = None
            self._forget_background()
            self._render_key = key
        self._still = [is_still(o.motion) for o in project.objects]
        self._rig_still = is_still(project.rig.motion)
        self.project = project
        self.radar.project = project
        self.tof_intrinsics = tof_render_intrinsics(project)
        self.radar_intrinsics = radar_render_intrinsics(project)

    def static_items(self) -> H5Items:
        """Run-constant datasets: object names and ids (and sensor axes)."""
        objects = self.project.objects
        return {
            "/objects/names": (np.array([o.name for o in objects], dtype=str), ""),
            "/objects/ids": (np.array([o.id for o in objects], dtype=np.int32), "1"),
            **static_axes_items(self.project.rig.radar, self.project.dsp),
        }

    @property
    def n_frames(self) -> int:
        """Number of frames of the project's timeline."""
        return self.project.timeline.n_frames

    def frame(self, index: int) -> Frame:
        """Compute frame ``index`` of the timeline.

        The GPU passes run on the calling thread (VTK is not used from other threads);
        the radar chain (radar shading, scatterers, IF synthesis, DSP) runs on a worker
        thread while the calling thread shades the ToF pass and runs the camera model.
        numpy and finufft release the GIL, so on two cores the two chains overlap.
        ``timings_ms`` holds each stage's own wall time (stages of the two chains overlap)
        and ``total``, the wall time of the whole frame.
        """
        start = time.perf_counter()
        timings: dict[str, float] = {}

        @contextmanager
        def stage(name: str) -> Iterator[None]:
            t0 = time.perf_counter()
            yield
            timings[name] = timings.get(name, 0.0) + (time.perf_counter() - t0) * 1e3

        t = self.project.timeline.frame_time(index)
        cached = self._render_cache.get(index)
        reuse = self.reuse_static and self._rig_still
        static_scene = reuse and all(self._still)
        radar_raster = bg_radar_raster = bg_tof_raster = None
        if cached is None:
            with stage("snapshot"):
                snap = take_snapshot(self.project, t)
            if static_scene and self._static_renders is not None:
                # Nothing moves: the last render is this frame's, up to its timestamp.
                tof_prev, radar_prev = self._static_renders
                cached = (snap, dataclasses.replace(tof_prev, time_s=snap.time_s),
                          dataclasses.replace(radar_prev, time_s=snap.time_s),
                          np.zeros(0, dtype=np.intp))
            else:
                with stage("render_radar"):
                    radar_raster = self.renderer.rasterize(snap, "radar", self.radar_intrinsics)
                if (reuse and not static_scene and any(self._still)
                        and self._background_key != self._render_key):
                    # The still objects alone, once: later frames shade only the pixels
                    # that differ from it and transform only the radar scatterers that do.
                    hide = [not still for still in self._still]
                    with stage("render_background"):
                        bg_radar_raster = self.renderer.rasterize(
                            snap, "radar", self.radar_intrinsics, hide=hide)
                        bg_tof_raster = self.renderer.rasterize(
                            snap, "tof", self.tof_intrinsics, hide=hide)
        else:
            snap = cached[0]
        if not reuse and self._background_key is not None:
            self._forget_background()
        project, seed = self.project, self.seed

        def radar_chain() -> tuple[RenderBuffers, RadarOutput, RadarProducts,
                                   NDArray[np.intp] | None]:
            if bg_radar_raster is not None:
                with stage("render_background"):
                    bg = self.renderer.shade(bg_radar_raster)
                self._bg_radar = (bg_radar_raster, bg)
                self.radar.set_background(snap, bg)
            changed: NDArray[np.intp] | None = None
            if radar_raster is not None:
                with stage("render_radar"):
                    radar_buf = self.renderer.shade(radar_raster, background=self._bg_radar)
                    changed = changed_pixels(radar_raster, self._bg_radar)
            else:
                assert cached is not None
                radar_buf, changed = cached[2], cached[3]
            if static_scene and self._background_key != self._render_key:
                # Every object is static: the frame's own render is the background.
                self.radar.set_background(snap, radar_buf)
                self._background_key = self._render_key
                changed = np.zeros(0, dtype=np.intp)
            rng = frame_rng(seed, index, "radar")
            radar = None
            if changed is not None and reuse:
                # Only the facets whose pixels differ from the background are computed.
                with stage("radar_synthesis"):
                    radar = self.radar.simulate_over_background(snap, radar_buf, changed,
                                                                 rng=rng)
            if radar is None:
                with stage("radar_scatterers"):
                    scatterers = self.radar.cached_scatterers(snap, radar_buf)
                with stage("radar_synthesis"):
                    radar = self.radar.synthesize(scatterers, rng=rng)
            with stage("dsp"):
                dsp = process_frame(radar.adc, project.rig.radar, project.dsp,
                                    radar_to_world=radar_buf.sensor.transform)
            return radar_buf, radar, dsp, changed

        future = self._radar_worker().submit(radar_chain)
        try:
            if cached is None:
                if bg_tof_raster is not None:
                    with stage("render_background"):
                        self._bg_tof = (bg_tof_raster, self.renderer.shade(bg_tof_raster))
                with stage("render_tof"):
                    tof_raster = self.renderer.rasterize(snap, "tof", self.tof_intrinsics)
                    tof_buf = self.renderer.shade(tof_raster, background=self._bg_tof)
            else:
                tof_buf = cached[1]
            # The camera model is a function of its render, its configuration and the
            # frame's noise stream: an edit of anything else (antennas, DSP) re-uses it.
            tof_key = (project.rig.tof.model_dump_json(), seed, index)
            if (self._tof_cache is not None and self._tof_cache[0] is tof_buf
                    and self._tof_cache[1] == tof_key):
                tof = self._tof_cache[2]
            else:
                samples = None
                if project.rig.tof.motion_artifacts and not static_scene:
                    with stage("render_tof_samples"):
                        samples = [tof_buf, *self._tof_sample_renders(t)]
                with stage("tof"):
                    tof = simulate_tof(tof_buf, project.rig.tof,
                                       rng=frame_rng(seed, index, "tof"),
                                       sample_buffers=samples)
                self._tof_cache = (tof_buf, tof_key, tof)
        finally:
            radar_buf, radar, dsp, changed = future.result()
        if bg_radar_raster is not None:
            self._background_key = self._render_key
        # Keep the latest frame's renders: edits that do not change them re-use them.
        self._render_cache = {index: (snap, tof_buf, radar_buf, changed)}
        if static_scene:
            self._static_renders = (tof_buf, radar_buf)
        timings["total"] = (time.perf_counter() - start) * 1e3
        return Frame(
            index=index,
            time_s=t,
            rig_pose=snap.rig.transform,
            object_poses=snap.object_transforms(),
            tof=tof,
            radar=radar,
            dsp=dsp,
            snapshot=snap,
            tof_buffers=tof_buf,
            radar_buffers=radar_buf,
            timings_ms=timings,
        )

    def _tof_sample_renders(self, t: float) -> list[RenderBuffers]:
        """ToF renders at the 2nd to 4th correlation samples' start times (motion artefacts)."""
        dt = self.project.rig.tof.sample_interval_s
        out = []
        for i in (1, 2, 3):
            snap = take_snapshot(self.project, t + i * dt)
            raster = self.renderer.rasterize(snap, "tof", self.tof_intrinsics)
            out.append(self.renderer.shade(raster, background=self._bg_tof))
        return out

    @property
    def render_count(self) -> int:
        """GPU passes run so far (edits of antennas or DSP settings do not add any)."""
        return self.renderer.render_count

    def _forget_background(self) -> None:
        self._background_key = None
        self._bg_radar = self._bg_tof = None
        self.radar.set_background(None, None)

    def _radar_worker(self) -> ThreadPoolExecutor:
        if self._worker is None:
            self._worker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="radar-chain",
                                              initializer=_single_threaded_blas)
        return self._worker

    def close(self) -> None:
        """Release rendering resources and the radar worker thread."""
        if self._worker is not None:
            self._worker.shutdown(wait=True)
            self._worker = None
        self.renderer.close()

    def __enter__(self) -> Simulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
