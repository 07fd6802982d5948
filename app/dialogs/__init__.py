"""Dialogs and menus that open beside the window.

Export, scene and mesh import, scenario export, recording comparison and Help.

May import: ``simcore``, :mod:`app.frame_view`, :mod:`app.document`, :mod:`app.widgets`
and each other. Never :mod:`app.main_window`, :mod:`app.editors`, :mod:`app.panels` or
:mod:`app.view`.
"""
