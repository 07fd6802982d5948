"""Editors: the widgets that change the project through the document.

Scene, sensor, rig, material, antenna (board, table, array analysis), person and timeline
editors, the one path of a field edit (:mod:`~app.editors.field_editors`) and the ToF
effects switches.

May import: ``simcore``, :mod:`app.document`, :mod:`app.widgets`, :mod:`app.dialogs` and
each other. Never :mod:`app.main_window` (it assembles them), :mod:`app.panels` or
:mod:`app.view`.
"""
