"""Hostile inputs of the five new kinds (issue 44): BVH clips, scenario specs, assets,
recordings and multi-rig projects.

Each case (built by a script from a valid input in ``hostile_inputs.py``) runs through
the command line in this process and its outcome is asserted: accepted (exit 0), or
refused with exit status 2 and ``tofradar: error:`` lines that name the file, field or
option (the expected text) and no bare exception class. A refused command leaves no
output behind. A FIFO or ``/dev/zero`` that hung a reader would fail the test by its
timeout instead of hanging the suite.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import h5py
import numpy as np
import pytest
from hostile_inputs import (
    OK,
    asset_cases,
    bvh_cases,
    bvh_text,
    person_project,
    recording_cases,
    rig_cases,
    spec_cases,
    spec_doc,
    write_recording,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from simcore.cli import main
from simcore.scene.project_io import ProjectError, project_from_dict

pytestmark = pytest.mark.timeout(60)

#: What no message may be: a class name alone, a traceback, a pydantic dump.
BARE = re.compile(r"\b(Overflow|LinAlg|Recursion|Attribute|Key|Type|Value|Index|ZeroDivision|"
                  r"Memory|Unicode(De|En)code|Validation|Runtime|Assertion|FloatingPoint|OS|"
                  r"Bvh|Mesh|Asset|Recording|Scenario|Project|Input(File)?)Error\b|"
                  r"run with --debug|Traceback|validation errors? for|input_value=|"
                  r"errors\.pydantic\.dev")


def outcome(argv: list[str], expect: str, capsys: pytest.CaptureFixture[str]) -> str:
    """Run ``tofradar ARGV`` here; assert the expected outcome; return stderr."""
    rc = main(argv)
    err = capsys.readouterr().err
    if expect == OK:
        assert rc == 0, err
        return err
    lines = err.strip().splitlines()
    assert rc == 2, (rc, err)
    assert lines and all(line.startswith("tofradar: error: ") for line in lines), err
    assert expect in err, (expect, err)
    assert not BARE.search(err), err
    return err


@pytest.mark.parametrize("kind", [bvh_cases, spec_cases, asset_cases, recording_cases,
                                  rig_cases], ids=lambda f: f.__name__)
def test_at_least_thirty_cases_per_kind(kind):
    cases = kind()
    assert len(cases) >= 30
    assert any(name.startswith("good") for name in cases)      # valid inputs stay accepted


# --------------------------------------------------------------------------------- BVH
@pytest.mark.parametrize("name", sorted(bvh_cases()))
def test_hostile_bvh(name, tmp_path, capsys):
    argv, expect = bvh_cases()[name](tmp_path)
    outcome(argv, expect, capsys)


def test_clip_memory_is_refused_from_the_header_before_reading(tmp_path, capsys):
    # 256 joints × 100000 frames: inside the joint and frame limits, about 19 GiB to read
    # with bvhio; refused with the numbers, from the header alone (the file is tiny).
    argv, _ = bvh_cases()["memory_over_budget"](tmp_path)
    err = outcome(argv, "251 joints × 100000 frames need about 18.7 GiB", capsys)
    assert (tmp_path / "sub" / "clip.bvh").stat().st_size < 100_000, err


def test_clip_root_motion_is_scaled_by_the_leg_lengths(tmp_path):
    # Known answer: the clip's leg is 45 + 43 = 88 units, the person's leg L metres; a
    # root moving 1 unit per frame along BVH z (forward) moves the pelvis L/88 m along
    # body x per frame.
    from simcore.scene.people.bvh import leg_length, load_bvh, map_joints, root_motion_m
    from simcore.scene.people.skeleton import build_skeleton

    (tmp_path / "c.bvh").write_text(bvh_text(frames=4))
    motion = load_bvh(tmp_path / "c.bvh")
    mapping = map_joints(motion)
    assert leg_length(motion, mapping) == pytest.approx(88.0)
    leg = build_skeleton(1.8).leg_length_m
    disp = root_motion_m(motion, mapping, leg)
    np.testing.assert_allclose(disp[:, 0], np.arange(4) * leg / 88.0)
    np.testing.assert_allclose(disp[:, 2], 93.0 * leg / 88.0)


# ------------------------------------------------------------------------ scenario specs
@pytest.mark.parametrize("name", sorted(spec_cases()))
def test_hostile_spec(name, tmp_path, capsys):
    argv, expect = spec_cases()[name](tmp_path)
    outcome(argv, expect, capsys)
    if expect != OK:
        leftovers = list((tmp_path / "out").glob("*")) if (tmp_path / "out").exists() else []
        assert leftovers == []


def test_generate_writes_nothing_when_a_late_scene_fails(tmp_path, capsys):
    # A late scene (34 of 60 with seed 0) draws a timeline of 10⁶ s, which takes the
    # corner reflector out of the world. Nothing is written, and an earlier run's scenes in
    # the folder stay as they were.
    spec = spec_doc()
    spec["vary"]["timeline.duration_s"] = {"choice": [1.0] * 40 + [1e6]}
    (tmp_path / "s.json").write_text(json.dumps(spec))
    out = tmp_path / "out"
    out.mkdir()
    (out / "scene_00000.json").write_text("earlier")
    argv = ["generate", str(tmp_path / "s.json"), "--count", "60", "--out", str(out),
            "--overwrite", "--quiet"]
    err = outcome(argv, "would not run", capsys)
    assert "nothing was written" in err
    assert int(re.search(r"scene (\d+) would not run", err).group(1)) > 0     # a late one
    assert sorted(p.name for p in out.iterdir()) == ["scene_00000.json"]
    assert (out / "scene_00000.json").read_text() == "earlier"


def test_generated_scenes_pass_validate(tmp_path, capsys):
    (tmp_path / "s.json").write_text(json.dumps(spec_doc()))
    assert main(["generate", str(tmp_path / "s.json"), "--count", "3", "--out",
                 str(tmp_path / "o"), "--quiet"]) == 0
    for path in sorted((tmp_path / "o").glob("scene_*.json")):
        assert main(["validate", str(path)]) == 0
    capsys.readouterr()


def test_generate_run_refuses_other_sensor_layouts_before_the_first_frame(tmp_path, capsys):
    spec = spec_doc()
    spec["vary"]["rig.radar.chirps_per_frame"] = {"choice": [16, 32]}
    (tmp_path / "s.json").write_text(json.dumps(spec))
    run = tmp_path / "run.h5"
    err = outcome(["generate", str(tmp_path / "s.json"), "--count", "4", "--out",
                   str(tmp_path / "o"), "--quiet", "--run", str(run), "--frames", "1"],
                  "other sensor axes", capsys)
    assert not run.exists(), err


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner,
                                                                 max_size=4),
    max_leaves=12)
FUZZ = settings(max_examples=40, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow,
                                       HealthCheck.function_scoped_fixture])


@FUZZ
@given(key=st.sampled_from(["uniform", "normal", "choice", "junk"]), value=JSON_VALUES)
def test_fuzzed_distributions_load_or_name_the_field(key, value, tmp_path_factory):
    from simcore.scenarios import ScenarioError, load_spec

    d = tmp_path_factory.mktemp("spec")
    spec = spec_doc()
    spec["vary"]["objects[0].pose.position_m[0]"] = {key: value}
    (d / "s.json").write_text(json.dumps(spec))
    try:
        loaded, _ = load_spec(d / "s.json")
    except ScenarioError as exc:
        text = str(exc)
        assert "\n" not in text and "s.json" in text and not BARE.search(text), text
        return
    dist = loaded.vary["objects[0].pose.position_m[0]"]
    draws = {json.dumps(dist.draw(np.random.default_rng(k))) for k in range(4)}
    assert draws          # a loaded distribution draws


# ------------------------------------------------------------------------------ assets
@pytest.mark.parametrize("name", sorted(asset_cases()))
def test_hostile_asset(name, tmp_path, capsys):
    argv, expect = asset_cases()[name](tmp_path)
    outcome(argv, expect, capsys)
    if expect != OK:
        assert not (tmp_path / "p.json").exists()
        assert not (tmp_path / "p.meshes").exists()


# -------------------------------------------------------------------------- recordings
@pytest.mark.parametrize("name", sorted(recording_cases()))
def test_hostile_recording(name, tmp_path, capsys):
    argv, expect = recording_cases()[name](tmp_path)
    outcome(argv, expect, capsys)
    if expect != OK:
        assert not (tmp_path / "out.h5").exists()
    else:
        with h5py.File(tmp_path / "out.h5") as f:
            t = f["time"][:]
            assert np.all(np.isfinite(t)) and np.all(np.diff(t) > 0) if len(t) > 1 else True


def test_converted_time_axis_is_the_frame_repetition_time(tmp_path, capsys):
    write_recording(tmp_path)
    assert main(["convert", str(tmp_path / "rec"), "--to", str(tmp_path / "o.h5")]) == 0
    with h5py.File(tmp_path / "o.h5") as f:
        np.testing.assert_allclose(f["time"][:], [0.0, 0.0773])
    capsys.readouterr()


def test_convert_project_into_a_missing_folder_writes_no_dataset(tmp_path, capsys):
    write_recording(tmp_path)
    (tmp_path / "file").write_text("")
    argv = ["convert", str(tmp_path / "rec"), "--to", str(tmp_path / "o.h5"), "--project",
            str(tmp_path / "file" / "p.json")]
    outcome(argv, "--project", capsys)
    assert not (tmp_path / "o.h5").exists()


def test_convert_removes_its_dataset_when_the_project_cannot_be_saved(tmp_path, capsys,
                                                                      monkeypatch):
    # A folder that turns read-only after the check (or a full disk): the dataset that was
    # begun goes too.
    import simcore.scene.project_io as project_io

    def refuse(project, path):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(project_io, "save_project", refuse)
    write_recording(tmp_path)
    argv = ["convert", str(tmp_path / "rec"), "--to", str(tmp_path / "o.h5"), "--project",
            str(tmp_path / "p.json")]
    outcome(argv, "Permission denied", capsys)
    assert not (tmp_path / "o.h5").exists()


@FUZZ
@given(key=st.sampled_from(sorted(
    ["aaf_cutoff_Hz", "chirp_repetition_time_s", "end_frequency_Hz", "frame_repetition_time_s",
     "hp_cutoff_Hz", "if_gain_dB", "mimo_mode", "num_chirps_per_frame",
     "num_samples_per_chirp", "rx_antennas", "sample_rate_Hz", "start_frequency_Hz",
     "tx_antennas", "tx_power_level"])), value=JSON_VALUES)
def test_fuzzed_recording_settings_read_or_name_the_file(key, value, tmp_path_factory):
    from hostile_inputs import SHAPE

    from simcore.io.recordings import RecordingError, read_recording

    d = tmp_path_factory.mktemp("rec")
    write_recording(d, shape={**SHAPE, key: value})
    try:
        rec = read_recording(d / "rec")
    except RecordingError as exc:
        text = str(exc)
        assert "\n" not in text and "config.json" in text and not BARE.search(text), text
        return
    assert 1e-4 <= rec.frame_repetition_time_s <= 3600.0
    assert np.all(np.isfinite(rec.frame_times_s()))


# -------------------------------------------------------------------- multi-rig projects
@pytest.mark.parametrize("name", sorted(rig_cases()))
def test_hostile_multi_rig_project(name, tmp_path, capsys):
    argv, expect = rig_cases()[name](tmp_path)
    outcome(argv, expect, capsys)


@FUZZ
@given(path=st.sampled_from([("pose", "position_m", 0), ("pose", "rotation_deg", 2),
                             ("motion", "velocity_mps", 0), ("sensors", "radar_b",
                                                             "trigger_offset_s"),
                             ("sensors", "radar_b", "chirps_per_frame"),
                             ("sensors", "tof_b", "width"), ("name",)]),
       value=JSON_VALUES)
def test_fuzzed_second_rig_validates_or_names_the_field(path, value, tmp_path_factory):
    from hostile_inputs import multi_rig_doc

    from simcore.preflight import check

    doc = multi_rig_doc()
    node = doc["rigs"][0]
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    try:
        project = project_from_dict(json.loads(json.dumps(doc)), base_dir=Path.cwd())
    except ProjectError as exc:
        assert exc.problems
        for p in exc.problems:
            assert "\n" not in p and "rigs" in p and not BARE.search(p), p
        return
    for p in check(project, memory_budget_bytes=4 * 2**30):
        assert "\n" not in p and not BARE.search(p), p


def test_person_project_clip_names_the_field(tmp_path, capsys):
    (tmp_path / "p.json").write_text(json.dumps(person_project("none.bvh")))
    outcome(["validate", str(tmp_path / "p.json")], "objects[0].geometry.motion.bvh.path",
            capsys)
