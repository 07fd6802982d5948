"""People through the engine: materials, the still background, the dataset reader.

Known answers: at normal incidence a half-space of complex permittivity ε reflects
|(1 − √ε)/(1 + √ε)|² of the power (Fresnel); dry skin at 60 GHz has ε = 7.98 − j10.9
(Gabriel et al. 1996), about 38 %. The accelerated path (stage cache, still background)
must give the plain path's frames bit for bit (ToF) when a person moves over still
furniture — so segments must count as moving.
"""

from __future__ import annotations

import cmath

import numpy as np
import pytest
from people_scenes import walker_project
from test_engine import assert_same_frame

from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.people.expand import expand_people, people_of
from simcore.scene.people.skeleton import SEGMENTS
from simcore.scene.project_io import material_table, project_from_dict
from simcore.scene.snapshot import take_snapshot


def test_skin_reflects_about_38_percent_at_60_ghz() -> None:
    eps = complex(7.98, -10.9)  # Gabriel, Lau & Gabriel (1996), dry skin, 60 GHz
    n = cmath.sqrt(eps)
    expected = abs((1 - n) / (1 + n)) ** 2
    assert 0.34 <= expected <= 0.42
    table = material_table(load_project(example_path("wall")))
    for name in ("skin", "clothing"):
        gamma, _ = table[name].band("radar").coefficients(60e9)
        assert abs(gamma) ** 2 == pytest.approx(expected, rel=1e-3)
    assert 0.5 <= table["skin"].band("tof").reflectance <= 0.6


def test_expanded_snapshot_holds_every_segment() -> None:
    project = project_from_dict(walker_project(speed=1.2, heading_deg=0.0, distance_m=3.0))
    expanded = expand_people(project)
    people = people_of(expanded)
    assert people is not None and len(expanded.objects) == len(SEGMENTS)
    assert {o.id for o in expanded.objects} == {1}  # every segment carries the person's id
    snap = take_snapshot(expanded, 0.4)
    speed = np.array([np.linalg.norm(s.velocity_mps) for s in snap.objects])
    assert np.all(speed[:5] > 0.5)  # the trunk and head are carried along by the walk
    feet = speed[[SEGMENTS.index("foot_l"), SEGMENTS.index("foot_r")]]
    assert feet.min() < 0.05 or feet.max() > 2.0  # one foot planted, or swinging fast
    assert people.body_part.tolist() == list(range(len(SEGMENTS)))


@pytest.mark.parametrize("example", ["vital_signs", "gesture"])
def test_accelerated_frames_equal_plain_with_people(example: str) -> None:
    path = example_path(example)
    project = load_project(path)
    project.rig.tof.width, project.rig.tof.height = 112, 86
    with Simulator(project, base_dir=path.parent) as fast:
        fast.frame(0)
        a = fast.frame(7)
        a_people = a.people
    with Simulator(project, base_dir=path.parent, reuse_static=False) as plain:
        b = plain.frame(7)
    assert_same_frame(a, b)
    assert a_people is not None and b.people is not None
    assert np.array_equal(a_people.segment_pose, b.people.segment_pose)
    # The chest moved between frame 0 and 7 (breathing or gesture): not a still background.
    assert not np.array_equal(a.outputs["tof"].depth_m, fast_first_depth(path, project))


def fast_first_depth(path, project):  # noqa: ANN001, ANN201 - helper of the test above
    with Simulator(project, base_dir=path.parent, reuse_static=False) as sim:
        return sim.frame(0).outputs["tof"].depth_m


def test_reader_names_people_dimensions(tmp_path) -> None:
    import json

    from simcore.cli import main
    from simcore.io.reader import open_dataset

    d = walker_project(speed=1.0, heading_deg=180.0, distance_m=3.0, frames=2)
    (tmp_path / "w.json").write_text(json.dumps(d))
    assert main(["run", str(tmp_path / "w.json"), "--out", str(tmp_path / "w.h5"),
                 "--quiet"]) == 0
    ds = open_dataset(tmp_path / "w.h5")
    try:
        assert ds["people_segments_radar_radial_velocity"].dims == ("frame", "segment")
        assert ds["tof_gt_body_part"].dims == ("frame", "row", "col")
        assert list(ds["segment_name"].values[:2]) == ["walker/pelvis", "walker/abdomen"]
        assert ds["people_breathing_rate"].dims == ("frame", "person")
    finally:
        ds.close()


def test_mcap_carries_segment_frames(tmp_path) -> None:
    import json

    import h5py
    from test_mcap import read_mcap

    from simcore.cli import main
    from simcore.io.ros2_messages import transform_matrix

    d = walker_project(speed=1.0, heading_deg=180.0, distance_m=3.0, frames=2)
    (tmp_path / "w.json").write_text(json.dumps(d))
    for suffix in ("mcap", "h5"):
        assert main(["run", str(tmp_path / "w.json"), "--out", str(tmp_path / f"w.{suffix}"),
                     "--quiet"]) == 0
    tf = read_mcap(tmp_path / "w.mcap")["/tf"]
    with h5py.File(tmp_path / "w.h5") as f:
        names = list(f["people/segments/names"].asstr()[:])
        for k in range(2):
            frames = {t.child_frame_id: transform_matrix(t.transform)
                      for t in tf[k][1].transforms}
            for i, name in enumerate(names):
                np.testing.assert_allclose(frames[name], f["people/segments/pose"][k, i],
                                           atol=1e-9)


def test_rgb_body_part_beside_object_id() -> None:
    from simcore.scene.rgb_config import RgbCameraConfig

    project = project_from_dict(walker_project(speed=1.0, heading_deg=180.0, distance_m=2.5))
    project.rig.rgb = RgbCameraConfig(width=64, height=48)
    with Simulator(project) as sim:
        rgb = sim.frame(1).outputs["rgb"]
    person = rgb.gt_object_id == 1
    assert person.sum() > 50
    assert np.all(rgb.gt_body_part[person] >= 0) and np.all(rgb.gt_body_part[~person] == -1)
