"""``tofradar products`` for a dataset with several radars: groups per radar (#30).

As in ``test_products.py``, the datasets are written by hand in the layout of several
sensors (``/<radar>/adc``, ``/<radar>/captured`` for a radar slower than the timeline) from
cubes synthesised by :mod:`tests.fmcw_synth`, so every radar's known answer (its chest's
breathing rate and range, its target's velocity) is the one put in.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from contextlib import redirect_stdout
from pathlib import Path

import h5py
import numpy as np
import pytest

from simcore.cli import main
from simcore.io.products import ProductsError, write_radar_products
from simcore.scene import Project
from simcore.scene.dsp_config import DspConfig
from simcore.scene.model import NamedRadar, Rig, SensorRig, Timeline
from simcore.scene.project_io import project_to_json
from simcore.scene.radar_config import Antenna, RadarConfig
from tests.fmcw_synth import chirp_times, synth_frames

RATE_HZ = 20.0


def put_radar(f: h5py.File, name: str, rc: RadarConfig, times: np.ndarray,
              scatterers: list, *, captured: np.ndarray | None = None) -> None:
    """``/<name>/adc`` and ``chirp_start_time``; with ``captured``, a row per frame whose
    rows of the frames it did not capture in are NaN (they must not be used)."""
    adc = synth_frames(rc, scatterers, times, noise_std=0.01, seed=len(name))
    t = chirp_times(rc, times)[:, :, None] + np.arange(len(rc.tx)) * rc.chirp_repetition_time_s
    if captured is not None:
        full = np.full((captured.size, *adc.shape[1:]), np.nan, dtype=adc.dtype)
        full[captured] = adc
        full_t = np.full((captured.size, *t.shape[1:]), np.nan)
        full_t[captured] = t
        adc, t = full, full_t
        f.create_dataset(f"{name}/captured", data=captured).attrs["per_frame"] = True
    f.create_dataset(f"{name}/adc", data=adc, chunks=(1, *adc.shape[1:])).attrs[
        "per_frame"] = True
    f.create_dataset(f"{name}/chirp_start_time", data=t).attrs["per_frame"] = True


def chest(range_m: float, rate_hz: float, amp_m: float) -> Callable[[np.ndarray], np.ndarray]:
    return lambda t: range_m + amp_m * np.sin(2 * np.pi * rate_hz * t)


def three_radar_dataset(path: Path) -> None:
    """The built-in radar (20 Hz), ``rear`` (20 Hz) and ``slow`` (10 Hz) see three chests."""
    rc = RadarConfig(samples_per_chirp=128, sample_rate_hz=5e5, chirps_per_frame=2,
                     rx=[Antenna(name="rx1")])
    fields = rc.model_dump()
    project = Project(
        timeline=Timeline(frame_rate_hz=RATE_HZ, duration_s=30.0),
        rig=SensorRig(radar=rc),
        rigs=[Rig(name="b", sensors={
            "rear": NamedRadar(**fields),
            "slow": NamedRadar(**{**fields, "frame_rate_hz": RATE_HZ / 2})})],
        dsp=DspConfig(vitals_window_s=20.0))
    frames = np.arange(600) / RATE_HZ
    captured = np.arange(600) % 2 == 0
    static = [(lambda t: 0.6 + 0 * t, 0.1), (lambda t: 2.0 + 0 * t, 0.2)]
    with h5py.File(path, "w") as f:
        meta = f.create_group("meta")
        meta.attrs["project_json"] = project_to_json(project)
        meta.attrs["n_frames"] = len(frames)
        f["time"] = frames
        put_radar(f, "radar", rc, frames, [(chest(0.9, 0.35, 3e-3), 0.05), *static])
        put_radar(f, "rear", rc, frames, [(chest(1.2, 0.25, 2e-3), 0.05), *static])
        put_radar(f, "slow", rc, frames[captured], [(chest(1.5, 0.3, 3e-3), 0.05), *static],
                  captured=captured)


@pytest.fixture(scope="module")
def products(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    path = tmp_path_factory.mktemp("products") / "three.h5"
    three_radar_dataset(path)
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["products", str(path)]) == 0
    return path, out.getvalue()


@pytest.mark.parametrize(("radar", "range_m", "rate_hz", "amp_m"), [
    ("radar", 0.9, 0.35, 3e-3), ("rear", 1.2, 0.25, 2e-3), ("slow", 1.5, 0.3, 3e-3)])
def test_vitals_per_radar(products: tuple[Path, str], radar: str, range_m: float,
                          rate_hz: float, amp_m: float) -> None:
    path, out = products
    assert f"/{radar}/spectrogram" in out and f"/{radar}/vitals written" in out
    with h5py.File(path) as f:
        g = f[f"{radar}/vitals"]
        assert abs(g.attrs["range_m"] - range_m) < 0.02
        assert abs(g.attrs["breathing_rate_hz"] - rate_hz) < 0.02
        assert abs(g.attrs["breathing_amplitude_m"] - amp_m) < 0.3 * amp_m
        assert f[f"{radar}/spectrogram/power"].shape[1] > 0
        rate = g["breathing_rate"][()]
        assert rate.shape == (600,)  # one value per frame of the dataset
        if radar == "slow":  # its 300 captures, 20 s of them at 10 Hz before the first
            rate, t = rate[::2], g["time"][()]
            assert np.all(np.isnan(g["breathing_rate"][1::2])) and np.all(np.isnan(t[1::2]))
            np.testing.assert_allclose(t[::2], f["slow/chirp_start_time"][::2, :, 0]
                                       .mean(axis=1))
        win = int(20.0 * (RATE_HZ / 2 if radar == "slow" else RATE_HZ))
        assert np.all(np.isnan(rate[:win - 1])) and np.all(np.abs(rate[win - 1:] - rate_hz)
                                                           < 0.02)


def test_one_radar_and_bad_names(products: tuple[Path, str],
                                 capsys: pytest.CaptureFixture[str]) -> None:
    path, _ = products
    assert main(["products", str(path), "--radar", "rear"]) == 0
    assert "/rear/vitals written" in capsys.readouterr().out
    assert main(["products", str(path), "--radar", "nosuch"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error: ") and "/nosuch/adc" in err[0]
    with h5py.File(path, "r+") as f:  # ADC data under a name that is no sensor
        f.create_dataset("ghost/adc", data=np.zeros((2, 1, 1, 4)))
        f.create_dataset("ghost/chirp_start_time", data=np.zeros((2, 1, 1)))
    with pytest.raises(ProductsError, match="no sensor 'ghost'"):
        write_radar_products(path, radar="ghost")


def truth_path(radar: str) -> str:
    """Objects' true range from a radar (the engine's layout)."""
    return "objects/radar_range" if radar == "radar" else f"objects/{radar}/range"


def test_spectrogram_follows_an_object_in_each_radars_own_truth(tmp_path: Path) -> None:
    rc = RadarConfig()
    project = Project(rig=SensorRig(radar=rc), rigs=[Rig(name="b", sensors={
        "rear": NamedRadar(**rc.model_dump())})])
    frames = np.arange(20) / 20.0
    ranges = {"radar": lambda t: 2.5 - 1.2 * t, "rear": lambda t: 1.0 + 0.8 * t}
    path = tmp_path / "walk.h5"
    with h5py.File(path, "w") as f:
        f.create_group("meta").attrs.update({"project_json": project_to_json(project),
                                             "n_frames": 20})
        f["time"] = frames
        f["objects/names"] = np.array([b"walker"])
        for name, r in ranges.items():
            put_radar(f, name, rc, frames, [(r, 0.05)])
            f.create_dataset(truth_path(name),
                             data=r(chirp_times(rc, frames).mean(axis=1))[:, None])
    assert main(["products", str(path), "--object", "walker"]) == 0
    with h5py.File(path) as f:
        for name, v_true in (("radar", -1.2), ("rear", 0.8)):
            g = f[f"{name}/spectrogram"]
            v = g["velocity_axis"][()]
            peak = v[np.argmax(g["power"][()], axis=1)]
            assert np.all(np.abs(peak - v_true) <= v[1] - v[0]), name
            np.testing.assert_allclose(g["gate_center"][()], f[truth_path(name)][:, 0])
