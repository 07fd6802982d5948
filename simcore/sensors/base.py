"""What a sensor is to the frame engine: a :class:`Sensor` protocol and a registry.

A sensor kind is one package under ``simcore/sensors/`` that registers its class; the
engine makes one instance per configured sensor (:func:`active_sensors`: a project may
carry several sensors of a kind, on several rigs), each with its ``name``. The engine
asks it which render pass it needs (:meth:`Sensor.render_request`), renders that pass
from the snapshot at its capture time, and hands it a :class:`SensorContext`; the sensor
returns its output (anything with ``hdf5_items()``), stored in the frame under the
sensor's name. The sensor's configuration is ``project.sensor_config(name)``
(:func:`sensor_config`): the first rig's built-in ``tof``/``radar``/``rgb`` field or an
entry of a rig's ``sensors`` table. The models write their dataset items under their
kind's group; :func:`rename_items` moves them to the sensor's own.

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
from simcore.scene.layout import SensorSchema
from simcore.scene.model import Project, sensor_kind
from simcore.scene.snapshot import SceneSnapshot
from simcore.sensors.schema import declare

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
        The project (``project.sensor_config(sensor.name)`` is the sensor's configuration).
    snapshot : SceneSnapshot
        The snapshot at the sensor's capture time (the frame's time plus its trigger
        offset); its output carries ``snapshot.time_s``.
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
        on the sensor's post thread and returns a :class:`DeferredOutput` for
        :meth:`Sensor.simulate` to return: the sensor's chain is then free for the next
        frame (a pipeline stage). Each sensor has its own post thread, which runs its
        frames in order. None: no post thread (return ``rest()``).
    name : str
        The sensor's name (:attr:`config` is its configuration).
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
    name: str = ""

    @property
    def config(self) -> Any:
        """The configuration of the sensor being run (``project.sensor_config(name)``)."""
        return self.project.sensor_config(self.name)

    @property
    def time_s(self) -> float:
        """Capture time of the sensor in this frame (s)."""
        return float(self.snapshot.time_s)


class Sensor(Protocol):
    """A sensor plug-in: one instance per configured sensor, made by its kind's class.

    Attributes
    ----------
    name : str
        The sensor's name (key of its configuration in the project, of ``Frame.outputs``
        and its dataset group).
    kind : str
        Its model (``"tof"``, ``"radar"``, ``"rgb"``): the key of its class in the registry.
    band : str
        The material band it sees (:data:`simcore.scene.materials.BANDS`).
    rng_stream : int
        Its independent random stream (:func:`sensor_rng_stream`: the built-in sensors
        keep theirs, another sensor's is its rig's and its place in the rig's table), so
        changing one sensor leaves the others' noise untouched.
    on_worker : bool
        Whether the engine runs its shading and simulation on a worker thread of its own
        (beside the calling thread's rendering and the other sensors).
    """

    name: str
    kind: str
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


#: Random streams of the built-in sensors (bit-identical noise in today's projects).
BUILTIN_STREAMS = {"tof": 0, "radar": 1, "rgb": 2}


#: Random streams of the sensors in rigs' ``sensors`` tables start here, this many per rig.
TABLE_STREAMS, STREAMS_PER_RIG = 1_000, 1_000


def sensor_rng_stream(kind: str, name: str, rig_index: int = 0, slot: int = 0) -> int:
    """The random stream of sensor ``name`` of kind ``kind``.

    A built-in sensor (the first rig's ``tof``, ``radar``, ``rgb`` fields) keeps its
    historical stream. A sensor of a rig's ``sensors`` table gets one from where it sits:
    rig ``rig_index`` (0 = the first rig), entry ``slot`` of its table. So renaming a
    sensor changes nothing but its names (its noise stays bit for bit), and adding or
    removing a sensor leaves the streams of the other rigs' sensors and of the sensors
    before it untouched.
    """
    if name == kind and kind in BUILTIN_STREAMS:
        return BUILTIN_STREAMS[kind]
    return TABLE_STREAMS + STREAMS_PER_RIG * rig_index + slot


class SensorBase:
    """What every sensor class shares: its name, its stream and its configuration.

    A subclass sets ``kind``, ``band`` and ``on_worker``; ``SensorClass(name)`` is the
    sensor called ``name`` (default: the kind's built-in sensor).
    """

    kind: str = ""
    band: str = ""
    on_worker: bool = False
    #: The kind's outputs (its package's ``schema.SCHEMA``).
    schema: SensorSchema | None = None

    def __init__(self, name: str | None = None, rng_stream: int | None = None):
        self.name = self.kind if name is None else name
        self.rng_stream = (sensor_rng_stream(self.kind, self.name) if rng_stream is None
                           else rng_stream)

    def config(self, project: Project) -> Any:
        """The sensor's configuration in ``project`` (ValueError when it is not there)."""
        cfg = sensor_config(project, self.name)
        if cfg is None:
            raise ValueError(f"the project has no sensor {self.name!r}")
        return cfg

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"


#: Sensor classes by kind: ``_REGISTRY[kind](name, rng_stream)`` is the sensor ``name``.
_REGISTRY: dict[str, Callable[..., Sensor]] = {}


def register(sensor: Sensor | type) -> Any:
    """Add a sensor kind: its class (or an instance of it, whose kind is its ``kind``)."""
    cls = sensor if isinstance(sensor, type) else type(sensor)
    kind = getattr(cls, "kind", "") or getattr(sensor, "name", "")
    if not kind:
        raise ValueError(f"{cls.__name__} has no kind")
    if kind in _REGISTRY:
        raise ValueError(f"a sensor kind {kind!r} is registered already")
    schema = getattr(cls, "schema", None)
    if schema is None or schema.kind != kind:
        raise ValueError(f"{cls.__name__} declares no output schema of kind {kind!r}")
    declare(schema)
    _REGISTRY[kind] = cls
    return sensor


def registered() -> dict[str, Sensor]:
    """The built-in sensor of every registered kind, by kind."""
    return {kind: factory(kind) for kind, factory in _REGISTRY.items()}


def sensor_config(project: Project, name: str) -> Any:
    """The configuration of sensor ``name`` on any of the project's rigs (None when absent)."""
    return project.sensor_configs().get(name)


def rename_items(items: dict[str, T], kind: str, name: str) -> dict[str, T]:
    """Dataset items of a sensor of ``kind``, moved from ``/<kind>/...`` to ``/<name>/...``.

    The sensor models write their items under their kind's group; a sensor named
    otherwise gets them under its own. Items outside that group stay where they are; a
    built-in sensor (``name == kind``) keeps every path.
    """
    if name == kind:
        return items
    old, new = f"/{kind}/", f"/{name}/"
    return {(new + path[len(old):] if path.startswith(old) else path): value
            for path, value in items.items()}


def active_sensors(project: Project) -> list[Sensor]:
    """One sensor per configured sensor of every rig, in the project's order."""
    out: list[Sensor] = []
    for rig_index, rig in enumerate(project.all_rigs()):
        table = list(rig.sensors)
        for name, cfg in rig.sensor_configs().items():
            kind = sensor_kind(cfg)
            if kind not in _REGISTRY:
                raise ValueError(f"sensor {name!r}: kind {kind!r} has no registered sensor "
                                 "model")
            stream = sensor_rng_stream(kind, name, rig_index,
                                       table.index(name) if name in table else 0)
            out.append(_REGISTRY[kind](name, stream))
    return out


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
