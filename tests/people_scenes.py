"""Projects with people for the people tests (built in code from the bundled examples)."""

from __future__ import annotations

import json
from typing import Any

from simcore.resources import example_path


def walker_project(*, speed: float, heading_deg: float, distance_m: float, offset_m: float = 0.0,
                   rigid: bool = False, frames: int = 12, frame_rate_hz: float = 10.0,
                   height_m: float = 1.75) -> dict[str, Any]:
    """One walker in free space in front of a fast-chirping radar (Doppler span ±8.3 m/s).

    The walker starts ``distance_m`` ahead of the rig (``offset_m`` to its left) and walks
    at ``heading_deg`` (0 = away from the rig along +x, 180 = towards it). ``rigid``: a
    cylinder of the person's size sliding at the same velocity instead.
    """
    d = json.loads(example_path("wall").read_text())
    d["name"] = "walker"
    d["timeline"] = {"frame_rate_hz": frame_rate_hz, "duration_s": frames / frame_rate_hz}
    radar = d["rig"]["radar"]
    radar.update({"bandwidth_hz": 2e9, "samples_per_chirp": 256, "chirp_time_s": 128e-6,
                  "chirp_repetition_time_s": 150e-6, "chirps_per_frame": 64,
                  "render_width": 320, "render_height": 320})
    d["rig"]["tof"].update({"width": 112, "height": 86, "supersampling": 1})
    if rigid:
        import math

        h = math.radians(heading_deg)
        obj = {"id": 1, "name": "walker", "geometry": {"kind": "cylinder", "radius_m": 0.2,
                                                         "height_m": height_m},
               "pose": {"position_m": [distance_m, offset_m, height_m / 2]},
               "material": "skin",
               "motion": {"velocity_mps": [speed * math.cos(h), speed * math.sin(h), 0.0]}}
    else:
        obj = {"id": 1, "name": "walker",
               "geometry": {"kind": "person", "height_m": height_m,
                            "motion": {"walk": {"speed_mps": speed}}},
               "pose": {"position_m": [distance_m, offset_m, 0.0],
                        "rotation_deg": [0.0, 0.0, heading_deg]}}
    d["objects"] = [obj]
    return d
