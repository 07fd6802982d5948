"""Frame-time and accuracy benchmark of the whole pipeline (``tofradar bench``).

:func:`run_benchmark` runs frames of a project through :class:`~simcore.pipeline.Simulator`
and reports per-stage medians, the frame rate, the IF synthesis error against the exact
direct sum and its speed-up, and the latency of an antenna edit (the GUI's drag path: cached
renders and scatterers, synthesis + DSP only). Timings are wall-clock medians; the machine
load is reported with them because other jobs on a shared machine change them.

CPU time changes much less with the load than wall time, so the benchmark also reports the
CPU time of each thread per frame (:func:`thread_cpu`) and from it the frame time a machine
with two free cores cannot beat: the busiest thread's CPU time (each thread runs its chain
in order) or half the process's, whichever is larger (``two_core_floor_ms``).
"""

from __future__ import annotations

import os
import platform
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from simcore.pipeline import Simulator
from simcore.scene.fieldpath import with_value
from simcore.scene.model import Project, sensor_kind
from simcore.scene.project_io import load_project
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import synthesize_if, synthesize_if_direct


def _median(values: list[float]) -> float:
    return float(np.median(values)) if values else float("nan")


def _load() -> list[float]:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - not on every platform
        return []


def _machine() -> dict[str, Any]:
    import finufft
    import scipy
    import vtkmodules

    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpu_count": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "finufft": finufft.__version__,
        "vtk": getattr(vtkmodules, "__version__", "?"),
    }


def _thread_times_ms() -> dict[int, tuple[str, float]]:
    """CPU time (user + system, ms) and name of each thread of this process, by native id.

    Linux (``/proc/self/task``); empty elsewhere. Python threads are named as in
    :mod:`threading` (the calling thread ``calling``, a pool's ``name_N`` without ``_N``
    when it has one thread), the others (llvmpipe's, OpenBLAS's) by their system name.
    """
    try:
        tids = os.listdir("/proc/self/task")
        tick = os.sysconf("SC_CLK_TCK")
    except (OSError, AttributeError, ValueError):
        return {}
    names = {t.native_id: t.name for t in threading.enumerate() if t.native_id is not None}
    names[threading.main_thread().native_id or -1] = "calling"
    out: dict[int, tuple[str, float]] = {}
    for tid in tids:
        try:
            with open(f"/proc/self/task/{tid}/stat", encoding="ascii", errors="replace") as f:
                head, tail = f.read().rsplit(")", 1)
        except (OSError, ValueError):
            continue
        fields = tail.split()
        name = names.get(int(tid)) or head.split("(", 1)[-1]
        out[int(tid)] = (name, (int(fields[11]) + int(fields[12])) * 1e3 / tick)
    return out


@contextmanager
def thread_cpu(frames: int) -> Iterator[dict[str, Any]]:
    """Measure the CPU time per frame of each thread over the ``with`` block.

    The yielded dict is filled on exit: ``thread_cpu_ms`` (thread name → CPU ms per frame,
    threads under 0.5 ms left out; empty where ``/proc`` is missing), ``cpu_ms`` (the
    process's CPU ms per frame) and ``two_core_floor_ms``: the larger of the busiest
    thread's and half the process's CPU ms per frame, the shortest frame interval two free
    cores allow (NaN without per-thread times). Resolution: a clock tick (10 ms) over all
    ``frames``.
    """
    out: dict[str, Any] = {}
    before, c0 = _thread_times_ms(), time.process_time()
    yield out
    cpu = (time.process_time() - c0) * 1e3 / max(frames, 1)
    times = _thread_times_ms()
    names = [name for name, _ in times.values()]
    per: dict[str, float] = {}
    for tid, (name, ms) in times.items():
        used = (ms - before.get(tid, (name, 0.0))[1]) / max(frames, 1)
        if used < 0.5:
            continue
        # A one-thread pool's "name_0" is named like its chain; other duplicates numbered.
        if name.endswith("_0") and name[:-2] + "_1" not in names:
            name = name[:-2]
        key, n = name, 1
        while key in per:
            n += 1
            key = f"{name}#{n}"
        per[key] = used
    out["thread_cpu_ms"] = dict(sorted(per.items(), key=lambda kv: -kv[1]))
    out["cpu_ms"] = cpu
    out["two_core_floor_ms"] = max(max(per.values()), 0.5 * cpu) if per else float("nan")


def first_of_kind(project: Project, kind: str) -> str | None:
    """Name of the project's first sensor of ``kind`` (None when it has none)."""
    return next(iter(project.sensors_of_kind(kind)), None)


def _moved_antennas(project: Project, shift_mm: float, radar: str) -> Project:
    """The project with every Rx antenna of ``radar`` moved by ``shift_mm`` along x."""
    cfg = project.sensor_config(radar)
    rx = [a.model_copy(update={"position_mm": (a.position_mm[0] + shift_mm, a.position_mm[1])})
          for a in cfg.rx]  # type: ignore[attr-defined]
    return with_value(project, f"{project.sensor_path(radar)}.rx", rx)


def without_kind(project: Project, kind: str) -> Project:
    """The project without its sensors of ``kind`` (every rig's)."""
    rigs = []
    for rig in project.all_rigs():
        update: dict[str, Any] = {"sensors": {n: c for n, c in rig.sensors.items()
                                              if sensor_kind(c) != kind}}
        if getattr(rig, kind, None) is not None:
            update[kind] = None
        rigs.append(rig.model_copy(update=update))
    return project.model_copy(update={"rig": rigs[0], "rigs": rigs[1:]})


def if_synthesis_accuracy(simulator: Simulator, index: int, *, subset: int = 1000,
                          seed: int = 0) -> dict[str, float]:
    """IF synthesis error and speed-up against the exact direct sum on one frame.

    The error is measured on a random subset of the frame's scatterers (all chirps and
    channels; the direct sum costs O(scatterers × samples × chirps × channels)); the
    direct sum's time is extrapolated linearly to all scatterers and compared with the
    NUFFT synthesis of all of them.

    Parameters
    ----------
    simulator : Simulator
        A simulator whose frame ``index`` has been computed (its renders are cached).
    index : int
        Frame index.
    subset : int, keyword-only
        Scatterers in the direct-sum comparison.
    seed : int, keyword-only
        Seed of the subset choice.

    Returns
    -------
    dict
        ``if_error_db`` (20 log10 of the relative L2 error of the real IF, or of the complex
        IF for IQ radars), ``if_speedup``, ``direct_ms_per_scatterer``,
        ``nufft_full_ms`` (NUFFT synthesis of all scatterers, no background re-use),
        ``subset`` (scatterers compared).
    """
    frame = simulator.frame(index)
    radar = first_of_kind(simulator.project, "radar")
    assert radar is not None, "the IF accuracy is a radar's"
    cfg = simulator.project.radar(radar)
    scatterers = radar_scatterers(RadarScene.from_project(simulator.engine.project,
                                                          frame.snapshot, radar),
                                  frame.buffers[radar], config=cfg, seed=simulator.seed,
                                  see_through=frame.see_through.get(radar))
    n = len(scatterers)
    rng = np.random.default_rng(seed)
    pick = np.sort(rng.choice(n, size=min(subset, n), replace=False))
    part = scatterers.subset(pick)
    t0 = time.perf_counter()
    ref = synthesize_if_direct(part, cfg)
    t_direct = time.perf_counter() - t0
    fast = synthesize_if(part, cfg)
    diff = fast - ref
    if not cfg.complex_iq:  # the real IF is what the ADC sees
        norm, err = float(np.linalg.norm(ref.real)), float(np.linalg.norm(diff.real))
    else:
        norm, err = float(np.linalg.norm(ref)), float(np.linalg.norm(diff))
    err = err / norm if norm > 0 else 0.0
    t_full = []
    for _ in range(3):
        t0 = time.perf_counter()
        synthesize_if(scatterers, cfg)
        t_full.append(time.perf_counter() - t0)
    per_scatterer = t_direct / max(len(part), 1)
    nufft = min(t_full)
    return {
        "if_error_db": 20.0 * float(np.log10(max(err, 1e-300))),
        "if_speedup": per_scatterer * n / nufft if nufft > 0 else float("inf"),
        "direct_ms_per_scatterer": per_scatterer * 1e3,
        "nufft_full_ms": nufft * 1e3,
        "subset": len(part),
    }


def antenna_edit_latency(simulator: Simulator, index: int, *, edits: int = 5) -> float:
    """Median wall time (ms) of a frame after moving the Rx antennas (no re-render)."""
    base = simulator.project
    radar = first_of_kind(base, "radar")
    if radar is None:
        return float("nan")
    times = []
    renders = simulator.render_count
    try:
        for k in range(edits):
            simulator.set_project(_moved_antennas(base, 0.25 * (1 + k % 2), radar))
            t0 = time.perf_counter()
            simulator.frame(index)
            times.append((time.perf_counter() - t0) * 1e3)
    finally:
        simulator.set_project(base)
    if simulator.render_count != renders:  # pragma: no cover - a regression
        raise RuntimeError("an antenna edit re-rendered the scene")
    return _median(times)


def run_benchmark(project_path: str | Path, *, frames: int, subset: int = 1000,
                  antenna_edits: int = 5) -> dict[str, Any]:
    """Run ``frames`` frames of a project and measure time, accuracy and GUI latency.

    Frame 0 is computed first as a warm-up (window creation, shader compilation, the
    static background and its IF) and not timed; then frames ``1 … frames`` (modulo the
    timeline length) are timed as a headless run computes them: in order, frame k+1's
    renders and ToF camera overlapping frame k's radar chain
    (:meth:`~simcore.pipeline.Simulator.frames`).

    Parameters
    ----------
    project_path : str or Path
        Project file.
    frames : int, keyword-only
        Frames to time.
    subset : int, keyword-only
        Scatterers in the direct-sum accuracy check.
    antenna_edits : int, keyword-only
        Antenna edits timed for the GUI latency (0: skip).

    Returns
    -------
    dict
        ``fps`` (1000 / median frame time: the interval between consecutive frames of
        the run), ``frame_ms_median``, ``frame_ms_p90``, ``cpu_ms_median`` (process CPU
        time per frame, all threads), ``thread_cpu_ms`` and ``two_core_floor_ms``
        (:func:`thread_cpu`), ``latency_ms_median`` (from a frame's start to its
        result; frames overlap, so it can exceed the frame time), ``stages_ms``
        (median wall time of each stage; the ToF and radar chains overlap, so they add up
        to more than the frame), ``if_error_db``, ``if_speedup`` and the other keys of
        :func:`if_synthesis_accuracy`, ``antenna_edit_ms``, ``scatterers``,
        ``scatterers_moving``, ``scatterers_transformed`` (median per frame, with the
        static background re-used), ``triangles``, ``config`` and ``machine`` (with the
        load average before and after).
    """
    path = Path(project_path)
    project = load_project(path)
    load_before = _load()
    with Simulator(project, base_dir=path.parent) as sim:
        n_frames = max(sim.n_frames, 1)
        sim.frame(0)
        indices = [(i + 1) % n_frames for i in range(frames)]
        index = indices[-1]
        timed = _time_frames(sim, indices, first_of_kind(project, "radar"))
        load_after = _load()
        latency = antenna_edit_latency(sim, index, edits=antenna_edits) if antenna_edits \
            else float("nan")
        radar_stats = _radar_stats(sim, timed.last, index, subset=subset)
        triangles = len(sim.engine.renderer.geometry.triangles)
    return {
        "project": str(path),
        "frames": frames,
        **timed.summary(),
        **radar_stats,
        "antenna_edit_ms": latency,
        "scatterers_transformed": (_median([float(x) for x in timed.transformed])
                                   if timed.transformed else float("nan")),
        "triangles": triangles,
        "sensors": {name: sensor_kind(cfg) for name, cfg in project.sensor_configs().items()},
        "config": _bench_config(project),
        "machine": {**_machine(), "load_before": load_before, "load_after": load_after},
    }


@dataclass
class _FrameTimes:
    """What :func:`_time_frames` measured, one entry per timed frame."""

    walls: list[float] = field(default_factory=list)        # frame intervals (ms)
    cpus: list[float] = field(default_factory=list)         # process CPU per frame (ms)
    latencies: list[float] = field(default_factory=list)    # start to result (ms)
    transformed: list[int] = field(default_factory=list)    # scatterers transformed
    stages: dict[str, list[float]] = field(default_factory=dict)  # stage wall times (ms)
    threads: dict[str, Any] = field(default_factory=dict)   # :func:`thread_cpu`'s figures
    last: Any = None                                        # the last frame computed

    def summary(self) -> dict[str, Any]:
        """Frame rate, medians and percentiles, per-thread CPU and per-stage times."""
        frame_ms = _median(self.walls)
        return {
            "fps": 1e3 / frame_ms if frame_ms > 0 else float("inf"),
            "frame_ms_median": frame_ms,
            "frame_ms_p90": float(np.percentile(self.walls, 90)) if self.walls
            else float("nan"),
            "cpu_ms_median": _median(self.cpus),
            "thread_cpu_ms": self.threads["thread_cpu_ms"],
            "two_core_floor_ms": self.threads["two_core_floor_ms"],
            "latency_ms_median": _median(self.latencies),
            "stages_ms": {name: _median(values) for name, values in self.stages.items()},
        }


def _time_frames(sim: Simulator, indices: list[int], radar: str | None) -> _FrameTimes:
    """Time frames ``indices`` as a headless run computes them (Simulator.frames)."""
    timed = _FrameTimes()
    c0, t0 = time.process_time(), time.perf_counter()
    # Consecutive frames overlapped, as in a headless run.
    with thread_cpu(len(indices)) as threads:
        for frame in sim.frames(indices):
            c1, t1 = time.process_time(), time.perf_counter()
            timed.walls.append((t1 - t0) * 1e3)
            timed.cpus.append((c1 - c0) * 1e3)
            c0, t0 = c1, t1
            timed.latencies.append(frame.timings_ms["total"])
            if radar in frame.outputs:
                timed.transformed.append(frame.outputs[radar].raw.transformed_scatterers)
            for name, value in frame.timings_ms.items():
                if name != "total":
                    timed.stages.setdefault(name, []).append(value)
            timed.last = frame
    timed.threads = threads
    return timed


def _radar_stats(sim: Simulator, frame: Any, index: int, *, subset: int) -> dict[str, Any]:
    """IF accuracy and scatterer counts of the project's first radar (empty without one)."""
    radar = first_of_kind(sim.project, "radar")
    if radar is None:
        return {}
    accuracy = if_synthesis_accuracy(sim, index, subset=subset)
    scatterers = radar_scatterers(RadarScene.from_project(sim.engine.project, frame.snapshot,
                                                          radar),
                                  frame.buffers[radar], config=sim.project.radar(radar),
                                  seed=sim.seed, see_through=frame.see_through.get(radar))
    moving = int(np.count_nonzero(np.any(scatterers.velocities_mps != 0.0, axis=1)))
    return {**accuracy, "scatterers": len(scatterers), "scatterers_moving": moving}


def _bench_config(project: Project) -> dict[str, Any]:
    """Sizes of the first ToF camera's and radar's renders and cubes (those it has)."""
    out: dict[str, Any] = {}
    tof, radar = first_of_kind(project, "tof"), first_of_kind(project, "radar")
    if tof is not None:
        tc = project.sensor_config(tof)
        out["tof_render"] = [tc.width * tc.supersampling,  # type: ignore[attr-defined]
                             tc.height * tc.supersampling]  # type: ignore[attr-defined]
    if radar is not None:
        rc: Any = project.sensor_config(radar)
        out.update({"radar_render": [rc.render_width * rc.render_supersampling,
                                     rc.render_height * rc.render_supersampling],
                    "chirps": rc.chirps_per_frame, "channels": rc.n_channels,
                    "samples": rc.samples_per_chirp, "nufft_tolerance": rc.nufft_tolerance})
    return out


def sensor_variants(project_path: str | Path, *, frames: int) -> dict[str, Any] | None:
    """The project with all its sensors, with its radars only and with its ToF cameras only.

    What a frame saves when it does only the work of the sensors a project has. None when
    the project lacks ToF cameras or radars (there is nothing to leave out).

    Returns
    -------
    dict or None
        ``all_sensors``, ``radar_only``, ``tof_only``: each ``fps``, ``frame_ms_median``,
        ``cpu_ms_per_frame`` (process CPU time, all threads), ``stages_ms``;
        ``radar_only_speedup`` and ``tof_only_speedup`` (frame time of all over that of
        the variant, same run), ``radar_only_cpu_ratio`` and ``tof_only_cpu_ratio`` (the
        same of CPU time per frame) and ``load``.
    """
    path = Path(project_path)
    project = load_project(path)
    if not project.sensors_of_kind("tof") or not project.sensors_of_kind("radar"):
        return None
    load_before = _load()
    out: dict[str, Any] = {
        "all_sensors": _time_variant(project, path.parent, frames),
        "radar_only": _time_variant(without_kind(project, "tof"), path.parent, frames),
        "tof_only": _time_variant(without_kind(project, "radar"), path.parent, frames),
    }
    full = out["all_sensors"]["frame_ms_median"]
    full_cpu = out["all_sensors"]["cpu_ms_per_frame"]
    for name in ("radar_only", "tof_only"):
        t, c = out[name]["frame_ms_median"], out[name]["cpu_ms_per_frame"]
        out[f"{name}_speedup"] = full / t if t > 0 else float("inf")
        out[f"{name}_cpu_ratio"] = full_cpu / c if c > 0 else float("inf")
    out["load"] = {"before": load_before, "after": _load()}
    return out


#: The ToF switches of :func:`effect_variants` (all on / all off).
TOF_EFFECTS = ("multipath", "motion_artifacts", "specular", "wiggling", "distortion",
               "vignetting", "stray_light", "ambient_light")


def with_effects(project: Project, *, on: bool, person: bool = True,
                 room: bool = False) -> Project:
    """The project with every ToF effect switch and radar multipath (order 1) on or off.

    Motion artefacts use reprojection (no extra ToF renders). ``room``: ToF multipath from
    the whole room (``multipath_model = "room"``, its moving objects to first order)
    instead of the project's model.

    ``person`` False also removes the objects named ``person`` (today's plain office).
    """
    update: dict[str, Any] = {}
    if project.rig.tof is not None:
        model = {"multipath_model": "room", "multipath_moving": "first_order"} if room else {}
        update["tof"] = project.rig.tof.model_copy(
            update={**dict.fromkeys(TOF_EFFECTS, on), "motion_sampling": "reprojection",
                    **model})
    if project.rig.radar is not None:
        update["radar"] = project.rig.radar.model_copy(
            update={"multipath_order": 1 if on else 0})
    rig = project.rig.model_copy(update=update)
    objects = [o for o in project.objects if person or o.name != "person"]
    return project.model_copy(update={"rig": rig, "objects": objects})


def _time_variant(project: Project, base_dir: Path, frames: int) -> dict[str, Any]:
    """Median frame interval and stage times of ``frames`` overlapped frames (after frame 0)."""
    with Simulator(project, base_dir=base_dir) as sim:
        n_frames = max(sim.n_frames, 1)
        sim.frame(0)
        walls: list[float] = []
        stages: dict[str, list[float]] = {}
        t0, c0 = time.perf_counter(), time.process_time()
        for frame in sim.frames([(i + 1) % n_frames for i in range(frames)]):
            t1 = time.perf_counter()
            walls.append((t1 - t0) * 1e3)
            t0 = t1
            for name, value in frame.timings_ms.items():
                if name != "total":
                    stages.setdefault(name, []).append(value)
        cpu_ms = (time.process_time() - c0) * 1e3 / max(frames, 1)
    frame_ms = _median(walls)
    return {"fps": 1e3 / frame_ms if frame_ms > 0 else float("inf"),
            "frame_ms_median": frame_ms, "cpu_ms_per_frame": cpu_ms,
            "stages_ms": {name: _median(v) for name, v in stages.items()}}


def effect_variants(project_path: str | Path, *, frames: int) -> dict[str, Any]:
    """Frame rate and stage times with every effect on, and plain (all off, no person).

    Both variants of the same project are timed in one run (one after the other), so
    their ratio is meaningful on a loaded machine even where absolute times are not.

    Returns
    -------
    dict
        ``all_effects``, ``all_effects_room`` (the same with ToF multipath from the whole
        room) and ``plain``: each ``fps``, ``frame_ms_median``, ``stages_ms``;
        ``load`` (load average before and after).
    """
    path = Path(project_path)
    project = load_project(path)
    before = _load()
    result: dict[str, Any] = {
        "all_effects": _time_variant(with_effects(project, on=True), path.parent, frames),
        "all_effects_room": _time_variant(with_effects(project, on=True, room=True),
                                          path.parent, frames),
        "plain": _time_variant(with_effects(project, on=False, person=False), path.parent,
                               frames),
    }
    result["load"] = {"before": before, "after": _load()}
    return result


def with_second_rig(project: Project, *, offset_m: tuple[float, float, float] = (0.5, -1.0, 0.0),
                    yaw_deg: float = 25.0, name: str = "rig2") -> Project:
    """The project with a copy of its first rig's ToF camera and radar on a second rig.

    The second rig stands ``offset_m`` from the first (in the first rig's body frame:
    forward, left, up) and is turned ``yaw_deg`` further left; it has the first rig's
    motion, and its sensors (``<name>_tof``, ``<name>_radar``) the built-ins' settings.
    """
    from simcore.scene.model import Rig, named_sensor
    from simcore.scene.motion import Pose

    first = project.rig
    yaw = np.radians(first.pose.rotation_deg[2])
    fwd, left, up = offset_m
    position = (first.pose.position_m[0] + fwd * np.cos(yaw) - left * np.sin(yaw),
                first.pose.position_m[1] + fwd * np.sin(yaw) + left * np.cos(yaw),
                first.pose.position_m[2] + up)
    rotation = (first.pose.rotation_deg[0], first.pose.rotation_deg[1],
                first.pose.rotation_deg[2] + yaw_deg)
    rig = Rig(name=name, pose=Pose(position_m=tuple(float(v) for v in position),
                                   rotation_deg=rotation),
              motion=first.motion,
              sensors={f"{name}_{kind}": named_sensor(cfg)
                       for kind, cfg in (("tof", first.tof), ("radar", first.radar))
                       if cfg is not None})
    doc = project.model_dump()
    doc["rigs"] = [*doc["rigs"], rig.model_dump()]
    return type(project).model_validate(doc)


def rig_variants(project_path: str | Path, *, frames: int) -> dict[str, Any]:
    """Frame rate of the project as it is and with a second rig (:func:`with_second_rig`).

    Both are timed in one run, one after the other (A/B): their ratio is meaningful on a
    loaded machine. Linear cost in the number of sensors means ``time_ratio`` (two-rig
    frame time / one-rig frame time) at most the ratio of sensors (2 for a rig with a ToF
    camera and a radar).

    Returns
    -------
    dict
        ``one_rig`` and ``two_rigs`` (``fps``, ``frame_ms_median``, ``stages_ms``,
        ``sensors``), the same of the plain project (:func:`with_effects` off, no person:
        ``plain_one_rig``, ``plain_two_rigs``), ``time_ratio`` and ``plain_time_ratio``,
        and ``load`` (load average before and after).
    """
    path = Path(project_path)
    project = load_project(path)
    plain = with_effects(project, on=False, person=False)
    before = _load()
    result: dict[str, Any] = {}
    for key, variant in (("one_rig", project), ("two_rigs", with_second_rig(project)),
                         ("plain_one_rig", plain), ("plain_two_rigs", with_second_rig(plain))):
        result[key] = {**_time_variant(variant, path.parent, frames),
                       "sensors": len(variant.sensor_configs())}
    for prefix in ("", "plain_"):
        one_ms = result[f"{prefix}one_rig"]["frame_ms_median"]
        two_ms = result[f"{prefix}two_rigs"]["frame_ms_median"]
        result[f"{prefix}time_ratio"] = two_ms / one_ms if one_ms > 0 else float("nan")
    result["load"] = {"before": before, "after": _load()}
    return result


def _frame_rate(project: Project, base_dir: Path, frames: int) -> tuple[float, float]:
    """Frames per second and two-core floor (ms, :func:`thread_cpu`) of ``frames`` frames.

    The frames are overlapped as in a headless run, after an untimed frame 0.
    """
    with Simulator(project, base_dir=base_dir) as sim:
        n = max(sim.n_frames, 1)
        sim.frame(0)
        indices = [(i + 1) % n for i in range(frames)]
        t0 = time.perf_counter()
        with thread_cpu(frames) as threads:
            for _ in sim.frames(indices):
                pass
        return frames / (time.perf_counter() - t0), threads["two_core_floor_ms"]


def rigid_stand_ins(project: Project, *, base_dir: Path | None = None,
                    max_keyframes: int = 2000) -> Project:
    """The project with each person replaced by a rigid stand-in that goes where it goes.

    The stand-in is a cylinder of the person's height and of the radius of its widest
    trunk segment (pelvis or chest), in its clothing, centred half its height above the
    body's placement (the floor point between the feet, :meth:`PersonBody.body_frame`)
    and carried by keyframes of that placement at the timeline's frame times (at most
    ``max_keyframes``, evenly spread). It moves through the scene like the person and
    hides what the person hides, without limbs: the reference that says what
    articulation costs beyond any moving object of a person's size.
    """
    from scipy.spatial.transform import Rotation

    from simcore.scene.geometry import Cylinder
    from simcore.scene.motion import Keyframe, Motion, Pose
    from simcore.scene.people import Person
    from simcore.scene.people.body import PersonBody
    from simcore.scene.people.skeleton import SEGMENT_INDEX

    timeline = project.timeline
    n = timeline.n_frames
    indices = np.unique(np.linspace(0, n - 1, min(n, max_keyframes)).round().astype(int))
    objects = []
    for obj in project.objects:
        geom = obj.geometry
        if not isinstance(geom, Person):
            objects.append(obj)
            continue
        body = PersonBody(geom, obj.pose, obj.motion, object_id=obj.id, seed=project.seed,
                          base_dir=base_dir)
        radii = body.skeleton.radii
        radius = float(max(radii[SEGMENT_INDEX[s]][:2].max() for s in ("pelvis", "chest")))
        centre = np.array([0.0, 0.0, 0.5 * geom.height_m, 1.0])
        keys = []
        for i in indices:
            t = timeline.frame_time(int(i))
            place = body.body_frame(t).placement
            angles = Rotation.from_matrix(place[:3, :3]).as_euler("xyz", degrees=True)
            keys.append(Keyframe(time_s=t, position_m=tuple(float(v) for v in
                                                           (place @ centre)[:3]),
                                 rotation_deg=tuple(float(a) for a in angles)))
        objects.append(obj.model_copy(update={
            "geometry": Cylinder(radius_m=radius, height_m=geom.height_m),
            "material": geom.clothing, "pose": Pose(),
            "motion": Motion(keyframes=keys, repeat="hold")}))
    return project.model_copy(update={"objects": objects})


def people_speed(project_path: str | Path, *, frames: int) -> dict[str, Any] | None:
    """Frame rate of a project with its people, without them and with rigid stand-ins.

    Each variant runs ``frames`` frames twice, in the order without, stand-ins, with and
    back; the numbers are the means of the two.

    Returns
    -------
    dict or None
        ``fps_with_people``, ``fps_without_people`` and their ratio ``ratio``, measured
        one after the other (A/B, same frames); the same from the two-core floors
        (:func:`thread_cpu`): ``floor_ms_with_people``, ``floor_ms_without_people`` and
        ``floor_ratio`` (without ÷ with: the ratio of frame rates two free cores would
        allow at best, steadier than ``ratio`` on a loaded machine); with each person
        replaced by its rigid stand-in (:func:`rigid_stand_ins`): ``fps_stand_ins``,
        ``floor_ms_stand_ins`` and ``ratio_to_stand_ins`` (with people ÷ with stand-ins:
        what articulation costs beyond a moving object of a person's size). None if the
        project has no people.
    """
    from simcore.scene.people import Person

    path = Path(project_path)
    project = load_project(path)
    if not any(isinstance(o.geometry, Person) for o in project.objects):
        return None
    without = project.model_copy(update={"objects": [
        o for o in project.objects if not isinstance(o.geometry, Person)]})
    stand_ins = rigid_stand_ins(project, base_dir=path.parent)
    variants = {"without": without, "stand_ins": stand_ins, "with": project}
    # Twice, in the order A B C then C B A: each variant's mean over the two cancels a
    # load that drifts linearly through the run.
    runs: dict[str, list[tuple[float, float]]] = {k: [] for k in variants}
    for order in (list(variants), list(variants)[::-1]):
        for key in order:
            runs[key].append(_frame_rate(variants[key], path.parent, frames))
    (fps_without, floor_without), (fps_stand, floor_stand), (fps_with, floor_with) = (
        (float(np.mean([r[0] for r in runs[k]])), float(np.mean([r[1] for r in runs[k]])))
        for k in variants)
    return {"fps_with_people": fps_with, "fps_without_people": fps_without,
            "ratio": fps_with / fps_without, "floor_ms_with_people": floor_with,
            "floor_ms_without_people": floor_without,
            "floor_ratio": floor_without / floor_with, "fps_stand_ins": fps_stand,
            "floor_ms_stand_ins": floor_stand, "ratio_to_stand_ins": fps_with / fps_stand,
            "load": _load()}


__all__ = ["antenna_edit_latency", "effect_variants", "if_synthesis_accuracy",
           "people_speed", "rigid_stand_ins", "run_benchmark", "sensor_variants", "thread_cpu",
           "with_effects", "without_kind"]
