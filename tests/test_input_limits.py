"""The documented limits of the input files are the enforced ones (issue 44).

Every number comes from ``simcore/scene/limits.py``, the one module the readers use; each
is found, formatted, in the page that documents it, and the readers' own names refer to
the same objects.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from simcore.scene import limits as L

DOCS = Path(__file__).resolve().parents[1] / "docs"


def n(value: float) -> str:
    """A count as the docs write it: groups of three digits with spaces (100 000)."""
    return f"{int(value):,}".replace(",", " ")


def mib(value: int) -> str:
    return f"{value // 2**20} MiB"


def gib(value: int) -> str:
    return f"{value // 2**30} GiB"


DOCUMENTED = {
    "people.md": [
        f"| file size | {mib(L.MAX_BVH_BYTES)} |",
        f"| joints | {L.MAX_BVH_JOINTS} |",
        f"| nesting depth | {L.MAX_BVH_DEPTH} |",
        f"| frames | {n(L.MAX_BVH_FRAMES)} |",
        f"| frame time | {L.MIN_BVH_FRAME_TIME_S:g} – {L.MAX_BVH_FRAME_TIME_S:g} s |",
        f"within ±{n(L.MAX_BVH_VALUE)} |",
        f"joints × frames × {L.BVH_BYTES_PER_JOINT_FRAME} bytes ≤ "
        f"{gib(L.MAX_BVH_READER_BYTES)} "
        f"({n(L.MAX_BVH_READER_BYTES // L.BVH_BYTES_PER_JOINT_FRAME)} joint-frames)",
        f"at least {L.MIN_BVH_LEG_FRACTION:g} of the clip's longest bone",
        f"| root speed on the person | {L.MAX_BVH_ROOT_SPEED_MPS:g} m/s",
    ],
    "scenarios.md": [
        f"| spec file | {mib(L.MAX_SPEC_BYTES)} |",
        f"| nesting depth | {L.MAX_SPEC_DEPTH} |",
        f"| values (YAML aliases counted each time used) | {n(L.MAX_SPEC_VALUES)} |",
        f"| projects of one `generate` (`--count`) | {n(L.MAX_SCENARIO_COUNT)} |",
        f"| fields varied by one spec | {L.MAX_SPEC_FIELDS} |",
        f"| values of one `choice` | {L.MAX_CHOICES} |",
    ],
    "assets.md": [
        f"| asset file, each external buffer | {mib(L.MAX_ASSET_BYTES)} |",
        f"| JSON part | {mib(L.MAX_ASSET_JSON_BYTES)} |",
        f"| `data:` URI | {L.MAX_DATA_URI_CHARS // 2**20} Mi characters",
        f"| nodes in the document | {n(L.MAX_ASSET_NODES)} |",
        f"| node hierarchy depth | {L.MAX_ASSET_NODE_DEPTH} |",
        f"| mesh objects imported | {L.MAX_ASSET_OBJECTS} ",
    ],
    "dataset.md": [
        f"| `config.json`, `meta.json` | {mib(L.MAX_RECORDING_JSON_BYTES)} each",
        f"| `radar.npy` | {gib(L.MAX_RECORDING_ARRAY_BYTES)},",
        f"| `frame_repetition_time_s` | {L.MIN_RECORDING_FRAME_TIME_S:g} – "
        f"{L.MAX_RECORDING_FRAME_TIME_S:g} s",
        f"| memory to convert one frame | {gib(L.MAX_RECORDING_FRAME_BYTES)} ",
    ],
}


@pytest.mark.parametrize("page", sorted(DOCUMENTED))
def test_documented_limits_are_the_enforced_ones(page):
    text = (DOCS / page).read_text(encoding="utf-8")
    missing = [item for item in DOCUMENTED[page] if item not in text]
    assert not missing, f"docs/{page} does not state: {missing}"


def test_the_readers_use_the_limits_module():
    from simcore.io import recordings
    from simcore.preflight import MAX_FRAMES
    from simcore.scenarios import MAX_COUNT, MAX_DEPTH, MAX_FIELDS, MAX_VALUES
    from simcore.scenarios import _dists as dists
    from simcore.scene import assets
    from simcore.scene.people import bvh

    assert (bvh.MAX_BVH_FRAMES, bvh.MAX_BVH_JOINTS, bvh.MAX_BVH_BYTES) == (
        L.MAX_BVH_FRAMES, L.MAX_BVH_JOINTS, L.MAX_BVH_BYTES)
    assert (MAX_COUNT, MAX_DEPTH, MAX_FIELDS, MAX_VALUES, dists.MAX_CHOICES) == (
        L.MAX_SCENARIO_COUNT, L.MAX_SPEC_DEPTH, L.MAX_SPEC_FIELDS, L.MAX_SPEC_VALUES,
        L.MAX_CHOICES)
    assert (assets.MAX_ASSET_BYTES, assets.MAX_NODES, assets.MAX_NODE_DEPTH,
            assets.MAX_JSON_BYTES, assets.MAX_ASSET_OBJECTS, assets.MAX_DATA_URI_CHARS) == (
        L.MAX_ASSET_BYTES, L.MAX_ASSET_NODES, L.MAX_ASSET_NODE_DEPTH, L.MAX_ASSET_JSON_BYTES,
        L.MAX_ASSET_OBJECTS, L.MAX_DATA_URI_CHARS)
    assert recordings.MAX_RECORDING_FRAME_TIME_S == L.MAX_RECORDING_FRAME_TIME_S
    assert f"| frames | {n(MAX_FRAMES)} |" in (DOCS / "dataset.md").read_text()


def test_a_clip_at_the_frame_limit_is_judged_by_its_count_not_as_a_value(tmp_path):
    # The frame count was once parsed as a frame value (±1e5): 100 001 frames were blamed
    # on "a value beyond ±100000". The count limit now speaks for itself.
    from hostile_inputs import bvh_text

    from simcore.scene.people.bvh import BvhError, check_bvh_text

    path = tmp_path / "c.bvh"
    path.write_text(bvh_text(header_frames=str(L.MAX_BVH_FRAMES + 1)))
    with pytest.raises(BvhError, match=f"frame count {L.MAX_BVH_FRAMES + 1}; allowed "
                                       f"1–{L.MAX_BVH_FRAMES}"):
        check_bvh_text(path)
    path.write_text(bvh_text(header_frames=str(L.MAX_BVH_FRAMES)))
    with pytest.raises(BvhError, match=f"declares {L.MAX_BVH_FRAMES} frames but has 3"):
        check_bvh_text(path)
