"""Performance machinery: `tofradar bench` reports its keys.

No timing assertions (timings depend on the machine and its load). That the fast paths
give the same data as the plain ones is tested in ``test_engine.py``.
"""

from __future__ import annotations

import json
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from simcore.bench import run_benchmark, thread_cpu
from simcore.cli import main
from simcore.resources import example_path


def test_run_benchmark_reports_the_issue_keys() -> None:
    result = run_benchmark(example_path("office"), frames=2, subset=200, antenna_edits=1)
    for key in ("fps", "frame_ms_median", "stages_ms", "if_error_db", "if_speedup",
                "antenna_edit_ms", "scatterers", "triangles", "machine"):
        assert key in result
    # How much faster the NUFFT is than the direct sum is a timing (benchmarks/, `tofradar
    # bench`); here only its definition: the direct sum's time per scatterer, times the
    # frame's scatterers, over the NUFFT's time for all of them.
    assert result["fps"] > 0 and result["if_speedup"] == pytest.approx(
        result["direct_ms_per_scatterer"] * result["scatterers"] / result["nufft_full_ms"])
    assert result["if_error_db"] <= -60.0
    assert {"render_tof", "render_radar", "tof", "radar_synthesis", "dsp"} <= set(
        result["stages_ms"])
    if os.path.isdir("/proc/self/task"):
        # The ToF camera model runs on its sensor's post thread, the radar's scatterers and
        # IF on its chain thread (the ToF chain thread only shades, which over a still
        # background can stay under the 0.5 ms a frame that thread_cpu reports).
        assert {"calling", "sensor-post-tof", "sensor-chain-radar"} <= set(
            result["thread_cpu_ms"])
        busiest = max(result["thread_cpu_ms"].values())
        assert result["two_core_floor_ms"] >= busiest


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="per-thread times: Linux")
def test_thread_cpu_charges_each_thread_its_own_time() -> None:
    """A thread that spins for a known CPU time (its own clock) is charged that time.

    Two named threads spin 0.3 s and 0.15 s of CPU each, one in a one-thread pool (named
    like its chain, without the pool's "_0"); over 2 frames each is charged half its time
    per frame (within two 10 ms clock ticks), and the floor is at least the busier one's.
    """
    spent: dict[str, float] = {}
    done, release = threading.Barrier(3), threading.Event()

    def spin(name: str, seconds: float) -> None:
        c0 = time.thread_time()
        while time.thread_time() - c0 < seconds:
            sum(range(1000))
        spent[name] = time.thread_time() - c0
        done.wait()
        release.wait()     # measured while the thread still exists

    worker = threading.Thread(target=spin, args=("spinner", 0.3), name="spinner")
    with ThreadPoolExecutor(1, thread_name_prefix="chain") as pool:
        with thread_cpu(2) as out:
            worker.start()
            job = pool.submit(spin, "chain", 0.15)
            done.wait()
        release.set()
        job.result()
        worker.join()
    assert out["thread_cpu_ms"]["spinner"] == pytest.approx(spent["spinner"] * 1e3 / 2,
                                                             abs=10.0)
    assert out["thread_cpu_ms"]["chain"] == pytest.approx(spent["chain"] * 1e3 / 2, abs=10.0)
    assert out["two_core_floor_ms"] >= out["thread_cpu_ms"]["spinner"]


def test_bench_cli_prints_one_json_object(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", str(example_path("wall")), "--frames", "1", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["frames"] == 1 and result["if_error_db"] <= -60.0


def test_bench_json_carries_the_effect_variants(capsys: pytest.CaptureFixture[str]) -> None:
    """``--effects --json``: the all-effects (own and whole-room ToF multipath) and plain
    variants are in the one object."""
    assert main(["bench", str(example_path("wall")), "--frames", "1", "--json",
                 "--effects"]) == 0
    effects = json.loads(capsys.readouterr().out)["effects"]
    for name in ("all_effects", "all_effects_room", "plain"):
        assert effects[name]["fps"] > 0
        assert {"tof", "dsp"} <= set(effects[name]["stages_ms"])


def test_rigid_stand_ins_go_where_the_people_go() -> None:
    """Each person becomes a cylinder of its height and widest trunk radius, in its
    clothing, whose centre at every frame time is half its height above the body's
    placement (the body model's own pose, the known answer); other objects unchanged."""
    from simcore.bench import rigid_stand_ins
    from simcore.scene.geometry import Cylinder
    from simcore.scene.motion import rigid_state
    from simcore.scene.people import Person
    from simcore.scene.people.body import PersonBody
    from simcore.scene.people.skeleton import SEGMENT_INDEX
    from simcore.scene.project_io import load_project

    path = example_path("person_walking")
    project = load_project(path)
    out = rigid_stand_ins(project, base_dir=path.parent)
    assert len(out.objects) == len(project.objects)
    for before, after in zip(project.objects, out.objects, strict=True):
        if not isinstance(before.geometry, Person):
            assert after == before
            continue
        person = before.geometry
        body = PersonBody(person, before.pose, before.motion, object_id=before.id,
                          seed=project.seed, base_dir=path.parent)
        radii = body.skeleton.radii
        assert isinstance(after.geometry, Cylinder)
        assert after.geometry.height_m == person.height_m
        assert after.geometry.radius_m == pytest.approx(max(
            radii[SEGMENT_INDEX["pelvis"]][:2].max(), radii[SEGMENT_INDEX["chest"]][:2].max()))
        assert after.material == person.clothing
        for i in (0, 7, project.timeline.n_frames - 1):
            t = project.timeline.frame_time(i)
            place = body.body_frame(t).placement
            state = rigid_state(after.pose, after.motion, t)
            np.testing.assert_allclose(state.origin, place[:3, :3] @ [0, 0, person.height_m / 2]
                                       + place[:3, 3], atol=1e-9)
            np.testing.assert_allclose(state.transform[:3, :3], place[:3, :3], atol=1e-9)
