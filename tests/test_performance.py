"""Performance machinery: `tofradar bench` reports its keys.

No timing assertions (timings depend on the machine and its load). That the fast paths
give the same data as the plain ones is tested in ``test_engine.py``.
"""

from __future__ import annotations

import json

import pytest

from simcore.bench import run_benchmark
from simcore.cli import main
from simcore.resources import example_path


def test_run_benchmark_reports_the_issue_keys() -> None:
    result = run_benchmark(example_path("office"), frames=2, subset=200, antenna_edits=1)
    for key in ("fps", "frame_ms_median", "stages_ms", "if_error_db", "if_speedup",
                "antenna_edit_ms", "scatterers", "triangles", "machine"):
        assert key in result
    assert result["fps"] > 0 and result["if_speedup"] > 1
    assert result["if_error_db"] <= -60.0
    assert {"render_tof", "render_radar", "tof", "radar_synthesis", "dsp"} <= set(
        result["stages_ms"])


def test_bench_cli_prints_one_json_object(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", str(example_path("wall")), "--frames", "1", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["frames"] == 1 and result["if_error_db"] <= -60.0


def test_bench_json_carries_the_effect_variants(capsys: pytest.CaptureFixture[str]) -> None:
    """``--effects --json``: the all-effects and plain variants are in the one object."""
    assert main(["bench", str(example_path("wall")), "--frames", "1", "--json",
                 "--effects"]) == 0
    effects = json.loads(capsys.readouterr().out)["effects"]
    for name in ("all_effects", "plain"):
        assert effects[name]["fps"] > 0
        assert {"tof", "dsp"} <= set(effects[name]["stages_ms"])
