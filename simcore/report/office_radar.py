"""Section: the office's radar range profile against the scene's geometry."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from simcore.pipeline import Frame
from simcore.report._common import (
    Figure,
    _office_scatterers,
    _plt,
    _receiver_profile_db,
    _save,
    corner_truth,
)
from simcore.scene.model import Project
from simcore.scene.radar_config import COVERAGE_LEVEL_DB


def office_radar_profile(frame: Frame, project: Project, out: Path
                         ) -> tuple[Figure, dict[str, Any]]:
    """Figure 2: range-FFT spectrum per Rx with leakage roll-off, noise floor, corner peak."""
    plt = _plt()
    dsp = frame.outputs["radar"].dsp
    r = dsp.axes.range_m
    cr = corner_truth(project, frame.time_s)[0]
    k = int(np.argmin(np.abs(r - cr["range"])))
    profile = dsp.range_profile_db
    integrated = dsp.range_profile_integrated_db
    window = slice(max(k - 2, 0), k + 3)
    peak_db = float(integrated[window].max())
    around = np.r_[max(k - 40, 0):max(k - 6, 0), k + 6:min(k + 40, len(r))]
    clutter_db = float(np.median(integrated[around]))
    # Noise floor: the same receiver and DSP with no scatterers at all (noise, leakage).
    scat = _office_scatterers(frame, project)
    noise_profile = _receiver_profile_db(project, scat.subset(np.zeros(len(scat), bool)), 12)
    noise_db = float(np.median(noise_profile[r > 0.5]))
    nearest_surface = float(np.nanmin(frame.buffers["radar"].range_m))
    rise = integrated - noise_profile
    above = np.nonzero((r > 0.3) & (rise >= 6.0))[0]
    clutter_start = float(r[above[0]]) if len(above) else float("nan")
    band = (r >= 1.5) & (r <= 2.3)
    band_over = float(10 * np.log10(np.mean(10 ** (integrated[band] / 10))
                                    / np.mean(10 ** (noise_profile[band] / 10))))
    height = float(frame.snapshot.sensors["radar"].position[2])
    half_fov = project.radar().render_fov_h_deg / 2
    near = r < 0.1
    numbers = {"corner_range_m": cr["range"], "corner_peak_db": peak_db,
               "nearest_surface_m": nearest_surface, "clutter_start_m": clutter_start,
               "clutter_1p5_2p3_over_noise_db": band_over, "radar_height_m": height,
               "corner_over_clutter_db": peak_db - clutter_db, "noise_floor_db": noise_db,
               "near_zero_db": float(integrated[near].min()) if near.any() else float("nan"),
               "leakage_peak_db": float(integrated[r < 0.15].max()),
               "max_scene_db": float(integrated.max())}
    fig, ax = plt.subplots(figsize=(11, 4.6), constrained_layout=True)
    for ch in range(profile.shape[0]):
        ax.plot(r, profile[ch], lw=0.9, label=f"Rx channel {ch + 1}")
    ax.axvline(cr["range"], color="k", ls="--", lw=0.8)
    ax.annotate("corner reflector behind the\nradar-transparent paper box",
                xy=(cr["range"], peak_db), xytext=(cr["range"] - 2.2, peak_db - 4),
                arrowprops={"arrowstyle": "->"}, fontsize=9)
    ax.plot(r, noise_profile, color="0.5", lw=0.8,
            label=f"receiver alone: noise floor {noise_db:.0f} dBFS (and leakage)")
    ax.axvspan(1.5, 2.3, color="tab:green", alpha=0.12,
               label=f"floor clutter 1.5–2.3 m ({band_over:.0f} dB over the noise)")
    ax.axvspan(0, 0.2, color="orange", alpha=0.15, label="IF high-pass / leakage roll-off")
    ax.set_xlabel("range (m)")
    ax.set_ylabel("power (dBFS)")
    ax.set_ylim(top=peak_db + 8)
    ax.set_title(f"Range-FFT spectrum per Rx — office.json, t = {frame.time_s:.2f} s "
                 "(Hann window, chirp-averaged)")
    ax.set_xlim(0, r[-1])
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3)
    name = "fig2_office_range_profile.png"
    _save(fig, out / name)
    text = (
        f"Every Rx channel shows the same features as the measured BGT60TR13C spectrum: the "
        f"80 kHz IF high-pass rolls the spectrum off towards 0 m (down to "
        f"{numbers['near_zero_db']:.0f} dBFS) and attenuates the Tx→Rx leakage tone to "
        f"{numbers['leakage_peak_db']:.0f} dBFS, and the receiver noise floor (the same "
        f"receiver and DSP without any scatterer) sits at {noise_db:.0f} dBFS. The radar "
        f"render covers the antennas' field of view (±{half_fov:.0f}°, the two-way element "
        f"pattern down to {COVERAGE_LEVEL_DB:.0f} dB), so the floor {height:.2f} m below "
        f"the radar is in the "
        f"scene from {nearest_surface:.2f} m, where the render's lower edge meets it: its "
        f"grazing clutter lifts the spectrum 6 dB over the noise from {clutter_start:.2f} m "
        f"and by {band_over:.0f} dB on average between 1.5 and 2.3 m (section 7.2 separates "
        f"the floor's own contribution), so no stretch of bare noise precedes the room's "
        f"objects; the "
        f"desks, chair, walls and the walking person add their returns beyond, and the "
        f"corner reflector hidden behind the paper box (paper transmits most of the 60 GHz "
        f"wave, and is opaque in near-IR) stands "
        f"{numbers['corner_over_clutter_db']:.1f} dB over the surrounding clutter at "
        f"{cr['range']:.2f} m ({peak_db:.1f} dBFS)."
    )
    return Figure(name, "Office scene, radar range spectrum", text), numbers
