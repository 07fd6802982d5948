"""File ▸ Export scenario spec…: a randomized family of the current scene (issue 32).

The spec (``docs/scenarios.md``) refers to the saved project file and varies what can move
without breaking the scene (:func:`simcore.scenarios.spec_from_project`);
``tofradar generate SPEC --count N --out DIR`` then writes the family's projects, which
the GUI opens like any project.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from PyQt6.QtGui import QAction
from PyQt6.QtWidgets import QFileDialog, QMenu


def export_scenario_spec(window: Any, target: str | Path | None = None) -> Path | None:
    """Save the project if needed, ask for a file name, write the spec; its path or None."""
    from simcore.scenarios import ScenarioError, export_spec

    doc = window.document
    if (doc.path is None or doc.is_dirty) and not window.save():
        return None                      # a spec refers to the saved project file
    if target is None:
        start = doc.path.with_name(f"{doc.path.stem}_family.json")
        chosen, _ = QFileDialog.getSaveFileName(window, "Export scenario spec", str(start),
                                                "Scenario specs (*.json)")
        if not chosen:
            return None
        target = chosen
    target = Path(target)
    try:
        spec = export_spec(doc.path, target)
    except (OSError, ValueError, ScenarioError) as exc:
        window.show_status_error(f"Cannot export the scenario spec: {exc}")
        return None
    window.statusBar().showMessage(
        f"Wrote {target.name} ({len(spec.vary)} varied fields); make projects with "
        f"'tofradar generate {target.name} --count N --out DIR'", 10000)
    return target


def add_export_spec_action(window: Any, menu: QMenu) -> QAction:
    """File menu entry "Export scenario spec…"."""
    action = QAction("Export &scenario spec…", window)
    action.setToolTip("Write a scenario spec that varies the rig and the free-standing "
                      "objects of this scene, for 'tofradar generate'")
    action.triggered.connect(lambda: export_scenario_spec(window))
    menu.addAction(action)
    return action


__all__ = ["add_export_spec_action", "export_scenario_spec"]
