"""What the report's sections share: the figure record, plotting, the office's truths."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.dsp import process_frame
from simcore.pipeline import Frame
from simcore.scene.geometry import CornerReflector
from simcore.scene.model import Project
from simcore.scene.people.expand import expand_people
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers, simulate_radar
from simcore.sensors.radar.scene import RadarScene

#: The reference simulator's bars (from the issues): range ¼ bin, velocity 1 bin, angle 2°,
#: power 0.5 dB, IF error −60 dB, resolution change 1 dB.
BARS = {"range_bins": 0.25, "velocity_bins": 1.0, "angle_deg": 2.0, "power_db": 0.5,
        "if_error_db": -60.0, "resolution_db": 1.0}


R_REF_OHM = 50.0   # receiver reference impedance of the documented calibration


@dataclass
class Figure:
    """One figure of the report: file, title, reading paragraph."""

    file: str
    title: str
    text: str
    section: str | None = None   # figures of one section share a heading


@dataclass
class ReportResult:
    """Numbers and figures of a generated report."""

    out_dir: Path
    numbers: dict[str, Any] = field(default_factory=dict)
    figures: list[Figure] = field(default_factory=list)


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: Path) -> None:
    """Write a figure as PNG and release it."""
    fig.savefig(path, dpi=110)
    _plt().close(fig)


def _object_id(project: Project, name: str) -> int:
    return project.object_by_name(name).id


def corner_truth(project: Project, t: float) -> list[dict[str, Any]]:
    """Range, azimuth and radial velocity of every corner apex as the radar sees it."""
    snap = take_snapshot(project, t)
    radar = snap.sensors["radar"]
    out = []
    for obj, state in zip(project.objects, snap.objects, strict=True):
        if not isinstance(obj.geometry, CornerReflector):
            continue
        rel = state.origin - radar.position
        opt = radar.rotation.T @ rel
        rng = float(np.linalg.norm(rel))
        vel = float((state.velocity_mps - radar.velocity_mps) @ rel / rng)
        out.append({"name": obj.name, "range": rng, "velocity": vel,
                    "azimuth_deg": float(np.degrees(np.arctan2(opt[0], opt[2]))),
                    "world": state.origin.tolist()})
    return out


def _nearest(det: NDArray[Any], rng: float) -> int | None:
    if len(det) == 0:
        return None
    return int(np.argmin(np.abs(det["range"] - rng)))


def _receiver_profile_db(project: Project, scatterers: Any, seed: int) -> NDArray[np.float64]:
    """Chirp- and channel-averaged range profile (dBFS) of ``scatterers``.

    Through the project's whole receiver (noise, leakage, IF chain, ADC) and DSP, as the
    frame's own profile.
    """
    cfg = project.radar()
    adc = simulate_radar(scatterers, cfg, rng=np.random.default_rng(seed)).adc
    return np.asarray(process_frame(adc, cfg, project.dsp).range_profile_integrated_db,
                      dtype=np.float64)


def _office_scatterers(frame: Frame, project: Project) -> Any:
    return radar_scatterers(RadarScene.from_project(expand_people(project), frame.snapshot),
                            frame.buffers["radar"], config=project.radar(),
                            seed=0,
                            see_through=frame.see_through.get("radar"))
