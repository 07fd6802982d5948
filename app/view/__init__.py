"""The 3D view: the viewport, its offscreen canvas and the scene's geometry for drawing.

May import: ``simcore``, :mod:`app.frame_view`, :mod:`app.document`, :mod:`app.widgets`
and each other. Never :mod:`app.main_window`, :mod:`app.editors` or :mod:`app.panels`.
"""
