"""The core must stay free of Qt: importing it (and running a frame) pulls in no GUI."""

from __future__ import annotations

import subprocess
import sys

GUI_MODULES = ("PyQt6", "pyvistaqt", "pyqtgraph", "app")


def test_import_simcore_loads_no_qt():
    code = (
        "import sys, simcore, simcore.pipeline, simcore.cli, simcore.io.hdf5_writer\n"
        "import simcore.report, simcore.runs.runner, simcore.runs.sweep\n"
        # The command modules are imported when the parser is built.
        "simcore.cli.build_parser()\n"
        "assert 'simcore.cli.run' in sys.modules and 'simcore.cli.report' in sys.modules\n"
        f"bad = [m for m in sys.modules if m.split('.')[0] in {GUI_MODULES!r}]\n"
        "print(','.join(bad))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=True)
    assert proc.stdout.strip() == ""
