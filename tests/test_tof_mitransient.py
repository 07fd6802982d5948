"""ToF multipath against an independent path tracer (mitransient's cached phasors).

The reference images were rendered by ``tools/references/mitransient`` (transient path
tracing, AMCW phasors from exact path lengths) and are committed as
``resources/references/tof_<scene>.npz``; the scenes are not among the bundled examples.
Acceptance (issue 42): the MPI bias (depth with multipath − without) within 10 % of the
reference's, near creases (within 10 px) and beyond them, and direct depths within 1 mm.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.report.tof_reference import (
    compare,
    compare_exported,
    phasor_depth,
    reference_phasors,
    scenes,
)


def _check(result):
    assert result["direct_error_mm"]["median"] < 1.0
    assert result["direct_error_mm"]["p95"] < 1.0
    for region in ("near", "beyond"):
        r = result[region]
        assert r["pixels"] > 50, region
        assert r["reference_mm"] > 5.0, region          # there is multipath to match
        assert abs(r["ratio"] - 1.0) < 0.10, (region, r)


def test_corner_mpi_bias_matches_the_path_tracer():
    _check(compare("corner"))


def _check_one_bounce(name):
    """One indirect bounce alone against the path tracer's paths of one indirect bounce."""
    ref = reference_phasors(name)
    freq = scenes()["camera"]["modulation_frequency_hz"]
    ref_bias = phasor_depth(ref["one_bounce"] / ref["direct"], freq)
    ours = compare(name, bounces=1)
    maps = ours["maps"]
    for region, mask in (("near", maps["near"]), ("beyond", maps["valid"] & ~maps["near"])):
        expected = float(np.median(ref_bias[mask]))
        got = float(np.median(maps["tofradar"][mask]))
        assert expected > 5e-3, region
        assert abs(got / expected - 1.0) < 0.10, (region, got, expected)
    return ours


def test_corner_one_bounce_matches_the_path_tracer_one_bounce():
    ours = _check_one_bounce("corner")
    # ... and the higher orders add to it: all bounces pull the depth farther.
    assert ours["near"]["tofradar_mm"] < 0.7 * compare("corner")["near"]["tofradar_mm"]


@pytest.mark.slow
def test_furnished_room_mpi_bias_matches_the_path_tracer():
    """A closed room (floor behind the camera, walls outside its view, furniture between
    surfaces): senders outside the view and occlusion are needed to match."""
    _check(compare("furnished"))
    _check_one_bounce("furnished")


def test_office_mpi_bias_matches_the_path_tracer():
    """The office example itself at t = 0 (resources/examples/office.json: its walker
    posed at t = 0, desks, chair, open behind the camera), exported and path-traced with
    its materials' Lambertian albedo; tofradar's side is built from the project file
    (ideal camera, 64 × 44, glossy and retroreflective terms off, the room model at the
    office's 0.6 m surfels). Near creases: within 3 px (nearly every pixel of a furnished
    room lies within 10 px of a crease). The walker's pixels are not held here (see
    docs/physics_tof.md §8b): the regions are the still surfaces'."""
    first_order = compare_exported("office")        # the default for moving objects
    assert first_order["moving"]["pixels"] > 10     # the walker is in view and moving
    _check(first_order)
    _check(compare_exported("office", multipath_moving="exact"))
    # One indirect bounce alone against the path tracer's one-bounce paths.
    _check(compare_exported("office", multipath_bounces=1, reference_key="one_bounce"))


def test_the_sensor_plugin_builds_the_room_from_the_snapshot():
    """The engine's ToF sensor (``multipath_model = "room"``) gives the frame of the
    comparison above: the room comes from the frame's snapshot and the render's meshes."""
    from simcore.pipeline import Simulator
    from simcore.report.tof_reference import camera_config, reference_project, simulate

    project = reference_project("corner", camera_config(multipath=True))
    with Simulator(project) as sim:
        frame = sim.frame(0)
    tof = next(out for out in frame.outputs.values() if hasattr(out, "depth_m"))
    np.testing.assert_array_equal(tof.depth_m, simulate("corner", multipath=True)["depth"])


def test_the_engine_gives_the_office_frame_compared():
    """The office's comparison is of the engine's own frame 0 (the walker expanded and
    flagged as moving, the first-order path taken), bit for bit."""
    from simcore.pipeline import Simulator
    from simcore.report.tof_reference import (
        exported_camera_config,
        exported_project,
        exported_project_path,
        simulate_exported,
    )

    cfg = exported_camera_config("office", multipath=True, multipath_model="room")
    with Simulator(exported_project("office", cfg),
                   base_dir=exported_project_path("office").parent) as sim:
        frame = sim.frame(0)
    tof = next(out for out in frame.outputs.values() if hasattr(out, "depth_m"))
    np.testing.assert_array_equal(tof.depth_m,
                                  simulate_exported("office", multipath=True)["depth"])


def test_an_edited_office_is_not_compared_with_the_old_reference():
    """The reference is the office as exported: a desk moved 1 cm, or a wall's albedo
    changed, and the comparison refuses (export and render again)."""
    from simcore.report import tof_reference as ref

    cfg = ref.exported_camera_config("office", multipath=False)
    project = ref.exported_project("office", cfg)
    ref._check_scene("office", project)                      # as exported: accepted
    desk = next(o for o in project.objects if o.name == "desk1_top")
    pose = desk.pose.model_copy(update={"position_m": (
        desk.pose.position_m[0] + 0.01, *desk.pose.position_m[1:])})
    moved = project.model_copy(update={"objects": [
        o.model_copy(update={"pose": pose}) if o is desk else o for o in project.objects]})
    with pytest.raises(ValueError, match="not the scene the path tracer rendered"):
        ref._check_scene("office", moved)
    paint = next(m for m in project.materials if m.name == "white_paint")
    tof = paint.band("tof").model_copy(update={"reflectance": 0.8})
    repainted = project.model_copy(update={"materials": [
        m.model_copy(update={"bands": {**m.bands, "tof": tof}}) if m is paint else m
        for m in project.materials]})
    with pytest.raises(ValueError, match="not the scene the path tracer rendered"):
        ref._check_scene("office", repainted)
