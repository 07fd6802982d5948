"""Every bundled example, as a user runs it: two frames through each writer, then read back.

``tofradar run`` to HDF5 (with ``--preview``), Zarr and MCAP; ``tofradar products`` where
the project has a radar; ``open_dataset`` of the HDF5 file and the Zarr store. An example
whose sensors are not named after their kinds (``robot_pair.json``: ``tof_b``) is written
like any other.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import pytest

from simcore.cli import main
from simcore.examples import list_examples
from simcore.io import open_dataset
from simcore.scene import load_project
from simcore.scene.model import sensor_kind
from simcore.sensors.schema import schema_of

EXAMPLES = [e.name for e in list_examples()]


@pytest.fixture(scope="module")
def copies(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The examples copied as a user would (``tofradar examples --copy DIR``)."""
    folder = tmp_path_factory.mktemp("examples")
    assert main(["examples", "--copy", str(folder / "ex")]) == 0
    return folder / "ex"


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_runs_through_every_writer(copies: Path, tmp_path: Path, name: str) -> None:
    project_path = copies / f"{name}.json"
    project = load_project(project_path)
    h5, store, mcap = tmp_path / "run.h5", tmp_path / "run.zarr", tmp_path / "run.mcap"
    previews = tmp_path / "previews"
    assert main(["run", str(project_path), "--out", str(h5), "--frames", "2", "--quiet",
                 "--preview", str(previews)]) == 0
    assert main(["run", str(project_path), "--out", str(store), "--frames", "2",
                 "--quiet"]) == 0
    assert main(["run", str(project_path), "--out", str(mcap), "--frames", "2",
                 "--quiet"]) == 0
    radars = list(project.sensors_of_kind("radar"))
    if radars:
        assert main(["products", str(h5)]) == 0
        with h5py.File(h5, "r") as f:
            assert all(f"{r}/spectrogram/power" in f for r in radars)
    written = {p.name for p in previews.iterdir()}
    for sensor, cfg in project.sensor_configs().items():
        schema = schema_of(sensor_kind(cfg))
        for output in schema.previews():
            assert f"frame_00001_{sensor}_{output.name}.png" in written, (sensor, output.name)
    for out in (h5, store):
        ds = open_dataset(out)
        try:
            assert ds.sizes["frame"] == 2
            for sensor, cfg in project.sensor_configs().items():
                schema = schema_of(sensor_kind(cfg))
                depth_like = next(o for o in schema.outputs if o.per_frame and o.finite)
                var = schema.dataset_path(sensor, depth_like.name).strip("/").replace("/", "_")
                assert ds[var].dims == ("frame", *schema.dims(sensor, depth_like))
        finally:
            ds.close()
    assert mcap.stat().st_size > 0
    shutil.rmtree(store)
