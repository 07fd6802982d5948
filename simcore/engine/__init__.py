"""Frame scheduling and the one stage cache; optional accelerators (still background)."""

from simcore.engine.cache import StageCache
from simcore.engine.engine import FrameEngine, FrameResult, StillBackground

__all__ = ["FrameEngine", "FrameResult", "StageCache", "StillBackground"]
