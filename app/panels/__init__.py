"""Live panels: one module per pyqtgraph panel that draws a frame.

:mod:`~app.panels.base` holds :class:`~app.panels.base.LivePanel` (sensor choice, title,
the common drawing steps); each other module is one panel (ToF images, range profile,
range–Doppler, range–azimuth, RGB image, micro-Doppler spectrogram).

May import: ``simcore``, :mod:`app.frame_view`, :mod:`app.document`, :mod:`app.widgets` and
each other. Never :mod:`app.main_window`, :mod:`app.editors` or :mod:`app.view`.
"""
