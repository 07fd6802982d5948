"""People seen by the radar and the ToF camera, measured from written datasets only.

Known answers: the torso's Doppler is its ground-truth radial velocity (written beside it
in ``/objects/radar_radial_velocity``); a rigid body of the person's size at the same
velocity spreads in Doppler only by its window leakage, so the limbs' Doppler beyond the
torso's must exceed the rigid body's spread by a good fraction of the walking speed; the
ToF camera's depth equals the ground-truth range of the pixels it sees (within noise)
and its body-part ids are the segments whose pixels they are.
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from people_scenes import walker_project

from simcore.cli import main


def _run(tmp_path: Path, name: str, project: dict, *extra: str) -> h5py.File:
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(project))
    out = tmp_path / f"{name}.h5"
    assert main(["run", str(path), "--out", str(out), "--quiet", *extra]) == 0
    return h5py.File(out, "r")


def _doppler(f: h5py.File) -> tuple[np.ndarray, np.ndarray, float]:
    """Per frame: the torso's measured Doppler and the Doppler spread (m/s), and bin width."""
    rd = f["radar/range_doppler"][()]
    va, ra = f["radar/velocity_axis"][()], f["radar/range_axis"][()]
    rng = f["objects/radar_range"][:, 0]
    truth = f["objects/radar_radial_velocity"][:, 0]
    torso, spread = np.zeros(len(rd)), np.zeros(len(rd))
    for k in range(len(rd)):
        ib = int(np.argmin(abs(ra - rng[k])))
        # The chest's front is up to ~0.2 m nearer than its centre: power summed over
        # those range bins.
        trunk = (10 ** (rd[k][:, max(ib - 3, 0): ib + 1] / 10)).sum(axis=1)
        torso[k] = va[np.argmax(trunk)]
        body = rd[k][:, max(ib - 10, 0): ib + 11].max(axis=1)
        strong = va[body > body.max() - 25.0]
        spread[k] = np.abs(strong - truth[k]).max()
    # One Doppler bin: the resolution λ / (2 N T_r), i.e. the axis step times the FFT's
    # zero-padding factor (axis length over the number of chirps).
    chirps = f["radar/adc"].shape[1]
    return torso, spread, float(va[1] - va[0]) * len(va) / chirps


WALKERS = [  # speed m/s, heading deg (0 = away), distance m, lateral offset m
    (1.3, 160.0, 4.5, -0.5),
    (0.9, 20.0, 2.5, 0.3),
    (1.6, 185.0, 5.0, 0.2),
]


@pytest.mark.parametrize(("speed", "heading", "distance", "offset"), WALKERS)
def test_walker_torso_doppler_and_limb_micro_doppler(tmp_path: Path, speed: float,
                                                     heading: float, distance: float,
                                                     offset: float) -> None:
    # 30 frames (about 2.5 gait cycles): the torso is not always the strongest return in
    # its range bins (a thigh passing through them, or the planted foot, can out-reflect
    # the trunk's ellipsoids for a frame), so the ≥ 80 % needs more than a dozen frames
    # to mean something.
    kw = dict(speed=speed, heading_deg=heading, distance_m=distance, offset_m=offset,
              frames=30)
    with _run(tmp_path, "person", walker_project(**kw)) as f:
        torso, spread, bin_width = _doppler(f)
        truth = f["objects/radar_radial_velocity"][:, 0]
        names = [n.decode() if isinstance(n, bytes) else n for n in f["people/segments/names"]]
        assert names[2] == "walker/chest"
        # /objects truth of the person is its torso's.
        assert np.allclose(f["people/segments/radar_radial_velocity"][:, 2], truth)
        det = f["radar/detections"][()]
        labelled = det[det["object_id"] == 1]
        assert labelled.size and np.all(labelled["body_part"] >= 0)
    with _run(tmp_path, "rigid", walker_project(rigid=True, **kw)) as f:
        _, rigid_spread, _ = _doppler(f)
    hits = np.abs(torso - truth) <= bin_width * 1.01
    assert hits.mean() >= 0.8, (torso, truth)
    assert spread.mean() - rigid_spread.mean() >= 0.4 * speed


def test_tof_silhouette_and_body_parts(tmp_path: Path) -> None:
    project = walker_project(speed=1.1, heading_deg=90.0, distance_m=2.5, offset_m=-1.0,
                             frames=2)
    with _run(tmp_path, "tof", project) as f:
        depth, valid = f["tof/depth"][()], f["tof/valid"][()]
        gt, ids = f["tof/gt_range"][()], f["tof/gt_object_id"][()]
        parts = f["tof/gt_body_part"][()]
    with _run(tmp_path, "tof2", project, "--seed", "7") as f:
        depth2 = f["tof/depth"][()]
    person = (ids == 1) & valid
    assert person.sum() > 200
    # Away from the silhouette's edges (flying pixels), the depth (a radial range) is the
    # ground-truth range plus the camera's noise, whose size two runs differing only in
    # their seed show: their difference has √2 times the noise's spread.
    inner = person.copy()
    for ax in (1, 2):
        for s in (1, -1):
            inner &= np.roll(ids == 1, s, axis=ax)
    err = (depth - gt)[inner]
    noise = np.std((depth - depth2)[inner]) / np.sqrt(2)
    assert noise > 0
    assert abs(np.mean(err)) < 3 * noise / np.sqrt(err.size) + 0.002
    assert np.std(err) < 1.2 * noise
    # Every person pixel has a body part; nothing else has one.
    assert np.all(parts[ids == 1] >= 0) and np.all(parts[ids != 1] == -1)
    assert len(np.unique(parts[ids == 1])) >= 8
    # Anatomy from top to bottom of the image (rows grow downwards): head, chest, thighs,
    # shins (segment indices of simcore.scene.people.SEGMENTS: 4, 2, 11/14, 12/15).
    rows = np.indices(parts.shape)[1]
    mean_row = [rows[np.isin(parts, p)].mean() for p in ([4], [2], [11, 14], [12, 15])]
    assert mean_row == sorted(mean_row)


def test_person_behind_paper_box_seen_by_radar_not_tof(tmp_path: Path) -> None:
    """Paper is opaque in the near-IR and nearly transparent at 60 GHz (the material
    library's dual-band paper): the ToF camera sees the box, the radar the person."""
    project = walker_project(speed=0.0, heading_deg=180.0, distance_m=1.6, frames=2)
    project["objects"][0]["geometry"]["motion"] = {
        "posture": "sitting", "vital_signs": {}, "sway_mm": 0.0}
    box = {"id": 2, "name": "paper_box", "geometry": {"kind": "box", "size_m": [0.05, 1.2, 2.0]},
           "pose": {"position_m": [1.0, 0.0, 1.0]}, "material": "paper"}
    project["objects"].append(box)
    with _run(tmp_path, "boxed", project) as f:
        ids = f["tof/gt_object_id"][()]
        profile = f["radar/range_profile_integrated"][()]
        ra = f["radar/range_axis"][()]
        chest = f["people/segments/radar_range"][:, 2]
    assert np.count_nonzero(ids == 1) == 0 and np.count_nonzero(ids == 2) > 1000
    empty = dict(project, objects=[box])
    with _run(tmp_path, "box_only", empty) as f:
        profile_box = f["radar/range_profile_integrated"][()]
    near = np.abs(ra - chest[0] + 0.1) < 0.15
    # The person behind the box adds well over 10 dB at the chest's range.
    assert (profile[0][near].max() - profile_box[0][near].max()) > 10.0


def test_micro_doppler_repeats_with_the_gait(tmp_path: Path) -> None:
    """The limbs' Doppler spread over frames (a spectrogram's envelope) repeats every half
    gait cycle (the legs alternate): Boulic's Dc / 2 = 1.346 / (2 √(v / leg))."""
    speed, height = 1.2, 1.75
    project = walker_project(speed=speed, heading_deg=180.0, distance_m=5.0, frames=64,
                             frame_rate_hz=20.0, height_m=height)
    with _run(tmp_path, "gait", project) as f:
        _, spread, _ = _doppler(f)
    half_cycle = 1.346 / np.sqrt(speed / ((0.245 + 0.246) * height)) / 2
    x = spread - spread.mean()
    lags = np.arange(4, 24)  # 0.2 … 1.15 s at 20 frames/s
    acf = np.array([np.dot(x[:-k], x[k:]) / (len(x) - k) for k in lags])
    best = lags[np.argmax(acf)] / 20.0
    assert best == pytest.approx(half_cycle, abs=0.08)


@pytest.mark.parametrize("sign", ["breathing", "heartbeat"])
def test_vital_sign_phase_comes_out_of_the_radar(tmp_path: Path, sign: str) -> None:
    """The chest's range bin carries the vital signs: its slow-time phase, static clutter
    removed, is 4π d(t)/λ for the configured d(t) = A sin(2π f t) (breathing 5 mm at
    0.25 Hz; heartbeat alone, 0.3 mm at 1.2 Hz)."""
    project = json.loads((Path(__file__).parents[1] / "resources" / "examples"
                          / "vital_signs.json").read_text())
    person = project["objects"][0]["geometry"]["motion"]
    person["sway_mm"] = 0.0
    other = "heart_amplitude_mm" if sign == "breathing" else "breathing_amplitude_mm"
    person["vital_signs"][other] = 0.0
    project["timeline"] = {"frame_rate_hz": 10.0, "duration_s": 12.0}
    project["rig"]["tof"].update({"width": 56, "height": 43, "supersampling": 1})
    project["rig"]["radar"].update({"render_width": 256, "render_height": 256})
    with _run(tmp_path, "vitals", project) as f:
        adc = f["radar/adc"][:, 0, 1, :].astype(np.float64)  # first chirp, rx2
        chest = f["people/segments/radar_range"][0, 2]
        truth = f[f"people/{sign}_displacement"][:, 0]
        t = f["time"][()]
    cfg = project["rig"]["radar"]
    n = adc.shape[1]
    spectrum = np.fft.rfft((adc - adc.mean(axis=1, keepdims=True)) * np.hanning(n), axis=1)
    rng = np.arange(spectrum.shape[1]) * 299_792_458.0 * cfg["sample_rate_hz"] / (
        2 * cfg["bandwidth_hz"] / cfg["chirp_time_s"] * n)
    window = (rng > chest - 0.2) & (rng < chest)  # the chest's front
    moving = spectrum - spectrum.mean(axis=0)  # static clutter removed
    b = np.flatnonzero(window)[np.argmax(np.abs(moving[:, window]).std(axis=0))]
    phase = np.unwrap(np.angle(moving[:, b]))
    wavelength = 299_792_458.0 / (cfg["start_frequency_hz"] + cfg["bandwidth_hz"] / 2)
    d = -(phase - phase.mean()) * wavelength / (4 * np.pi)  # + = towards the radar
    # Fit a sine over a grid of frequencies: the rate and the amplitude.
    rate_hz, tolerance = (0.25, 0.02) if sign == "breathing" else (1.2, 0.1)
    freqs = np.arange(rate_hz - 0.3 * rate_hz, rate_hz + 0.3 * rate_hz, 0.001)
    fits = []
    for fr in freqs:
        basis = np.column_stack([np.sin(2 * np.pi * fr * t), np.cos(2 * np.pi * fr * t),
                                 np.ones_like(t)])
        coef, res, *_ = np.linalg.lstsq(basis, d, rcond=None)
        fits.append((float(res[0]) if res.size else 0.0, fr, np.hypot(*coef[:2])))
    _, rate, amplitude = min(fits)
    assert rate == pytest.approx(rate_hz, abs=tolerance)
    if sign == "breathing":  # an arc of 4π: the clutter-free phasor's phase is the motion
        assert amplitude == pytest.approx(np.abs(truth).max(), rel=0.2)


def test_products_spectrogram_shows_the_gait_period(tmp_path: Path) -> None:
    """``tofradar products --object walker`` on a walker unlike the examples' (1.0 m/s,
    heading 200°, from 4.5 m): the stored spectrogram's micro-Doppler spread widens twice
    per gait cycle, at Boulic's step rate 2 / Dc = 2 √(v / leg) / 1.346."""
    from simcore.dsp.microdoppler import Spectrogram, step_frequency_hz

    speed, height = 1.0, 1.75
    project = walker_project(speed=speed, heading_deg=200.0, distance_m=4.5, offset_m=0.4,
                             frames=80, frame_rate_hz=20.0, height_m=height)
    with _run(tmp_path, "gait_products", project):
        pass
    assert main(["products", str(tmp_path / "gait_products.h5"), "--object", "walker"]) == 0
    with h5py.File(tmp_path / "gait_products.h5") as f:
        g = f["radar/spectrogram"]
        sg = Spectrogram(g["time"][()], g["velocity_axis"][()], g["power"][()])
        truth = f["objects/radar_radial_velocity"][:, 0]
    step_hz = 2.0 * np.sqrt(speed / ((0.245 + 0.246) * height)) / 1.346
    assert step_frequency_hz(sg, threshold_db=25.0) == pytest.approx(step_hz, abs=0.15)
    # The spectrogram's strongest line is the torso's: within one Doppler resolution
    # (the axis step times the zero-padding factor) of its truth in most columns.
    v = sg.velocity_mps
    resolution = (v[1] - v[0]) * len(v) / project["rig"]["radar"]["chirps_per_frame"]
    assert np.mean(np.abs(sg.peak_velocity_mps() - truth) <= 1.01 * resolution) >= 0.8
