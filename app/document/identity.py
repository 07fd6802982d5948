"""Which sensor of a project is "the same" sensor after an edit.

A panel that shows sensor ``radar_b`` keeps showing it when the sensor is renamed (and when
the rename is undone). The document (:mod:`app.document.document`) follows its current
sensors with this on every project change, and the sensor edits
(:mod:`app.document.sensors`) edit documents: so this part, which needs neither, sits below
both and keeps them out of an import circle.
"""

from __future__ import annotations

from typing import Any

from simcore.scene import Project
from simcore.scene.model import named_sensor


def follow_sensor(before: Project | None, after: Project, name: str, kind: str) -> str | None:
    """The name in ``after`` of the sensor called ``name`` in ``before``.

    ``name`` itself while ``after`` has a sensor of ``kind`` by that name; after a rename
    (the sensor gone, one new sensor with the same configuration on the same rig), the new
    name; else the first sensor of ``kind`` (None when ``after`` has none).
    """
    now = after.sensors_of_kind(kind)
    if name in now:
        return name
    if before is not None:
        old = before.sensor_configs().get(name)
        if old is not None:
            was = before.sensor_configs()
            new = [n for n, c in now.items() if n not in was and _same_sensor(c, old)]
            if len(new) == 1:
                return new[0]
    return next(iter(now), None)


def _same_sensor(a: Any, b: Any) -> bool:
    return bool(named_sensor(a).model_dump() == named_sensor(b).model_dump())
