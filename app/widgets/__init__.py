"""Small shared widgets.

Number boxes with units and field errors, the wrapping row, the time controls.

May import: ``simcore``, :mod:`app.document` and each other. Never the GUI's larger parts
(:mod:`app.main_window`, :mod:`app.editors`, :mod:`app.panels`, :mod:`app.view`,
:mod:`app.dialogs`).
"""
