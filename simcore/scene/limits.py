"""The limits of the input files: one place that the readers, the checks and the docs use.

``tests/test_input_limits.py`` reads these numbers and finds each in the page that
documents it (docs/people.md, docs/scenarios.md, docs/assets.md, docs/dataset.md), so a
limit changed here and not in the docs (or the other way round) fails the tests.
Sizes are bytes, times seconds.
"""

from __future__ import annotations

# ------------------------------------------------------------------ BVH clips (people.md)
#: Largest BVH file, most joints, deepest nesting.
MAX_BVH_BYTES = 64 * 2**20
MAX_BVH_JOINTS = 256
MAX_BVH_DEPTH = 64
#: Most frames of a clip (about 14 minutes at 120 frames/s).
MAX_BVH_FRAMES = 100_000
#: Largest magnitude of an offset or a frame value.
MAX_BVH_VALUE = 1e5
#: Shortest and longest frame time (s).
MIN_BVH_FRAME_TIME_S = 1e-5
MAX_BVH_FRAME_TIME_S = 10.0
#: Memory the reader needs per joint and frame (bytes): ``bvhio``'s keyframe objects and
#: the rotation arrays, measured at 550–660 bytes (17 joints, 3 000–12 000 frames) and
#: rounded up.
BVH_BYTES_PER_JOINT_FRAME = 800
#: Memory budget of reading one clip (bytes): joints × frames × the above must stay below.
MAX_BVH_READER_BYTES = 2 * 2**30
#: Shortest leg (thigh + shin) of a clip's skeleton, as a fraction of its longest offset:
#: the root's motion is scaled by the person's leg length over this one.
MIN_BVH_LEG_FRACTION = 1e-3
#: Fastest root motion between two frames of a clip played on a person (m/s): far above
#: a sprint (≈ 12 m/s), far below what a clip at the wrong scale gives.
MAX_BVH_ROOT_SPEED_MPS = 50.0

# ------------------------------------------------------------ scenario specs (scenarios.md)
#: Largest spec file, deepest nesting, most values (YAML aliases counted each time used).
MAX_SPEC_BYTES = 1 << 20
MAX_SPEC_DEPTH = 32
MAX_SPEC_VALUES = 200_000
#: Most projects of one ``generate``, fields varied by one spec, values of one choice.
MAX_SCENARIO_COUNT = 100_000
MAX_SPEC_FIELDS = 256
MAX_CHOICES = 1000

# -------------------------------------------------------------------- assets (assets.md)
#: Largest asset file and external buffer, JSON part, ``data:`` URI (characters).
MAX_ASSET_BYTES = 256 * 2**20
MAX_ASSET_JSON_BYTES = 64 * 2**20
MAX_DATA_URI_CHARS = 64 * 2**20
#: Most nodes, deepest node hierarchy, most mesh objects imported.
MAX_ASSET_NODES = 100_000
MAX_ASSET_NODE_DEPTH = 256
MAX_ASSET_OBJECTS = 4096

# ------------------------------------------------------------- recordings (dataset.md)
#: Largest ``config.json`` / ``meta.json`` of a recording.
MAX_RECORDING_JSON_BYTES = 1 << 20
#: Largest ``radar.npy`` (it is memory-mapped and read a frame at a time).
MAX_RECORDING_ARRAY_BYTES = 64 * 2**30
#: Shortest and longest frame repetition time (s) of a converted recording.
MIN_RECORDING_FRAME_TIME_S = 1e-4
MAX_RECORDING_FRAME_TIME_S = 3600.0
#: Memory budget of converting one frame (bytes): its ADC codes and samples and the DSP
#: products of :func:`simcore.preflight.estimate_cost`.
MAX_RECORDING_FRAME_BYTES = 2 * 2**30

__all__ = [name for name in dir() if name.isupper()]
