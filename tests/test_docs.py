"""Docs that run: the README's and docs/*.md's Python blocks, and the numpydoc Examples.

Every ```python block of README.md runs as it stands, in a fresh interpreter, from an
empty temporary folder (so it cannot lean on the repository's working directory). Blocks
of docs/*.md are fragments that name objects the surrounding text introduces; PRELUDES
gives each such file the few lines that create them, and the block runs after those.
"""

from __future__ import annotations

import doctest
import importlib
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC_FILES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.M | re.S)

# Set-up run before the blocks of a docs file: the names their text takes as given.
_FRAME = """
import numpy as np
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
project = load_project(example_path("point_targets"))
with Simulator(project) as _sim:
    _frame = _sim.frame(0)
"""
PRELUDES: dict[str, str] = {
    "dataset.md": """
import subprocess, sys
from simcore.resources import example_path
from simcore.scene import load_project
subprocess.run([sys.executable, "-m", "simcore.cli", "run", str(example_path("wall")),
                "--out", "out/demo.h5", "--frames", "2", "--quiet"], check=True)
""",
    # A recording for the MCAP reader, and a live server (any free port: the client's
    # connect() to the documented 8765 is sent there) for the WebSocket client.
    "robotics.md": """
import atexit, subprocess, sys
import websockets.sync.client as _client
from simcore.resources import example_path
subprocess.run([sys.executable, "-m", "simcore.cli", "run", str(example_path("point_targets")),
                "--out", "run.mcap", "--frames", "2", "--quiet"], check=True)
_server = subprocess.Popen([sys.executable, "-m", "simcore.cli", "serve",
                            str(example_path("point_targets")), "--port", "0", "--frames", "3",
                            "--fast"], stdout=subprocess.PIPE, text=True)
atexit.register(_server.kill)
_port = _server.stdout.readline().split()[2].rsplit(":", 1)[1]
_connect = _client.connect
_client.connect = lambda url, **kw: _connect(url.replace(":8765", ":" + _port), **kw)
""",
    "dsp.md": _FRAME + """
cube, radar_config, frame_index = _frame.outputs["radar"].raw.adc, project.rig.radar, 0
T = _frame.snapshot.sensor("radar").transform
""",
    "physics_radar.md": _FRAME + """
snapshot, radar_buffers, seed = _frame.snapshot, _frame.buffers["radar"], 1
""",
}

# Modules whose numpydoc Examples run as doctests.
DOCTEST_MODULES = [
    "simcore.dsp.angle",
    "simcore.dsp.interference",
    "simcore.dsp.cfar",
    "simcore.dsp.maps",
    "simcore.dsp.microdoppler",
    "simcore.dsp.peaks",
    "simcore.dsp.spectrum",
    "simcore.dsp.vitals",
    "simcore.dsp.windows",
    "simcore.examples",
    "simcore.pipeline",
    "simcore.resources",
    "simcore.scene.camera",
    "simcore.scene.fieldpath",
    "simcore.scene.motion",
    "simcore.scene.radar_arrays",
    "simcore.sensors.rgb.camera",
]
# Public functions of those modules that need a whole project or frame to show anything;
# their behaviour is covered by the end-to-end tests instead.
NO_EXAMPLE = {"simcore.dsp.angle.estimate_angles", "simcore.examples.copy_examples",
              "simcore.sensors.rgb.camera.simulate_rgb"}


def python_blocks(path: Path) -> list[tuple[int, str]]:
    """(line number, code) of every ```python block of a Markdown file."""
    text = path.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 2, m.group(1)) for m in FENCE.finditer(text)]


BLOCKS = [pytest.param(path, line, code, id=f"{path.relative_to(ROOT)}:{line}")
          for path in DOC_FILES for line, code in python_blocks(path)]


def test_readme_has_python_blocks():
    assert python_blocks(ROOT / "README.md")


@pytest.mark.parametrize(("path", "line", "code"), BLOCKS)
def test_doc_block_runs(path, line, code, tmp_path):
    prelude = "" if path.name == "README.md" else PRELUDES.get(path.name, "")
    env = dict(os.environ, MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    script = textwrap.dedent(prelude) + "\n" + code
    proc = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, (
        f"{path.relative_to(ROOT)}:{line} failed:\n{proc.stderr[-3000:]}")


@pytest.mark.parametrize("name", DOCTEST_MODULES)
def test_numpydoc_examples(name):
    module = importlib.import_module(name)
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=flags)
    tests = finder.find(module, name)
    out: list[str] = []
    for test in tests:
        runner.run(test, out=out.append)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0, f"{name} has no examples"
    assert result.failed == 0, "".join(out)


@pytest.mark.parametrize("name", DOCTEST_MODULES)
def test_public_functions_have_examples(name):
    module = importlib.import_module(name)
    missing = []
    for attr, obj in vars(module).items():
        func = getattr(obj, "__wrapped__", obj)  # lru_cache
        if attr.startswith("_") or not callable(func) or isinstance(obj, type):
            continue
        if getattr(func, "__module__", None) != name or f"{name}.{attr}" in NO_EXAMPLE:
            continue
        if ">>>" not in (func.__doc__ or ""):
            missing.append(attr)
    assert not missing, f"{name}: public functions without Examples: {missing}"
