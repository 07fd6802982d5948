"""ToF–ToF interference through the renderer: two cameras facing a white wall.

The victim is ``rig.tof`` at the origin looking along +x at a flat wall ``D`` ahead; the
aggressor, an identical camera, is ``B`` to the side (another rig), looking at the same
wall. Known answers written out here from the geometry: at the victim's centre pixel the
wall point is at ``D`` (normal incidence), the aggressor's emitter at
``d_a = √(D² + B²)`` with incidence cosine ``D / d_a`` (Lambertian), so the aggressor's
correlation amplitude over the victim's own is ``(D / d_a) · D² / d_a²`` and its path
``d_a + D``: the measured phase is that of the phasor sum
``e^{j 4π f D / c} + (D/d_a)³ e^{j 2π f (d_a + D) / c}`` (both cameras triggered together).
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.pipeline import Simulator
from simcore.render import RenderRequest, render_once
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.model import NamedTof, Rig, SensorRig, Timeline
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.tof.camera import simulate_tof
from simcore.sensors.tof.interference import Illuminator, overlap_fraction

WALL_M = 2.0


def camera(**kw: object) -> TofCameraConfig:
    return TofCameraConfig(crosstalk_sigma_px=0.0, width=64, height=48, **kw)


def wall_project(victim: TofCameraConfig, aggressor: TofCameraConfig | None,
                 side_m: float) -> Project:
    wall = SceneObject(id=1, name="wall", geometry=Box(size_m=(0.02, 8.0, 4.0)),
                       pose=Pose(position_m=(WALL_M + 0.01, 0.0, 1.0)), material="white_paint")
    rigs = []
    if aggressor is not None:
        rigs = [Rig(name="other", pose=Pose(position_m=(0.0, side_m, 1.0)),
                    sensors={"tof2": NamedTof.model_validate(aggressor.model_dump())})]
    return Project(objects=[wall], timeline=Timeline(frame_rate_hz=10.0, duration_s=0.5),
                   rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0)), tof=victim),
                   rigs=rigs)


def optical_pose(position: tuple[float, float, float]) -> np.ndarray:
    """Optical frame of a camera looking along world +x (x right = −y, y down = −z)."""
    pose = np.eye(4)
    pose[:3, 0] = (0.0, -1.0, 0.0)
    pose[:3, 1] = (0.0, 0.0, -1.0)
    pose[:3, 2] = (1.0, 0.0, 0.0)
    pose[:3, 3] = position
    return pose


def ideal_depth(project: Project, lights: list[Illuminator]) -> np.ndarray:
    cfg = project.rig.tof
    buf = render_once(project, RenderRequest("tof", "tof", cfg.render_intrinsics()))
    return simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                        illuminators=lights).depth_m


@pytest.mark.parametrize(("side_m", "frequency_hz"), [(1.0, 20e6), (0.8, 30e6)])
def test_same_frequency_biases_the_depth_like_the_phasor_sum(side_m: float,
                                                             frequency_hz: float) -> None:
    cfg = camera(modulation_frequencies_hz=[frequency_hz])
    p = wall_project(cfg, None, side_m)
    light = Illuminator(cfg, optical_pose((0.0, side_m, 1.0)), 0.0)
    alone = ideal_depth(p, [])
    biased = ideal_depth(p, [light])
    d_a = np.hypot(WALL_M, side_m)
    k = 2 * np.pi * frequency_hz / SPEED_OF_LIGHT
    ratio = (WALL_M / d_a) ** 3
    phasor = np.exp(1j * 2 * k * WALL_M) + ratio * np.exp(1j * k * (d_a + WALL_M))
    expect = np.mod(np.angle(phasor), 2 * np.pi) / (2 * k)
    h, w = alone.shape
    # The centre pixel's ray is half a pixel off the axis: compare the bias, and
    # 4 px around the centre average that.
    got = float(biased[h // 2 - 1:h // 2 + 1, w // 2 - 1:w // 2 + 1].mean())
    base = float(alone[h // 2 - 1:h // 2 + 1, w // 2 - 1:w // 2 + 1].mean())
    print(f"depth {base:.4f} m alone, {got:.4f} m with the aggressor, formula {expect:.4f} m")
    assert abs(base - WALL_M) < 2e-3
    assert abs(got - expect) < 3e-3
    assert abs(expect - WALL_M) > 0.02                  # a real bias, well above 3 mm


def test_different_frequencies_leave_only_shot_noise() -> None:
    """20 MHz victim, 23.3 MHz aggressor over a 1 ms exposure: the cross term is
    ≤ 1/(π Δf T) ≈ 1e-4 of the aggressor's amplitude: the ideal depth moves < 1 mm,
    while its photons raise the offset (shot noise) by the aggressor's DC part."""
    victim = camera(modulation_frequencies_hz=[20e6])
    aggressor = camera(modulation_frequencies_hz=[23.3e6])
    p = wall_project(victim, None, 0.3)
    light = Illuminator(aggressor, optical_pose((0.0, 0.3, 1.0)), 0.0)
    alone = ideal_depth(p, [])
    mixed = ideal_depth(p, [light])
    h, w = alone.shape
    centre = (slice(h // 4, 3 * h // 4), slice(w // 4, 3 * w // 4))
    assert np.abs(mixed[centre] - alone[centre]).max() < 1e-3


def test_time_multiplexed_exposures_do_not_overlap() -> None:
    cfg = camera()
    span = 3 * cfg.sample_interval_s + cfg.exposure_time_s
    assert overlap_fraction(cfg, cfg, 0.0) == 1.0
    assert overlap_fraction(cfg, cfg, span + 1e-6) == 0.0
    assert overlap_fraction(cfg, cfg, 0.5 * cfg.exposure_time_s) == pytest.approx(0.5)


def test_in_frames_the_aggressor_biases_and_time_multiplexing_removes_it() -> None:
    """Through the engine (with noise): same trigger → the median depth over the centre
    follows the phasor sum; the aggressor triggered after the victim's exposures → the
    victim's frame is bit for bit the one without the aggressor."""
    side = 0.5
    victim = camera(modulation_frequencies_hz=[20e6])
    alone_p = wall_project(victim, None, side)
    with Simulator(alone_p) as sim:
        alone = sim.frame(0).outputs["tof"].depth_m
    same_p = wall_project(victim, victim, side)
    with Simulator(same_p) as sim:
        same = sim.frame(0).outputs["tof"].depth_m
    span = 3 * victim.sample_interval_s + victim.exposure_time_s
    later = victim.model_copy(update={"trigger_offset_s": span + 1e-3})
    muxed_p = wall_project(victim, later, side)
    with Simulator(muxed_p) as sim:
        muxed = sim.frame(0).outputs["tof"].depth_m
    d_a = np.hypot(WALL_M, side)
    k = 2 * np.pi * 20e6 / SPEED_OF_LIGHT
    phasor = np.exp(2j * k * WALL_M) + (WALL_M / d_a) ** 3 * np.exp(1j * k * (d_a + WALL_M))
    expect = np.mod(np.angle(phasor), 2 * np.pi) / (2 * k)
    h, w = alone.shape
    c = (slice(h // 2 - 2, h // 2 + 2), slice(w // 2 - 2, w // 2 + 2))
    print(f"median depth {np.median(alone[c]):.4f} alone, {np.median(same[c]):.4f} same "
          f"trigger (formula {expect:.4f}), {np.median(muxed[c]):.4f} time multiplexed")
    assert abs(float(np.median(same[c])) - expect) < 0.01
    assert np.array_equal(muxed, alone)


def test_facing_cameras_see_the_emitter_at_half_its_distance() -> None:
    """No scene: the aggressor 3 m ahead, facing the victim, is a point source imaged on
    the centre pixel with ``I_a / d² · π (f / 2N)² · T · QE · λ / (h c)`` electrons per
    correlation sample, over a one-way path: the depth reads d / 2."""
    from simcore.scene.tof_config import PLANCK

    plain = {"vignetting": False, "stray_light": False, "distortion": False,
             "ambient_light": False}
    victim = camera(**plain)
    aggressor = camera(**plain, illumination_power_w=1e-4)
    d = 3.0
    pose = optical_pose((d, 0.0, 1.0))
    pose[:3, 0] *= -1                    # turned round: looks along −x
    pose[:3, 2] *= -1
    p = Project(rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0)), tof=victim))
    buf = render_once(p, RenderRequest("tof", "tof", victim.render_intrinsics()))
    out = simulate_tof(buf, victim, rng=np.random.default_rng(0), noise=False,
                       illuminators=[Illuminator(aggressor, pose, 0.0)])
    intensity_w = aggressor.illumination_power_w / aggressor.illumination_solid_angle_sr
    focal = victim.intrinsics().fx * victim.pixel_pitch_um * 1e-6
    electrons = (intensity_w / d**2 * np.pi * (focal / (2 * victim.f_number)) ** 2
                 * victim.exposure_time_s * victim.quantum_efficiency
                 * victim.wavelength_nm * 1e-9 / (PLANCK * SPEED_OF_LIGHT))
    row, col = victim.height // 2, victim.width // 2
    lit = np.argwhere(out.intensity > 0)
    assert lit.tolist() == [[row, col]]
    expect_dn = electrons * victim.conversion_gain_dn_per_electron
    print(f"emitter pixel {out.intensity[row, col]:.1f} DN (formula {expect_dn:.1f}), depth "
          f"{out.depth_m[row, col]:.4f} m")
    assert out.intensity[row, col] == pytest.approx(expect_dn, rel=0.01, abs=1.0)
    assert out.depth_m[row, col] == pytest.approx(d / 2, abs=1e-3)


def test_per_frame_hopping_removes_the_bias_when_the_channels_differ() -> None:
    """Both cameras hop over 4 channels 1 MHz apart with their own seeds: in frames on
    different channels the median depth is the one without the aggressor (within the
    noise); on the same channel it is biased like the phasor sum at that frequency."""
    from simcore.sensors.tof.interference import hopped_config

    side = 0.5
    hop = {"hop_step_hz": 1e6, "hop_channels": 4}
    victim = camera(modulation_frequencies_hz=[20e6], hop_seed=1, **hop)
    aggressor = camera(modulation_frequencies_hz=[20e6], hop_seed=2, **hop)
    d_a = np.hypot(WALL_M, side)
    same_seen = differ_seen = 0
    with Simulator(wall_project(victim, aggressor, side)) as sim, \
            Simulator(wall_project(victim, None, side)) as alone_sim:
        for i in range(6):
            f_v = hopped_config(victim, i).modulation_frequencies_hz[0]
            f_a = hopped_config(aggressor, i).modulation_frequencies_hz[0]
            depth = sim.frame(i).outputs["tof"].depth_m
            alone = alone_sim.frame(i).outputs["tof"].depth_m
            h, w = depth.shape
            c = (slice(h // 2 - 2, h // 2 + 2), slice(w // 2 - 2, w // 2 + 2))
            got, base = float(np.median(depth[c])), float(np.median(alone[c]))
            if f_v == f_a:
                k = 2 * np.pi * f_v / SPEED_OF_LIGHT
                phasor = (np.exp(2j * k * WALL_M)
                          + (WALL_M / d_a) ** 3 * np.exp(1j * k * (d_a + WALL_M)))
                expect = np.mod(np.angle(phasor), 2 * np.pi) / (2 * k)
                assert abs(got - expect) < 0.01, (i, got, expect)
                same_seen += 1
            else:
                assert abs(got - base) < 0.004, (i, got, base)
                differ_seen += 1
    assert same_seen and differ_seen
