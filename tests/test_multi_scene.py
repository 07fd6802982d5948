"""Runs over a folder of generated scenes (issue 32): one dataset, a scene index per frame,
each frame bit-identical to the same frame of its scene run alone, spread over workers."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from fresh_process import peak_rss_per_frame
from hostile import base_project_dict, write_project

from simcore.cli import main
from simcore.io import open_dataset

FRAMES = 2


def scenes(tmp_path: Path, count: int = 3, vary: dict[str, object] | None = None) -> Path:
    """``count`` scenes of a tiny family: the corners moved, the rig's height, the radar's
    transmit power and a material drawn per scene (values, not the layout)."""
    doc = base_project_dict()
    doc["timeline"] = {"frame_rate_hz": 20.0, "duration_s": FRAMES / 20.0}
    write_project(doc, tmp_path / "tiny.json")
    spec = {"name": "tiny_family", "base": "tiny.json", "vary": vary or {
        "objects[0].pose.position_m[0]": {"uniform": [1.0, 3.0]},
        "objects[1].material": {"choice": ["aluminium", "concrete"]},
        "rig.pose.position_m[2]": {"normal": {"mean": 1.0, "std": 0.1}},
        "rig.radar.tx_power_dbm": {"uniform": [0.0, 5.0]}}}
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    out = tmp_path / "scenes"
    assert main(["generate", str(tmp_path / "spec.json"), "--out", str(out), "--count",
                 str(count), "--seed", "9", "--quiet"]) == 0
    return out


def alone(folder: Path, tmp_path: Path) -> list:
    """Each scene run by itself, the reference."""
    out = []
    for i, scene in enumerate(sorted(folder.glob("scene_*.json"))):
        path = tmp_path / f"alone_{i}.h5"
        assert main(["run", str(scene), "--out", str(path), "--frames", str(FRAMES),
                     "--quiet"]) == 0
        out.append(open_dataset(path))
    return out


def assert_frames_equal_scenes_alone(ds, refs) -> None:
    n = len(refs)
    np.testing.assert_array_equal(ds.scene_index.values, np.repeat(np.arange(n), FRAMES))
    for s, ref in enumerate(refs):
        frames = slice(s * FRAMES, (s + 1) * FRAMES)
        for name in ("radar_adc", "tof_depth", "tof_amplitude", "poses_objects",
                     "radar_detections_count"):
            a, b = ds[name].values[frames], ref[name].values
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), (name, s)
        count = ref.radar_detections_count.values
        for field in ("range", "velocity", "azimuth_deg"):
            a = ds[f"radar_detections_by_frame_{field}"].values[frames]
            b = ref[f"radar_detections_by_frame_{field}"].values
            for k in range(FRAMES):
                assert a[k, : count[k]].tobytes() == b[k, : count[k]].tobytes(), (field, s, k)
    names = [json.loads(ref.attrs["project_json"])["name"] for ref in refs]
    stored = [v.decode() if isinstance(v, bytes) else str(v) for v in ds.scenes_names.values]
    assert stored == names


def test_a_folder_of_scenes_is_one_dataset_equal_to_each_scene_alone(tmp_path):
    folder = scenes(tmp_path)
    refs = alone(folder, tmp_path)
    assert main(["run", str(folder), "--out", str(tmp_path / "all.h5"), "--frames",
                 str(FRAMES), "--quiet"]) == 0
    ds = open_dataset(tmp_path / "all.h5")
    assert_frames_equal_scenes_alone(ds, refs)
    assert ds.attrs["scenes"] == 3 and ds.attrs["frames_per_scene"] == FRAMES
    # The flat detection table numbers rows by dataset frame.
    import h5py

    with h5py.File(tmp_path / "all.h5") as f:
        rows = f["/radar/detections"][:]
        assert set(rows["frame"]) <= set(range(3 * FRAMES))
        counts = f["/radar/detections_count"][:]
        np.testing.assert_array_equal(np.bincount(rows["frame"], minlength=3 * FRAMES),
                                      counts)


@pytest.mark.slow
def test_generate_run_spreads_scenes_over_workers_into_zarr_shards(tmp_path):
    """Shards of 3 frames straddle the scenes (2 frames each); two local worker processes,
    then two Dask workers write them."""
    folder = scenes(tmp_path)
    refs = alone(folder, tmp_path)
    assert main(["generate", str(tmp_path / "spec.json"), "--out", str(folder), "--count",
                 "3", "--seed", "9", "--overwrite", "--quiet", "--run",
                 str(tmp_path / "all.zarr"), "--frames", str(FRAMES), "--workers", "2",
                 "--shard-frames", "3"]) == 0
    ds = open_dataset(tmp_path / "all.zarr")
    assert_frames_equal_scenes_alone(ds, refs)
    # Resuming the complete store of the same scenes has nothing to do.
    assert main(["run", str(folder), "--out", str(tmp_path / "all.zarr"), "--frames",
                 str(FRAMES), "--resume", "--quiet"]) == 0
    # The same on an embedded Dask cluster: its workers write the shards.
    assert main(["run", str(folder), "--out", str(tmp_path / "dask.zarr"), "--frames",
                 str(FRAMES), "--workers", "2", "--scheduler", "local", "--shard-frames",
                 "3", "--quiet"]) == 0
    assert_frames_equal_scenes_alone(open_dataset(tmp_path / "dask.zarr"), refs)


def test_scenes_of_another_layout_or_a_bad_folder_get_one_error_line(tmp_path, capsys):
    folder = scenes(tmp_path, 2)
    other = tmp_path / "other"
    other.mkdir()
    for i, path in enumerate(sorted(folder.glob("*.json"))):
        doc = json.loads(path.read_text())
        doc["rig"]["radar"]["chirps_per_frame"] = 8 * (i + 1)    # scene 1: another layout
        (other / path.name).write_text(json.dumps(doc))
    (tmp_path / "empty").mkdir()
    cases = [([str(tmp_path / "empty"), "--out", str(tmp_path / "e.h5")], "found none"),
             ([str(folder), "--out", str(tmp_path / "s.h5"), "--seed", "3"], "own project seed"),
             ([str(folder), "--out", str(tmp_path / "m.mcap")], "not MCAP"),
             ([str(other), "--out", str(tmp_path / "x.h5")], "one layout")]
    capsys.readouterr()
    for argv, needle in cases:
        assert main(["run", *argv, "--frames", "1", "--quiet"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("tofradar: error: ") and needle in err[0], err


@pytest.mark.slow
def test_memory_stays_flat_over_a_1000_frame_run_of_50_scenes(tmp_path):
    """Peak RSS over the last 30 scenes (600 frames) grows < 25 MiB: each scene's simulator
    and its seed's speckle phases are released when the run moves on, and the engine's
    bounded caches (radar sweeps and DSP constants of the last 8 configurations) are
    full after the first 20 scenes (measured: +55 MiB over those, +4 MiB after)."""
    from simcore.scene import load_project
    from simcore.scene.project_io import project_to_json

    folder = scenes(tmp_path, 50)
    todo = [(project_to_json(load_project(p)), p.parent)
            for p in sorted(folder.glob("scene_*.json"))]
    report, rss = peak_rss_per_frame("simcore.runs.runner.run_scenes", todo,
                                     tmp_path / "long.zarr", frames_per_scene=20,
                                     shard_frames=16)
    assert report.frames_done == 1000 and len(rss) == 1000
    growth = rss[-1] - rss[399]
    assert growth < 25, f"peak RSS grew {growth:.1f} MiB over the last 600 frames (30 scenes)"
    ds = open_dataset(tmp_path / "long.zarr")
    np.testing.assert_array_equal(ds.scene_index.values, np.repeat(np.arange(50), 20))


def test_progress_of_generate_and_of_a_run_over_scenes_shows_rate_eta_and_scene(tmp_path,
                                                                                 capsys):
    doc = base_project_dict()
    doc["timeline"] = {"frame_rate_hz": 20.0, "duration_s": 0.05}
    write_project(doc, tmp_path / "tiny.json")
    (tmp_path / "spec.json").write_text(json.dumps({"name": "p", "base": "tiny.json", "vary": {
        "objects[0].pose.position_m[0]": {"uniform": [1.0, 3.0]}}}))
    assert main(["generate", str(tmp_path / "spec.json"), "--out", str(tmp_path / "s"),
                 "--count", "2", "--run", str(tmp_path / "p.h5"), "--frames", "1"]) == 0
    err = capsys.readouterr().err
    # tqdm: "projects: 100%|…| 2/2 [00:00<00:00, 9.1project/s]" (elapsed<ETA, rate)
    assert "2/2 [" in err and ("project/s" in err or "s/project" in err) and "<" in err
    assert ("frame/s" in err or "s/frame" in err) and "scene 2/2" in err


# ------------------------------------------------------------ scenes of different counts
def scenes_of_counts(tmp_path: Path) -> Path:
    """Three scenes of 2, 5 and 3 objects; the 5-object one has a walking person."""
    base = base_project_dict()
    base["timeline"] = {"frame_rate_hz": 20.0, "duration_s": FRAMES / 20.0}
    corners, wall = base["objects"][:3], base["objects"][3]
    person = {"id": 5, "name": "walker",
              "geometry": {"kind": "person", "height_m": 1.7,
                           "motion": {"walk": {"speed_mps": 0.8}}},
              "pose": {"position_m": [2.5, 0.8, 0.0], "rotation_deg": [0.0, 0.0, 180.0]}}
    folder = tmp_path / "counts"
    folder.mkdir()
    lists = [[corners[0], wall], [*corners, person, wall], [corners[2], corners[1], wall]]
    for i, objects in enumerate(lists):
        doc = json.loads(json.dumps(base))
        doc["name"], doc["seed"], doc["objects"] = f"counts_{i}", 40 + i, objects
        write_project(doc, folder / f"scene_{i:02d}.json")
    return folder


PER_OBJECT = ("poses_objects", "objects_velocity", "objects_aabb", "objects_obb_size",
              "objects_radar_range", "objects_radar_azimuth")
PER_PERSON = ("people_breathing_rate", "people_gait_phase")
PER_SEGMENT = ("people_segments_pose", "people_segments_radar_range")


def assert_padded_scenes_equal_alone(ds, refs) -> None:
    """Counts, masks, names and per-object (person, segment) truth of each scene equal its
    own dataset's; the padded slots hold NaN (or −1, "")."""
    n_obj, n_people, n_seg = 5, 1, 17
    np.testing.assert_array_equal(ds.scene_index.values, np.repeat(np.arange(3), FRAMES))
    np.testing.assert_array_equal(ds.scenes_objects_count.values, [2, 5, 3])
    np.testing.assert_array_equal(ds.scenes_people_count.values, [0, 1, 0])
    assert ds.objects_valid.shape == (3 * FRAMES, n_obj)
    for s, ref in enumerate(refs):
        frames = slice(s * FRAMES, (s + 1) * FRAMES)
        n = ref.sizes["object"]
        np.testing.assert_array_equal(ds.objects_count.values[frames], n)
        np.testing.assert_array_equal(ds.objects_valid.values[frames],
                                      np.broadcast_to(np.arange(n_obj) < n, (FRAMES, n_obj)))
        names = [str(v) for v in ds.scenes_objects_names.values[s]]
        assert names == [str(v) for v in ref.object_name.values] + [""] * (n_obj - n)
        np.testing.assert_array_equal(ds.scenes_objects_ids.values[s],
                                      [*ref.object_id.values, *[-1] * (n_obj - n)])
        for name in PER_OBJECT:
            a, b = ds[name].values[frames], ref[name].values
            assert a.dtype == b.dtype and a[:, :n].tobytes() == b.tobytes(), (name, s)
            assert np.isnan(a[:, n:]).all(), (name, s)
        people = ref.sizes.get("person", 0)
        np.testing.assert_array_equal(ds.people_count.values[frames], people)
        np.testing.assert_array_equal(ds.people_segments_count.values[frames], 17 * people)
        for name in (*PER_PERSON, *PER_SEGMENT):
            a = ds[name].values[frames]
            if people:
                assert a.tobytes() == ref[name].values.tobytes(), (name, s)
            else:
                assert a.shape[1] in (n_people, n_seg) and np.isnan(a).all(), (name, s)
        # Arrays that only scenes with people have are filled with "no person".
        body = ds.tof_gt_body_part.values[frames]
        if people:
            assert body.tobytes() == ref.tof_gt_body_part.values.tobytes()
        else:
            assert (body == -1).all()
        for name in ("radar_adc", "tof_depth", "radar_detections_count"):
            a, b = ds[name].values[frames], ref[name].values
            assert a.tobytes() == b.tobytes(), (name, s)


@pytest.mark.parametrize("suffix, how", [
    ("h5", []), ("zarr", []),
    pytest.param("zarr", ["--workers", "2", "--shard-frames", "3"], marks=pytest.mark.slow)])
def test_scenes_of_2_5_and_3_objects_run_into_one_padded_dataset(tmp_path, suffix, how):
    """Known answer: each scene's own single-scene dataset. With workers, shards of 3
    frames straddle scenes of different counts."""
    folder = scenes_of_counts(tmp_path)
    refs = alone(folder, tmp_path)
    assert [ref.sizes["object"] for ref in refs] == [2, 5, 3]
    out = tmp_path / f"all.{suffix}"
    assert main(["run", str(folder), "--out", str(out), "--frames", str(FRAMES), "--quiet",
                 *how]) == 0
    assert_padded_scenes_equal_alone(open_dataset(out), refs)


@pytest.mark.parametrize("suffix", ["h5", "zarr"])
def test_a_padded_run_stopped_in_scene_1_resumes_to_the_same_dataset(tmp_path, suffix):
    from simcore.runs.runner import run_scenes
    from simcore.scene import load_project
    from simcore.scene.project_io import project_to_json

    folder = scenes_of_counts(tmp_path)
    refs = alone(folder, tmp_path)
    todo = [(project_to_json(load_project(p)), p.parent)
            for p in sorted(folder.glob("scene_*.json"))]
    out = tmp_path / f"cut.{suffix}"
    report = run_scenes(todo, out, frames_per_scene=FRAMES, shard_frames=1,
                        on_frame=lambda done, total, result: done < FRAMES + 1)
    assert report.interrupted and 0 < report.frames_done < 3 * FRAMES
    assert main(["run", str(folder), "--out", str(out), "--frames", str(FRAMES),
                 "--resume", "--quiet"]) == 0
    assert_padded_scenes_equal_alone(open_dataset(out), refs)


@pytest.mark.slow
def test_the_office_family_whose_counts_vary_runs_into_one_dataset(tmp_path):
    """Known answer: each generated project's own object and people lists."""
    from simcore.resources import RESOURCES_DIR

    folder = tmp_path / "office"
    assert main(["generate", str(RESOURCES_DIR / "scenarios" / "office_family.json"),
                 "--count", "4", "--seed", "3", "--out", str(folder), "--quiet", "--run",
                 str(tmp_path / "office.h5"), "--frames", "1"]) == 0
    docs = [json.loads(p.read_text()) for p in sorted(folder.glob("scene_*.json"))]
    names = [[o["name"] for o in d["objects"]] for d in docs]
    people = [[o["name"] for o in d["objects"] if o["geometry"]["kind"] == "person"]
              for d in docs]
    assert len({len(n) for n in names}) > 1 and len({len(p) for p in people}) > 1
    ds = open_dataset(tmp_path / "office.h5")
    width = max(len(n) for n in names)
    np.testing.assert_array_equal(ds.objects_count.values, [len(n) for n in names])
    np.testing.assert_array_equal(ds.people_count.values, [len(p) for p in people])
    np.testing.assert_array_equal(ds.people_segments_count.values, [17 * len(p) for p in people])
    for s, scene_names in enumerate(names):
        assert list(ds.scenes_objects_names.values[s]) == scene_names + [""] * (
            width - len(scene_names))
        assert list(ds.scenes_people_names.values[s][: len(people[s])]) == people[s]
        valid = ds.objects_valid.values[s]
        assert valid.sum() == len(scene_names) and valid[: len(scene_names)].all()
        assert np.isfinite(ds.poses_objects.values[s][valid]).all()
        assert np.isnan(ds.poses_objects.values[s][~valid]).all()
