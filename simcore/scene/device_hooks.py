"""Where the sensor configurations meet the device library, without importing it.

A radar or ToF configuration that names a device preset (``"preset": "ti_iwr6843isk"``)
takes the device's values for the fields it leaves out and must stay within the device's
limits. The device library (:mod:`simcore.scene.devices`) builds configurations, so the
configuration classes cannot import it: it installs its functions here when it is
imported (``simcore.scene`` imports it), and the classes call them through this module.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

_defaults: Callable[[str, str], dict[str, Any] | None] | None = None
_limits: Callable[[Any], list[str]] | None = None
_cameras: Mapping[str, Callable[[], Any]] = {}


def install(*, defaults: Callable[[str, str], dict[str, Any] | None],
            limits: Callable[[Any], list[str]],
            cameras: Mapping[str, Callable[[], Any]]) -> None:
    """Install the device library's preset defaults, limit check and camera presets."""
    global _defaults, _limits, _cameras
    _defaults, _limits, _cameras = defaults, limits, cameras


def preset_defaults(kind: str, name: str) -> dict[str, Any] | None:
    """Field values of device ``name`` of ``kind`` (None: no such device, or no library)."""
    return None if _defaults is None else _defaults(kind, name)


def limit_problems(config: Any) -> list[str]:
    """Where ``config`` leaves its device preset's limits (empty: none, or no library)."""
    return [] if _limits is None else _limits(config)


def camera_presets() -> Mapping[str, Callable[[], Any]]:
    """The device library's ToF camera presets, by name."""
    return _cameras
