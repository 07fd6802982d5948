"""Old import path of :mod:`simcore.runs.runner`, kept only for ``app/export.py``.

Remove this module once ``app/export.py`` imports ``simcore.runs.runner`` (the GUI is
being regrouped in parallel; its import moves there).
"""

from simcore.runs.runner import frame_count, run_dataset

__all__ = ["frame_count", "run_dataset"]
