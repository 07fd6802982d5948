"""Ground-truth labels of radar detections (simcore.sensors.radar.labels)."""

from __future__ import annotations

import numpy as np
import pytest

from simcore.dsp import radar_axes
from simcore.dsp.detections import Detections
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.dsp_config import DspConfig
from simcore.scene.geometry import corner_reflector_axes
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.radar.labels import label_detections
from simcore.sensors.radar.scatterers import Scatterers


def _detections(range_index, doppler_index, axes) -> Detections:
    ri = np.asarray(range_index, dtype=np.int64)
    di = np.asarray(doppler_index, dtype=np.int64)
    z = np.zeros(ri.size)
    xyz = np.stack([z, z, axes.range_m[ri]], axis=1)
    return Detections(di, ri, axes.range_m[ri], axes.velocity_mps[di], z, z.copy(), z + 20,
                      z.copy(), xyz)


def test_two_objects_in_one_cell_share_its_power_by_rcs() -> None:
    rc = RadarConfig(noise_variance_adc=1e-16, if_highpass_hz=0)
    dc = DspConfig()
    axes = radar_axes(rc, dc)
    ri, di = 100, axes.velocity_mps.size // 2 + 3  # a range bin centre, a moving Doppler bin
    r, v = axes.range_m[ri], axes.velocity_mps[di]
    scat = Scatterers.from_arrays(np.array([[0, 0, r], [0, 0, r]]), np.array([3.0, 1.0]),
                                  velocities_mps=np.array([[0, 0, v], [0, 0, v]]))
    scat = Scatterers(**{**scat.__dict__, "object_index": np.array([0, 1], dtype=np.int32)})
    det = _detections([ri, ri + 60], [di, di], axes)  # the two targets' cell; an empty one
    labels = label_detections(det, scat, np.array([10, 20]), rc, dc, axes)
    np.testing.assert_array_equal(labels.object_id, [10, -1])
    np.testing.assert_allclose(labels.power_fraction, [0.75, 0.0], atol=1e-4)
    np.testing.assert_array_equal(labels.ghost, [False, False])


def test_static_clutter_removal_leaves_a_still_target_unlabelled() -> None:
    rc = RadarConfig(noise_variance_adc=1e-12, if_highpass_hz=0)
    dc = DspConfig(static_clutter_removal=True)
    axes = radar_axes(rc, dc)
    ri, di = 100, axes.velocity_mps.size // 2  # zero velocity
    scat = Scatterers.from_arrays(np.array([[0, 0, axes.range_m[ri]]]), np.array([1.0]))
    scat = Scatterers(**{**scat.__dict__, "object_index": np.array([0], dtype=np.int32)})
    labels = label_detections(_detections([ri], [di], axes), scat, np.array([7]), rc, dc, axes)
    np.testing.assert_array_equal(labels.object_id, [-1])


POINT_TARGETS = load_project(example_path("point_targets"))


def _corner_ranges(frame) -> dict[int, float]:
    radar = frame.snapshot.sensor("radar").position
    return {o.id: float(np.linalg.norm(s.origin - radar))
            for o, s in zip(POINT_TARGETS.objects, frame.snapshot.objects, strict=True)}


@pytest.fixture(scope="module")
def point_target_frames():
    # A high false-alarm rate puts detections in empty space too.
    dsp = POINT_TARGETS.dsp.model_copy(update={"cfar_pfa": 0.05,
                                               "doppler_sidelobe_margin_db": None})
    noisy = POINT_TARGETS.model_copy(update={"dsp": dsp})
    with Simulator(POINT_TARGETS) as sim:
        plain = sim.frame(2)
    with Simulator(noisy) as sim:
        alarms = sim.frame(2)
    return plain, alarms


def test_every_point_target_detection_carries_its_corner_reflectors_id(point_target_frames):
    frame = point_target_frames[0]
    rows = frame.outputs["radar"].table_rows(frame.index)["/radar/detections"]
    ranges = _corner_ranges(frame)
    assert len(rows) == 3
    for row in rows:
        nearest = min(ranges, key=lambda k: abs(ranges[k] - row["range"]))
        assert row["object_id"] == nearest
        assert row["power_fraction"] > 0.99
        assert not row["ghost"]
    assert sorted(rows["object_id"]) == [1, 2, 3]


def test_detections_of_empty_space_are_noise(point_target_frames):
    frame = point_target_frames[1]
    rows = frame.outputs["radar"].table_rows(frame.index)["/radar/detections"]
    ranges = np.array(list(_corner_ranges(frame).values()))
    far = np.min(np.abs(rows["range"][:, None] - ranges[None, :]), axis=1) > 0.3
    assert np.count_nonzero(far) >= 10
    np.testing.assert_array_equal(rows["object_id"][far], -1)
    np.testing.assert_array_equal(rows["power_fraction"][far], 0.0)
    assert set(rows["object_id"][~far]) <= {-1, 1, 2, 3}


@pytest.mark.parametrize("multipath", [False, True])
def test_corner_reflector_behind_the_paper_box_is_labelled(multipath: bool) -> None:
    """The hidden corner reflector's detection carries its id. Without multipath it holds
    over 90 % of its cell's power; with the office's multipath (as shipped) its ghosts via
    the desk and the room share the cell, and the detection is still its direct return."""
    project = load_project(example_path("office"))
    if not multipath:
        radar = project.rig.radar.model_copy(update={"multipath_order": 0})
        project = project.model_copy(update={"rig": project.rig.model_copy(
            update={"radar": radar})})
    assert (project.rig.radar.multipath_order > 0) is multipath
    corner = next(o for o in project.objects if o.name == "corner_reflector")
    results = []
    for accelerate in (True, False):
        with Simulator(project, reuse_static=accelerate) as sim:
            sim.frame(0)
            frame = sim.frame(1)  # over the still background when accelerated
        results.append(frame.outputs["radar"].table_rows(1)["/radar/detections"])
        radar = frame.snapshot.sensor("radar").transform
        index = [o.id for o in project.objects].index(corner.id)
        apex = np.linalg.inv(radar) @ np.append(frame.snapshot.objects[index].origin, 1.0)
    rows = results[0]
    near = np.linalg.norm(np.stack([rows["x"], rows["y"], rows["z"]], 1) - apex[:3], axis=1)
    k = int(np.argmin(near))
    assert near[k] < 0.3
    assert rows["object_id"][k] == corner.id
    assert not rows["ghost"][k]
    assert rows["power_fraction"][k] > (0.5 if multipath else 0.9)
    # The still-background accelerator builds the same scatterers: the same labels.
    np.testing.assert_array_equal(results[0]["object_id"], results[1]["object_id"])
    np.testing.assert_allclose(results[0]["power_fraction"], results[1]["power_fraction"],
                               atol=1e-3)


def test_object_ground_truth_matches_the_detections_and_the_geometry(point_target_frames):
    frame = point_target_frames[0]
    truth = frame.objects
    rows = frame.outputs["radar"].table_rows(frame.index)["/radar/detections"]
    for row in rows:
        k = [o.id for o in POINT_TARGETS.objects].index(int(row["object_id"]))
        assert abs(truth.radar_range_m[k] - row["range"]) < 0.01
        assert abs(truth.radar_radial_velocity_mps[k] - row["velocity"]) < 0.05
        assert abs(truth.radar_azimuth_deg[k] - row["azimuth_deg"]) < 1.0
    # corner_2 moves at 1 m/s along boresight; the others stand still.
    np.testing.assert_allclose(truth.radar_radial_velocity_mps, [0.0, 1.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(truth.velocity_mps, axis=1), [0.0, 1.0, 0.0])
    # A trihedral: apex at the origin, edge vectors a · corner_reflector_axes().
    local = np.vstack([np.zeros(3), corner_reflector_axes() * 0.06])
    np.testing.assert_allclose(truth.obb_size_m, np.tile(np.ptp(local, axis=0), (3, 1)))
    for k in range(3):
        corners = truth.aabb_m[k]
        assert np.all(corners[0] <= truth.obb_center_m[k]) and np.all(
            truth.obb_center_m[k] <= corners[1])
        np.testing.assert_allclose(truth.obb_rotation[k], frame.object_poses[k][:3, :3])
    items = frame.hdf5_items()
    assert items["/objects/aabb"][0].shape == (3, 2, 3)
    assert items["/objects/radar_azimuth"][1] == "deg"


def test_a_noiseless_receiver_labels_without_warnings() -> None:
    rc = RadarConfig(noise_variance_adc=0.0, if_highpass_hz=0)
    dc = DspConfig()
    axes = radar_axes(rc, dc)
    scat = Scatterers.from_arrays(np.array([[0, 0, axes.range_m[50]]]), np.array([1.0]))
    scat = Scatterers(**{**scat.__dict__, "object_index": np.array([0], dtype=np.int32)})
    mid = axes.velocity_mps.size // 2
    with np.errstate(all="raise"):
        labels = label_detections(_detections([50, 200], [mid, mid], axes), scat,
                                  np.array([4]), rc, dc, axes)
    np.testing.assert_array_equal(labels.object_id, [4, -1])
    np.testing.assert_allclose(labels.power_fraction, [1.0, 0.0])


# --------------------------------------------------------------------------------------
# The compiled label terms against the previous numpy implementation
# --------------------------------------------------------------------------------------


def prepare_reference(scatterers: Scatterers, rc: RadarConfig) -> dict[str, np.ndarray]:
    """prepare_scatterers as numpy (the previous implementation): argsort, vector formulas."""
    from simcore.dsp.angle import virtual_array_positions_m
    from simcore.scene.radar_config import SPEED_OF_LIGHT
    from simcore.sensors.radar.equation import amplitude_scale_fs, element_gain

    pos = scatterers.positions_m
    r = np.maximum(np.sqrt(np.einsum("ij,ij->i", pos, pos)), 1e-9)
    order = np.argsort(r, kind="stable")
    pos, r = pos[order], r[order]
    u = pos / r[:, None]
    v_radial = np.einsum("ij,ij->i", scatterers.velocities_mps[order], u)
    g_tx = np.mean([element_gain(a.pattern or rc.element_pattern, pos) for a in rc.tx], axis=0)
    g_rx = np.mean([element_gain(a.pattern or rc.element_pattern, pos) for a in rc.rx], axis=0)
    power = amplitude_scale_fs(rc) ** 2 * scatterers.rcs_m2[order] * g_tx * g_rx / r**4
    if rc.if_highpass_hz > 0:
        x = (2.0 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT / rc.if_highpass_hz) ** (
            2 * rc.if_highpass_order)
        power *= x / (1.0 + x)
    if rc.if_lowpass_hz > 0:
        x = (2.0 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT / rc.if_lowpass_hz) ** (
            2 * rc.if_lowpass_order)
        power /= 1.0 + x
    phase = u @ (-2.0 * np.pi / rc.wavelength_m * virtual_array_positions_m(rc).T)
    steering = np.exp(1j * phase.astype(np.float32)).astype(np.complex64)
    cycles = v_radial * 2.0 * len(rc.tx) * rc.chirp_repetition_time_s / rc.wavelength_m
    return {"range_m": r, "velocity_mps": v_radial, "power": power, "steering": steering,
            "object_index": scatterers.object_index[order], "doppler_cycles": cycles}


def cell_power_reference(prepared, detections, n_objects, rc, dc, axes) -> np.ndarray:
    """cell_power_by_object as a numpy loop over detections (the previous implementation)."""
    from simcore.dsp.angle import direction_vectors, virtual_array_positions_m
    from simcore.scene.radar_config import SPEED_OF_LIGHT
    from simcore.sensors.radar import labels as lab

    out = np.zeros((len(detections), n_objects + 1))
    range_table = lab._window_power_table(dc.range_window, rc.samples_per_chirp,
                                          dc.range_window_sidelobe_db, axes.range_fft_size)
    doppler_table = lab._window_power_table(dc.doppler_window, rc.chirps_per_frame,
                                            dc.doppler_window_sidelobe_db,
                                            axes.doppler_fft_size)
    dr = SPEED_OF_LIGHT * rc.sample_rate_hz / (2.0 * rc.slope_hz_per_s * axes.range_fft_size)
    dv = float(axes.velocity_mps[1] - axes.velocity_mps[0])
    reach_m = lab._range_reach_bins(range_table) * dr
    cell_range = axes.range_m[detections.range_index]
    cell_velocity = axes.velocity_mps[detections.doppler_index]
    a_det = np.exp(-2j * np.pi * (direction_vectors(
        np.deg2rad(detections.azimuth_deg), np.deg2rad(detections.elevation_deg))
        @ virtual_array_positions_m(rc).T) / rc.wavelength_m).astype(np.complex64)
    column = np.where((prepared.object_index >= 0) & (prepared.object_index < n_objects),
                      prepared.object_index, n_objects)
    n_ch = a_det.shape[1]
    for j in range(len(detections)):
        near = slice(*np.searchsorted(prepared.range_m, [cell_range[j] - reach_m,
                                                         cell_range[j] + reach_m]))
        power = prepared.power[near] * lab._lookup(
            range_table, (prepared.range_m[near] - cell_range[j]) / dr)
        power *= lab._lookup(doppler_table,
                             (prepared.velocity_mps[near] - cell_velocity[j]) / dv)
        power *= np.abs(prepared.steering[near] @ a_det[j].conj()) ** 2 / n_ch**2
        if dc.static_clutter_removal:
            power *= lab._clutter_filter(prepared.doppler_cycles[near], rc.chirps_per_frame)
        out[j] = np.bincount(column[near], weights=power, minlength=n_objects + 1)
    return out


def _random_scene(rc: RadarConfig, axes, m: int, n_objects: int, seed: int):
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.3, 0.9 * axes.range_m[-1], m)
    r[:20] = r[20]                                   # equal ranges keep their order
    az, el = rng.uniform(-1.2, 1.2, m), rng.uniform(-0.8, 0.8, m)
    pos = r[:, None] * np.stack([np.sin(az) * np.cos(el), -np.sin(el),
                                 np.cos(az) * np.cos(el)], axis=1)
    pos[-1] = 0.0                                    # at the radar
    vel = rng.uniform(-0.6, 0.6, (m, 3)) * axes.velocity_mps[-1]
    scat = Scatterers.from_arrays(pos, rng.uniform(0.01, 2.0, m), velocities_mps=vel)
    obj = rng.integers(-1, n_objects + 1, m).astype(np.int32)   # −1 and out of range too
    scat = Scatterers(**{**scat.__dict__, "object_index": obj})
    n_det = 30
    ri = rng.integers(1, axes.range_m.size - 1, n_det)
    di = rng.integers(0, axes.velocity_mps.size, n_det)
    z = np.zeros(n_det)
    det = Detections(di.astype(np.int64), ri.astype(np.int64), axes.range_m[ri],
                     axes.velocity_mps[di], rng.uniform(-60, 60, n_det),
                     rng.uniform(-40, 40, n_det), z + 20, z.copy(), np.zeros((n_det, 3)))
    return scat, det


LABEL_CASES = {
    "preset": (RadarConfig(), DspConfig()),
    "clutter_filter_lowpass": (RadarConfig(if_lowpass_hz=8e5, if_lowpass_order=4),
                               DspConfig(static_clutter_removal=True)),
    "tdm_mimo_own_patterns": (
        RadarConfig.model_validate({
            **RadarConfig().model_dump(),
            "tx": [{"name": "tx1", "position_mm": (0.0, 0.0)},
                   {"name": "tx2", "position_mm": (7.5, 0.0),
                    "pattern": {"kind": "cosine", "exponent_az": 1.0, "exponent_el": 3.0}}],
            "if_highpass_order": 2}),
        DspConfig(range_window="blackman", doppler_window="hann")),
    "table_pattern": (
        RadarConfig.model_validate({
            **RadarConfig().model_dump(),
            "element_pattern": {"kind": "table", "azimuth_deg": [-90.0, 0.0, 90.0],
                                "elevation_deg": [-90.0, 0.0, 90.0],
                                "gain_db": [[-20.0, -10.0, -20.0], [-6.0, 0.0, -3.0],
                                            [-20.0, -12.0, -20.0]]}}),
        DspConfig()),
}


@pytest.mark.parametrize("case", list(LABEL_CASES))
def test_label_terms_equal_the_numpy_reference(case: str) -> None:
    from simcore.sensors.radar.labels import cell_power_by_object, prepare_scatterers

    rc, dc = LABEL_CASES[case]
    axes = radar_axes(rc, dc)
    scat, det = _random_scene(rc, axes, 3000, 4, seed=len(case))
    got = prepare_scatterers(scat, rc)
    want = prepare_reference(scat, rc)
    for name, value in want.items():
        np.testing.assert_allclose(getattr(got, name), value, rtol=1e-13, atol=0,
                                   err_msg=name)
    np.testing.assert_array_equal(got.range_m, want["range_m"])      # the same order
    powers = cell_power_by_object(got, det, 4, rc, dc, axes)
    assert np.count_nonzero(powers) > 10
    # The beam term is float32 in the reference: its rounding, no more.
    np.testing.assert_allclose(powers, cell_power_reference(got, det, 4, rc, dc, axes),
                               rtol=2e-6, atol=1e-12 * powers.max())
