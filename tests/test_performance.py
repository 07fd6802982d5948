"""Performance machinery: static-background re-use is exact, the benchmark reports its keys.

No timing assertions (timings depend on the machine and its load); these tests check that
the fast paths give the same data as the plain ones and that `tofradar bench` works.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from simcore.bench import run_benchmark
from simcore.cli import main
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.sensors.radar.synthesis import synthesize_if


def relative_error_db(fast: np.ndarray, ref: np.ndarray) -> float:
    return float(20 * np.log10(max(np.linalg.norm(fast - ref), 1e-300) / np.linalg.norm(ref)))


def test_static_background_reuse_equals_the_full_synthesis() -> None:
    """office.json (a person walks past still furniture): same IF, same ADC, same maps."""
    path = example_path("office")
    project = load_project(path)
    with Simulator(project, base_dir=path.parent) as fast, \
            Simulator(project, base_dir=path.parent, reuse_static=False) as plain:
        for index in (3, 11):
            a, b = fast.frame(index), plain.frame(index)
            scatterers = fast.radar.cached_scatterers(a.snapshot, a.radar_buffers)
            assert 0 < fast.radar.last_transformed < 0.1 * len(scatterers)
            err = relative_error_db(fast.radar.ideal_if(scatterers),
                                    synthesize_if(scatterers, project.rig.radar))
            print(f"frame {index}: {fast.radar.last_transformed} of {len(scatterers)} "
                  f"scatterers transformed, {err:.0f} dB from the full synthesis")
            assert err < -200.0
            assert_array_equal(a.radar.adc, b.radar.adc)
            assert_array_equal(a.tof.depth_m, b.tof.depth_m)
            assert_array_equal(a.dsp.range_doppler_db, b.dsp.range_doppler_db)


def test_static_scene_renders_once_and_frames_keep_their_time() -> None:
    path = example_path("wall")  # nothing moves
    project = load_project(path)
    with Simulator(project, base_dir=path.parent) as sim:
        first = sim.frame(0)
        renders = sim.renderer.render_count
        later = sim.frame(3)
        assert sim.renderer.render_count == renders
        assert later.time_s == pytest.approx(3 / project.timeline.frame_rate_hz)
        assert later.radar_buffers.time_s == later.time_s
        assert later.radar.time_s == later.time_s
        assert_array_equal(later.radar_buffers.range_m, first.radar_buffers.range_m)
    with Simulator(project, base_dir=path.parent, reuse_static=False) as plain:
        assert_array_equal(plain.frame(3).radar.adc, later.radar.adc)


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
