"""The RGB camera plug-in: colour where the ToF ground truth puts each object."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.runs.runner import run_dataset
from simcore.scene import Box, DualBandMaterial, Pose, Project, SceneObject, load_project
from simcore.scene.materials import BandMaterial
from simcore.scene.model import SensorRig
from simcore.scene.project_io import project_to_json
from simcore.scene.rgb_config import RgbCameraConfig
from simcore.scene.tof_config import TofCameraConfig

RED, BLUE, GREY = (0.8, 0.05, 0.05), (0.05, 0.1, 0.8), (0.5, 0.5, 0.5)


def colour_project() -> Project:
    """A grey wall 3 m ahead with a red and a blue box in front; RGB shares the ToF's pose
    and pixel grid (224×171 over 62°×45°)."""
    def material(name: str, rgb: tuple[float, float, float]) -> DualBandMaterial:
        return DualBandMaterial(name=name, color_rgb=rgb,
                                bands={"visible": BandMaterial(reflectance=1.0)})

    objects = [
        SceneObject(id=10, name="wall", geometry=Box(size_m=(0.2, 2.5, 2.0)),
                    pose=Pose(position_m=(3.1, 0.0, 0.0)), material="grey"),
        SceneObject(id=11, name="red_box", geometry=Box(size_m=(0.3, 0.5, 0.5)),
                    pose=Pose(position_m=(2.0, 0.5, 0.1)), material="red"),
        SceneObject(id=12, name="blue_box", geometry=Box(size_m=(0.3, 0.4, 0.6)),
                    pose=Pose(position_m=(2.4, -0.6, -0.2), rotation_deg=(0, 0, 20)),
                    material="blue"),
    ]
    tof = TofCameraConfig(pose_on_rig=Pose(position_m=(0.0, 0.02, 0.0)))
    rgb = RgbCameraConfig(width=tof.width, height=tof.height, fov_h_deg=tof.fov_h_deg,
                          fov_v_deg=tof.fov_v_deg, pose_on_rig=tof.pose_on_rig)
    return Project(materials=[material("red", RED), material("blue", BLUE),
                              material("grey", GREY)],
                   objects=objects, rig=SensorRig(tof=tof, rgb=rgb))


def test_rgb_pixels_show_the_objects_where_the_tof_ground_truth_has_them() -> None:
    project = colour_project()
    with Simulator(project) as sim:
        frame = sim.frame(0)
    image = frame.outputs["rgb"].image.astype(float)
    gt = frame.outputs["tof"].gt_object_id
    assert image.shape == (171, 224, 3)
    # Pixels whose 3×3 ToF neighbourhood is one object (away from silhouettes, where the
    # supersampled ToF ground truth votes over sub-pixels).
    pure = np.ones_like(gt, dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            pure &= np.roll(np.roll(gt, dy, axis=0), dx, axis=1) == gt
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    checks = {
        11: (r > 2 * g) & (r > 2 * b),                   # red box
        12: (b > 2 * r) & (b > 1.5 * g),                 # blue box
        10: (np.abs(r - g) < 8) & (np.abs(g - b) < 8),   # grey wall
    }
    for object_id, is_colour in checks.items():
        where = pure & (gt == object_id)
        assert where.sum() > 200, object_id
        assert is_colour[where].mean() > 0.99, (object_id, is_colour[where].mean())
    sky = np.array(project.rig.rgb.background_rgb)
    where = pure & (gt == -1)
    assert where.sum() > 200
    expected_sky = np.rint(255 * (1.055 * sky ** (1 / 2.4) - 0.055))   # sRGB of the sky
    assert np.all(np.abs(image[where] - expected_sky) <= 1)
    # The camera's own ground truth agrees with the ToF's on the pure pixels.
    assert (frame.outputs["rgb"].gt_object_id[pure] == gt[pure]).mean() > 0.999


def test_lambertian_shading_of_a_facing_wall() -> None:
    """A grey wall facing the camera: L = c (ambient + lamp cos θ), cos θ from the pixel ray."""
    project = colour_project()
    project.objects = project.objects[:1]
    with Simulator(project) as sim:
        frame = sim.frame(0)
    rgb = project.rig.rgb
    intr = rgb.intrinsics()
    row, col = 85, 40
    x = (col + 0.5 - intr.cx) / intr.fx
    y = (row + 0.5 - intr.cy) / intr.fy
    cos_theta = 1.0 / np.sqrt(1 + x * x + y * y)         # wall normal = optical axis
    linear = GREY[0] * (rgb.ambient + rgb.lamp * cos_theta)
    expected = np.rint(255 * (1.055 * linear ** (1 / 2.4) - 0.055))
    assert frame.outputs["rgb"].image[row, col, 0] == pytest.approx(expected, abs=1)


def test_rgb_frames_land_in_the_dataset(tmp_path) -> None:
    project = colour_project()
    out = tmp_path / "rgb.h5"
    run_dataset(project_to_json(project), tmp_path, out, n_frames=2, seed=0)
    with h5py.File(out) as f:
        assert f["/rgb/image"].shape == (2, 171, 224, 3)
        assert f["/rgb/image"].dtype == np.uint8
        assert f["/rgb/gt_object_id"].shape == (2, 171, 224)


def test_the_bundled_rgb_example_sets_the_camera() -> None:
    project = load_project(example_path("office_rgb"))
    assert project.rig.rgb is not None
    assert load_project(example_path("office")).rig.rgb is None
