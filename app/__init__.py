"""Desktop GUI of tofradar (PyQt6 + pyvistaqt + pyqtgraph).

Grouped by role: :mod:`app.document` (the evented document and its edits, no widget),
:mod:`app.editors`, :mod:`app.panels` (one module per live panel), :mod:`app.view` (the 3D
view), :mod:`app.dialogs` and :mod:`app.widgets`; :mod:`app.main_window` is the one module
that assembles them. ``app`` may import ``simcore``; ``simcore`` never imports ``app``.

The GUI is a view and an editor of the same :class:`simcore.scene.Project` the CLI uses.
Every edit goes through :class:`app.document.document.ProjectDocument` (an undo command that
replaces the project by a validated copy and emits one ``projectChanged`` signal); views
listen to the document and hold no simulation state of their own. Frames are computed in
a separate simulation process (:mod:`app.sim_process`) driven by
:class:`app.simulation.SimulationController`.
"""
