"""Attacks on inputs (issue #19): hostile project files, meshes, paths, sizes and options.

Every attack must end in a refusal that names the field (exit status 2, one line
``tofradar: error: …``), or in a run whose outputs are numbers; never a traceback, a
signal, a hang or an all-NaN dataset.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pytest
from hostile import (
    HOSTILE_VALUES,
    base_project_dict,
    leaf_paths,
    mutate,
    scale_numbers,
    set_path,
    write_project,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from simcore.cli import main
from simcore.preflight import check, estimate_cost
from simcore.scene import load_project
from simcore.scene.mesh_files import MeshError, read_mesh_arrays
from simcore.scene.model import Project
from simcore.scene.project_io import ProjectError, project_from_dict

BAD_MESHES = Path(__file__).parent / "data" / "bad_meshes"
#: Hostile projects run through `validate` and `run` by the campaign (raise it for a long
#: attack, e.g. TOFRADAR_FUZZ_RUNS=300).
FUZZ_RUNS = int(os.environ.get("TOFRADAR_FUZZ_RUNS", "24"))

FUZZ = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])


def assert_one_line_problems(problems: list[str]) -> None:
    for p in problems:
        assert "\n" not in p and 0 < len(p) <= 400, p


# ------------------------------------------------------------------ project fuzzing
@FUZZ
@given(edits=st.lists(st.tuples(st.integers(0, 10**6), st.sampled_from(HOSTILE_VALUES)
                                | st.floats(allow_nan=False, allow_infinity=False)
                                | st.integers(-2**70, 2**70)), min_size=1, max_size=4))
def test_fuzzed_project_documents_validate_or_name_the_field(edits):
    doc = base_project_dict()
    for index, value in edits:
        paths = leaf_paths(doc)
        set_path(doc, paths[index % len(paths)], value)
    try:
        project = project_from_dict(json.loads(json.dumps(doc)), base_dir=Path.cwd())
    except ProjectError as exc:
        assert exc.problems
        assert_one_line_problems(exc.problems)
        return
    problems = check(project, base_dir=Path.cwd(), memory_budget_bytes=4 * 2**30)
    assert_one_line_problems(problems)


@FUZZ
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4))
def test_fuzzed_structural_mutations_validate_or_name_the_field(seed, n, tmp_path):
    path = write_project(mutate(base_project_dict(), random.Random(seed), n),
                         tmp_path / "p.json")
    try:
        project = load_project(path)
    except ProjectError as exc:
        assert_one_line_problems(exc.problems)
        return
    assert_one_line_problems(check(project, base_dir=tmp_path, memory_budget_bytes=4 * 2**30))


CAMPAIGN = textwrap.dedent("""
    import contextlib, io, json, sys
    import h5py, numpy as np
    from simcore.cli import main
    for path in sys.argv[1:]:
        print(json.dumps({"start": path}), flush=True)
        result = {"path": path}
        for cmd in (["validate", path],
                    ["run", path, "--out", path + ".h5", "--frames", "2", "--quiet"]):
            err = io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                rc = main(cmd)
            result[cmd[0]] = [rc, err.getvalue()]
            if rc != 0:
                break
        else:
            with h5py.File(path + ".h5") as f:
                empty = []
                def visit(name, obj):
                    if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" \\
                            and obj.size and name != "tof/gt_range" \\
                            and not np.isfinite(obj[()]).any():
                        empty.append(name)
                f.visititems(visit)
            result["all_nan"] = empty
        print(json.dumps(result), flush=True)
""")


def run_campaign(paths: list[Path], timeout: float) -> list[dict]:
    """Validate and run every project in one child process; report each outcome."""
    proc = subprocess.run([sys.executable, "-c", CAMPAIGN, *map(str, paths)],
                          capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    lines = [json.loads(x) for x in proc.stdout.splitlines() if x.startswith("{")]
    results = [x for x in lines if "start" not in x]
    if proc.returncode != 0:
        started = [x["start"] for x in lines if "start" in x]
        pytest.fail(f"the campaign died (status {proc.returncode}) on {started[-1:]}: "
                    f"{proc.stderr[-2000:]}")
    return results


def assert_clean(results: list[dict]) -> dict[str, int]:
    outcome = {"ok": 0, "refused": 0}
    for r in results:
        for cmd in ("validate", "run"):
            if cmd not in r:
                continue
            rc, err = r[cmd]
            assert rc in (0, 2), (r["path"], cmd, rc, err)
            assert "Traceback" not in err and "--debug for the traceback" not in err, err
            if rc == 2:
                lines = err.strip().splitlines()
                assert lines and all(x.startswith("tofradar: error: ") for x in lines), err
                assert all(len(x) <= 620 for x in lines)
        assert not r.get("all_nan"), r
        outcome["ok" if "all_nan" in r else "refused"] += 1
    return outcome


def test_hostile_projects_and_meshes_through_validate_and_run(tmp_path):
    rng = random.Random(int(os.environ.get("TOFRADAR_FUZZ_SEED", "19")))
    base = base_project_dict()
    paths = []
    for i in range(FUZZ_RUNS):
        # Half of them scale numbers (many still validate and reach `run`).
        doc = (mutate(base, rng, rng.randint(1, 3)) if i % 2 else
               scale_numbers(base, rng, rng.randint(1, 3)))
        paths.append(write_project(doc, tmp_path / f"hostile_{i:03d}.json"))
    # Every mesh of the malformed corpus, as an object of the base project.
    for mesh in sorted(BAD_MESHES.iterdir()):
        doc = json.loads(json.dumps(base))
        (tmp_path / mesh.name).write_bytes(mesh.read_bytes())
        doc["objects"].append({"id": 50, "name": "mesh", "geometry": {"kind": "mesh",
                               "path": mesh.name}})
        paths.append(write_project(doc, tmp_path / f"mesh_{mesh.stem}.json"))
    results = run_campaign(paths, timeout=120 + 15 * len(paths))
    assert len(results) == len(paths)
    outcome = assert_clean(results)
    print(f"hostile campaign: {len(paths)} projects, {outcome}")
    mesh_results = [r for r in results if "/mesh_" in r["path"]]
    assert all(r["validate"][0] == 2 for r in mesh_results), mesh_results


# ------------------------------------------------------------------ meshes
@pytest.mark.parametrize("name", sorted(p.name for p in BAD_MESHES.iterdir()))
def test_malformed_mesh_is_refused_before_native_code(name):
    with pytest.raises(MeshError) as info:
        read_mesh_arrays(BAD_MESHES / name)
    assert name in str(info.value) and "\n" not in str(info.value)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(data=st.binary(max_size=600), suffix=st.sampled_from([".obj", ".ply", ".stl"]),
       header=st.sampled_from([b"", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x"
                               b"\nproperty float y\nproperty float z\nelement face 1\nproperty"
                               b" list uchar int vertex_indices\nend_header\n",
                               b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                               b"property float x\nproperty float y\nproperty float z\nelement "
                               b"face 1\nproperty list uchar int vertex_indices\nend_header\n",
                               b"solid s\n", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n"]))
def test_fuzzed_mesh_bytes_parse_or_raise_mesh_error(data, suffix, header, tmp_path_factory):
    path = tmp_path_factory.mktemp("m") / f"fuzz{suffix}"
    path.write_bytes(header + data)
    try:
        points, tris = read_mesh_arrays(path)
    except MeshError:
        return
    assert np.isfinite(points).all() and tris.min() >= 0 and tris.max() < len(points)


def mesh_project(tmp_path: Path, mesh_path: str) -> Path:
    doc = base_project_dict()
    doc["objects"].append({"id": 50, "name": "mesh", "geometry": {"kind": "mesh",
                           "path": mesh_path}})
    return write_project(doc, tmp_path / "mesh_project.json")


def good_obj(path: Path) -> Path:
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return path


def validate(path: Path, *extra: str, capsys) -> tuple[int, str]:
    rc = main(["validate", str(path), *extra])
    return rc, capsys.readouterr().err


def test_mesh_path_policy(tmp_path, capsys):
    inside = tmp_path / "project"
    inside.mkdir()
    outside = good_obj(tmp_path / "outside.obj")
    good_obj(inside / "ok.obj")
    assert validate(mesh_project(inside, "ok.obj"), capsys=capsys)[0] == 0
    for mesh_path in (str(outside), "../outside.obj"):
        rc, err = validate(mesh_project(inside, mesh_path), capsys=capsys)
        assert rc == 2 and "outside the project folder" in err and "--allow-outside-paths" in err
        assert validate(mesh_project(inside, mesh_path), "--allow-outside-paths",
                        capsys=capsys)[0] == 0
    (inside / "link.obj").symlink_to(outside)
    rc, err = validate(mesh_project(inside, "link.obj"), capsys=capsys)
    assert rc == 2 and "outside the project folder" in err
    (inside / "loop.obj").symlink_to(inside / "loop.obj")
    rc, err = validate(mesh_project(inside, "loop.obj"), capsys=capsys)
    assert rc == 2 and ("symlink loop" in err or "not found" in err), err
    os.mkfifo(inside / "fifo.obj")
    rc, err = validate(mesh_project(inside, "fifo.obj"), capsys=capsys)
    assert rc == 2 and "fifo.obj" in err
    (inside / "zero.obj").symlink_to("/dev/zero")
    rc, err = validate(mesh_project(inside, "zero.obj"), "--allow-outside-paths",
                       capsys=capsys)
    assert rc == 2 and "not a regular file" in err, err


# ------------------------------------------------------------------ named attacks
def project_with(tmp_path: Path, edit) -> Path:
    doc = base_project_dict()
    edit(doc)
    return write_project(doc, tmp_path / "attack.json")


ATTACKS = {
    "no objects": (lambda d: d.update(objects=[]), "objects"),
    "NUL in a name": (lambda d: d["objects"][0].update(name="a\u0000b"), "objects[0].name"),
    "seed 2**63": (lambda d: d.update(seed=2**63), "seed"),
    "range FFT below samples": (lambda d: d["dsp"].update(range_fft_size=64),
                                "dsp.range_fft_size"),
    "Doppler FFT below chirps": (lambda d: d["dsp"].update(doppler_fft_size=4),
                                 "dsp.doppler_fft_size"),
    "tiny max_range_m": (lambda d: d["dsp"].update(max_range_m=1e-9), "max_range_m"),
    "max_range_m below one bin": (lambda d: d["dsp"].update(max_range_m=1e-3, min_range_m=0),
                                  "dsp.max_range_m"),
    "bandwidth 1e300": (lambda d: d["rig"]["radar"].update(bandwidth_hz=1e300),
                        "rig.radar.bandwidth_hz"),
    "start frequency 1e300": (lambda d: d["rig"]["radar"].update(start_frequency_hz=1e300),
                              "rig.radar.start_frequency_hz"),
    "bandwidth beyond ADC": (lambda d: d["rig"]["radar"].update(bandwidth_hz=2.9e10,
                                                                chirp_time_s=1e-6,
                                                                samples_per_chirp=8),
                             "rig.radar"),
    "f_number 1e-300": (lambda d: d["rig"]["tof"].update(f_number=1e-300),
                        "rig.tof.f_number"),
    "pixel pitch 1e300": (lambda d: d["rig"]["tof"].update(pixel_pitch_um=1e300),
                          "rig.tof.pixel_pitch_um"),
    "velocity 1e308": (lambda d: d["objects"][0]["motion"].update(velocity_mps=[1e308, 0, 0]),
                       "objects[0].motion.velocity_mps[0]"),
    "keyframes 1e-300 s apart": (lambda d: d["objects"][0]["motion"].update(keyframes=[
        {"time_s": 0.0}, {"time_s": 1e-300, "position_m": [1, 0, 0]}]),
        "objects[0].motion"),
    "keyframe at 1e300 m": (lambda d: d["objects"][0]["motion"].update(keyframes=[
        {"time_s": 0.0}, {"time_s": 1.0, "position_m": [1e300, 0, 0]}]),
        "objects[0].motion.keyframes[1].position_m[0]"),
    "Rx kilometres apart": (lambda d: d["rig"]["radar"]["rx"][0].update(
        position_mm=[2e6, 0]), "rig.radar.rx[0].position_mm[0]"),
    "10**4 Rx": (lambda d: d["rig"]["radar"].update(rx=[{"name": f"r{i}"} for i in
                                                        range(10_000)]), "rig.radar.rx"),
    "tiny angle step": (lambda d: d["dsp"].update(azimuth_step_deg=1e-9), "dsp"),
    "supersampling over the render limit": (lambda d: d["rig"]["radar"].update(
        render_width=8192, render_height=8192, render_supersampling=8), "rig.radar"),
    "object 1e300 m away": (lambda d: d["objects"][0]["pose"].update(
        position_m=[1e300, 0, 0]), "objects[0].pose.position_m[0]"),
    "timeline of 1e600 frames": (lambda d: d.update(timeline={"frame_rate_hz": 1e300,
                                                             "duration_s": 1e300}),
                                 "timeline.duration_s × frame_rate_hz"),
    "frame rate 1e-300": (lambda d: d.update(timeline={"frame_rate_hz": 1e-300,
                                                      "duration_s": 1e-300}),
                          "timeline.frame_rate_hz"),
    "IF high-pass 1e-300 Hz": (lambda d: d["rig"]["radar"].update(if_highpass_hz=1e-300),
                               "rig.radar: if_highpass_hz"),
    "ToF field of view 1e-300°": (lambda d: d["rig"]["tof"].update(fov_v_deg=1e-300),
                                  "rig.tof.fov_v_deg"),
    "corner reflector on the radar": (lambda d: d["objects"][1]["pose"].update(
        position_m=[1e-300, -0.03, 1.0]), "objects[1].pose"),
    "object drifting out of the world": (lambda d: (
        d["objects"][0]["motion"].update(velocity_mps=[9000, 0, 0]),
        d["timeline"].update(duration_s=100.0)), "objects[0].motion"),
}


@pytest.mark.parametrize("name", sorted(ATTACKS))
def test_named_attack_is_refused_naming_the_field(name, tmp_path, capsys):
    edit, field = ATTACKS[name]
    rc, err = validate(project_with(tmp_path, edit), capsys=capsys)
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert all(x.startswith("tofradar: error: ") and len(x) <= 620 for x in lines), err
    assert field in err, err
    assert "Traceback" not in err


def test_absurd_size_is_refused_naming_field_and_memory(tmp_path):
    project = Project()
    project.objects = load_project(mesh_free_example()).objects
    project.rig.radar.render_width = project.rig.radar.render_height = 8192
    project.rig.radar.render_supersampling = 2
    problems = check(project, memory_budget_bytes=8 * 2**30)
    assert any(p.startswith("memory:") and "GiB" in p and "rig.radar render" in p
               for p in problems), problems
    cost = estimate_cost(project)
    assert cost.render_pixels >= 16384**2
    assert cost.memory_bytes > 8 * 2**30
    assert "render pixels" in cost.describe()


def mesh_free_example() -> Path:
    from simcore.resources import example_path
    return example_path("point_targets")


def test_bundled_examples_pass_preflight():
    from simcore.resources import example_path
    for name in ("office", "point_targets", "wall", "doppler_back_and_forth"):
        path = example_path(name)
        assert check(load_project(path), base_dir=path.parent) == [], name


def test_validate_reads_no_device_and_no_deep_nesting(tmp_path, capsys):
    rc, err = validate(Path("/dev/zero"), capsys=capsys)
    assert rc == 2 and "not a regular file" in err, err
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 2000 + "]" * 2000)
    rc, err = validate(deep, capsys=capsys)
    assert rc == 2 and "nested" in err or "expected a JSON object" in err
    deep.write_text('{"format_version": 1, "description": ' + "[" * 2000 + "]" * 2000 + "}")
    rc, err = validate(deep, capsys=capsys)
    assert rc == 2 and "nested" in err, err
    big = tmp_path / "big.json"
    with open(big, "wb") as fh:
        fh.truncate(65 * 2**20)
    rc, err = validate(big, capsys=capsys)
    assert rc == 2 and "at most" in err


@pytest.mark.parametrize("args,expected", [
    (["--frames", "1e12"], "expected a positive integer"),
    (["--frames", "1000000000000"], "up to 10000000"),
    (["--seed", str(2**63)], "up to 9223372036854775807"),
    (["--workers", "100000"], "up to 256"),
])
def test_bad_run_options_are_one_line_errors(args, expected, tmp_path, capsys):
    project = project_with(tmp_path, lambda d: None)
    with pytest.raises(SystemExit) as info:
        main(["run", str(project), "--out", str(tmp_path / "o.h5"), "--quiet", *args])
    rc = info.value.code
    err = capsys.readouterr().err
    assert rc == 2 and expected in err, err
    assert err.count("\n") == 1 and err.startswith("tofradar: error: ")
    assert not (tmp_path / "o.h5").exists()


def test_bad_run_values_are_one_line_errors_without_a_file(tmp_path, capsys):
    project = project_with(tmp_path, lambda d: None)
    for args, expected in ((["--duration", "1e300"], "allowed at most 10000000"),
                           (["--scheduler", "http://localhost:80"], "unknown scheme 'http'"),
                           (["--scheduler", "tcp://host"], "HOST:PORT")):
        rc = main(["run", str(project), "--out", str(tmp_path / "o.h5"), "--quiet", *args])
        err = capsys.readouterr().err
        assert rc == 2 and expected in err and err.count("\n") == 1, err
    rc = main(["sweep", str(project), "--vary", "seed=0:1:1e-320", "--out",
               str(tmp_path / "sweep")])
    err = capsys.readouterr().err
    assert rc == 2 and "allowed at most" in err and err.count("\n") == 1, err
    assert not (tmp_path / "o.h5").exists()


def test_run_refuses_a_failed_start_leaves_no_file(tmp_path, capsys):
    project = project_with(tmp_path, lambda d: d["rig"]["radar"].update(bandwidth_hz=1e300))
    out = tmp_path / "o.h5"
    assert main(["run", str(project), "--out", str(out), "--quiet"]) == 2
    assert "rig.radar.bandwidth_hz" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == [project]


def test_unanswering_and_wrong_dask_services_fail_within_the_timeout(tmp_path, capsys):
    import socket
    import threading

    project = project_with(tmp_path, lambda d: None)
    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen()
    http = socket.socket()
    http.bind(("127.0.0.1", 0))
    http.listen()

    def answer_http() -> None:
        conn, _ = http.accept()
        conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
        conn.close()

    threading.Thread(target=answer_http, daemon=True).start()
    try:
        for sock, expected in ((silent, "sent no Dask handshake within 1 s"),
                               (http, "does not speak the Dask protocol")):
            port = sock.getsockname()[1]
            rc = main(["run", str(project), "--out", str(tmp_path / "o.h5"), "--quiet",
                       "--scheduler", f"tcp://127.0.0.1:{port}", "--connect-timeout", "1"])
            err = capsys.readouterr().err
            assert rc == 2 and expected in err, err
            assert not (tmp_path / "o.h5").exists()
    finally:
        silent.close()
        http.close()


def test_internal_errors_are_one_line_and_debug_shows_the_traceback(tmp_path, capsys,
                                                                    monkeypatch):
    import simcore.cli as cli
    import simcore.cli.validate as command

    def boom(args):
        raise ZeroDivisionError("x" * 5000)

    project = project_with(tmp_path, lambda d: None)
    monkeypatch.setattr(command, "cmd_validate", boom)
    rc = cli.main(["validate", str(project)])
    err = capsys.readouterr().err
    assert rc == 1 and err.count("\n") == 1 and len(err) <= 620
    assert "ZeroDivisionError" in err and "--debug" in err
    with pytest.raises(ZeroDivisionError):
        cli.main(["validate", str(project), "--debug"])


def test_validate_is_linear_in_antennas():
    # 256 Rx with one duplicate name: found by a set, named in the message.
    from simcore.scene.radar_config import Antenna, RadarConfig
    rx = [Antenna(name=f"r{i}") for i in range(255)] + [Antenna(name="r7")]
    with pytest.raises(ValueError, match="duplicate antenna names \\['r7'\\]"):
        RadarConfig(rx=rx)


# ------------------------------------------------------------------ saves
def test_save_keeps_mode_and_symlink_and_cleans_stale_temps(tmp_path):
    from simcore.scene import save_project
    from simcore.scene.project_io import STALE_TEMP_AGE_S

    real = tmp_path / "real.json"
    save_project(Project(name="a"), real)
    os.chmod(real, 0o640)
    link = tmp_path / "link.json"
    link.symlink_to(real)
    stale = tmp_path / ".real.json.abc123.tmp"
    stale.write_text("left by a killed save")
    old = os.stat(stale).st_mtime - STALE_TEMP_AGE_S - 10
    os.utime(stale, (old, old))
    save_project(Project(name="b"), link)
    assert link.is_symlink() and link.resolve() == real
    assert load_project(real).name == "b"
    assert (os.stat(real).st_mode & 0o777) == 0o640
    assert not stale.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json", "real.json"]


def test_out_must_be_a_regular_file_and_a_symlink_stays(tmp_path, capsys):
    project = project_with(tmp_path, lambda d: None)
    fifo = tmp_path / "fifo.h5"
    os.mkfifo(fifo)
    for out in ("/dev/null", str(fifo)):
        rc = main(["run", str(project), "--out", out, "--frames", "1", "--quiet",
                   "--overwrite"])
        err = capsys.readouterr().err
        assert rc == 2 and "not a regular file" in err and err.count("\n") == 1, err
    assert Path("/dev/null").is_char_device() and fifo.is_fifo()
    target = tmp_path / "target.h5"
    link = tmp_path / "link.h5"
    assert main(["run", str(project), "--out", str(target), "--frames", "1", "--quiet"]) == 0
    link.symlink_to(target)
    assert main(["run", str(project), "--out", str(link), "--frames", "2", "--quiet",
                 "--overwrite"]) == 0
    assert link.is_symlink()
    with h5py.File(target, "r") as f:
        assert f["meta"].attrs["n_frames"] == 2


def test_object_count_is_capped_before_validation():
    from simcore.scene.project_io import MAX_OBJECTS

    doc = base_project_dict()
    doc["objects"] = [dict(doc["objects"][-1], id=i, name=f"o{i}")
                      for i in range(MAX_OBJECTS + 1)]
    with pytest.raises(ProjectError, match=f"objects: {MAX_OBJECTS + 1} entries; allowed at "
                                           f"most {MAX_OBJECTS}"):
        project_from_dict(doc)


def test_a_run_over_the_time_budget_is_refused_with_the_numbers(tmp_path, capsys):
    """The estimated wall time (frames × the preflight's seconds per frame) against
    --max-hours: refused by name unless --force, before any file is written."""
    from simcore.cli import main
    from simcore.preflight import estimate_cost
    from simcore.resources import example_path
    from simcore.scene import load_project

    path = example_path("wall")
    per_frame = estimate_cost(load_project(path), base_dir=path.parent).seconds_per_frame
    frames = 1000
    hours = 0.5 * per_frame * frames / 3600          # half of what the run needs
    out = tmp_path / "x.h5"
    code = main(["run", str(path), "--out", str(out), "--frames", str(frames),
                 "--max-hours", f"{hours:.9f}"])
    err = capsys.readouterr().err
    assert code != 0 and not out.exists()
    assert len(err.strip().splitlines()) == 1 and "--max-hours" in err
    assert f"{per_frame * frames / 3600:.1f} h" in err
