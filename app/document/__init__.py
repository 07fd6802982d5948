"""The evented project document and its edits: the GUI's model, with no widget in it.

Holds :class:`~app.document.document.ProjectDocument` (the project, its file, selection and
undo stack; every edit is one validated undo step), the sensor and rig edits
(:mod:`~app.document.sensors`), scene edits (:mod:`~app.document.scene_edits`), which sensor
follows which across an edit (:mod:`~app.document.identity`) and the wording of refused
edits (:mod:`~app.document.validation`).

May import: ``simcore``, ``PyQt6.QtCore``/``PyQt6.QtGui`` (signals, undo stack) and its
own modules. Never ``PyQt6.QtWidgets``, ``pyqtgraph``, ``pyvistaqt`` or any other package
of ``app`` (checked by the import-linter contracts in ``pyproject.toml``).
"""
