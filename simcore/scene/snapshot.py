"""Scene snapshot: the state of every object and sensor at one instant.

A snapshot is the single source of truth for one frame: every sensor output of a frame is
computed from the snapshot taken at the frame's timestamp.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from simcore.scene.model import Project
from simcore.scene.motion import RigidState, make_transform, rigid_state

#: Sensor body frame (x forward, y left, z up) → optical frame (x right, y down, z forward).
#: Columns are the optical axes expressed in body coordinates.
BODY_FROM_OPTICAL = np.array(
    [
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
    ]
)


@dataclass(frozen=True)
class SensorState:
    """World pose of a sensor's optical frame and the velocity of its origin.

    Attributes
    ----------
    transform : ndarray, shape (4, 4)
        Optical frame (x right, y down, z forward) → world.
    velocity_mps : ndarray, shape (3,)
        World velocity of the sensor's origin (m/s).
    angular_velocity_rps : ndarray, shape (3,)
        World angular velocity of the rig (rad/s).
    """

    transform: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    angular_velocity_rps: NDArray[np.float64]

    @property
    def position(self) -> NDArray[np.float64]:
        """World position of the sensor (m)."""
        return self.transform[:3, 3]

    @property
    def rotation(self) -> NDArray[np.float64]:
        """Rotation optical → world, shape (3, 3)."""
        return self.transform[:3, :3]


@dataclass(frozen=True)
class SceneSnapshot:
    """State of the whole scene at ``time_s``.

    Attributes
    ----------
    time_s : float
        Timestamp shared by every sensor output of the frame.
    objects : list of RigidState
        One state per project object, in project order.
    rig : RigidState
        The first rig's body frame (``project.rig``).
    sensors : dict of str to SensorState
        Optical-frame pose of every sensor of every rig, by sensor name.
    rigs : dict of str to RigidState
        Body frame of every rig, by rig name (the first rig's is :attr:`rig`).
    sensor_rigs : dict of str to str
        Name of the rig that carries each sensor.
    """

    time_s: float
    objects: list[RigidState]
    rig: RigidState
    sensors: dict[str, SensorState]
    rigs: dict[str, RigidState] = field(default_factory=dict)
    sensor_rigs: dict[str, str] = field(default_factory=dict)

    def sensor(self, name: str) -> SensorState:
        """The state of sensor ``name`` (KeyError naming the sensors there are)."""
        try:
            return self.sensors[name]
        except KeyError:
            raise KeyError(f"no sensor {name!r} on the rig (sensors: "
                           f"{', '.join(self.sensors)})") from None

    def rig_of(self, sensor: str) -> RigidState:
        """The body frame of the rig that carries sensor ``sensor`` (the first rig's if unknown)."""
        rig = self.sensor_rigs.get(sensor)
        return self.rig if rig is None else self.rigs[rig]

    def object_transforms(self) -> NDArray[np.float64]:
        """World transforms of all objects, shape (objects, 4, 4) (a new array each call).

        Stacked once per snapshot (a frame asks for them a few dozen times: with an asset
        of many nodes, stacking them each time cost milliseconds); the states must not be
        changed after the snapshot is taken.
        """
        stacked = self.__dict__.get("_transforms")
        if stacked is None:
            stacked = (np.stack([s.transform for s in self.objects]) if self.objects
                       else np.zeros((0, 4, 4)))
            self.__dict__["_transforms"] = stacked       # frozen dataclass: a private cache
        return stacked.copy()


def _sensor_state(rig: RigidState, mount: NDArray[np.float64]) -> SensorState:
    optical = make_transform(BODY_FROM_OPTICAL, np.zeros(3))
    transform = rig.transform @ mount @ optical
    position = transform[:3, 3]
    return SensorState(
        transform=transform,
        velocity_mps=rig.point_velocity(position),
        angular_velocity_rps=rig.angular_velocity_rps,
    )


#: What a person's segment holds until :meth:`PeopleExpansion.apply` puts its state.
_STILL_PLACEHOLDER = RigidState(np.eye(4), np.zeros(3), np.zeros(3))


def take_snapshot(project: Project, t: float) -> SceneSnapshot:
    """Evaluate every object's, rig's and sensor's pose and velocity at time ``t`` (s)."""
    rigs = {r.name: rigid_state(r.pose, r.motion, t) for r in project.all_rigs()}
    sensors: dict[str, SensorState] = {}
    owners: dict[str, str] = {}
    for r in project.all_rigs():
        for name, cfg in r.sensor_configs().items():
            sensors[name] = _sensor_state(rigs[r.name], cfg.pose_on_rig.matrix())  # type: ignore[attr-defined]
            owners[name] = r.name
    people = getattr(project, "_people", None)
    if people is None:
        objects = [rigid_state(o.pose, o.motion, t) for o in project.objects]
    else:  # segments of people (simcore.scene.people.expand): their states from the body
        still = _STILL_PLACEHOLDER
        objects = [rigid_state(o.pose, o.motion, t) if part < 0 else still
                   for o, part in zip(project.objects, people.body_part, strict=True)]
        people.apply(objects, float(t))
    return SceneSnapshot(
        time_s=float(t),
        objects=objects,
        rig=rigs[project.rig.name],
        sensors=sensors,
        rigs=rigs,
        sensor_rigs=owners,
    )
