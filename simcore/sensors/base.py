"""What a sensor is to the frame engine: a :class:`Sensor` protocol and a registry.

A sensor is one package under ``simcore/sensors/`` that registers one :class:`Sensor`
object. The engine asks it which render pass it needs (:meth:`Sensor.render_request`),
renders that pass from the frame's snapshot, and hands it a :class:`SensorContext`; the
sensor returns its output (anything with ``hdf5_items()``), stored in the frame under the
sensor's name. The sensor's configuration is the rig field of the same name
(``project.rig.<name>``), ``None`` when an optional sensor is off.

The physics inside a sensor are plain functions of (inputs, config, rng); a sensor runs
them through :meth:`SensorContext.stage`, which lets the engine's one stage cache skip a
step whose inputs and configuration are unchanged (an antenna edit re-runs only what
follows the scatterers).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.render.renderer import RenderRequest
from simcore.scene.base import Model
from simcore.scene.model import Project
from simcore.scene.snapshot import SceneSnapshot

#: HDF5 items of a frame: dataset path → (array without the frame axis, unit).
H5Items = dict[str, tuple[NDArray[np.generic], str]]

T = TypeVar("T")


@runtime_checkable
class SensorOutput(Protocol):
    """One frame of a sensor's output."""

    def hdf5_items(self) -> H5Items:
        """Per-frame datasets: HDF5 path → (array without the frame axis, unit)."""
        ...


class StageRunner(Protocol):
    """Runs a named step of a sensor, or returns its cached result (the engine's cache)."""

    def __call__(self, name: str, fn: Callable[[], T], *, reads: Hashable,
                 inputs: Sequence[object] = ()) -> T:
        """Result of ``fn()`` for configuration ``reads`` and ``inputs`` (by identity)."""
        ...


@dataclass(frozen=True)
class Background:
    """A render of the still objects alone that a frame's render differs from at ``changed``.

    Given to a sensor by the engine's still-background accelerator (rig and some objects
    still): every pixel outside ``changed`` holds exactly the background's values.

    Attributes
    ----------
    buffers : RenderBuffers
        The still objects' render (same pass, same sensor pose).
    changed : ndarray of intp, shape (K,)
        Flat pixel indices where the frame's render differs from ``buffers`` (or its
        see-through pass from ``see_through``).
    see_through : RenderBuffers or None
        The still objects' see-through pass (:attr:`SensorContext.see_through`), when the
        sensor has one.
    """

    buffers: RenderBuffers
    changed: NDArray[np.intp]
    see_through: RenderBuffers | None = None


class DeferredOutput:
    """A sensor's output whose last steps still run on the engine's post thread.

    Returned by :attr:`SensorContext.defer`; the engine waits for it before the frame is
    complete (:meth:`result`), so callers of the engine never see one.
    """

    def __init__(self, future: Future[SensorOutput]):
        self.future = future

    def result(self) -> SensorOutput:
        """The output (waits for the post thread; raises what the steps raised)."""
        return self.future.result()

    def hdf5_items(self) -> H5Items:
        """The output's items (waits for it)."""
        return self.result().hdf5_items()


@dataclass(frozen=True)
class SensorContext:
    """Everything a sensor gets for one frame.

    Attributes
    ----------
    project : Project
        The project (its ``rig.<sensor name>`` is the sensor's configuration).
    snapshot : SceneSnapshot
        The frame's snapshot; every output of the frame carries ``snapshot.time_s``.
    index : int
        Frame index.
    seed : int
        The run's seed.
    buffers : RenderBuffers
        The sensor's render pass. For a scene where nothing moved since an earlier frame
        it is that frame's render (same values; use ``time_s``, not ``buffers.time_s``).
    sample_buffers : tuple of RenderBuffers
        Extra renders at ``time_s + offset`` for the offsets the sensor asked for
        (:meth:`Sensor.sample_offsets_s`), in that order.
    rng : numpy.random.Generator
        The sensor's own random stream for this frame (seed, index, ``rng_stream``).
    stage : StageRunner
        Runs or re-uses a named step (see :class:`StageRunner`).
    background : Background or None
        Still-background information for this sensor's render, when the accelerator applies.
    see_through : RenderBuffers or None
        The same pass with the objects of :meth:`Sensor.see_through` hidden (what lies
        behind the band's partially transparent objects); None when it hides nothing.
    defer : callable or None
        ``defer(rest)`` runs ``rest()`` — the frame's last steps, returning the output —
        on the engine's post thread and returns a :class:`DeferredOutput` for
        :meth:`Sensor.simulate` to return: the sensor's chain is then free for the next
        frame (a pipeline stage). The post thread runs frames in order. None: no post
        thread (return ``rest()``).
    """

    project: Project
    snapshot: SceneSnapshot
    index: int
    seed: int
    buffers: RenderBuffers
    sample_buffers: tuple[RenderBuffers, ...]
    rng: np.random.Generator
    stage: StageRunner
    background: Background | None = None
    see_through: RenderBuffers | None = None
    defer: Callable[[Callable[[], SensorOutput]], DeferredOutput] | None = None

    @property
    def time_s(self) -> float:
        """Timestamp of the frame (s)."""
        return float(self.snapshot.time_s)


class Sensor(Protocol):
    """A sensor plug-in: one object per sensor kind, registered with :func:`register`.

    Attributes
    ----------
    name : str
        Rig field of its configuration, key of ``Frame.outputs`` and its HDF5 group.
    band : str
        The material band it sees (:data:`simcore.scene.materials.BANDS`).
    rng_stream : int
        Its independent random stream (unique per sensor; changing one sensor leaves the
        others' noise untouched).
    on_worker : bool
        Whether the engine runs its simulation on the worker thread (beside the
        calling thread's rendering and the other sensors).
    """

    name: str
    band: str
    rng_stream: int
    on_worker: bool

    def render_request(self, project: Project) -> RenderRequest:
        """The render pass the sensor needs."""
        ...

    def sample_offsets_s(self, project: Project) -> tuple[float, ...]:
        """Times after the frame's (s) at which it needs extra renders of the same pass."""
        ...

    def see_through(self, project: Project) -> tuple[bool, ...] | None:
        """Objects to hide in a second pass that sees through them (partial transmission).

        None (or no True) when the band has no partially transparent object; otherwise
        the engine renders the pass again without them (:attr:`SensorContext.see_through`).
        A sensor class without this method gets no second pass.
        """
        ...

    def simulate(self, ctx: SensorContext) -> SensorOutput:
        """The sensor's output for one frame."""
        ...

    def static_items(self, project: Project) -> H5Items:
        """Run-constant datasets (axes, calibration) of the sensor."""
        ...


_REGISTRY: dict[str, Sensor] = {}


def register(sensor: Sensor) -> Sensor:
    """Add a sensor kind to the registry (its ``name`` and ``rng_stream`` must be new)."""
    if sensor.name in _REGISTRY:
        raise ValueError(f"a sensor named {sensor.name!r} is registered already")
    streams = {s.rng_stream: s.name for s in _REGISTRY.values()}
    if sensor.rng_stream in streams:
        raise ValueError(f"sensor {sensor.name!r}: random stream {sensor.rng_stream} is "
                         f"{streams[sensor.rng_stream]!r}'s")
    _REGISTRY[sensor.name] = sensor
    return sensor


def registered() -> dict[str, Sensor]:
    """Every registered sensor kind, by name."""
    return dict(_REGISTRY)


def sensor_config(project: Project, name: str) -> Any:
    """The configuration of sensor ``name`` on the project's rig (None when it is off)."""
    return getattr(project.rig, name, None)


def active_sensors(project: Project) -> list[Sensor]:
    """The registered sensors that the project's rig carries, in registration order."""
    configs = project.rig.sensor_configs()
    unknown = sorted(set(configs) - set(_REGISTRY))
    if unknown:
        raise ValueError(f"rig sensor {unknown[0]!r} has no registered sensor model")
    return [s for name, s in _REGISTRY.items() if name in configs]


def frame_rng(seed: int, index: int, stream: int) -> np.random.Generator:
    """Random generator of one sensor in frame ``index``, whatever order frames run in."""
    return np.random.default_rng([seed, index, stream])


def config_key(*models: Model | None) -> str:
    """A configuration slice as text, for :meth:`SensorContext.stage`'s ``reads``."""
    return "\n".join("null" if m is None else m.model_dump_json() + _private_key(m)
                     for m in models)


def _private_key(model: Model) -> str:
    """A radar frame copy's chirp jitter, which its JSON does not hold.

    (:func:`simcore.sensors.radar.transmit.frame_transmit_config`.)
    """
    delays = getattr(model, "_chirp_delays_s", None)
    return "" if delays is None else "\n" + delays.tobytes().hex()
