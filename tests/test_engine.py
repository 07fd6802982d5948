"""The frame engine: every accelerator against the plain path, sensors as plug-ins.

The plain path (``Simulator(..., reuse_static=False)``) runs every step of every frame: no
stage cache, no still background. Each accelerated case must give the same outputs —
bit for bit in the ToF camera and the ADC cube (the still background's IF differs from the
full synthesis by rounding, far below one ADC step) — while doing less work.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.engine import FrameEngine
from simcore.pipeline import Frame, Simulator
from simcore.resources import example_path
from simcore.scene import Project, load_project
from simcore.sensors import registered
from simcore.sensors.base import DeferredOutput
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.sensor import RadarSensor
from simcore.sensors.radar.synthesis import synthesize_if


def assert_same_frame(a: Frame, b: Frame) -> None:
    assert a.time_s == b.time_s
    assert sorted(a.outputs) == sorted(b.outputs)
    tof_a, tof_b = a.outputs["tof"], b.outputs["tof"]
    assert_array_equal(tof_a.depth_m, tof_b.depth_m)
    assert_array_equal(tof_a.correlation, tof_b.correlation)
    radar_a, radar_b = a.outputs["radar"], b.outputs["radar"]
    assert_array_equal(radar_a.raw.adc, radar_b.raw.adc)
    assert_array_equal(radar_a.raw.chirp_start_s, radar_b.raw.chirp_start_s)
    assert_allclose(radar_a.dsp.range_doppler_db, radar_b.dsp.range_doppler_db, atol=1e-4)
    assert_array_equal(radar_a.dsp.detection_records(0), radar_b.dsp.detection_records(0))
    for name in a.buffers:
        assert a.buffers[name].time_s == a.time_s
        assert_array_equal(a.buffers[name].range_m, b.buffers[name].range_m)
    for name in a.objects.__dataclass_fields__:       # ground truth (kept for still objects)
        assert_array_equal(getattr(a.objects, name), getattr(b.objects, name), err_msg=name)


def _move_rx(project: Project) -> Project:
    edited = project.model_copy(deep=True)
    x, y = edited.rig.radar.rx[0].position_mm
    edited.rig.radar.rx[0].position_mm = (x + 0.7, y)
    return edited


def _dsp_edit(project: Project) -> Project:
    edited = project.model_copy(deep=True)
    edited.dsp.cfar_pfa = 1e-4
    return edited


def _tof_edit(project: Project) -> Project:
    edited = project.model_copy(deep=True)
    edited.rig.tof.exposure_time_s *= 0.5
    return edited


#: (example, edit applied between frames or None, frames, what must not be recomputed)
CASES: dict[str, tuple[str, Callable[[Project], Project] | None, tuple[int, ...], set[str]]] = {
    # A person walks past still furniture: the still background is rendered once and its IF
    # re-used; each frame shades and transforms only what the person changes.
    "still background": ("office", None, (3, 11), set()),
    # Nothing moves: one render serves every frame (with that frame's time).
    "static scene": ("wall", None, (0, 3), {"render_radar", "render_tof", "radar_scatterers",
                                            "radar_synthesis"}),
    # Antenna edit: renders and scatterers re-used, the IF synthesised again.
    "antenna edit": ("wall", _move_rx, (2, 2), {"render_radar", "render_tof",
                                                "radar_scatterers", "radar_prepare", "tof"}),
    # The same over a still background (a corner reflector moves): the background's
    # scatterers are re-used, its IF is synthesised again for the new antennas.
    "antenna edit over background": ("point_targets", _move_rx, (2, 2), {
        "render_radar", "render_tof", "radar_background_scatterers",
        "radar_background_prepare", "tof"}),
    # DSP edit: everything up to the ADC cube re-used.
    "dsp edit": ("point_targets", _dsp_edit, (2, 2), {"render_radar", "radar_synthesis",
                                                     "radar_receiver", "tof"}),
    # ToF edit: the radar frame re-used whole.
    "tof edit": ("point_targets", _tof_edit, (2, 2), {"render_radar", "radar_synthesis",
                                                     "dsp"}),
}


@pytest.mark.parametrize("case", list(CASES))
def test_accelerated_frames_equal_the_plain_path(case: str) -> None:
    example, edit, frames, reused = CASES[case]
    path = example_path(example)
    project = load_project(path)
    with Simulator(project, base_dir=path.parent) as fast:
        fast.frame(frames[0])
        if edit is not None:
            project = edit(project)
            fast.set_project(project)
        renders = fast.render_count
        out = fast.frame(frames[1])
        skipped = reused & set(out.timings_ms)
        assert not skipped, f"{case}: {sorted(skipped)} ran again"
        if reused & {"render_radar", "render_tof"}:
            assert fast.render_count == renders
    with Simulator(project, base_dir=path.parent, reuse_static=False) as plain:
        assert_same_frame(out, plain.frame(frames[1]))


@pytest.mark.parametrize("example", ["office_walkthrough", "office"])
def test_overlapped_frames_equal_one_at_a_time(example: str) -> None:
    """Simulator.frames (frame k+1 started while frame k's radar ends) = frame() by frame()."""
    path = example_path(example)
    project = load_project(path)
    indices = [0, 1, 2, 7, 3]
    with Simulator(project, base_dir=path.parent) as one:
        expected = [one.frame(i) for i in indices]
    with Simulator(project, base_dir=path.parent) as sim:
        got = list(sim.frames(indices))
        assert [f.index for f in got] == indices
        for a, b in zip(got, expected, strict=True):
            assert_same_frame(a, b)
        # Leaving an iteration early waits for the frame in flight; the simulator goes on.
        for frame in sim.frames([4, 5, 6]):
            assert frame.index == 4
            break
        assert_same_frame(sim.frame(3), expected[-1])


def test_the_frame_after_a_scene_edit_skips_the_still_background() -> None:
    """An edit's frame is computed plainly (no background to rebuild); the next uses it."""
    path = example_path("office")
    project = load_project(path)
    edited = project.model_copy(deep=True)
    x, y, z = edited.objects[0].pose.position_m
    edited.objects[0].pose.position_m = (x + 0.05, y, z)
    with Simulator(project, base_dir=path.parent) as sim:
        assert "render_background" in sim.frame(2).timings_ms     # first project: built
        sim.set_project(edited)
        after_edit = sim.frame(3)
        assert "render_background" not in after_edit.timings_ms
        assert "render_background" in sim.frame(4).timings_ms     # built again
    with Simulator(edited, base_dir=path.parent, reuse_static=False) as plain:
        assert_same_frame(after_edit, plain.frame(3))


def test_post_thread_gives_the_results_of_one_thread() -> None:
    """The radar's receiver, DSP and labels on the post thread (ctx.defer) = all inline."""
    path = example_path("office_walkthrough")
    project = load_project(path)
    inline = FrameEngine(project, base_dir=path.parent, threads=False)
    try:
        expected = [inline.frame(i) for i in (1, 2, 3)]
    finally:
        inline.close()
    assert not any(isinstance(r.outputs["radar"], DeferredOutput) for r in expected)
    with Simulator(project, base_dir=path.parent) as sim:
        got = list(sim.frames([1, 2, 3]))
    for a, b in zip(got, expected, strict=True):
        assert type(a.outputs["radar"]) is type(b.outputs["radar"])
        assert_array_equal(a.outputs["radar"].raw.adc, b.outputs["radar"].raw.adc)
        assert_array_equal(a.outputs["radar"].dsp.detection_records(0),
                           b.outputs["radar"].dsp.detection_records(0))
        assert_array_equal(a.outputs["radar"].labels.object_id,
                           b.outputs["radar"].labels.object_id)
        assert_array_equal(a.outputs["tof"].depth_m, b.outputs["tof"].depth_m)


def test_a_frame_started_ahead_is_adopted_or_dropped() -> None:
    """frame(i, then=j) starts j early; asking for j adopts it, an edit or another index not."""
    path = example_path("office_walkthrough")
    project = load_project(path)
    edited = _move_rx(project)
    with Simulator(project, base_dir=path.parent) as one:
        expected = {i: one.frame(i) for i in (1, 2, 4)}
        one.set_project(edited)
        expected_edit = one.frame(3)
    with Simulator(project, base_dir=path.parent) as sim:
        assert_same_frame(sim.frame(1, then=2), expected[1])      # frames 1 and 2 rendered
        per_frame, rem = divmod(sim.render_count, 2)
        assert per_frame > 0 and rem == 0
        assert_same_frame(sim.frame(2, then=3), expected[2])      # 2 adopted: no new render
        assert sim.render_count == 3 * per_frame                   # only frame 3's passes
        assert_same_frame(sim.frame(4), expected[4])               # 3 dropped
        sim.frame(2, then=3)
        sim.set_project(edited)                                    # 3 was for the old rig
        assert_same_frame(sim.frame(3), expected_edit)


def test_still_background_transforms_only_what_moves() -> None:
    path = example_path("office")
    project = load_project(path)
    with Simulator(project, base_dir=path.parent) as sim:
        sim.frame(0)
        frame = sim.frame(5)
    raw = frame.outputs["radar"].raw
    # Only the cells the walking person covers are transformed: the person's facets and the
    # background facets there (once to remove, once as the frame's), a small share.
    # The engine's project: the person expanded into its segments ("person/<segment>").
    engine_project = sim.engine.project
    names = [o.name for o in engine_project.objects]
    scat_all = radar_scatterers(RadarScene.from_project(engine_project, frame.snapshot),
                                frame.buffers["radar"],
                                seed=project.seed, see_through=frame.see_through["radar"],
                                config=engine_project.rig.radar)
    segments = [i for i, n in enumerate(names) if n.startswith("person/")]
    assert len(segments) == 17
    person = int(np.count_nonzero(np.isin(scat_all.object_index, segments)))
    assert person <= raw.transformed_scatterers < 0.2 * raw.n_scatterers
    scatterers = radar_scatterers(RadarScene.from_project(engine_project, frame.snapshot),
                                  frame.buffers["radar"],
                                  seed=project.seed, see_through=frame.see_through["radar"],
                                  config=engine_project.rig.radar)
    assert raw.n_scatterers == len(scatterers)


def test_over_background_if_equals_the_full_synthesis() -> None:
    """IF(background) − IF(changed background facets) + IF(frame's facets) = IF(frame)."""
    path = example_path("office")
    project = load_project(path)
    cfg = project.rig.radar
    with Simulator(project, base_dir=path.parent) as sim:
        sim.frame(0)
        frame = sim.frame(7)
        ideal = next(v for k, v in _cached(sim, "radar_synthesis"))
    # The engine's project: people expanded into the segments the snapshot holds.
    scatterers = radar_scatterers(RadarScene.from_project(sim.engine.project, frame.snapshot),
                                  frame.buffers["radar"],
                                  seed=project.seed, see_through=frame.see_through["radar"],
                                  config=sim.engine.project.rig.radar)
    full = synthesize_if(scatterers, cfg)
    err = np.linalg.norm(ideal[0] - full) / np.linalg.norm(full)
    assert 20 * np.log10(err) < -120.0


def _cached(sim: Simulator, name: str) -> list[tuple[int, object]]:
    entries = sim.engine.cache._entries[name]
    return [(k, e.value) for k, e in reversed(entries.items())]


def test_sensors_are_plugins_with_their_own_outputs_and_streams() -> None:
    sensors = registered()
    assert {"tof", "radar", "rgb"} <= set(sensors)
    assert len({s.rng_stream for s in sensors.values()}) == len(sensors)
    project = load_project(example_path("wall"))
    with Simulator(project) as sim:
        frame = sim.frame(0)
        items = frame.hdf5_items()
        static = sim.static_items()
    assert sorted(frame.outputs) == ["radar", "tof"], "RGB is off unless rig.rgb is set"
    assert "/tof/depth" in items and "/radar/adc" in items and "/radar/range_doppler" in items
    assert not any(k.startswith("/rgb") for k in items)
    assert "/radar/range_axis" in static
    assert set(frame.table_rows()) == {"/radar/detections"}


def test_a_wavelength_edit_recomputes_the_scatterers() -> None:
    """Corner-reflector RCS depends on λ: a carrier edit must not re-use the scatterers."""
    path = example_path("point_targets")
    project = load_project(path)
    with Simulator(project, base_dir=path.parent) as sim:
        first = sim.frame(1)
        edited = project.model_copy(deep=True)
        edited.rig.radar.start_frequency_hz = 61e9
        sim.set_project(edited)
        second = sim.frame(1)
    assert {"radar_scatterers", "radar_background_scatterers"} & set(second.timings_ms)
    assert "render_radar" not in second.timings_ms
    peak = [f.outputs["radar"].dsp.range_doppler_db.max() for f in (first, second)]
    # σ = 4πa⁴/(3λ²): 61 GHz vs 60 GHz gives (61/60)² in power at the same range.
    assert peak[1] - peak[0] > 0


def test_auto_exposure_looks_at_the_previous_frame() -> None:
    """With auto-exposure the ToF sensor asks for a render one frame period earlier; run in
    order, that render is the previous frame's own (no extra GPU pass)."""
    path = example_path("office")
    project = load_project(path)
    project.rig.tof.auto_exposure = True
    with Simulator(project, base_dir=path.parent) as sim:
        sim.frame(0)
        renders = sim.render_count
        frame = sim.frame(1)
        # Radar (and its see-through pass) + ToF of frame 1 only.
        see_through = RadarSensor().see_through(project) is not None
        assert sim.render_count - renders == 2 + see_through
    exposure = frame.outputs["tof"].exposure_time_s
    low, high = project.rig.tof.exposure_range_s
    assert low <= exposure <= high
    assert frame.hdf5_items()["/tof/exposure_time"][0] == exposure
