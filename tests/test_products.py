"""``tofradar products``: spectrogram and vital signs written into a finished dataset.

The datasets here are written by hand with h5py in the dataset layout (``docs/dataset.md``)
from cubes synthesised by :mod:`tests.fmcw_synth`, so the known answers (breathing rate
and amplitude, a target's velocity) are those put in, not the simulator's.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from simcore.cli import main
from simcore.io.reader import open_dataset
from simcore.scene import Project
from simcore.scene.dsp_config import DspConfig
from simcore.scene.model import SensorRig
from simcore.scene.project_io import project_to_json
from simcore.scene.radar_config import Antenna, RadarConfig
from tests.fmcw_synth import chirp_times, synth_frames


def write_dataset(path: Path, rc: RadarConfig, dsp: DspConfig, frames: np.ndarray,
                  scatterers: list, *, object_range: np.ndarray | None = None) -> None:
    adc = synth_frames(rc, scatterers, frames, noise_std=0.01, seed=5)
    project = Project(rig=SensorRig(radar=rc), dsp=dsp)
    with h5py.File(path, "w") as f:
        meta = f.create_group("meta")
        meta.attrs["project_json"] = project_to_json(project)
        meta.attrs["n_frames"] = len(frames)
        f["time"] = frames
        ds = f.create_dataset("radar/adc", data=adc, chunks=(1, *adc.shape[1:]))
        ds.attrs["per_frame"] = True
        t = chirp_times(rc, frames)[:, :, None] + np.arange(len(rc.tx)) * \
            rc.chirp_repetition_time_s
        f.create_dataset("radar/chirp_start_time", data=t).attrs["per_frame"] = True
        if object_range is not None:
            f["objects/names"] = np.array([b"walker"])
            f.create_dataset("objects/radar_range", data=object_range[:, None]
                             ).attrs["per_frame"] = True


def test_vitals_written_to_the_dataset(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    rc = RadarConfig(samples_per_chirp=128, sample_rate_hz=5e5, chirps_per_frame=2,
                     rx=[Antenna(name="rx1")])
    frames = np.arange(600) / 20.0

    def chest(t: np.ndarray) -> np.ndarray:
        return 0.9 + 3e-3 * np.sin(2 * np.pi * 0.35 * t)

    path = tmp_path / "vitals.h5"
    write_dataset(path, rc, DspConfig(vitals_window_s=20.0), frames,
                  [(chest, 0.05), (lambda t: 0.9 + 0 * t, 0.1), (lambda t: 1.3 + 0 * t, 0.2)])
    assert main(["products", str(path)]) == 0
    out = capsys.readouterr().out
    assert "/radar/vitals written" in out
    with h5py.File(path) as f:
        g = f["radar/vitals"]
        assert abs(g.attrs["range_m"] - 0.9) < 0.02
        assert abs(g.attrs["breathing_rate_hz"] - 0.35) < 0.02
        assert abs(g.attrs["breathing_amplitude_m"] - 3e-3) < 0.6e-3
        rate = g["breathing_rate"][()]
        assert g["displacement"].attrs["unit"] == "m"
        assert np.all(np.isnan(rate[:399])) and not np.any(np.isnan(rate[399:]))
        assert np.all(np.abs(rate[399:] - 0.35) < 0.02)
    ds = open_dataset(path)
    try:
        assert ds.radar_vitals_breathing_rate.dims == ("frame",)
        assert ds.radar_spectrogram_power.dims == ("spectrogram_time", "spectrogram_velocity")
    finally:
        ds.close()


def test_spectrogram_follows_an_object_and_reruns_replace_it(tmp_path: Path) -> None:
    rc = RadarConfig()
    frames = np.arange(20) / 20.0

    def walker(t: np.ndarray) -> np.ndarray:
        return 2.5 - 1.2 * t

    path = tmp_path / "walk.h5"
    truth = walker(chirp_times(rc, frames).mean(axis=1))
    write_dataset(path, rc, DspConfig(), frames, [(walker, 0.05)], object_range=truth)
    for _ in range(2):  # a second run replaces the groups
        assert main(["products", str(path), "--object", "walker"]) == 0
    with h5py.File(path) as f:
        g = f["radar/spectrogram"]
        v = g["velocity_axis"][()]
        peak = v[np.argmax(g["power"][()], axis=1)]
        assert g["power"].shape == (20, 32)
        assert np.all(np.abs(peak + 1.2) <= v[1] - v[0])
        np.testing.assert_allclose(g["gate_center"][()], truth)


def test_stft_mode_from_the_project(tmp_path: Path) -> None:
    rc = RadarConfig()
    period = rc.chirps_per_frame * rc.chirp_repetition_time_s
    frames = np.arange(16) * period                 # contiguous bursts
    path = tmp_path / "stft.h5"
    dsp = DspConfig(spectrogram_mode="stft", spectrogram_segment_chirps=64,
                    spectrogram_overlap=0.5, spectrogram_range_m=(1.0, 2.0))
    write_dataset(path, rc, dsp, frames, [(lambda t: 1.5 + 0.7 * t, 0.05)])
    assert main(["products", str(path)]) == 0
    with h5py.File(path) as f:
        g = f["radar/spectrogram"]
        assert g.attrs["mode"] == "stft"
        assert g["power"].shape == ((16 * 16 - 64) // 32 + 1, 128)
        v = g["velocity_axis"][()]
        assert np.all(np.abs(v[np.argmax(g["power"][()], axis=1)] - 0.7) <= v[1] - v[0])


def test_bad_datasets_are_one_line_errors(tmp_path: Path, capsys: pytest.CaptureFixture
                                          ) -> None:
    missing = tmp_path / "none.h5"
    assert main(["products", str(missing)]) == 2
    junk = tmp_path / "junk.h5"
    junk.write_text("not hdf5")
    assert main(["products", str(junk)]) == 2
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w") as f:
        f.create_group("meta")
    assert main(["products", str(empty)]) == 2
    rc = RadarConfig()
    walk = tmp_path / "walk.h5"
    write_dataset(walk, rc, DspConfig(), np.arange(3) / 20.0, [(lambda t: 2.0 + 0 * t, 0.05)])
    assert main(["products", str(walk), "--object", "nobody"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 4
    assert all(line.startswith("tofradar: error: ") for line in err)
    assert "no such dataset" in err[0] and "/radar/adc" in err[2] and "objects" in err[3]


@pytest.mark.slow
def test_products_of_a_simulated_run(tmp_path: Path) -> None:
    """The real layout written by ``tofradar run`` (a wall at 2 m, nothing moves)."""
    from simcore.resources import example_path

    out = tmp_path / "wall.h5"
    assert main(["run", str(example_path("wall")), "--out", str(out), "--frames", "3",
                 "--quiet"]) == 0
    assert main(["products", str(out)]) == 0
    with h5py.File(out) as f:
        n_doppler = f["radar/spectrogram/velocity_axis"].shape[0]
        assert f["radar/spectrogram/power"].shape == (3, n_doppler)
        np.testing.assert_allclose(f["radar/vitals/time"][()],
                                   f["radar/chirp_start_time"][:, :, 0].mean(axis=1))


@pytest.mark.slow
def test_simulated_mover_spectrogram_follows_its_true_radial_velocity(tmp_path: Path) -> None:
    """Simulator → dataset → products: the corner's Doppler line against its ground truth."""
    from simcore.resources import example_path
    from simcore.scene import load_project, save_project

    project = load_project(example_path("doppler_back_and_forth"))
    # The corner swings at ±0.4 m/s, under one resolution cell (0.5 m/s): per-frame
    # clutter removal would take it away with the statics, so it is off here.
    project.dsp.spectrogram_clutter_removal = False
    src = tmp_path / "p.json"
    save_project(project, src)
    out = tmp_path / "d.h5"
    assert main(["run", str(src), "--out", str(out), "--frames", "16", "--quiet"]) == 0
    assert main(["products", str(out), "--object", "corner"]) == 0
    with h5py.File(out) as f:
        g = f["radar/spectrogram"]
        v = g["velocity_axis"][()]
        peak = v[np.argmax(g["power"][()], axis=1)]
        truth = f["objects/radar_radial_velocity"][:, 0]
        assert np.ptp(truth) > 0.3                       # it does move
        assert np.mean(np.abs(peak - truth) <= v[1] - v[0]) >= 0.8
