"""simcore.io.open_dataset: the HDF5 layout as a lazy xarray.Dataset."""

from __future__ import annotations

import re
from pathlib import Path

import h5py
import numpy as np
import pytest

from simcore.cli import main
from simcore.io import open_dataset
from simcore.io.reader import COORDS, DIMS
from simcore.resources import example_path

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def run_h5(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("reader") / "out" / "demo.h5"
    assert main(["run", str(example_path("office_rgb")), "--out", str(out), "--frames", "2",
                 "--quiet"]) == 0
    return out


def _hdf5_datasets(path: Path) -> dict[str, tuple[np.ndarray, dict]]:
    found = {}
    with h5py.File(path) as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                data = obj.asstr()[()] if obj.dtype.kind == "O" else obj[()]
                found["/" + name] = (data, dict(obj.attrs))
        f.visititems(visit)
    return found


def test_every_dataset_round_trips_with_its_dims_and_unit(run_h5):
    datasets = _hdf5_datasets(run_h5)
    ds = open_dataset(run_h5)
    try:
        for path, (data, attrs) in datasets.items():
            if attrs.get("table"):
                for field in data.dtype.names:
                    var = ds[f"detection_{field}"]
                    assert var.dims == ("detection",)
                    np.testing.assert_array_equal(var.values, data[field])
                continue
            if attrs.get("table_rows"):
                for field in data.dtype.names:
                    var = ds[f"radar_detections_by_frame_{field}"]
                    assert var.dims == ("frame", "slot")
                    np.testing.assert_array_equal(var.values, data[field])
                continue
            name = "time" if path == "/time" else COORDS.get(
                path, path.strip("/").replace("/", "_"))
            var = ds[name]
            per_frame = bool(attrs.get("per_frame"))
            expected = (("frame",) if per_frame else ()) + DIMS.get(path, ())
            assert var.dims == expected, path
            assert var.attrs["units"] == attrs["unit"], path
            np.testing.assert_array_equal(var.values, data, err_msg=path)
        # The run writes every dataset of the layout (office_rgb has all three sensors).
        assert set(DIMS) | {"/time", "/radar/detections"} <= set(datasets)
        # The dimensions the layout promises, with SI coordinates.
        assert ds.radar_adc.dims == ("frame", "chirp", "channel", "sample")
        assert ds.tof_depth.dims == ("frame", "row", "col")
        assert ds.radar_range_doppler.dims == ("frame", "velocity", "range")
        assert ds.radar_range_azimuth.dims == ("frame", "azimuth", "range")
        assert (ds.range.attrs["units"], ds.velocity.attrs["units"],
                ds.azimuth.attrs["units"], ds.time.attrs["units"]) == ("m", "m/s", "deg", "s")
        assert ds.time.dims == ("frame",) and ds.sizes["frame"] == 2
        assert list(ds.object_name.values[:2]) == ["floor", "ceiling"]
    finally:
        ds.close()


def test_the_notebook_example_in_dataset_md_runs(run_h5, monkeypatch):
    text = (ROOT / "docs" / "dataset.md").read_text()
    section = text[text.index("## Reading with xarray"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(run_h5.parent.parent)  # the example reads out/demo.h5
    exec(compile(code, "dataset.md", "exec"), {})


def _rss_bytes() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS")


def test_opening_a_2_gb_file_reads_nothing_until_asked(tmp_path):
    if not Path("/proc/self/status").exists():
        pytest.skip("needs /proc")
    path = tmp_path / "big.h5"
    n, shape = 1400, (64, 12, 512)      # 1400 frames × 1.5 MB of ADC data = 2.2 GB
    with h5py.File(path, "w") as f:
        f.create_group("meta").attrs["n_frames"] = n
        t = f.create_dataset("time", data=np.arange(n) * 0.1, chunks=(1024,))
        t.attrs["unit"], t.attrs["per_frame"] = "s", True
        adc = f.create_dataset("radar/adc", shape=(n, *shape), dtype="f4",
                               chunks=(1, *shape))  # sparse: unwritten chunks take no space
        adc.attrs["unit"], adc.attrs["per_frame"] = "FS", True
        adc[n - 1] = 0.25
    assert path.stat().st_size < 50e6
    before = _rss_bytes()
    ds = open_dataset(path)
    try:
        assert ds.radar_adc.nbytes > 2e9
        assert _rss_bytes() - before < 200e6
        last = ds.radar_adc.isel(frame=-1).values
        np.testing.assert_array_equal(last, 0.25)
        assert _rss_bytes() - before < 200e6
    finally:
        ds.close()
