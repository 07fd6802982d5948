"""The ideal-sensor switch (``TofCameraConfig.ideal``): no noise, no quantisation."""

from __future__ import annotations

import json

import numpy as np
from numpy.testing import assert_array_equal

from simcore.render import RenderRequest, render_once
from simcore.report.tof_reference import camera_config, reference_project
from simcore.scene.project_io import project_from_dict, project_to_json
from simcore.sensors.tof.camera import simulate_tof


def test_ideal_camera_is_the_noise_free_one_and_reaches_project_files():
    real = camera_config(multipath=False).model_copy(update={"ideal": False,
                                                             "read_noise_electrons": 50.0})
    ideal = real.model_copy(update={"ideal": True})
    project = reference_project("corner", ideal)
    assert project_from_dict(json.loads(project_to_json(project))).rig.tof.ideal is True
    buf = render_once(project, RenderRequest("tof", "tof", ideal.render_intrinsics()))
    a = simulate_tof(buf, ideal, rng=np.random.default_rng(1))
    b = simulate_tof(buf, ideal, rng=np.random.default_rng(2))
    quiet = simulate_tof(buf, real, rng=np.random.default_rng(3), noise=False)
    noisy = simulate_tof(buf, real, rng=np.random.default_rng(1))
    assert_array_equal(a.depth_m, b.depth_m)
    assert_array_equal(a.depth_m, quiet.depth_m)
    assert_array_equal(a.correlation, quiet.correlation)
    assert not np.array_equal(a.depth_m, noisy.depth_m)
