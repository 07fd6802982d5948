"""The layout of a dataset: what each group holds, declared once.

The datasets of a run are the outputs of its sensors (each sensor kind declares its own in
its package: :mod:`simcore.sensors.schema`) plus the groups every run writes beside them:
``/meta``, ``/time``, ``/poses``, the objects' and people's truth, a scene run's
``/scenes``. This module holds the declaration types both use (:class:`Output`,
:class:`Preview`, :class:`SensorSchema`) and the common groups, and derives from them the
names a sensor or rig may not take (:func:`reserved_names`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

#: A preview figure's physical frame: (extent (left, right, bottom, top), x label, y label,
#: flip rows) from the sensor's configuration and its static datasets (by output name).
PreviewFrame = tuple[tuple[float, float, float, float], str, str, bool]
AxesOf = Callable[[Any, Mapping[str, NDArray[np.generic]]], PreviewFrame | None]


@dataclass(frozen=True)
class Preview:
    """How an output is drawn as a labelled PNG figure (``--preview``) and in the GUI.

    Attributes
    ----------
    title : str
        What the figure shows (``"range–Doppler"``); the sensor's name is put before it.
    label : str
        The colour bar's label, with its unit (``"power (dB)"``).
    cmap : str
        Matplotlib colour map.
    mask : str or None
        Output (boolean, same shape) whose False pixels are drawn grey (invalid depth).
    axes : callable or None
        ``axes(config, statics)`` → the figure's physical extent and axis labels (statics:
        the sensor's static datasets by output name), or None for pixel/bin axes.
    """

    title: str
    label: str
    cmap: str = "viridis"
    mask: str | None = None
    axes: AxesOf | None = None


@dataclass(frozen=True)
class Output:
    """One dataset a sensor kind writes under its sensor's group.

    Attributes
    ----------
    name : str
        Path inside the group (``"depth"``, ``"spectrogram/power"``).
    dims : tuple of str
        Dimension names, without the leading ``frame`` of per-frame outputs. A sensor not
        named after its kind gets its name before each dimension that is not common
        (:data:`COMMON_DIMS`): ``front_range``.
    unit : str
        SI unit (``"1"`` dimensionless, ``"dB"``, ``"DN"``...).
    dtype : str
        NumPy dtype name (``"float32"``; ``"complex64|float32"`` where the configuration
        chooses; ``"record"`` for a table).
    per_frame : bool
        One value per frame (leading frame axis) or one per run.
    nan : bool
        NaN is a legal value (no surface, no cell); otherwise every value must be finite
        where :attr:`finite` says so.
    finite : bool
        Raw data whose every value the runner checks to be finite before writing.
    coord : str or None
        The coordinate this (static, 1-D) output becomes in ``open_dataset``.
    optional : bool
        Written only when the scene or configuration calls for it (people, interference).
    product : bool
        Added after a run by ``tofradar products`` rather than by the sensor.
    preview : Preview or None
        How it is previewed.
    topic : str or None
        Foxglove / MCAP topic suffix (``/<sensor>/<topic>``) that carries it.
    message : str or None
        ROS 2 message type of that topic.
    description : str
        One line for docs/dataset.md and tooltips.
    """

    name: str
    dims: tuple[str, ...]
    unit: str
    dtype: str
    per_frame: bool = True
    nan: bool = False
    finite: bool = False
    coord: str | None = None
    optional: bool = False
    product: bool = False
    preview: Preview | None = None
    topic: str | None = None
    message: str | None = None
    description: str = ""


#: Dimensions that keep their name under a named sensor's group: they carry label
#: coordinates or mean the same for every sensor.
COMMON_DIMS = frozenset({"xyz", "corner", "color", "axis", "pose_row", "pose_col", "object",
                         "segment", "person", "frame"})


@dataclass(frozen=True)
class SensorSchema:
    """Every output of one sensor kind.

    Attributes
    ----------
    kind : str
        The sensor kind (``"tof"``, ``"radar"``, ``"rgb"``).
    outputs : tuple of Output
        Its datasets, in the order they are documented.
    tables : tuple of str
        Outputs that are row tables over all frames (the radar's detections).
    truth : tuple of Output
        Per-object truth the kind adds under ``/objects/<sensor>/`` (the built-in sensor's
        under ``/objects/<kind>_<name>``, as datasets always had it).
    derived_topics : dict of str to str
        MCAP / live-stream topics made from several outputs (a camera's ``camera_info``
        and ``points``): topic suffix → ROS 2 message type.
    """

    kind: str
    outputs: tuple[Output, ...]
    tables: tuple[str, ...] = ()
    truth: tuple[Output, ...] = ()
    derived_topics: Mapping[str, str] = field(default_factory=dict)
    _by_name: dict[str, Output] = field(default_factory=dict, init=False, repr=False,
                                        compare=False)

    def __post_init__(self) -> None:
        for out in (*self.outputs, *self.truth):
            if out.name in self._by_name and out not in self.truth:
                raise ValueError(f"sensor kind {self.kind!r}: output {out.name!r} twice")
        self._by_name.update({o.name: o for o in self.outputs})

    def output(self, name: str) -> Output:
        """The output called ``name`` (KeyError naming the outputs there are)."""
        try:
            return self._by_name[name]
        except KeyError:
            raise KeyError(f"sensor kind {self.kind!r} has no output {name!r} (outputs: "
                           f"{', '.join(self._by_name)})") from None

    def find(self, name: str) -> Output | None:
        """The output called ``name``, None when the kind has none."""
        return self._by_name.get(name)

    def dataset_path(self, sensor: str, output: str) -> str:
        """HDF5/Zarr path of output ``output`` of sensor ``sensor``."""
        return f"/{sensor}/{output}"

    def dims(self, sensor: str, output: Output) -> tuple[str, ...]:
        """Dimension names of ``output`` for sensor ``sensor`` (prefixed unless built-in)."""
        if sensor == self.kind:
            return output.dims
        return tuple(d if d in COMMON_DIMS else f"{sensor}_{d}" for d in output.dims)

    def coord(self, sensor: str, output: Output) -> str | None:
        """Coordinate name of ``output`` for sensor ``sensor`` (None when it is none)."""
        if output.coord is None or sensor == self.kind:
            return output.coord
        return f"{sensor}_{output.coord}"

    def topics(self) -> dict[str, str]:
        """Every topic suffix of a sensor of this kind → its ROS 2 message type."""
        own = {o.topic: o.message for o in self.outputs if o.topic and o.message}
        return {**own, **self.derived_topics}

    def previews(self) -> Iterator[Output]:
        """The outputs that have a preview figure."""
        return (o for o in self.outputs if o.preview is not None)



#: Top-level groups and datasets every run may write beside its sensors' groups.
LAYOUT_GROUPS = ("meta", "time", "poses", "objects", "people", "scenes", "scene_index",
                 "rig", "rigs", "labels", "frame", "frames", "checksum", "products", "world")

#: Per-frame datasets under ``/objects`` (dims without the frame axis). A radar's truth
#: goes beside them: ``/objects/radar_*`` for the built-in radar, ``/objects/<name>/*``
#: for another.
OBJECT_DATASETS: dict[str, tuple[str, ...]] = {
    "names": ("object",),
    "ids": ("object",),
    "velocity": ("object", "xyz"),
    "angular_velocity": ("object", "xyz"),
    "aabb": ("object", "corner", "xyz"),
    "obb_center": ("object", "xyz"),
    "obb_rotation": ("object", "xyz", "axis"),
    "obb_size": ("object", "axis"),
    "reference_point": ("object", "xyz"),
    "radar_range": ("object",),
    "radar_radial_velocity": ("object",),
    "radar_azimuth": ("object",),
    "radar_elevation": ("object",),
}

#: Datasets under ``/people`` (docs/people.md); ``segments/<radar>/*`` per named radar.
PEOPLE_DATASETS: dict[str, tuple[str, ...]] = {
    "names": ("person",),
    "object_ids": ("person",),
    "body_part_names": ("body_part",),
    "segments/names": ("segment",),
    "segments/person": ("segment",),
    "segments/body_part": ("segment",),
    "segments/pose": ("segment", "pose_row", "pose_col"),
    "segments/velocity": ("segment", "xyz"),
    "segments/angular_velocity": ("segment", "xyz"),
    "segments/radar_range": ("segment",),
    "segments/radar_radial_velocity": ("segment",),
    "segments/radar_azimuth": ("segment",),
    "segments/radar_elevation": ("segment",),
    "breathing_displacement": ("person",),
    "heartbeat_displacement": ("person",),
    "breathing_rate": ("person",),
    "heart_rate": ("person",),
    "gait_phase": ("person",),
}

#: The other common datasets: poses, the frame checksums.
COMMON_DATASETS: dict[str, tuple[str, ...]] = {
    "/poses/rig": ("pose_row", "pose_col"),
    "/poses/objects": ("object", "pose_row", "pose_col"),
    "/meta/frame_sha256": (),
}

#: Coordinates of the common datasets: path → coordinate name.
COMMON_COORDS = {
    "/objects/names": "object_name",
    "/poses/rig_names": "rig_name",
    "/objects/ids": "object_id",
    "/people/names": "person_name",
    "/people/segments/names": "segment_name",
    "/people/body_part_names": "body_part_name",
}


def reserved_names() -> frozenset[str]:
    """Names a sensor or rig may not take, derived from the layout.

    The top-level groups every run may write (:data:`LAYOUT_GROUPS`), and every dataset
    name under ``/objects`` and ``/people`` and its first path part: a radar's truth is
    written at ``/objects/<name>/...`` and ``/people/segments/<name>/...``, so a radar
    called ``velocity`` would collide with ``/objects/velocity``, one called ``segments``
    with ``/people/segments``.
    """
    names = set(LAYOUT_GROUPS)
    for table in (OBJECT_DATASETS, PEOPLE_DATASETS):
        for path in table:
            names.add(path.split("/")[0])
            names.add(path.rsplit("/", 1)[-1])
    names.update(p.strip("/").split("/")[-1] for p in COMMON_DATASETS)
    return frozenset(names)


def reserved_reason(name: str) -> str | None:
    """Why ``name`` is reserved (the dataset or group it would collide with), or None."""
    if name in LAYOUT_GROUPS:
        return f"the top-level dataset group /{name}"
    for group, table in (("objects", OBJECT_DATASETS), ("people", PEOPLE_DATASETS)):
        for path in table:
            parts = path.split("/")
            if name in (parts[0], parts[-1]):
                return f"the dataset /{group}/{path}"
    for path in COMMON_DATASETS:
        if path.strip("/").split("/")[-1] == name:
            return f"the dataset {path}"
    return None
