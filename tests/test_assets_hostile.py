"""Hostile asset files through ``tofradar import``: one error line each, no traceback, no
signal, no hang.

Every file is generated here. They run through the real command line in a child process
(a native crash or a hang would show there as a signal or a timeout, not kill pytest),
one ``tofradar import`` per file, in one interpreter to keep the start-up cost once.
"""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
from gltf_assets import Gltf, box, glb_bytes

ROOT = Path(__file__).resolve().parents[1]

CAMPAIGN = r"""
import contextlib, io, json, sys
from simcore.cli import main
out = []
for path in sys.argv[2:]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        rc = main(["import", path, "--out", sys.argv[1]])
    out.append({"path": path, "rc": rc, "stderr": err.getvalue()})
print(json.dumps(out))
"""


def good() -> Gltf:
    g = Gltf()
    m = g.material("Steel")
    g.node("box", mesh=g.mesh([(*box((1, 1, 1)), m)]))
    return g


def mutated(edit) -> bytes:
    """A good GLB whose JSON document ``edit(doc)`` changed."""
    g = good()
    doc = g.finish()
    edit(doc)
    return glb_bytes(doc, bytes(g.blob))


def with_points(points: np.ndarray, tris: np.ndarray | None = None) -> bytes:
    g = Gltf()
    g.node("bad", mesh=g.mesh([(points, box((1, 1, 1))[1] if tris is None else tris, None)]))
    doc = g.finish()
    for acc in doc["accessors"]:      # NaN bounds could not be written as JSON
        acc.pop("min", None)
        acc.pop("max", None)
    return glb_bytes(doc, bytes(g.blob))


def chain(n: int) -> bytes:
    g = good()
    doc = g.finish()
    doc["nodes"] = [{"name": f"n{i}", "children": [i + 1]} for i in range(n)] + [
        {"name": "leaf", "mesh": 0}]
    doc["scenes"] = [{"nodes": [0]}]
    return glb_bytes(doc, bytes(g.blob))


def instanced(n_nodes: int, n_tris: int) -> bytes:
    g = Gltf()
    k = int(np.ceil(np.sqrt(n_tris / 2))) + 1
    xs, ys = np.meshgrid(np.arange(k, dtype=np.float32), np.arange(k, dtype=np.float32))
    pts = np.stack([xs.ravel(), ys.ravel(), np.zeros(k * k, np.float32)], 1)
    i = (np.arange(k - 1)[:, None] * k + np.arange(k - 1)[None, :]).ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + k], 1), np.stack([i + 1, i + k + 1, i + k],
                                                                   1)]).astype(np.uint32)
    mesh = g.mesh([(pts * 0.01, tris, None)])
    for j in range(n_nodes):
        g.node(f"copy{j}", mesh=mesh, translation=[0, 0, float(j)])
    return g.glb()


def hostile_files(folder: Path) -> list[Path]:
    """Write the corpus; returns the paths."""
    secret = folder.parent / "secret.bin"
    secret.write_bytes(b"\0" * 4096)
    good_doc = good()
    files: dict[str, bytes | str] = {
        "empty.glb": b"",
        "random.glb": np.random.default_rng(1).bytes(5000),
        "text.gltf": "hello, this is not glTF",
        "png.glb": b"\x89PNG\r\n\x1a\n" + b"\0" * 100,
        "wrong_magic.glb": b"XXXX" + good_doc.glb()[4:],
        "version1.glb": good_doc.glb()[:4] + struct.pack("<I", 1) + good_doc.glb()[8:],
        "truncated.glb": good_doc.glb()[:-17],
        "length_lies.glb": good_doc.glb()[:8] + struct.pack("<I", 10**9) + good_doc.glb()[12:],
        "chunk_huge.glb": good_doc.glb()[:12] + struct.pack("<I", 2**31) + good_doc.glb()[16:],
        "bin_first.glb": struct.pack("<III", 0x46546C67, 2, 28) + struct.pack(
            "<II", 8, 0x004E4942) + b"\0" * 8,
        "bad_json.glb": struct.pack("<III", 0x46546C67, 2, 32) + struct.pack(
            "<II", 12, 0x4E4F534A) + b"{not json   ",
        "array.gltf": "[]",
        "version_1.gltf": json.dumps({"asset": {"version": "1.0"}}),
        "no_asset.gltf": json.dumps({"nodes": []}),
        "deep.gltf": "[" * 100_000 + "]" * 100_000,
        "nan_constant.gltf": '{"asset": {"version": "2.0"}, "nodes": [{"scale": [NaN, 1, 1]}]}',
        "no_meshes.gltf": json.dumps({"asset": {"version": "2.0"}, "nodes": [{"name": "x"}]}),
        "absurd_count.glb": mutated(lambda d: d["accessors"][0].update(count=2**31)),
        "count_past_view.glb": mutated(lambda d: d["accessors"][1].update(count=300)),
        "view_past_buffer.glb": mutated(lambda d: d["bufferViews"][0].update(byteLength=10**6)),
        "negative_offset.glb": mutated(lambda d: d["bufferViews"][0].update(byteOffset=-4)),
        "buffer_too_long.glb": mutated(lambda d: d["buffers"][0].update(byteLength=10**6)),
        "stride_3.glb": mutated(lambda d: d["bufferViews"][0].update(byteStride=3)),
        "draco.glb": mutated(lambda d: d.update(
            extensionsRequired=["KHR_draco_mesh_compression"])),
        "sparse.glb": mutated(lambda d: d["accessors"][0].update(sparse={"count": 1})),
        "int_positions.glb": mutated(lambda d: d["accessors"][0].update(componentType=5121)),
        "indices_not_3.glb": mutated(lambda d: d["accessors"][1].update(count=35)),
        "cycle.glb": mutated(lambda d: d.update(nodes=[{"children": [1]}, {"children": [0],
                                                                         "mesh": 0}])),
        "two_parents.glb": mutated(lambda d: d.update(
            nodes=[{"children": [2]}, {"children": [2]}, {"mesh": 0}],
            scenes=[{"nodes": [0, 1]}])),
        "child_out_of_range.glb": mutated(lambda d: d["nodes"][0].update(children=[99])),
        "mesh_out_of_range.glb": mutated(lambda d: d["nodes"][0].update(mesh=7)),
        "material_out_of_range.glb": mutated(
            lambda d: d["meshes"][0]["primitives"][0].update(material=5)),
        "huge_scale.glb": mutated(lambda d: d["nodes"][0].update(scale=[1e300, 1, 1])),
        "string_matrix.glb": mutated(lambda d: d["nodes"][0].update(matrix="eye")),
        "zero_scale.glb": mutated(lambda d: d["nodes"][0].update(scale=[0, 0, 0])),
        "bad_quaternion.glb": mutated(lambda d: d["nodes"][0].update(rotation=[0, 0, 0, 0])),
        "scene_out_of_range.glb": mutated(lambda d: d.update(scene=3)),
        "nan_points.glb": with_points(np.full((8, 3), np.nan, np.float32)),
        "inf_points.glb": with_points(np.full((8, 3), np.inf, np.float32)),
        "huge_points.glb": with_points(np.full((8, 3), 1e30, np.float32)),
        "index_out_of_range.glb": with_points(box((1, 1, 1))[0], np.full((12, 3), 10**6,
                                                                        np.uint32)),
        "deep_chain.glb": chain(1000),
        "too_many_nodes.glb": mutated(lambda d: d.update(nodes=[{}] * 100_001)),
        "too_many_triangles.glb": instanced(41, 100_000),
        "data_uri_not_base64.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": "data:application/octet-stream;base64,@@@@"}]}),
        "data_uri_huge.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": "data:application/octet-stream;base64,"
             + "A" * (65 * 2**20)}]}),
        "missing_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": len(good_doc.blob), "uri": "nowhere.bin"}]}),
        "outside_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": "../secret.bin"}]}),
        "absolute_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": str(secret)}]}),
        "url_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": "http://127.0.0.1:9/x.bin"}]}),
        "file_url_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": f"file://{secret}"}]}),
        "device_buffer.gltf": json.dumps({**good_doc.finish(), "buffers": [
            {"byteLength": 100, "uri": "../../../../../../../dev/zero"}]}),
        "obj_out_of_range.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n",
        "obj_nan.obj": "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "obj_words.obj": "v a b c\nf 1 2 3\n",
        "obj_index_zero.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "obj_empty.obj": "# nothing\n",
        "unknown.fbx": "Kaydara FBX Binary",
    }
    paths = []
    for name, data in files.items():
        path = folder / name
        if isinstance(data, str):
            path.write_text(data)
        else:
            path.write_bytes(data)
        paths.append(path)
    (folder / "dir.glb").mkdir()
    fifo = folder / "fifo.glb"
    os.mkfifo(fifo)
    loop = folder / "loop.glb"
    loop.symlink_to(loop)
    return [*paths, folder / "dir.glb", fifo, loop, folder / "does_not_exist.glb"]


EXPECTED = {
    "nan_points.glb": "NaN", "huge_points.glb": "exceeds", "outside_buffer.gltf": "outside",
    "device_buffer.gltf": "outside", "url_buffer.gltf": "URLs are refused",
    "absurd_count.glb": "count", "too_many_triangles.glb": "triangles in the scene",
    "data_uri_huge.gltf": "bytes; at most", "truncated.glb": "truncated",
    "index_out_of_range.glb": "out of range", "cycle.glb": "child",
    "deep_chain.glb": "deeper", "draco.glb": "extensions", "missing_buffer.gltf": "No such file",
}


def test_hostile_assets_give_one_error_line_each(tmp_path):
    folder = tmp_path / "assets"
    folder.mkdir()
    paths = hostile_files(folder)
    assert len(paths) >= 30
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-c", CAMPAIGN, str(tmp_path / "out.json"),
                           *map(str, paths)], capture_output=True, text=True, timeout=600,
                          env=env, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]          # no signal, no crash
    results = json.loads(proc.stdout.strip().splitlines()[-1])
    assert len(results) == len(paths)
    problems = []
    for r in results:
        lines = r["stderr"].strip().splitlines()
        if (r["rc"] != 2 or len(lines) != 1 or not lines[0].startswith("tofradar: error: ")
                or "Traceback" in r["stderr"] or "--debug" in r["stderr"]):
            problems.append(f"{Path(r['path']).name}: rc {r['rc']}: {r['stderr'][:300]!r}")
    assert not problems, "\n".join(problems)
    # The line names what is wrong.
    said = {Path(r["path"]).name: r["stderr"] for r in results}
    for name, words in EXPECTED.items():
        assert words in said[name], (name, said[name])
    assert not (tmp_path / "out.json").exists()


def test_the_real_command_refuses_a_file_in_its_own_process(tmp_path):
    bad = tmp_path / "x.glb"
    bad.write_bytes(b"glTF" + b"\xff" * 40)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "simcore.cli", "import", str(bad), "--out",
                           str(tmp_path / "p.json")], capture_output=True, text=True,
                          timeout=120, env=env)
    assert proc.returncode == 2
    assert proc.stderr.startswith("tofradar: error: x.glb: ")
    assert len(proc.stderr.strip().splitlines()) == 1
