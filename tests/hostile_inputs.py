"""Builders of hostile inputs of the five new kinds, each made by a script from a valid one.

Every builder writes its files into a folder and returns the command line that reads
them and the expected outcome: ``OK`` (accepted) or a text the one-line refusal must
contain (the file, the field or the option it names). The valid inputs are tiny, so the
accepted ones run in milliseconds.
"""

from __future__ import annotations

import copy
import json
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

OK = "OK"
Case = Callable[[Path], tuple[list[str], str]]

# ------------------------------------------------------------------------------ BVH
_JOINTS = [("Hips", -1, (0, 0, 0)), ("LowerBack", 0, (0, 10, 0)), ("Spine1", 1, (0, 20, 0)),
           ("Neck", 2, (0, 20, 0)), ("Head", 3, (0, 10, 0)),
           ("LeftUpLeg", 0, (9, -5, 0)), ("LeftLeg", 5, (0, -45, 0)),
           ("LeftFoot", 6, (0, -43, 0)),
           ("RightUpLeg", 0, (-9, -5, 0)), ("RightLeg", 8, (0, -45, 0)),
           ("RightFoot", 9, (0, -43, 0))]


def bvh_text(*, frames: int = 3, frame_time: str = "0.0333", scale: float = 1.0,
             root: Callable[[int], tuple[float, float, float]] | None = None,
             header_frames: str | None = None, n_joints_extra: int = 0) -> str:
    """A CMU-named clip (cm), its root walking 1 cm a frame along z."""
    lines = ["HIERARCHY"]

    def emit(k: int, depth: int) -> None:
        name, _, off = _JOINTS[k]
        pad = "  " * depth
        lines.append(f"{pad}{'ROOT' if k == 0 else 'JOINT'} {name}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET " + " ".join(f"{v * scale:g}" for v in off))
        lines.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
                     "Yrotation" if k == 0 else f"{pad}  CHANNELS 3 Zrotation Xrotation "
                     "Yrotation")
        kids = [c for c, j in enumerate(_JOINTS) if j[1] == k]
        for c in kids:
            emit(c, depth + 1)
        if k == 0:
            for e in range(n_joints_extra):
                lines.append(f"{pad}  JOINT Extra{e}\n{pad}  {{\n{pad}    OFFSET 0 1 0\n"
                             f"{pad}    CHANNELS 3 Zrotation Xrotation Yrotation\n"
                             f"{pad}    End Site\n{pad}    {{\n{pad}      OFFSET 0 1 0\n"
                             f"{pad}    }}\n{pad}  }}")
        if not kids:
            lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET 0 5 0", f"{pad}  }}"])
        lines.append(f"{pad}}}")

    emit(0, 0)
    channels = 6 + 3 * (len(_JOINTS) - 1 + n_joints_extra)
    lines += ["MOTION", f"Frames: {header_frames or frames}", f"Frame Time: {frame_time}"]
    for f in range(frames):
        x, y, z = root(f) if root else (0.0, 93.0 * scale, float(f))
        lines.append(" ".join(f"{v:g}" for v in [x, y, z] + [0.0] * (channels - 3)))
    return "\n".join(lines) + "\n"


def person_project(clip: str, *, position: tuple[float, float, float] = (2.0, 0.0, 0.0)
                   ) -> dict[str, Any]:
    """wall.json with one person playing ``clip``."""
    from simcore.resources import example_path

    doc = json.loads(Path(example_path("wall")).read_text())
    doc["objects"] = [{"id": 1, "name": "p", "pose": {"position_m": list(position)},
                       "geometry": {"kind": "person", "motion": {"bvh": {"path": clip}}}}]
    return doc


def _bvh(text: str | bytes | None, *, clip: str = "clip.bvh", special: str | None = None,
         extra: list[str] | None = None, expect: str = "clip.bvh",
         project: Callable[[str], dict[str, Any]] = person_project) -> Case:
    def build(d: Path) -> tuple[list[str], str]:
        (d / "sub").mkdir()
        path = d / "sub" / "clip.bvh"
        if special == "fifo":
            os.mkfifo(path)
        elif special == "zero":
            path.symlink_to("/dev/zero")
        elif special == "dir":
            path.mkdir()
        elif special == "loop":
            path.symlink_to(d / "sub" / "clip.bvh")
        elif isinstance(text, bytes):
            path.write_bytes(text)
        elif text is not None:
            path.write_text(text)
        (d / "clip.bvh").write_text(bvh_text())          # a good clip outside sub/
        (d / "sub" / "p.json").write_text(json.dumps(project(clip)))
        return ["validate", str(d / "sub" / "p.json"), *(extra or [])], expect
    return build


def bvh_cases() -> dict[str, Case]:
    good = bvh_text()
    zero = re.sub(r"OFFSET [-0-9.e]+ [-0-9.e]+ [-0-9.e]+", "OFFSET 0 0 0", good)
    cases: dict[str, Case] = {
        "good": _bvh(good, expect=OK),
        "good_crlf": _bvh(good.replace("\n", "\r\n"), expect=OK),
        "good_2_frames_loop": _bvh(bvh_text(frames=2), expect=OK),
        "good_one_frame": _bvh(bvh_text(frames=1), expect=OK),
        "good_running_8mps": _bvh(bvh_text(frames=3, root=lambda f: (0, 93, 800 * f / 30)),
                                  expect=OK),
        "frames_at_limit_declared": _bvh(bvh_text(header_frames="100000"),
                                         expect="declares 100000 frames but has 3"),
        "frames_over_limit": _bvh(bvh_text(header_frames="100001"),
                                  expect="frame count 100001; allowed 1–100000"),
        "frames_1e6": _bvh(bvh_text(header_frames="1000000"), expect="allowed 1–100000"),
        "frames_zero": _bvh(bvh_text(header_frames="0"), expect="frame count 0"),
        "frames_negative": _bvh(bvh_text(header_frames="-3"), expect="not a whole number"),
        "frames_fraction": _bvh(bvh_text(header_frames="2.5"), expect="not a whole number"),
        "frames_huge_digits": _bvh(bvh_text(header_frames="9" * 5000),
                                   expect="not a whole number"),
        "memory_over_budget": _bvh(bvh_text(header_frames="100000", n_joints_extra=240),
                                   expect="GiB to read; the budget is 2 GiB"),
        "frame_time_zero": _bvh(bvh_text(frame_time="0"), expect="frame time 0 s"),
        "frame_time_tiny": _bvh(bvh_text(frame_time="1e-300"), expect="frame time"),
        "frame_time_huge": _bvh(bvh_text(frame_time="1e300"), expect="frame time 1e300 s"),
        "frame_time_nan": _bvh(bvh_text(frame_time="nan"), expect="frame time nan s"),
        "frame_time_word": _bvh(bvh_text(frame_time="fast"), expect="frame time 'fast'"),
        "value_nan": _bvh(good.replace("\n0 93 1 ", "\nnan 93 1 "), expect="frame 1"),
        "value_inf": _bvh(good.replace("\n0 93 1 ", "\ninf 93 1 "), expect="frame 1"),
        "value_huge": _bvh(good.replace("\n0 93 1 ", "\n1e300 93 1 "), expect="frame 1"),
        "offset_nan": _bvh(good.replace("OFFSET 0 10 0", "OFFSET nan 10 0"), expect="line"),
        "zero_length_bones": _bvh(zero, expect="LeftUpLeg → LeftLeg is 0 units long"),
        "millimetre_skeleton": _bvh(bvh_text(scale=1e-4, root=lambda f: (0, 0, 4e4 * f)),
                                    expect="joint 'Hips' at frame 2 puts the person"),
        "teleporting_root": _bvh(bvh_text(root=lambda f: (0, 93, 1e4 * f)),
                                 expect="allowed at most 50 m/s"),
        "values_missing": _bvh(good.replace("\n0 93 1 0", "\n0 93 1"), expect="frame 1 has"),
        "truncated_half": _bvh(good[: len(good) // 2], expect="clip.bvh"),
        "truncated_motion": _bvh(good[: good.index("MOTION") + 12], expect="clip.bvh"),
        "truncated_last_line": _bvh(good[:-20], expect="clip.bvh"),
        "empty": _bvh("", expect="clip.bvh"),
        "binary": _bvh(bytes(range(256)) * 4, expect="clip.bvh"),
        "utf16": _bvh(good.encode("utf-16"), expect="clip.bvh"),
        "brace_without_joint": _bvh(re.sub(r"\n *JOINT Head\n", "\n", good),
                                    expect="clip.bvh"),
        "nul_bytes": _bvh(good.replace("Hips", "Hi\0ps"), expect="NUL"),
        "too_many_joints": _bvh(bvh_text(n_joints_extra=250), expect="more than 256 joints"),
        "missing_legs": _bvh(good.replace("LeftUpLeg", "Thing1").replace("LeftLeg", "Thing2"),
                             expect="BVH file clip.bvh: BVH joints for thigh_l, shin_l not found"),
        "fifo": _bvh(None, special="fifo", expect="not a regular file"),
        "dev_zero_symlink": _bvh(None, special="zero", expect="outside the project folder"),
        "dev_zero_symlink_allowed": _bvh(None, special="zero", extra=["--allow-outside-paths"],
                                         expect="not a regular file"),
        "directory": _bvh(None, special="dir", expect="not a regular file"),
        "symlink_loop": _bvh(None, special="loop", expect="symlink loop"),
        "missing_file": _bvh(None, expect="No such file"),
        "parent_escape": _bvh(None, clip="../clip.bvh", expect="outside the project folder"),
        "parent_escape_allowed": _bvh(None, clip="../clip.bvh", extra=["--allow-outside-paths"],
                                      expect=OK),
        "absolute_outside": _bvh(None, clip="/etc/hostname", expect="outside the project"),
        "far_person": _bvh(bvh_text(root=lambda f: (0, 93, 5e6 * f / 1e4)),
                           project=lambda c: person_project(c, position=(99_999.0, 0, 0)),
                           expect="from the origin"),
    }
    return cases


# ----------------------------------------------------------------------- scenario specs
def spec_doc() -> dict[str, Any]:
    """A valid spec over the point-target example."""
    return {"name": "fam", "base": "point_targets",
            "vary": {"objects[0].pose.position_m[0]": {"uniform": [2.0, 3.0]},
                     "objects[0].pose.position_m[1]": {"normal": {"mean": 0.0, "std": 0.2,
                                                                  "min": -0.5, "max": 0.5}}}}


def _spec(edit: Callable[[dict[str, Any]], Any] | None = None, *, expect: str,
          raw: str | bytes | None = None, name: str = "spec.json", special: str | None = None,
          count: int = 3, extra: list[str] | None = None,
          prepare: Callable[[Path], None] | None = None) -> Case:
    def build(d: Path) -> tuple[list[str], str]:
        path = d / name
        if special == "fifo":
            os.mkfifo(path)
        elif special == "zero":
            path.symlink_to("/dev/zero")
        elif special == "dir":
            path.mkdir()
        elif special == "none":
            pass
        elif isinstance(raw, bytes):
            path.write_bytes(raw)
        elif raw is not None:
            path.write_text(raw)
        else:
            doc = spec_doc()
            if edit is not None:
                doc = edit(doc) or doc
            path.write_text(json.dumps(doc))
        if prepare is not None:
            prepare(d)
        return ["generate", str(path), "--count", str(count), "--out", str(d / "out"),
                "--quiet", *(extra or [])], expect
    return build


def _set(path: str, dist: Any) -> Callable[[dict[str, Any]], None]:
    return lambda doc: doc["vary"].__setitem__(path, dist)


def _base_with_mesh(d: Path) -> None:
    from simcore.resources import example_path

    doc = json.loads(Path(example_path("point_targets")).read_text())
    (d / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    doc["objects"].append({"id": 99, "name": "m", "geometry": {"kind": "mesh",
                           "path": "tri.obj"}, "pose": {"position_m": [3, 0, 0]}})
    (d / "base.json").write_text(json.dumps(doc))


def spec_cases() -> dict[str, Case]:
    yaml_bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
        f"*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}]\n"
        for i in range(8))
    deep: Any = 1
    for _ in range(40):
        deep = [deep]
    return {
        "good": _spec(expect=OK),
        "good_yaml": _spec(raw="name: fam\nbase: point_targets\nvary:\n  "
                               "objects[0].pose.position_m[0]: {uniform: [2.0, 3.0]}\n",
                           name="spec.yaml", expect=OK),
        "good_choice_objects": _spec(_set("objects[0].material", {"choice": ["aluminium"]}),
                                     expect=OK),
        "normal_min_above_max": _spec(_set("objects[0].pose.position_m[1]", {"normal": {
            "mean": 0, "std": 1, "min": 2, "max": -2}}), expect="min 2 is above max -2"),
        "uniform_reversed": _spec(_set("objects[0].pose.position_m[0]", {"uniform": [3, 2]}),
                                  expect="low <= high"),
        "uniform_nan_token": _spec(raw=json.dumps(spec_doc()).replace("2.0, 3.0", "NaN, 3.0"),
                                   expect="spec.json"),
        "uniform_infinity": _spec(raw=json.dumps(spec_doc()).replace("3.0]", "Infinity]"),
                                  expect="spec.json"),
        "uniform_huge": _spec(_set("objects[0].pose.position_m[0]", {"uniform": [1e300, 1e300]}),
                              expect="scene 0"),
        "uniform_overflows": _spec(_set("objects[0].pose.position_m[0]", {"uniform": [
            -1.7e308, 1.7e308]}), expect="overflows"),
        "uniform_strings": _spec(_set("objects[0].pose.position_m[0]", {"uniform": ["a", "b"]}),
                                 expect="vary.objects[0].pose.position_m[0]"),
        "uniform_three": _spec(_set("objects[0].pose.position_m[0]", {"uniform": [1, 2, 3]}),
                               expect="vary.objects[0].pose.position_m[0]"),
        "normal_negative_std": _spec(_set("objects[0].pose.position_m[0]", {"normal": {
            "mean": 0, "std": -1}}), expect="std"),
        "two_kinds": _spec(_set("objects[0].pose.position_m[0]", {"uniform": [1, 2],
                                                                  "choice": [1]}),
                           expect="a distribution is one of"),
        "choice_empty": _spec(_set("objects[0].material", {"choice": []}), expect="choice"),
        "choice_1001": _spec(_set("objects[0].material", {"choice": ["aluminium"] * 1001}),
                             expect="choice"),
        "choice_bad_material": _spec(_set("objects[0].material", {"choice": ["unobtainium"]}),
                                     expect="unobtainium"),
        "unknown_field_path": _spec(_set("objects[0].nonsense", {"uniform": [1, 2]}),
                                    expect="objects[0].nonsense"),
        "index_out_of_range": _spec(_set("objects[999].pose.position_m[0]", {"uniform": [1, 2]}),
                                    expect="objects[999]"),
        "ten_million_frames": _spec(_set("timeline.duration_s", {"choice": [1e6]}),
                                    expect="scene 0 would not run"),
        "leaves_the_world": _spec(lambda d: d["vary"].update({
            "objects[0].motion.velocity_mps": {"choice": [[9000, 0, 0]]},
            "timeline.duration_s": {"choice": [100.0]}}), expect="scene 0 would not run"),
        "mesh_outside_folder": _spec(lambda d: {**d, "base": "base.json"}, prepare=_base_with_mesh,
                                     expect="mesh file not found"),
        "unknown_key": _spec(lambda d: {**d, "extra": 1}, expect="extra"),
        "wrong_format": _spec(lambda d: {**d, "format": "other/9"}, expect="format"),
        "name_missing": _spec(lambda d: {k: v for k, v in d.items() if k != "name"},
                              expect="name"),
        "base_unknown": _spec(lambda d: {**d, "base": "nowhere"}, expect="base 'nowhere'"),
        "base_fifo": _spec(lambda d: {**d, "base": "fifo.json"},
                           prepare=lambda d: os.mkfifo(d / "fifo.json"),
                           expect="base 'fifo.json' is not a regular file"),
        "not_an_object": _spec(raw="[1, 2, 3]", expect="a spec is an object"),
        "truncated": _spec(raw=json.dumps(spec_doc())[:40], expect="spec.json"),
        "empty": _spec(raw="", expect="spec.json"),
        "binary": _spec(raw=bytes(range(256)), expect="spec.json"),
        "too_deep": _spec(lambda d: {**d, "vary": {"x": {"choice": [deep]}}},
                          expect="nested deeper than 32"),
        "yaml_bomb": _spec(raw=yaml_bomb, name="spec.yaml", expect="more than 200000 values"),
        "yaml_python_tag": _spec(raw="name: !!python/object/apply:os.system ['true']\n",
                                 name="spec.yaml", expect="spec.yaml"),
        "too_large": _spec(raw=" " * (1 << 20) + "{}", expect="at most 1048576"),
        "fifo": _spec(special="fifo", expect="not a regular file"),
        "dev_zero_symlink": _spec(special="zero", expect="not a regular file"),
        "directory": _spec(special="dir", expect="not a regular file"),
        "missing": _spec(raw=None, special="none", expect="no such spec file"),
        "furniture_without_room": _spec(lambda d: {**d, "furniture": [{"piece": "desk",
                                                                       "count": [1, 1]}]},
                                        expect="(spec): furniture and people need a 'room'"),
        "furniture_count_reversed": _spec(lambda d: {**d, "room": {"x_m": [0, 5], "y_m": [-2, 2]},
                                                     "furniture": [{"piece": "desk",
                                                                    "count": [3, 1]}]},
                                          expect="count"),
        "room_reversed": _spec(lambda d: {**d, "room": {"x_m": [5, 0], "y_m": [-2, 2]}},
                               expect="room"),
    }


# ----------------------------------------------------------------------------- assets
def asset_cases() -> dict[str, Case]:
    from gltf_assets import Gltf, box, glb_bytes

    def good_gltf() -> tuple[dict[str, Any], bytes]:
        g = Gltf()
        m = g.material("Steel")
        g.node("box", mesh=g.mesh([(*box((1, 1, 1)), m)]))
        return g.finish(), bytes(g.blob)

    def glb(edit: Callable[[dict[str, Any]], Any] | None = None, *, cut: int | None = None,
            expect: str) -> Case:
        def build(d: Path) -> tuple[list[str], str]:
            doc, blob = good_gltf()
            if edit is not None:
                edit(doc)
            data = glb_bytes(doc, blob)
            (d / "a.glb").write_bytes(data if cut is None else data[:cut])
            return ["import", str(d / "a.glb"), "--out", str(d / "p.json")], expect
        return build

    def gltf_file(uri: str, *, prepare: Callable[[Path], None] | None = None,
                  expect: str, extra: list[str] | None = None) -> Case:
        def build(d: Path) -> tuple[list[str], str]:
            doc, blob = good_gltf()
            (d / "sub").mkdir()
            (d / "sub" / "buf.bin").write_bytes(blob)
            (d / "outside.bin").write_bytes(blob)
            if prepare is not None:
                prepare(d)
            doc["buffers"] = [{"byteLength": len(blob), "uri": uri}]
            (d / "sub" / "a.gltf").write_text(json.dumps(doc))
            return ["import", str(d / "sub" / "a.gltf"), "--out", str(d / "p.json"),
                    *(extra or [])], expect
        return build

    def obj(text: str | bytes, *, expect: str, special: str | None = None) -> Case:
        def build(d: Path) -> tuple[list[str], str]:
            path = d / "a.obj"
            if special == "fifo":
                os.mkfifo(path)
            elif special == "zero":
                path.symlink_to("/dev/zero")
            elif isinstance(text, bytes):
                path.write_bytes(text)
            else:
                path.write_text(text)
            return ["import", str(path), "--out", str(d / "p.json")], expect
        return build

    def setp(*keys: Any, value: Any) -> Callable[[dict[str, Any]], None]:
        def edit(doc: dict[str, Any]) -> None:
            node = doc
            for k in keys[:-1]:
                node = node[k]
            node[keys[-1]] = value
        return edit

    tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    return {
        "good_glb": glb(expect=OK),
        "good_obj": obj(tri, expect=OK),
        "good_gltf_buffer_beside": gltf_file("buf.bin", expect=OK),
        "glb_truncated_header": glb(cut=10, expect="a.glb"),
        "glb_truncated_json": glb(cut=40, expect="a.glb"),
        "glb_truncated_binary": glb(cut=-8, expect="a.glb"),
        "accessor_count_huge": glb(setp("accessors", 0, "count", value=2**31), expect="a.glb"),
        "accessor_count_negative": glb(setp("accessors", 0, "count", value=-1), expect="a.glb"),
        "accessor_count_string": glb(setp("accessors", 0, "count", value="many"),
                                     expect="a.glb"),
        "accessor_count_float": glb(setp("accessors", 0, "count", value=1.5), expect="a.glb"),
        "view_offset_huge": glb(setp("bufferViews", 0, "byteOffset", value=10**12),
                                expect="a.glb"),
        "view_length_nan": glb(setp("bufferViews", 0, "byteLength", value=float("nan")),
                               expect="a.glb"),
        "buffer_length_huge": glb(setp("buffers", 0, "byteLength", value=2**40), expect="a.glb"),
        "node_translation_huge": glb(setp("nodes", 0, "translation", value=[1e300, 0, 0]),
                                     expect="a.glb"),
        "node_beyond_project_world": glb(setp("nodes", 0, "translation", value=[5e5, 0, 0]),
                                         expect="a project allows ±100000 m"),
        "view_buffer_list": glb(setp("bufferViews", 0, "buffer", value=[0]),
                                expect="bufferView.buffer '[0]' is not an index"),
        "node_scale_nan": glb(setp("nodes", 0, "scale", value=[float("nan"), 1, 1]),
                              expect="a.glb"),
        "node_rotation_zero": glb(setp("nodes", 0, "rotation", value=[0, 0, 0, 0]),
                                  expect="a.glb"),
        "node_matrix_singular": glb(setp("nodes", 0, "matrix", value=[0] * 16), expect="a.glb"),
        "node_matrix_short": glb(setp("nodes", 0, "matrix", value=[1, 0, 0]), expect="a.glb"),
        "node_self_child": glb(setp("nodes", 0, "children", value=[0]), expect="a.glb"),
        "nodes_not_list": glb(setp("nodes", value={"a": 1}), expect="a.glb"),
        "mesh_index_out_of_range": glb(setp("nodes", 0, "mesh", value=99), expect="a.glb"),
        "primitive_mode_points": glb(setp("meshes", 0, "primitives", 0, "mode", value=0),
                                     expect="no mesh node with triangles"),
        "material_index_bad": glb(setp("meshes", 0, "primitives", 0, "material", value=-5),
                                  expect="a.glb"),
        "scene_index_bad": glb(setp("scene", value=7), expect="a.glb"),
        "many_nodes": glb(setp("nodes", value=[{}] * 100_001), expect="a.glb"),
        "uri_parent_escape": gltf_file("../outside.bin", expect="outside the asset's folder"),
        "uri_parent_escape_allowed": gltf_file("../outside.bin", extra=["--allow-outside-paths"],
                                               expect=OK),
        "uri_dev_zero_allowed": gltf_file(
            "z.bin", prepare=lambda d: (d / "sub" / "z.bin").symlink_to("/dev/zero"),
            extra=["--allow-outside-paths"], expect="not a regular file"),
        "uri_absolute": gltf_file("/etc/hostname", expect="not a relative path"),
        "uri_url": gltf_file("http://example.com/x.bin", expect="not a relative path"),
        "uri_fifo": gltf_file("fifo.bin", prepare=lambda d: os.mkfifo(d / "sub" / "fifo.bin"),
                              expect="not a regular file"),
        "uri_dev_zero_symlink": gltf_file(
            "z.bin", prepare=lambda d: (d / "sub" / "z.bin").symlink_to("/dev/zero"),
            expect="outside the asset's folder"),
        "uri_missing": gltf_file("nothing.bin", expect="a.gltf"),
        "obj_nan": obj("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", expect="a.obj"),
        "obj_huge": obj("v 1e300 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", expect="a.obj"),
        "obj_index_out_of_range": obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n", expect="a.obj"),
        "obj_negative_index": obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n", expect="a.obj"),
        "obj_huge_index_digits": obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " + "9" * 5000 + "\n",
                                     expect="a.obj"),
        "obj_words": obj("v a b c\nf 1 2 3\n", expect="a.obj"),
        "obj_empty": obj("", expect="a.obj"),
        "obj_binary": obj(bytes(range(256)) * 8, expect="a.obj"),
        "obj_fifo": obj("", special="fifo", expect="not a regular file"),
        "obj_dev_zero": obj("", special="zero", expect="not a regular file"),
    }


# -------------------------------------------------------------------------- recordings
SHAPE = {"aaf_cutoff_Hz": 500000, "chirp_repetition_time_s": 0.000591,
         "end_frequency_Hz": 63500000000, "frame_repetition_time_s": 0.0773,
         "hp_cutoff_Hz": 80000, "if_gain_dB": 23, "mimo_mode": "off",
         "num_chirps_per_frame": 4, "num_samples_per_chirp": 32, "rx_antennas": [1, 2, 3],
         "sample_rate_Hz": 2000000, "start_frequency_Hz": 58000000000, "tx_antennas": [1],
         "tx_power_level": 31}


def write_recording(d: Path, *, shape: dict[str, Any] | None = None,
                    codes: np.ndarray | None = None, config_text: str | None = None,
                    meta: Any = None) -> Path:
    """A tiny valid recording (2 frames of a tone) under ``d/rec``, with edits."""
    stream = d / "rec" / "RadarIfxAvian_00"
    stream.mkdir(parents=True)
    settings = dict(SHAPE if shape is None else shape)
    (stream / "config.json").write_text(
        config_text if config_text is not None
        else json.dumps({"device_config": {"fmcw_single_shape": settings}}))
    (stream / "meta.json").write_text(json.dumps({"adc_resolution": 12} if meta is None
                                                 else meta))
    if codes is None:
        tone = 2048 + 200 * np.cos(2 * np.pi * 6 * np.arange(32) / 32)
        codes = np.broadcast_to(np.rint(tone), (2, 3, 4, 32)).astype(np.uint16)
    np.save(stream / "radar.npy", codes)
    return stream


def _rec(*, expect: str, edit: Callable[[dict[str, Any]], Any] | None = None,
         codes: np.ndarray | None = None, after: Callable[[Path, Path], None] | None = None,
         config_text: str | None = None, meta: Any = None, project: bool = False,
         extra: list[str] | None = None) -> Case:
    def build(d: Path) -> tuple[list[str], str]:
        shape = copy.deepcopy(SHAPE)
        if edit is not None:
            edit(shape)
        stream = write_recording(d, shape=shape, codes=codes, config_text=config_text,
                                 meta=meta)
        if after is not None:
            after(d, stream)
        argv = ["convert", str(d / "rec"), "--to", str(d / "out.h5")]
        if project:
            argv += ["--project", str(d / "ro" / "p.json")]
        return [*argv, *(extra or [])], expect
    return build


def _key(key: str, value: Any) -> Callable[[dict[str, Any]], None]:
    return lambda s: s.__setitem__(key, value)


def _replace(part: str, how: str) -> Callable[[Path, Path], None]:
    def after(d: Path, stream: Path) -> None:
        path = stream / part
        path.unlink()
        if how == "fifo":
            os.mkfifo(path)
        elif how == "zero":
            path.symlink_to("/dev/zero")
        elif how == "dir":
            path.mkdir()
        elif how == "outside":
            (d / "elsewhere").mkdir()
            (d / "elsewhere" / part).write_bytes(b"{}")
            path.symlink_to(d / "elsewhere" / part)
    return after


def recording_cases() -> dict[str, Case]:
    good = np.full((2, 3, 4, 32), 2048, np.uint16)
    cases: dict[str, Case] = {
        "good": _rec(expect=OK),
        "good_flat_codes": _rec(codes=good, expect=OK),
        "good_one_frame": _rec(codes=good[:1], expect=OK),
        "good_tdm_one_tx": _rec(edit=_key("mimo_mode", "tdm"), expect=OK),
        "frame_time_1e-300": _rec(edit=_key("frame_repetition_time_s", 1e-300),
                                  expect="frame_repetition_time_s = 1e-300 s; allowed"),
        "frame_time_1e300": _rec(edit=_key("frame_repetition_time_s", 1e300),
                                 expect="frame_repetition_time_s = 1e+300 s; allowed"),
        "frame_time_zero": _rec(edit=_key("frame_repetition_time_s", 0),
                                expect="frame_repetition_time_s"),
        "frame_time_string": _rec(edit=_key("frame_repetition_time_s", "fast"),
                                  expect="frame_repetition_time_s"),
        "frame_time_nan_token": _rec(config_text=json.dumps({"device_config": {
            "fmcw_single_shape": SHAPE}}).replace("0.0773", "NaN"), expect="config.json"),
        "frame_time_shorter_than_chirps": _rec(edit=_key("frame_repetition_time_s", 0.001),
                                               expect="chirps of 0.000591 s"),
        "chirps_huge": _rec(edit=_key("num_chirps_per_frame", 10**8), expect="config.json"),
        "samples_huge": _rec(edit=_key("num_samples_per_chirp", 10**9), expect="config.json"),
        "frame_memory_over_budget": _rec(edit=lambda s: s.update(
            num_chirps_per_frame=1024, num_samples_per_chirp=8192, sample_rate_Hz=4000000,
            chirp_repetition_time_s=0.003, frame_repetition_time_s=4.0),
            expect="the budget is 2 GiB"),
        "chirps_zero": _rec(edit=_key("num_chirps_per_frame", 0), expect="num_chirps_per_frame"),
        "chirps_bool": _rec(edit=_key("num_chirps_per_frame", True),
                            expect="num_chirps_per_frame"),
        "sample_rate_negative": _rec(edit=_key("sample_rate_Hz", -1), expect="sample_rate_Hz"),
        "frequency_huge": _rec(edit=_key("end_frequency_Hz", 1e300), expect="config.json"),
        "down_chirp": _rec(edit=_key("end_frequency_Hz", 57e9), expect="config.json"),
        "rx_duplicate": _rec(edit=_key("rx_antennas", [1, 1, 2]), expect="rx_antennas"),
        "rx_empty": _rec(edit=_key("rx_antennas", []), expect="rx_antennas"),
        "tx_two_mimo_off": _rec(edit=_key("tx_antennas", [1, 2]), expect="mimo_mode"),
        "unknown_key": _rec(edit=_key("warp_drive", 1), expect="warp_drive"),
        "missing_key": _rec(edit=lambda s: s.pop("sample_rate_Hz"), expect="sample_rate_Hz"),
        "config_not_object": _rec(config_text="[1]", expect="config.json"),
        "config_truncated": _rec(config_text='{"device_config": {"fmcw', expect="config.json"),
        "config_deep": _rec(config_text="[" * 100_000 + "]" * 100_000, expect="config.json"),
        "config_huge_int": _rec(config_text='{"a": ' + "9" * 5000 + "}", expect="config.json"),
        "config_binary": _rec(after=lambda d, s: (s / "config.json").write_bytes(b"\xff\xfe\0"),
                              expect="config.json"),
        "meta_bits_zero": _rec(meta={"adc_resolution": 0}, expect="adc_resolution"),
        "meta_bits_string": _rec(meta={"adc_resolution": "12"}, expect="adc_resolution"),
        "meta_not_object": _rec(meta=[12], expect="meta.json"),
        "codes_beyond_adc": _rec(codes=np.full((2, 3, 4, 32), 5000, np.uint16),
                                 expect="outside the 12-bit ADC range"),
        "codes_float": _rec(codes=np.zeros((2, 3, 4, 32), np.float32), expect="dtype float32"),
        "codes_wrong_shape": _rec(codes=good[:, :2], expect="shape"),
        "codes_3d": _rec(codes=good[0], expect="shape"),
        "codes_fortran": _rec(codes=np.asfortranarray(good), expect="Fortran"),
        "codes_pickled": _rec(after=lambda d, s: np.save(s / "radar.npy", np.array(
            [{"x": 1}], dtype=object), allow_pickle=True), expect="radar.npy"),
        "npy_truncated": _rec(after=lambda d, s: (s / "radar.npy").write_bytes(
            (s / "radar.npy").read_bytes()[:-100]), expect="truncated"),
        "npy_header_only": _rec(after=lambda d, s: (s / "radar.npy").write_bytes(
            (s / "radar.npy").read_bytes()[:128]), expect="truncated"),
        "npy_garbage": _rec(after=lambda d, s: (s / "radar.npy").write_bytes(b"\x93NUMPY" +
                                                                            b"\xff" * 300),
                            expect="radar.npy"),
        "npy_header_claims_more_frames": _rec(after=lambda d, s: (s / "radar.npy").write_bytes(
            (s / "radar.npy").read_bytes().replace(b"(2, 3, 4, 32)", b"(2000, 3, 4, 32)")
            .replace(b"   \n", b"\n", 1)), expect="truncated or damaged"),
        "npy_header_claims_1e8_frames": _rec(after=lambda d, s: (s / "radar.npy").write_bytes(
            (s / "radar.npy").read_bytes().replace(b"(2, 3, 4, 32)", b"(99999999, 3, 4, 32)")
            .replace(b"       \n", b"\n", 1)), expect="frames; allowed at most 10000000"),
        "radar_fifo": _rec(after=_replace("radar.npy", "fifo"), expect="not a regular file"),
        "config_fifo": _rec(after=_replace("config.json", "fifo"), expect="not a regular file"),
        "meta_fifo": _rec(after=_replace("meta.json", "fifo"), expect="not a regular file"),
        "config_dev_zero": _rec(after=_replace("config.json", "zero"),
                                expect="outside the recording folder"),
        "config_dev_zero_allowed": _rec(after=_replace("config.json", "zero"),
                                        extra=["--allow-outside-paths"],
                                        expect="not a regular file"),
        "radar_dev_zero": _rec(after=_replace("radar.npy", "zero"), expect="outside"),
        "config_directory": _rec(after=_replace("config.json", "dir"),
                                 expect="not a regular file"),
        "config_outside": _rec(after=_replace("config.json", "outside"),
                               expect="outside the recording folder"),
        "radar_missing": _rec(after=lambda d, s: (s / "radar.npy").unlink(), expect="missing"),
        "project_folder_missing": _rec(project=True, expect="--project"),
    }
    return cases


# --------------------------------------------------------------------- multi-rig projects
def multi_rig_doc() -> dict[str, Any]:
    """robot_pair.json (two rigs, four sensors) with tiny sensors."""
    from simcore.resources import example_path

    doc = json.loads(Path(example_path("robot_pair")).read_text())
    for rig in [doc["rig"], *doc["rigs"]]:
        for cfg in [rig.get("tof"), rig.get("radar"), *rig["sensors"].values()]:
            if cfg is None:
                continue
            if "width" in cfg:
                cfg.update(width=16, height=12, supersampling=1)
            if "chirps_per_frame" in cfg:
                cfg.update(chirps_per_frame=8, samples_per_chirp=32, render_width=32,
                           render_height=8)
    return doc


def _rig(edit: Callable[[dict[str, Any]], Any], *, expect: str,
         extra: list[str] | None = None) -> Case:
    def build(d: Path) -> tuple[list[str], str]:
        doc = multi_rig_doc()
        doc = edit(doc) or doc
        text = json.dumps(doc, allow_nan=True)
        (d / "p.json").write_text(text)
        return ["validate", str(d / "p.json"), *(extra or [])], expect
    return build


def _at(*keys: Any, value: Any) -> Callable[[dict[str, Any]], None]:
    def edit(doc: dict[str, Any]) -> None:
        node = doc
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = copy.deepcopy(value)
    return edit


def _sensor(key: str, value: Any) -> Callable[[dict[str, Any]], None]:
    return _at("rigs", 0, "sensors", "radar_b", key, value=value)


def rig_cases() -> dict[str, Case]:
    def third_rig(doc: dict[str, Any]) -> None:
        rig = copy.deepcopy(doc["rigs"][0])
        rig["name"] = "robot_c"
        rig["sensors"] = {f"{k}_c": v for k, v in rig["sensors"].items()}
        doc["rigs"].append(rig)

    def many_rigs(n: int) -> Callable[[dict[str, Any]], None]:
        def edit(doc: dict[str, Any]) -> None:
            base = doc["rigs"][0]
            doc["rigs"] = []
            for i in range(n):
                rig = copy.deepcopy(base)
                rig["name"] = f"r{i}"
                rig["sensors"] = {f"s{i}": rig["sensors"]["radar_b"]}
                doc["rigs"].append(rig)
        return edit

    return {
        "good": _rig(lambda d: None, expect=OK),
        "good_third_rig": _rig(third_rig, expect=OK),
        "good_rig_without_sensors": _rig(_at("rigs", 0, "sensors", value={}), expect=OK),
        "good_divider": _rig(_sensor("frame_rate_hz", 5.0), expect=OK),
        "rig_position_huge": _rig(_at("rigs", 0, "pose", "position_m", value=[1e300, 0, 0]),
                                  expect="rigs[0].pose.position_m"),
        "rig_position_nan": _rig(_at("rigs", 0, "pose", "position_m", value=[float("nan"), 0, 0]),
                                 expect="p.json"),
        "rig_position_string": _rig(_at("rigs", 0, "pose", "position_m", value=["a", 0, 0]),
                                    expect="rigs[0].pose.position_m"),
        "rig_position_short": _rig(_at("rigs", 0, "pose", "position_m", value=[0, 0]),
                                   expect="rigs[0].pose.position_m"),
        "rig_rotation_huge": _rig(_at("rigs", 0, "pose", "rotation_deg", value=[0, 0, 1e30]),
                                  expect="rigs[0].pose.rotation_deg"),
        "rig_speed_huge": _rig(_at("rigs", 0, "motion", "velocity_mps", value=[1e9, 0, 0]),
                               expect="rigs[0].motion"),
        "rig_leaves_world": _rig(lambda d: _at("rigs", 0, "motion", "velocity_mps", value=[
            9000, 0, 0])(d) or _at("timeline", "duration_s", value=20.0)(d),
            expect="rigs[0].motion: the rig reaches"),
        "rig_keyframes_teleport": _rig(_at("rigs", 0, "motion", "keyframes", value=[
            {"time_s": 0.0, "position_m": [0, 0, 0]},
            {"time_s": 1e-6, "position_m": [1e5, 0, 0]}]), expect="rigs[0]"),
        "rig_keyframes_unsorted": _rig(_at("rigs", 0, "motion", "keyframes", value=[
            {"time_s": 1.0, "position_m": [0, 0, 0]},
            {"time_s": 0.0, "position_m": [1, 0, 0]}]), expect="rigs[0].motion"),
        "rig_name_empty": _rig(_at("rigs", 0, "name", value=""), expect="rigs[0].name"),
        "rig_name_nul": _rig(_at("rigs", 0, "name", value="a\0b"), expect="rigs[0].name"),
        "rig_not_object": _rig(_at("rigs", 0, value=[1, 2]), expect="rigs[0]"),
        "rigs_not_list": _rig(_at("rigs", value={"a": 1}), expect="rigs"),
        "rigs_many": _rig(many_rigs(70), expect="p.json"),
        "sensors_65": _rig(_at("rigs", 0, "sensors", value={
            f"s{i}": multi_rig_doc()["rigs"][0]["sensors"]["radar_b"] for i in range(65)}),
            expect="rigs[0].sensors"),
        "sensor_kind_unknown": _rig(_sensor("kind", "lidar"), expect="rigs[0].sensors"),
        "sensor_kind_missing": _rig(lambda d: {**d, "rigs": [{**d["rigs"][0], "sensors": {
            "radar_b": {k: v for k, v in d["rigs"][0]["sensors"]["radar_b"].items()
                        if k != "kind"}}}]}, expect="rigs[0].sensors.radar_b"),
        "sensor_not_object": _rig(_at("rigs", 0, "sensors", "radar_b", value=5),
                                  expect="rigs[0].sensors"),
        "sensor_pose_huge": _rig(_sensor("pose_on_rig", {"position_m": [1e300, 0, 0]}),
                                 expect="rigs[0].sensors.radar_b(radar).pose_on_rig"),
        "trigger_offset_nan": _rig(_sensor("trigger_offset_s", float("nan")), expect="p.json"),
        "trigger_offset_huge": _rig(_sensor("trigger_offset_s", 1e300),
                                    expect="rigs[0].sensors.radar_b(radar).trigger_offset_s"),
        "trigger_offset_negative": _rig(_sensor("trigger_offset_s", -1.0),
                                        expect="rigs[0].sensors.radar_b(radar).trigger_offset_s"),
        "frame_rate_zero": _rig(_sensor("frame_rate_hz", 0.0),
                                expect="rigs[0].sensors.radar_b(radar).frame_rate_hz"),
        "frame_rate_above_timeline": _rig(_sensor("frame_rate_hz", 1e6),
                                          expect="rigs[0].sensors.radar_b.frame_rate_hz: 1e+06 Hz"),
        "frame_rate_not_divider": _rig(_sensor("frame_rate_hz", 3.0),
                                       expect="rigs[0].sensors.radar_b.frame_rate_hz: 3 Hz"),
        "chirps_huge": _rig(_sensor("chirps_per_frame", 10**9), expect="radar_b"),
        "chirps_string": _rig(_sensor("chirps_per_frame", "many"), expect="radar_b"),
        "samples_float": _rig(_sensor("samples_per_chirp", 64.5), expect="radar_b"),
        "tof_width_huge": _rig(_at("rigs", 0, "sensors", "tof_b", "width", value=10**7),
                               expect="tof_b"),
        "memory_over_budget": _rig(lambda d: d["rigs"][0]["sensors"]["tof_b"].update(
            width=4096, height=4096, supersampling=4), expect="memory: a frame would need"),
        "timeline_frames_huge": _rig(_at("timeline", "duration_s", value=1e9),
                                     expect="timeline"),
        "timeline_rate_tiny": _rig(_at("timeline", "frame_rate_hz", value=1e-300),
                                   expect="timeline.frame_rate_hz"),
        "document_deep": _rig(_at("rigs", 0, "motion", value=json.loads("[" * 60 + "]" * 60)),
                              expect="rigs[0].motion"),
    }


__all__ = ["OK", "asset_cases", "bvh_cases", "bvh_text", "multi_rig_doc", "person_project",
           "recording_cases", "rig_cases", "spec_cases", "spec_doc", "write_recording"]
