"""IF synthesis of moving scatterers: range–Doppler coupling, range migration, rig motion.

Every reference here is computed in this file: the coupling shift from the FMCW formula, the
exact positions of the scatterers at every sample from the rig's motion written out with
rotation matrices, and the IF of a moving scatterer written out by hand. The fast path
(:func:`synthesize_if`) is compared with the direct sum given those exact positions.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Box, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.motion import Keyframe, Motion, Pose, RigidState
from simcore.scene.radar_arrays import custom_array
from simcore.scene.radar_config import SPEED_OF_LIGHT, CosinePattern, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c, tdm_mimo_2tx4rx
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import synthesis
from simcore.sensors.radar.kinematics import motion_maps_batch, rigid_point_motion
from simcore.sensors.radar.scatterers import Scatterers, scatterers_from_render
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import prepare, synthesize_if, synthesize_if_direct

IDEAL = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
         "if_highpass_hz": 0.0, "if_lowpass_hz": 0.0}
#: Optical frame (x right, y down, z forward) → rig body frame (x forward, y left, z up).
BODY_FROM_OPTICAL = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])

Trajectory = Callable[[np.ndarray], np.ndarray]


def error_db(fast: np.ndarray, ref: np.ndarray) -> float:
    return float(20 * np.log10(np.linalg.norm(fast - ref) / np.linalg.norm(ref)))


def unit(az_deg: float, el_deg: float) -> np.ndarray:
    az, el = np.deg2rad(az_deg), np.deg2rad(el_deg)
    return np.array([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)])


def radial_targets(v: float) -> Scatterers:
    """Five point targets moving along their line of sight from the array origin at ``v``."""
    dirs = np.array([unit(a, e) for a, e in [(0, 0), (20, 5), (-35, -10), (10, 15), (-5, 0)]])
    ranges = np.array([0.7, 1.9, 2.6, 4.1, 5.7])
    return Scatterers.from_arrays(ranges[:, None] * dirs, [1.0, 0.3, 2.0, 0.5, 1.5],
                                  velocities_mps=v * dirs,
                                  phase_rad=[0.0, 1.0, 2.0, 3.0, 4.0])


# --------------------------------------------------------------------------- coupling
def test_receding_target_shows_the_up_chirp_range_doppler_coupling() -> None:
    """Acceptance 1: the range-FFT peak of a target receding at 5 m/s sits at R + f_D c/(2K).

    Within a chirp the beat frequency is ``d/dt (f_inst τ) = K τ(t) + f_inst(t) τ'``; over
    the sampling window its mean is ``K τ(t_mid) + f_mid 2v/c``: the range at the window
    centre plus the Doppler shift ``f_D = 2v/λ_mid`` (λ at the window's centre frequency)
    read as range, ``f_D c / (2K)``.
    """
    cfg = bgt60tr13c(**IDEAL, rx=custom_array([(0.0, 0.0)]),
                     element_pattern=CosinePattern(exponent_az=0, exponent_el=0))
    r0, v = 2.5, 5.0
    scene = Scatterers.from_arrays(np.array([[0.0, 0.0, r0]]), [1.0],
                                   velocities_mps=np.array([[0.0, 0.0, v]]))
    y = synthesize_if(scene, cfg)[0, 0]                # complex IF of chirp 0
    n, fs, k = cfg.samples_per_chirp, cfg.sample_rate_hz, cfg.slope_hz_per_s
    pad = 64
    spec = np.abs(np.fft.fft(y * np.hanning(n), n=pad * n))
    i = int(np.argmax(spec[: pad * n // 2]))
    a, b, c = np.log(spec[i - 1 : i + 2])
    peak_bin = (i + 0.5 * (a - c) / (a - 2 * b + c)) / pad   # in range bins (fs / n)
    t_mid = 0.5 * (n - 1) / fs
    f_mid = cfg.start_frequency_hz + k * t_mid
    f_doppler = 2 * v * f_mid / SPEED_OF_LIGHT
    shift_m = f_doppler * SPEED_OF_LIGHT / (2 * k)
    bin_m = SPEED_OF_LIGHT * fs / (2 * k * n)
    expected_bin = (r0 + v * t_mid + shift_m) / bin_m
    print(f"coupling shift {shift_m * 1e3:.2f} mm = {shift_m / bin_m:.3f} bin; peak "
          f"{peak_bin:.4f} bin, expected {expected_bin:.4f} bin")
    assert shift_m == pytest.approx(0.0135, abs=5e-4)
    assert abs(peak_bin - expected_bin) <= 0.05
    # Without the coupling the peak would sit a third of a bin and more nearer.
    assert abs(peak_bin - (r0 + v * t_mid) / bin_m) > 0.4


def test_direct_sum_of_a_moving_scatterer_by_hand() -> None:
    """The reference itself: delay from the exact position at every sample, written out."""
    cfg = bgt60tr13c(**IDEAL, chirps_per_frame=4,
                     element_pattern=CosinePattern(exponent_az=0, exponent_el=0))
    x0, vel = np.array([0.3, -0.2, 2.0]), np.array([1.5, 0.5, -4.0])
    scene = Scatterers.from_arrays(x0[None], [0.5], velocities_mps=vel[None])
    y = synthesize_if_direct(scene, cfg)
    m, r = 3, 2
    p_rx = cfg.rx_positions_m()[r]
    t = cfg.chirp_start_times_s()[m, 0] + cfg.sample_times_s()
    x = x0[None] + vel[None] * t[:, None]
    tau = (np.linalg.norm(x, axis=1) + np.linalg.norm(x - p_rx, axis=1)) / SPEED_OF_LIGHT
    f_inst = cfg.start_frequency_hz + cfg.slope_hz_per_s * cfg.sample_times_s()
    r_t, r_r = np.linalg.norm(x0), np.linalg.norm(x0 - p_rx)
    p_r = (1e-3 * 10 ** (cfg.tx_power_dbm / 10) * 10 ** ((cfg.tx_gain_dbi + cfg.rx_gain_dbi) / 10)
           * cfg.wavelength_m**2 * 0.5 / ((4 * np.pi) ** 3 * r_t**2 * r_r**2))
    amp = np.sqrt(2 * 50.0 * p_r) * 10 ** (cfg.if_gain_db / 20) / cfg.adc_full_scale_v
    expected = amp * np.exp(1j * (2 * np.pi * f_inst * tau - np.pi * cfg.slope_hz_per_s * tau**2))
    assert_allclose(y[m, r], expected, rtol=1e-9, atol=1e-12 * amp)


# --------------------------------------------------------------------------- linear motion
@pytest.mark.parametrize("v", [0.5, 20.0])
@pytest.mark.parametrize("chirps", [16, 64])
@pytest.mark.parametrize("array", ["1tx3rx", "2tx4rx"])
def test_constant_radial_velocity_targets_match_the_direct_sum(v: float, chirps: int,
                                                               array: str) -> None:
    """Acceptance 2: linear motion, −80 dB at the default tolerance (TDM timing included)."""
    cfg = (bgt60tr13c(chirps_per_frame=chirps) if array == "1tx3rx"
           else tdm_mimo_2tx4rx(chirps_per_frame=chirps))
    scene = radial_targets(v)
    err = error_db(synthesize_if(scene, cfg), synthesize_if_direct(scene, cfg))
    print(f"{array}, {chirps} chirps, {v} m/s: {err:.1f} dB")
    assert err <= -80.0


def test_accelerating_scatterers_match_the_direct_sum() -> None:
    """The motion model's acceleration (curvature series, shorter blocks where needed)."""
    rng = np.random.default_rng(5)
    n = 60
    pos = rng.uniform([-2, -0.5, 0.5], [2, 0.5, 6], (n, 3))
    vel = rng.uniform(-2, 2, (n, 3))
    acc = rng.uniform(-30, 30, (n, 3))
    scene = Scatterers.from_arrays(pos, rng.lognormal(-2, 1, n), velocities_mps=vel,
                                   accelerations_mps2=acc, phase_rad=rng.uniform(0, 6, n))
    for cfg in (bgt60tr13c(), tdm_mimo_2tx4rx(chirps_per_frame=16)):
        err = error_db(synthesize_if(scene, cfg), synthesize_if_direct(scene, cfg))
        print(f"{cfg.preset}: accelerating scatterers {err:.1f} dB")
        assert err <= -60.0


def test_fallback_is_per_scatterer(monkeypatch: pytest.MonkeyPatch) -> None:
    """One scatterer far from linear motion goes to the exact sum; the others do not."""
    linear = radial_targets(3.0)
    wild = Scatterers.from_arrays(np.array([[0.1, 0.0, 0.15]]), [1.0],
                                  velocities_mps=np.array([[30.0, 0.0, 0.0]]),
                                  accelerations_mps2=np.array([[0.0, 0.0, 4000.0]]))
    scene = Scatterers.from_arrays(
        np.concatenate([linear.positions_m, wild.positions_m]),
        np.concatenate([linear.rcs_m2, wild.rcs_m2]),
        velocities_mps=np.concatenate([linear.velocities_mps, wild.velocities_mps]),
        accelerations_mps2=np.concatenate([np.zeros((5, 3)), wild.accelerations]))
    sizes: list[int] = []
    direct = synthesis._direct_chirp

    def counting(*args: object) -> np.ndarray:
        weights = args[-1]
        assert isinstance(weights, np.ndarray)
        sizes.append(len(weights))
        return direct(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(synthesis, "_direct_chirp", counting)
    cfg = bgt60tr13c()
    fast = synthesize_if(scene, cfg)
    assert sizes and set(sizes) == {1}
    assert error_db(fast, synthesize_if_direct(scene, cfg)) <= -60.0


def points_spanning(near_m: float, far_m: float, n: int = 12, seed: int = 3) -> Scatterers:
    """``n`` scatterers at ranges ``near … far`` m, moving up to 2 m/s."""
    rng = np.random.default_rng(seed)
    dirs = np.array([unit(a, e) for a, e in rng.uniform([-40, -10], [40, 10], (n, 2))])
    ranges = np.linspace(near_m, far_m, n)
    return Scatterers.from_arrays(ranges[:, None] * dirs, rng.uniform(0.2, 2.0, n),
                                  velocities_mps=rng.uniform(-2, 2, (n, 3)),
                                  phase_rad=rng.uniform(0, 6, n))


@pytest.mark.parametrize(("near_m", "far_m", "samples", "single"),
                         [(0.7, 5.7, 512, True), (3.0, 3.5, 512, True),
                          (0.5, 24.0, 2048, False)])
def test_transform_precision_follows_the_points_spread(
        monkeypatch: pytest.MonkeyPatch, near_m: float, far_m: float, samples: int,
        single: bool) -> None:
    """complex64 transforms where the centred phase span keeps their rounding in budget.

    The span ``max|s| · ½(x_max − x_min)`` is half the beat phase swept over a chirp between
    the nearest and the farthest scatterer: ≈ π × the range bins between them. 5 m at the
    preset's 2.5 cm bins (≈ 310 rad) is within the single-precision bound, 23.5 m over 2048
    samples (≈ 3000 rad) is not; either way the cube stays within −80 dB of the direct sum.
    """
    chosen: list[bool] = []
    of = synthesis._Points.of

    def recording(*args: object) -> object:
        points = of(*args)  # type: ignore[arg-type]
        chosen.append(points.single)
        return points

    monkeypatch.setattr(synthesis._Points, "of", recording)
    cfg = bgt60tr13c(samples_per_chirp=samples, sample_rate_hz=2e6 * samples / 512,
                     complex_iq=True)
    scene = points_spanning(near_m, far_m)
    err = error_db(synthesize_if(scene, cfg), synthesize_if_direct(scene, cfg))
    print(f"{near_m}–{far_m} m, {samples} samples: single={chosen}, {err:.1f} dB")
    assert chosen and set(chosen) == {single}
    assert err <= -80.0


# --------------------------------------------------------------------------- rig motion
def rotation_z(angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((*np.shape(angle), 3, 3))
    out[..., 0, 0], out[..., 0, 1], out[..., 1, 0], out[..., 1, 1] = c, -s, s, c
    out[..., 2, 2] = 1.0
    return out


def world_points(project: Project, t0: float, n: int, seed: int) -> np.ndarray:
    """Random static world points in front of the radar at ``t0`` (0.4–6 m)."""
    rng = np.random.default_rng(seed)
    radar = take_snapshot(project, t0).sensors["radar"]
    r = rng.uniform(0.4, 6.0, n)
    local = r[:, None] * np.array([unit(a, e) for a, e in
                                   zip(rng.uniform(-50, 50, n), rng.uniform(-20, 20, n),
                                       strict=True)])
    return local @ radar.rotation.T + radar.position


def radar_frame(points: np.ndarray, rig_rot: np.ndarray, rig_pos: np.ndarray,
                mount: np.ndarray) -> np.ndarray:
    """Points in the radar optical frame for rig rotations (T, 3, 3) and positions (T, 3)."""
    r_s = rig_rot @ BODY_FROM_OPTICAL                                  # (T, 3, 3)
    s = rig_pos + np.einsum("tij,j->ti", rig_rot, mount)               # (T, 3)
    d = points[:, None, :] - s[None]                                   # (M, T, 3)
    return np.einsum("mti,tij->mtj", d, r_s)


def scatterers_at(project: Project, t0: float, points: np.ndarray) -> Scatterers:
    """Scatterers of static world points from the snapshot's rigid states (the helper)."""
    snap = take_snapshot(project, t0)
    still = RigidState(np.eye(4), np.zeros(3), np.zeros(3))
    pos, vel, acc = rigid_point_motion(points, still, snap.rig, snap.sensors["radar"])
    rng = np.random.default_rng(1)
    return Scatterers.from_arrays(pos, rng.lognormal(-3, 1, len(pos)), velocities_mps=vel,
                                  accelerations_mps2=acc,
                                  phase_rad=rng.uniform(0, 2 * np.pi, len(pos)))


@pytest.mark.parametrize("rate_dps", [10.0, 90.0])
def test_turning_and_translating_rig_matches_the_exact_positions(rate_dps: float) -> None:
    """Acceptance 2: a rig turning about z (radar off the axis) while moving at 0.3 m/s."""
    project = Project()
    p0, v_rig, mount = np.array([0.0, 0.0, 1.2]), np.array([0.3, 0.1, 0.0]), np.array(
        [0.05, -0.03, 0.02])
    omega = np.deg2rad(rate_dps)
    project.rig.pose = Pose(position_m=tuple(p0))
    project.rig.motion = Motion(velocity_mps=tuple(v_rig),
                                angular_velocity_dps=(0.0, 0.0, rate_dps))
    project.rig.radar = bgt60tr13c(pose_on_rig=Pose(position_m=tuple(mount)))
    t0 = 0.37
    points = world_points(project, t0, 150, seed=2)
    scene = scatterers_at(project, t0, points)

    def trajectory(times: np.ndarray) -> np.ndarray:
        t = t0 + np.asarray(times)
        return radar_frame(points, rotation_z(omega * t), p0 + v_rig * t[:, None], mount)

    assert_allclose(trajectory(np.zeros(1))[:, 0], scene.positions_m, atol=1e-12)
    cfg = project.rig.radar
    err = error_db(synthesize_if(scene, cfg),
                   synthesize_if_direct(scene, cfg, trajectory=trajectory))
    print(f"rig turning at {rate_dps}°/s: {err:.1f} dB")
    assert err <= -60.0


def test_accelerating_keyframed_rig_matches_the_exact_positions() -> None:
    """Acceptance 2: keyframes every millisecond on x = a t²/2 (kinks inside the frame).

    The snapshot gives each scatterer only its velocity on the current segment; the exact
    trajectory (piecewise linear, written out here) is handed to the fast path, which fits
    its model block by block and falls back where a kink spoils it.
    """
    accel, step = 40.0, 1e-3
    key_t = np.arange(0.0, 0.05, step)
    key_x = 0.5 * accel * key_t**2
    project = Project()
    p0, mount = np.array([0.0, 0.0, 1.2]), np.array([0.0, -0.03, 0.0])
    project.rig.pose = Pose(position_m=tuple(p0))
    project.rig.motion = Motion(keyframes=[Keyframe(time_s=float(t), position_m=(float(x), 0, 0))
                                           for t, x in zip(key_t, key_x, strict=True)])
    project.rig.radar = bgt60tr13c(pose_on_rig=Pose(position_m=tuple(mount)))
    t0 = 0.0205
    points = world_points(project, t0, 80, seed=4)
    scene = scatterers_at(project, t0, points)

    def trajectory(times: np.ndarray) -> np.ndarray:
        t = t0 + np.asarray(times)
        x = np.interp(t, key_t, key_x)
        rig_pos = p0 + x[:, None] * np.array([1.0, 0.0, 0.0])
        return radar_frame(points, np.broadcast_to(np.eye(3), (len(t), 3, 3)), rig_pos, mount)

    assert_allclose(trajectory(np.zeros(1))[:, 0], scene.positions_m, atol=1e-12)
    cfg = project.rig.radar
    ref = synthesize_if_direct(scene, cfg, trajectory=trajectory)
    err = error_db(synthesize_if(scene, cfg, trajectory=trajectory), ref)
    print(f"keyframed accelerating rig: {err:.1f} dB")
    assert err <= -60.0
    # The segment velocity alone (no trajectory) is not the motion: the check has teeth.
    assert error_db(synthesize_if(scene, cfg), ref) > -40.0


def test_rigid_point_motion_matches_finite_differences_of_the_exact_motion() -> None:
    project = Project()
    p0, v_rig, mount = np.array([0.5, -0.2, 1.2]), np.array([0.4, -0.2, 0.1]), np.array(
        [0.1, -0.05, 0.03])
    omega = np.deg2rad(40.0)
    project.rig.pose = Pose(position_m=tuple(p0))
    project.rig.motion = Motion(velocity_mps=tuple(v_rig), angular_velocity_dps=(0, 0, 40.0))
    project.rig.radar = RadarConfig(pose_on_rig=Pose(position_m=tuple(mount)))
    t0, h = 0.8, 1e-4
    points = world_points(project, t0, 20, seed=7)
    t = t0 + np.array([-h, 0.0, h])
    x = radar_frame(points, rotation_z(omega * t), p0 + v_rig * t[:, None], mount)
    snap = take_snapshot(project, t0)
    still = RigidState(np.eye(4), np.zeros(3), np.zeros(3))
    pos, vel, acc = rigid_point_motion(points, still, snap.rig, snap.sensors["radar"])
    assert_allclose(pos, x[:, 1], atol=1e-12)
    assert_allclose(vel, (x[:, 2] - x[:, 0]) / (2 * h), atol=1e-7)
    assert_allclose(acc, (x[:, 2] - 2 * x[:, 1] + x[:, 0]) / h**2, atol=1e-4)


def test_batched_motion_maps_match_finite_differences_of_spinning_bodies() -> None:
    """Several bodies spinning about their own moving origins, seen from a turning rig."""
    project = Project()
    p0, v_rig, mount = np.array([0.5, -0.2, 1.2]), np.array([0.4, -0.2, 0.1]), np.array(
        [0.1, -0.05, 0.03])
    project.rig.pose = Pose(position_m=tuple(p0))
    project.rig.motion = Motion(velocity_mps=tuple(v_rig), angular_velocity_dps=(0, 0, 40.0))
    project.rig.radar = RadarConfig(pose_on_rig=Pose(position_m=tuple(mount)))
    t0, h, omega = 0.8, 1e-4, np.deg2rad(40.0)
    snap = take_snapshot(project, t0)
    radar = snap.sensors["radar"]
    rng = np.random.default_rng(3)
    spins = rng.normal(0.0, 2.0, (3, 3))                 # rad/s, world frame
    spins[2] = 0.0                                       # one body only translates
    vels, origins = rng.normal(0.0, 0.5, (3, 3)), rng.uniform(-1.0, 3.0, (3, 3))
    m_v, c_v, m_a, c_a = motion_maps_batch(spins, vels, origins, snap.rig, radar)
    assert m_v.shape == (3, 3, 3) and c_a.shape == (3, 3)
    dt = np.array([-h, 0.0, h])
    for g in range(3):
        points = world_points(project, t0, 10, seed=g)
        # Exact motion: rotation by |ω| t about ω's axis around the origin moving at v.
        angle = np.linalg.norm(spins[g])
        axis = spins[g] / angle if angle else np.zeros(3)
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        x = []
        for tau in dt:
            rot = np.eye(3) + np.sin(angle * tau) * k + (1 - np.cos(angle * tau)) * k @ k
            moved = origins[g] + vels[g] * tau + (points - origins[g]) @ rot.T
            x.append(radar_frame(moved, rotation_z(omega * (t0 + tau))[None],
                                 (p0 + v_rig * (t0 + tau))[None], mount)[:, 0])
        pos = x[1]
        assert_allclose(pos @ m_v[g].T + c_v[g], (x[2] - x[0]) / (2 * h), atol=1e-6)
        assert_allclose(pos @ m_a[g].T + c_a[g], (x[2] - 2 * x[1] + x[0]) / h**2, atol=1e-3)


# --------------------------------------------------------------------------- stateless
def test_prepared_arrays_are_an_explicit_argument() -> None:
    scene = radial_targets(2.0)
    cfg = bgt60tr13c(chirps_per_frame=8)
    prep = prepare(scene)
    assert_allclose(synthesize_if(scene, cfg, prepared=prep), synthesize_if(scene, cfg),
                    rtol=0, atol=0)
    with pytest.raises(ValueError, match="another Scatterers"):
        synthesize_if(radial_targets(1.0), cfg, prepared=prep)
    assert not hasattr(synthesis, "_PREPARED")


# --------------------------------------------------------------------------- rendered scene
def test_rendered_scatterers_of_a_turning_rig_carry_its_rotation(
        make_renderer: Callable[..., SceneRenderer]) -> None:
    """Facets of a still wall seen from a turning, moving rig: exact relative kinematics.

    Each facet is a fixed world point; its radar-frame velocity and acceleration are
    compared with finite differences of that point's position written out with the rig's
    rotation matrices (the render's own velocities ignore the rig's rotation).
    """
    wall = SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 6.0, 3.0)),
                       pose=Pose(position_m=(3.0, 0.5, 1.2)))
    p0, v_rig, mount = np.array([0.0, 0.0, 1.2]), np.array([0.3, 0.0, 0.0]), np.array(
        [0.0, -0.03, 0.0])
    rate = 30.0
    cfg = bgt60tr13c(render_width=200, render_height=80,
                     pose_on_rig=Pose(position_m=tuple(mount)))
    project = Project(objects=[wall], rig=SensorRig(
        pose=Pose(position_m=tuple(p0)), radar=cfg,
        motion=Motion(velocity_mps=tuple(v_rig), angular_velocity_dps=(0.0, 0.0, rate))))
    t0, h = 0.2, 1e-4
    snap = take_snapshot(project, t0)
    buffers = make_renderer(project).render(
        snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    sc = scatterers_from_render(RadarScene.from_project(project, snap), buffers,
                                wavelength_m=cfg.wavelength_m)
    assert len(sc) > 1000 and sc.accelerations_mps2 is not None
    world = sc.positions_m @ snap.sensors["radar"].rotation.T + snap.sensors["radar"].position
    t = t0 + np.array([-h, 0.0, h])
    x = radar_frame(world, rotation_z(np.deg2rad(rate) * t), p0 + v_rig * t[:, None], mount)
    assert_allclose(sc.velocities_mps, (x[:, 2] - x[:, 0]) / (2 * h), atol=1e-6)
    assert_allclose(sc.accelerations_mps2, (x[:, 2] - 2 * x[:, 1] + x[:, 0]) / h**2,
                    atol=1e-3)
