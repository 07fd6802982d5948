"""What the radar physics reads of a frame: its slice of the project and snapshot.

The radar's physics (scatterers, surfaces, multipath) takes this slice, its own
:class:`~simcore.scene.radar_config.RadarConfig` and its render — never the project. The
slice names the radar's own state (its optical frame and its rig's body frame), so any radar
of any rig runs the same functions: nothing in them reads a built-in ``"radar"``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from simcore.scene.materials import DualBandMaterial
from simcore.scene.model import Project, SceneObject
from simcore.scene.motion import RigidState
from simcore.scene.project_io import material_table
from simcore.scene.snapshot import SceneSnapshot, SensorState


@dataclass(frozen=True)
class RadarScene:
    """One radar's view of one frame: the objects, their materials and states, its pose.

    Attributes
    ----------
    objects : sequence of SceneObject
        The scene's objects (geometry, material name, id), in snapshot order.
    materials : mapping of str to DualBandMaterial
        The material table (library and the project's own materials).
    snapshot : SceneSnapshot
        The frame's snapshot: ``snapshot.objects[i]`` is the state of ``objects[i]``.
    radar : SensorState
        This radar's optical frame (x right, y down, z boresight) and velocity.
    rig : RigidState
        The body frame of the rig that carries it.
    seed : int
        Default speckle realisation (the project's seed).
    """

    objects: Sequence[SceneObject]
    materials: Mapping[str, DualBandMaterial]
    snapshot: SceneSnapshot
    radar: SensorState
    rig: RigidState
    seed: int = 0

    def __post_init__(self) -> None:
        if len(self.snapshot.objects) != len(self.objects):
            raise ValueError("snapshot and scene have different numbers of objects")

    @property
    def time_s(self) -> float:
        """The frame's timestamp (s)."""
        return float(self.snapshot.time_s)

    @classmethod
    def from_project(cls, project: Project, snapshot: SceneSnapshot, name: str = "radar"
                     ) -> RadarScene:
        """The slice radar ``name`` reads of ``project`` at ``snapshot`` (the adapter).

        Raises
        ------
        KeyError
            When the snapshot has no sensor ``name``.
        """
        return cls(objects=project.objects, materials=material_table(project, copy=False),
                   snapshot=snapshot, radar=snapshot.sensor(name), rig=snapshot.rig_of(name),
                   seed=project.seed)


__all__ = ["RadarScene"]
