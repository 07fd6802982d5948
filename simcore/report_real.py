"""Validation-report section "simulation and a real BGT60TR13C" (issue #35).

The shared recording (``../shared/real/bgt60tr13c_breathing`` beside the repository, or
``$TOFRADAR_REAL_RECORDING``) measured as its README says (:mod:`simcore.io.recordings`),
beside the project made from it simulated with an empty scene, before and after the
calibration of ``docs/physics_radar.md``; a skin ellipsoid the size of a torso at the
recording's target range; the breathing phase of the real recording over time.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.io.recordings import (
    RadarRecording,
    RecordingLevels,
    read_recording,
    recording_levels,
)
from simcore.scene.radar_config import RadarConfig

#: Environment variable naming a recording to use instead of the shared one.
RECORDING_ENV = "TOFRADAR_REAL_RECORDING"
#: Range of the recording's target (m) and the torso-sized ellipsoid's semi-axes (m):
#: depth (along the boresight), width, height.
TARGET_RANGE_M = 0.33
TORSO_SEMI_AXES_M = (0.10, 0.18, 0.30)
#: The front end before the calibration (the RadarConfig defaults of tofradar 0.2).
BEFORE_LEVELS: dict[str, Any] = {
    "tx_power_dbm": 5.0, "tx_gain_dbi": 6.0, "rx_gain_dbi": 6.0, "if_gain_db": 66.0,
    "noise_figure_db": 12.0, "leakage_dbc": -40.0, "leakage_path_mm": None,
    "leakage_echoes": [], "adc_noise_fs": 0.0}


def shared_recording() -> Path | None:
    """The real recording to compare with, or None when it is absent.

    ``$TOFRADAR_REAL_RECORDING`` when set; else the first recording folder under
    ``../shared/real/bgt60tr13c_breathing`` relative to the repository root.
    """
    env = os.environ.get(RECORDING_ENV)
    if env:
        return Path(env) if Path(env).is_dir() else None
    root = Path(__file__).resolve().parents[1] / ".." / "shared" / "real" / "bgt60tr13c_breathing"
    if not root.is_dir():
        return None
    found = sorted(p.parent.parent for p in root.glob("*/RadarIfxAvian_*/radar.npy"))
    return found[0] if found else None


def empty_scene_frames(config: RadarConfig, *, frames: int, seed: int = 0
                       ) -> NDArray[np.float32]:
    """Simulated frames of an empty scene: the receiver alone (leakage, noise, ADC).

    Returns
    -------
    ndarray, shape (frames, chirps, channels, samples), float32
        ADC samples (FS).
    """
    from simcore.sensors.radar import simulate_radar
    from simcore.sensors.radar.scatterers import Scatterers

    rng = np.random.default_rng(seed)
    empty = Scatterers.from_arrays(np.zeros((0, 3)), np.zeros(0))
    return np.stack([simulate_radar(empty, config, rng=rng).adc for _ in range(frames)]
                    ).astype(np.float32)


def before_config(config: RadarConfig) -> RadarConfig:
    """``config`` with the front-end levels tofradar had before the calibration."""
    return RadarConfig.model_validate(config.model_dump() | BEFORE_LEVELS)


def torso_frames(config: RadarConfig, *, frames: int, seed: int = 0) -> NDArray[np.float32]:
    """Frames of a skin ellipsoid the size of a torso, its front at :data:`TARGET_RANGE_M`.

    The ellipsoid (semi-axes :data:`TORSO_SEMI_AXES_M`) is a mesh rendered like any
    object; the receiver is the whole front end.
    """
    from simcore.render import RenderRequest, SceneRenderer
    from simcore.scene.geometry import Mesh
    from simcore.scene.model import Project, SceneObject, SensorRig
    from simcore.scene.motion import Pose
    from simcore.scene.snapshot import take_snapshot
    from simcore.sensors.radar import radar_scatterers, simulate_radar

    depth = TORSO_SEMI_AXES_M[0]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "torso.obj"
        path.write_text(ellipsoid_obj(TORSO_SEMI_AXES_M))
        project = Project(objects=[SceneObject(
            id=1, name="torso", geometry=Mesh(path=str(path)), material="skin",
            pose=Pose(position_m=(TARGET_RANGE_M + depth, 0.0, 0.0)))],
            rig=SensorRig(radar=config))
        renderer = SceneRenderer(project)
        try:
            snap = take_snapshot(project, 0.0)
            buffers = renderer.render(snap, RenderRequest(
                "radar", "radar", config.render_intrinsics(), geometry_only=True))
            scat = radar_scatterers(project, snap, buffers, config=config, seed=seed)
        finally:
            renderer.close()
    rng = np.random.default_rng(seed)
    return np.stack([simulate_radar(scat, config, rng=rng).adc for _ in range(frames)]
                    ).astype(np.float32)


def ellipsoid_obj(semi_axes_m: tuple[float, float, float], *, n_lat: int = 64,
                  n_lon: int = 128) -> str:
    """Wavefront OBJ text of an ellipsoid (latitude–longitude grid, outward faces).

    Parameters
    ----------
    semi_axes_m : tuple of float
        Semi-axes along the object's local x, y, z (m).
    n_lat, n_lon : int
        Grid rings and segments.
    """
    a, b, c = semi_axes_m
    theta = np.linspace(0.0, np.pi, n_lat + 1)[1:-1]            # ring polar angles
    phi = np.linspace(0.0, 2 * np.pi, n_lon, endpoint=False)
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    ring = np.stack([a * st * np.cos(phi), b * st * np.sin(phi),
                     np.broadcast_to(c * ct, (len(theta), n_lon))], axis=-1).reshape(-1, 3)
    verts = np.vstack([[0.0, 0.0, c], ring, [0.0, 0.0, -c]])
    top, bottom = 1, len(verts)                                   # OBJ indices from 1
    idx = 2 + np.arange(len(theta) * n_lon).reshape(len(theta), n_lon)
    nxt = np.roll(idx, -1, axis=1)
    faces = [(top, idx[0, j], nxt[0, j]) for j in range(n_lon)]
    for i in range(len(theta) - 1):
        for j in range(n_lon):
            faces += [(idx[i, j], idx[i + 1, j], nxt[i, j]),
                      (nxt[i, j], idx[i + 1, j], nxt[i + 1, j])]
    faces += [(idx[-1, j], bottom, nxt[-1, j]) for j in range(n_lon)]
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
    lines += [f"f {i} {j} {k}" for i, j, k in faces]
    return "\n".join(lines) + "\n"


def breathing_phase(recording: RadarRecording, *, band_m: tuple[float, float] = (0.25, 0.45),
                    rate_band_hz: tuple[float, float] = (0.1, 0.7)
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], float, float]:
    """Slow-time phase of the strongest moving range bin, and its rate.

    Per frame: the range FFT (:func:`simcore.dsp.spectrum.range_fft`, Hann, mean removed)
    averaged over chirps and channels of the bin in ``band_m`` whose complex value varies
    most over the frames; its phase unwrapped, mean removed; the rate is the largest
    spectral peak of the phase in ``rate_band_hz``.

    Returns
    -------
    time_s : ndarray, shape (frames,)
    phase_rad : ndarray, shape (frames,)
    rate_hz : float
        Breathing rate (Hz).
    range_m : float
        Range of the bin (m).
    """
    from simcore.dsp.spectrum import range_fft

    x = recording.adc()                                   # (frames, chirps, channels, n)
    n = x.shape[-1]
    spec = range_fft(x.reshape(-1, *x.shape[2:]), window="hann", fft_size=n, remove_dc=True,
                     n_bins=n // 2)
    spec = spec.reshape(x.shape[0], x.shape[1], *spec.shape[1:]).mean(axis=1)  # (f, ch, bins)
    cfg = recording.config
    bin_m = cfg.sample_rate_hz / n * 299_792_458.0 / (2 * cfg.slope_hz_per_s)
    r = np.arange(spec.shape[-1]) * bin_m
    inside = np.flatnonzero((r >= band_m[0]) & (r <= band_m[1]))
    motion = np.abs(spec - spec.mean(axis=0)).mean(axis=(0, 1))
    k = int(inside[np.argmax(motion[inside])])
    phase = np.unwrap(np.angle(spec[:, 0, k]))
    phase = phase - phase.mean()
    t = recording.frame_times_s()
    f = np.fft.rfftfreq(len(phase), recording.frame_repetition_time_s)
    p = np.abs(np.fft.rfft(phase * np.hanning(len(phase)))) ** 2
    sel = (f >= rate_band_hz[0]) & (f <= rate_band_hz[1])
    rate = float(f[sel][np.argmax(p[sel])])
    return t, phase, rate, float(r[k])


def _level_rows(real: RecordingLevels, before: RecordingLevels, after: RecordingLevels
                ) -> list[tuple[str, float, float, float]]:
    rows = []
    for key, value in real.table().items():
        if key != "target":
            rows.append((key, value, before.table()[key], after.table()[key]))
    return rows


def real_section(out: Path, *, quick: bool) -> tuple[str, str, str, dict[str, Any]]:
    """Figure and text of the section: (file, title, text, numbers).

    Without the recording the text says so and no figure is drawn (file "").
    """
    source = shared_recording()
    title = "Simulation and a real BGT60TR13C"
    if source is None:
        return "", title, (
            "The shared real recording (`../shared/real/bgt60tr13c_breathing`, or "
            f"`${RECORDING_ENV}`) is not present on this machine, so this section was not "
            "measured; see docs/physics_radar.md for the calibration numbers."), {
            "recording": None}
    rec = read_recording(source)
    cfg = rec.config
    n = 16 if quick else 64
    real = recording_levels(rec.adc(), cfg)
    after = recording_levels(empty_scene_frames(cfg, frames=n, seed=1), cfg)
    before = recording_levels(empty_scene_frames(before_config(cfg), frames=n, seed=1), cfg)
    try:
        torso = recording_levels(torso_frames(cfg, frames=max(4, n // 8), seed=1), cfg)
        torso_db: float | None = torso.target_dbfs
    except Exception:   # noqa: BLE001 — no OpenGL context: the section goes on without it
        torso, torso_db = None, None
    t, phase, rate, r_breath = breathing_phase(rec)
    numbers: dict[str, Any] = {
        "recording": source.name, "rows": _level_rows(real, before, after),
        "target_real_dbfs": real.target_dbfs, "torso_dbfs": torso_db,
        "breathing_rate_hz": rate, "breathing_range_m": r_breath}
    file = "fig_real_bgt60tr13c.png"
    _figure(out / file, real, before, after, torso, (t, phase, rate, r_breath))
    return file, title, _text(numbers), numbers


def _figure(path: Path, real: RecordingLevels, before: RecordingLevels,
            after: RecordingLevels, torso: RecordingLevels | None,
            breath: tuple[NDArray[np.float64], NDArray[np.float64], float, float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8), constrained_layout=True)
    r = real.range_m
    ax.plot(r, real.profile_dbfs, "k-", lw=2, label="real BGT60TR13C (breathing person)")
    ax.plot(r, after.profile_dbfs, "C0-", label="simulated, empty scene (calibrated)")
    ax.plot(r, before.profile_dbfs, "C3--", label="simulated, empty scene (before)")
    if torso is not None:
        ax.plot(r, torso.profile_dbfs, "C2:", lw=2,
                label="simulated, skin torso ellipsoid at 0.33 m")
    ax.set_xlabel("range (m)")
    ax.set_ylabel("power (dBFS, Hann, full-scale sine = 0 dB)")
    ax.set_title("Range profile: real vs simulated (same configuration and DSP)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    t, phase, rate, r_b = breath
    bx.plot(t, phase, "k-")
    bx.set_xlabel("time (s)")
    bx.set_ylabel("phase (rad)")
    bx.set_title(f"Real recording: slow-time phase at {r_b:.2f} m, rate {rate:.2f} Hz "
                 f"({60 * rate:.1f} / min)")
    bx.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _text(nums: dict[str, Any]) -> str:
    lines = [
        f"The recording `{nums['recording']}` (a real BGT60TR13C, 58–63.5 GHz, 64 samples at "
        "2 MHz, IF gain 23 dB, high-pass 80 kHz, anti-aliasing 500 kHz) converted by "
        "`tofradar convert` and measured as its README says, beside the project made from "
        "it (`--project`) simulated with an empty scene, before and after the calibration "
        "(docs/physics_radar.md). Levels in dBFS:", "",
        "| figure | real | simulated before | simulated after |", "|---|---|---|---|"]
    lines += [f"| {k} | {a:.1f} | {b:.1f} | {c:.1f} |" for k, a, b, c in nums["rows"]]
    torso = nums["torso_dbfs"]
    lines += ["", (
        f"At 0.33 m the recording reads {nums['target_real_dbfs']:.1f} dBFS (the person); a "
        "skin ellipsoid the size of a torso (semi-axes 10 × 18 × 30 cm) there reads "
        + (f"{torso:.1f} dBFS" if torso is not None else "— (no OpenGL here)")
        + ". The person's pose, clothing, angle and distance are not documented, and at "
        "0.33 m the body fills the beam (near field), so this is a plausibility check, not a "
        "calibration target. "
        f"The breathing phase (right) oscillates at {nums['breathing_rate_hz']:.2f} Hz "
        f"({60 * nums['breathing_rate_hz']:.0f} breaths per minute) at "
        f"{nums['breathing_range_m']:.2f} m.")]
    return "\n".join(lines)
