"""Radar multipath (image method): ghosts at the analytic range, angle, Doppler and power.

Scene: a trihedral corner reflector at range R on boresight and a large aluminium plate
parallel to boresight at lateral offset H (to the radar's left). The image of the corner
in the plate is at lateral 2H, range ``R_m = √(R² + 4H²)``; the ghosts of order 1 lie at
``(R + R_m)/2`` and order 2 at ``R_m`` in the direction of the image. The expected powers
are computed independently from the same corner seen by a radar moved to the mirrored
position (the image geometry: its element pattern and the corner's aspect there) and from
the direct return, times |Γ| per bounce.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Box, CornerReflector, Plane, PointTarget, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.motion import Motion
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.multipath import find_reflectors, ghost_scatterers, multipath_if
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import synthesize_if, synthesize_if_direct

Renderer = Callable[..., SceneRenderer]

R, H, Z = 3.0, 1.0, 1.0
N_RX = 16


def radar_config(**kw: object) -> RadarConfig:
    lam = SPEED_OF_LIGHT / 63e9
    rx = [Antenna(name=f"rx{i}", position_mm=(i * 0.5 * lam * 1e3, 0.0)) for i in range(N_RX)]
    base = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
            "if_highpass_hz": 0.0, "speckle": False, "rx": rx, "render_width": 200,
            "render_height": 200, "multipath_order": 2}
    base.update(kw)
    return RadarConfig(**base)  # type: ignore[arg-type]


def scene(plate_material: str = "aluminium", *, rig_y: float = 0.0, plate: bool = True,
          occluder: bool = False, velocity: float = 0.0, point: bool = False,
          **kw: object) -> Project:
    """The corner (or, ``point``, a 10 m² point target: it scatters bistatically as it does
    back, where a trihedral returns a wave only towards where it came from)."""
    cfg = radar_config(**kw)
    geometry = PointTarget(rcs_m2=10.0) if point else CornerReflector(edge_m=0.1)
    objs = [SceneObject(id=1, name="corner", geometry=geometry,
                        pose=Pose(position_m=(R, 0.0, Z), rotation_deg=(0, -90, 0)),
                        material="radar_retroreflector",
                        motion=Motion(velocity_mps=(velocity, 0.0, 0.0)))]
    if plate:
        objs.append(SceneObject(id=2, name="plate", geometry=Plane(size_m=(8.0, 2.0)),
                                pose=Pose(position_m=(3.0, H, Z), rotation_deg=(90, 0, 0)),
                                material=plate_material))
    if occluder:
        # An absorber block in front of the plate around the order-2 reflection point
        # (x = R/2 on the plate), clear of the direct line of sight.
        objs.append(SceneObject(id=3, name="block", geometry=Box(size_m=(1.6, 0.2, 1.0)),
                                pose=Pose(position_m=(1.6, H - 0.2, Z)),
                                material="radar_absorber"))
    return Project(objects=objs, rig=SensorRig(pose=Pose(position_m=(0.0, rig_y, Z)),
                                               radar=cfg))


def frame(make_renderer: Renderer, project: Project
          ) -> tuple[Scatterers, np.ndarray, np.ndarray]:
    """(scatterers, direct IF, ghost IF) of frame 0."""
    cfg = project.rig.radar
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    buf = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    sc = radar_scatterers(RadarScene.from_project(project, snap), buf, config=project.rig.radar)
    ghost = multipath_if(RadarScene.from_project(project, snap), sc, cfg, buffers=buf)
    return sc, synthesize_if(sc, cfg), ghost


def k_mid(cfg: RadarConfig) -> float:
    """Wavenumber at the centre of the sampled sweep (rad/m)."""
    t = cfg.sample_times_s()
    return 2 * np.pi * (cfg.start_frequency_hz + cfg.slope_hz_per_s * t.mean()) / SPEED_OF_LIGHT


def beam_range(cfg: RadarConfig, y: np.ndarray, az_deg: float, pad: int = 16
               ) -> tuple[np.ndarray, np.ndarray]:
    """(ranges (m), complex amplitude) of chirp rows ``y`` (chirps, rx, samples) steered to
    ``az_deg`` (Hann over Rx and samples, normalised so a lone tone of amplitude A gives A)."""
    x = cfg.rx_positions_m()[:, 0]
    w_a = np.hanning(N_RX + 2)[1:-1]
    steer = w_a * np.exp(1j * k_mid(cfg) * x * np.sin(np.radians(az_deg))) / w_a.sum()
    beam = np.einsum("mrn,r->mn", y, steer)
    n = cfg.samples_per_chirp
    w = np.hanning(n)
    spec = np.fft.fft(beam * w, n=pad * n, axis=-1) / w.sum()
    f = np.fft.fftfreq(pad * n, 1 / cfg.sample_rate_hz)
    ranges = SPEED_OF_LIGHT * f / (2 * cfg.slope_hz_per_s)
    return ranges, spec


def peak(cfg: RadarConfig, y: np.ndarray, az_deg: float, r_expect: float
         ) -> tuple[float, float]:
    """(range, amplitude) of the largest peak within ±1 range bin of ``r_expect``."""
    ranges, spec = beam_range(cfg, y[:1], az_deg)
    near = np.flatnonzero(np.abs(ranges - r_expect) <= cfg.range_resolution_m)
    i = near[np.argmax(np.abs(spec[0, near]))]
    return float(ranges[i]), float(np.abs(spec[0, i]))


def best_angle(cfg: RadarConfig, y: np.ndarray, r: float, around: float) -> float:
    """Azimuth (deg) of the largest beam at range ``r`` within ±15° of ``around``."""
    angles = np.arange(around - 15, around + 15.01, 0.1)
    amps = [peak(cfg, y, a, r)[1] for a in angles]
    return float(angles[int(np.argmax(amps))])


def image_geometry() -> tuple[float, float, float]:
    """(R_m, azimuth of the image in degrees (board x right = world −y), θ_m)."""
    r_m = float(np.hypot(R, 2 * H))
    az = float(np.degrees(np.arctan2(-2 * H, R)))
    return r_m, az, abs(az)


def db(a: float, b: float) -> float:
    return float(20 * np.log10(a / b))


def test_ghosts_at_image_range_angle_and_power(make_renderer: Renderer) -> None:
    """Acceptance: R, (R+R_m)/2, R_m within ¼ bin, image angles ±2°, power ±1 dB (a point
    target: its order-1 ghosts are the bistatic radar equation's geometric mean)."""
    project = scene(point=True)
    cfg = project.rig.radar
    sc, direct, ghost = frame(make_renderer, project)
    r_m, az_img, _ = image_geometry()
    quarter = 0.25 * cfg.range_resolution_m
    total = direct + ghost

    # Direct corner at R, boresight; its amplitude is the reference of the direct leg.
    r0, a_direct = peak(cfg, total, 0.0, R)
    assert abs(r0 - R) < quarter
    assert abs(best_angle(cfg, total, R, 0.0)) < 2.0

    # The same corner seen by a radar at the mirrored position (the image geometry).
    mirror = scene(rig_y=2 * H, plate=False, point=True)
    _, direct_m, _ = frame(make_renderer, mirror)
    _, a_mirror = peak(cfg, direct_m, -az_img, r_m)   # seen at +θ_m from there
    gamma = 1.0                                        # aluminium, height 10 µm: |Γ| ≈ 1

    # Order 2 at R_m in the image direction: amplitude |Γ|² × the mirrored radar's.
    r2, a2 = peak(cfg, total, az_img, r_m)
    assert abs(r2 - r_m) < quarter, (r2, r_m)
    assert abs(best_angle(cfg, total, r_m, az_img) - az_img) < 2.0
    print(f"order 2 angle {best_angle(cfg, total, r_m, az_img):+.1f}° (image {az_img:+.1f}°)")
    assert abs(db(a2, gamma**2 * a_mirror)) < 1.0, db(a2, a_mirror)
    print(f"direct {r0:.4f} m (R {R}); order 2 {r2:.4f} m (R_m {r_m:.4f}), "
          f"{db(a2, gamma**2 * a_mirror):+.2f} dB vs image radar equation")

    # Order 1 at (R + R_m)/2: path (a) arrives from the target (Rx leg direct), path (b)
    # from the image; each has |Γ| × the geometric mean of the two monostatic amplitudes
    # (bistatic radar equation: √(g(0) g(θ_m)) and the corner's aspect in both directions).
    r1 = 0.5 * (R + r_m)
    expect1 = gamma * np.sqrt(a_direct * a_mirror)
    for az in (0.0, az_img):
        rr, a1 = peak(cfg, ghost, az, r1)
        assert abs(rr - r1) < quarter, (rr, r1)
        assert abs(best_angle(cfg, ghost, r1, az) - az) < 2.0
        assert abs(db(a1, expect1)) < 1.0, (az, db(a1, expect1))
        print(f"order 1 at az {az:+.1f}°: {rr:.4f} m ((R+R_m)/2 {r1:.4f}), angle "
              f"{best_angle(cfg, ghost, r1, az):+.1f}°, {db(a1, expect1):+.2f} dB")
    rr, _ = peak(cfg, total, 0.0, r1)
    assert abs(rr - r1) < quarter


def test_a_trihedral_returns_its_order_one_ghosts_only_as_its_diffraction_lobe(
        make_renderer: Renderer) -> None:
    """A trihedral sends a wave back where it came from (GO: no triple-bounce path to the
    radar from the image 34° away; its aperture's lobe |2J₁(x)/x|² at x = k r sin β ≈ 28 is
    −40 dB): its order-1 ghosts lie 30 dB or more under the bistatic radar equation's
    geometric mean, while its order-2 ghost (the image radar's own return) is full."""
    project = scene()
    cfg = project.rig.radar
    _, direct, ghost = frame(make_renderer, project)
    r_m, az_img, _ = image_geometry()
    _, a_direct = peak(cfg, direct, 0.0, R)
    _, direct_m, _ = frame(make_renderer, scene(rig_y=2 * H, plate=False))
    _, a_mirror = peak(cfg, direct_m, -az_img, r_m)
    _, a2 = peak(cfg, direct + ghost, az_img, r_m)
    assert abs(db(a2, a_mirror)) < 1.0
    for az in (0.0, az_img):
        _, a1 = peak(cfg, ghost, az, 0.5 * (R + r_m))
        assert db(a1, np.sqrt(a_direct * a_mirror)) < -30.0, db(a1, np.sqrt(a_direct * a_mirror))


def test_absorber_and_occluder_remove_the_ghosts(make_renderer: Renderer) -> None:
    """An absorber plate (Γ = 0) or a block hiding the reflection point: no ghosts."""
    r_m, az_img, _ = image_geometry()
    metal = scene()
    cfg = metal.rig.radar
    _, direct, ghost = frame(make_renderer, metal)
    _, a_metal = peak(cfg, direct + ghost, az_img, r_m)

    absorber = scene("radar_absorber")
    assert find_reflectors(RadarScene.from_project(absorber, take_snapshot(absorber, 0.0)),
                           cfg.wavelength_m) == []
    _, direct_a, ghost_a = frame(make_renderer, absorber)
    assert not np.any(ghost_a)
    _, a_abs = peak(cfg, direct_a + ghost_a, az_img, r_m)
    assert db(a_abs, a_metal) < -30.0, db(a_abs, a_metal)

    blocked = scene(occluder=True)
    _, direct_b, ghost_b = frame(make_renderer, blocked)
    _, a_blk = peak(cfg, ghost_b, az_img, r_m)
    assert db(a_blk, a_metal) < -30.0, db(a_blk, a_metal)
    print(f"ghost cell: absorber {db(a_abs, a_metal):.1f} dB, occluded "
          f"{db(a_blk, a_metal) if a_blk > 0 else -np.inf:.1f} dB vs metal")


def test_a_block_on_the_leg_from_the_wall_to_the_target_removes_its_ghosts(
        make_renderer: Renderer) -> None:
    """Occlusion on the second leg: a concrete block on the segment from the reflection
    point (R/2, H) on the plate to the corner (R, 0) — off the direct line and off the
    radar → plate leg — leaves no ghost of the corner; moved 0.8 m towards the radar (off
    every leg) it blocks nothing and the ghosts come back."""
    def corner_ghosts(block_xy: tuple[float, float] | None) -> int:
        project = scene(render_width=120, render_height=120)
        if block_xy is not None:
            block = SceneObject(id=5, name="block", geometry=Box(size_m=(0.2, 0.2, 0.6)),
                                pose=Pose(position_m=(block_xy[0], block_xy[1], Z)),
                                material="concrete")
            project = project.model_copy(update={"objects": [*project.objects, block]})
        cfg = project.rig.radar
        renderer = make_renderer(project)
        snap = take_snapshot(project, 0.0)
        buf = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
        sc = radar_scatterers(RadarScene.from_project(project, snap), buf, config=project.rig.radar)
        assert np.any(sc.object_index == 0)                      # the corner is seen
        sets = ghost_scatterers(RadarScene.from_project(project, snap), sc, cfg, buffers=buf)
        return sum(int(np.sum(g.scatterers.object_index == 0)) for g in sets)

    on_leg = (0.75 * R, 0.5 * H)          # midpoint of (R/2, H) → (R, 0); world y = left
    assert corner_ghosts(None) > 0
    assert corner_ghosts(on_leg) == 0
    assert corner_ghosts((0.75 * R - 0.8, 0.5 * H)) > 0


def test_segment_tests_against_a_unit_box() -> None:
    """The slab and Möller–Trumbore tests on known segments: through, beside, parallel
    inside a face's slab, ending short of the box, inside it."""
    from simcore.render.meshes import build_mesh
    from simcore.sensors.radar.multipath import _segments_hit_box, _segments_hit_triangles

    mesh = build_mesh(Box(size_m=(1.0, 1.0, 1.0)))
    tri = mesh.points[mesh.triangles]
    box = np.array([[-0.5] * 3, [0.5] * 3])
    a = np.array([[-2, 0, 0], [-2, 0.7, 0], [-2, 0.2, 0.3], [-2, 0, 0], [0, 0, 0.1]], float)
    b = np.array([[2, 0, 0], [2, 0.7, 0], [-0.6, 0.2, 0.3], [-0.51, 0, 0], [0.1, 0.1, 0.1]],
                 float)
    expect_box = [True, False, False, False, True]
    np.testing.assert_array_equal(_segments_hit_box(a, b, box), expect_box)
    # A segment inside the box crosses no face.
    np.testing.assert_array_equal(_segments_hit_triangles(a, b, tri),
                                  [True, False, False, False, False])


def test_moving_target_ghost_doppler_is_the_image_radial_velocity(make_renderer: Renderer
                                                                   ) -> None:
    """A corner receding at v along the plate: the order-2 ghost moves at v cos θ_m."""
    v = 1.0
    project = scene(velocity=v)
    cfg = project.rig.radar
    _, direct, ghost = frame(make_renderer, project)
    r_m, az_img, theta_m = image_geometry()

    def radial(y: np.ndarray, az: float, r: float) -> float:
        ranges, spec = beam_range(cfg, y, az)
        i = np.argmin(np.abs(ranges - r))
        i = i - 8 + int(np.argmax(np.abs(spec[0, i - 8:i + 9])))
        z = spec[:, i]
        dphi = float(np.angle(np.sum(z[1:] * np.conj(z[:-1]))))
        return dphi * SPEED_OF_LIGHT / (k_mid(cfg) * SPEED_OF_LIGHT * 2
                                        * cfg.chirp_repetition_time_s)

    v_direct, v_ghost = radial(direct, 0.0, R), radial(ghost, az_img, r_m)
    print(f"radial velocity: direct {v_direct:.4f} m/s, ghost {v_ghost:.4f} m/s "
          f"(image {v * np.cos(np.radians(theta_m)):.4f})")
    assert v_direct == pytest.approx(v, abs=0.02)
    assert v_ghost == pytest.approx(v * np.cos(np.radians(theta_m)), abs=0.02)


def test_order_one_has_no_second_bounce(make_renderer: Renderer) -> None:
    """multipath_order 1 synthesises paths (a) and (b) only; 0 nothing."""
    project = scene(multipath_order=1)
    cfg = project.rig.radar
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    buf = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    sc = radar_scatterers(RadarScene.from_project(project, snap), buf, config=project.rig.radar)
    sets = ghost_scatterers(RadarScene.from_project(project, snap), sc, cfg, buffers=buf)
    assert sorted(g.order for g in sets) == [1, 1]
    assert ghost_scatterers(RadarScene.from_project(project, snap), sc, cfg, buffers=buf,
                            order=0) == []


def test_synthesis_antenna_override_matches_the_direct_sum() -> None:
    """``tx_positions_m`` / ``rx_positions_m``: NUFFT path = direct sum, static and moving."""
    cfg = radar_config(chirps_per_frame=4, samples_per_chirp=128, chirp_time_s=64e-6,
                       sample_rate_hz=2e6, chirp_repetition_time_s=100e-6)
    rng = np.random.default_rng(3)
    m = 20
    pos = np.column_stack([rng.uniform(-1, 1, m), rng.uniform(-0.5, 0.5, m),
                           rng.uniform(1, 4, m)])
    vel = np.zeros((m, 3))
    vel[::2] = rng.uniform(-2, 2, (m // 2, 3))
    sc = Scatterers(time_s=0.0, wavelength_m=cfg.wavelength_m, positions_m=pos,
                    velocities_mps=vel, rcs_m2=rng.uniform(0.1, 1, m),
                    phase_rad=rng.uniform(-np.pi, np.pi, m),
                    object_index=np.zeros(m, np.int32), kind=np.zeros(m, np.int8))
    tx = cfg.tx_positions_m() + np.array([1.3, 0.0, 0.2])
    rx = cfg.rx_positions_m() + np.array([-0.4, 0.1, 0.0])
    fast = synthesize_if(sc, cfg, tx_positions_m=tx, rx_positions_m=rx)
    ref = synthesize_if_direct(sc, cfg, tx_positions_m=tx, rx_positions_m=rx)
    # The moving-scatterer model's budget is MOTION_TOLERANCE_FLOOR (1e-4) per scatterer.
    err = np.max(np.abs(fast - ref)) / np.max(np.abs(ref))
    print(f"override: NUFFT vs direct sum, max error {err:.2e} of the peak")
    assert err < 1e-4
    plain = synthesize_if_direct(sc, cfg)
    assert np.max(np.abs(plain - ref)) > 0.1 * np.max(np.abs(ref))   # the override acts
    with pytest.raises(ValueError, match="tx_positions_m"):
        synthesize_if(sc, cfg, tx_positions_m=np.zeros((2, 3)))


def test_order_two_sets_of_several_reflectors_sum_like_separate_syntheses() -> None:
    """synthesize_ghosts joins the order-2 sets of all reflectors into one synthesis; with
    one set accelerating and one not, the cube is the sum of their separate syntheses."""
    from simcore.sensors.radar.multipath import GhostSet, synthesize_ghosts

    cfg = radar_config(chirps_per_frame=4, samples_per_chirp=128, chirp_time_s=64e-6,
                       sample_rate_hz=2e6, chirp_repetition_time_s=100e-6)
    rng = np.random.default_rng(7)

    def one(m: int, accelerating: bool) -> Scatterers:
        return Scatterers(
            time_s=0.0, wavelength_m=cfg.wavelength_m,
            positions_m=np.column_stack([rng.uniform(-1, 1, m), np.zeros(m),
                                         rng.uniform(1, 4, m)]),
            velocities_mps=rng.uniform(-2, 2, (m, 3)), rcs_m2=rng.uniform(0.1, 1, m),
            phase_rad=rng.uniform(-np.pi, np.pi, m), object_index=np.zeros(m, np.int32),
            kind=np.zeros(m, np.int8),
            accelerations_mps2=rng.uniform(-20, 20, (m, 3)) if accelerating else None)

    a, b = one(5, True), one(7, False)
    joined = synthesize_ghosts([GhostSet(a, 2, 0), GhostSet(b, 2, 1)], cfg)
    apart = synthesize_if_direct(a, cfg) + synthesize_if_direct(b, cfg)
    assert np.max(np.abs(joined - apart)) < 1e-4 * np.max(np.abs(apart))


def test_sets_with_their_own_antennas_share_one_synthesis() -> None:
    """synthesize_if_sets: sets with their own (mirrored) antennas, static, moving and
    accelerating rows, 2 Tx × 3 Rx, synthesised together, equal the sum of each set's
    direct sum with its antennas (the image method's ghost sets)."""
    from simcore.sensors.radar.multipath import GhostSet, synthesize_ghosts
    from simcore.sensors.radar.synthesis import synthesize_if_sets

    lam = SPEED_OF_LIGHT / 63e9
    cfg = radar_config(chirps_per_frame=4, samples_per_chirp=128, chirp_time_s=64e-6,
                       sample_rate_hz=2e6, chirp_repetition_time_s=100e-6,
                       tx=[Antenna(name="tx1", position_mm=(0.0, 0.0)),
                           Antenna(name="tx2", position_mm=(0.0, 2 * lam * 1e3))],
                       rx=[Antenna(name=f"rx{i}", position_mm=(i * 0.5 * lam * 1e3, 0.0))
                           for i in range(3)])
    rng = np.random.default_rng(11)

    def one(m: int, *, moving: bool, accelerating: bool) -> Scatterers:
        vel = rng.uniform(-2, 2, (m, 3)) if moving else np.zeros((m, 3))
        return Scatterers(
            time_s=0.0, wavelength_m=cfg.wavelength_m,
            positions_m=np.column_stack([rng.uniform(-1, 1, m), rng.uniform(-0.5, 0.5, m),
                                         rng.uniform(1, 4, m)]),
            velocities_mps=vel, rcs_m2=rng.uniform(0.1, 1, m),
            phase_rad=rng.uniform(-np.pi, np.pi, m), object_index=np.zeros(m, np.int32),
            kind=np.zeros(m, np.int8),
            accelerations_mps2=rng.uniform(-20, 20, (m, 3)) if accelerating else None)

    tx, rx = cfg.tx_positions_m(), cfg.rx_positions_m()
    mirror = np.array([1.0, -1.0, 1.0])          # a wall at y = 0.8 m: p → (x, 1.6 − y, z)
    shift = np.array([0.0, 1.6, 0.0])
    sets = [(one(6, moving=True, accelerating=True), tx * mirror + shift, None),
            (one(5, moving=False, accelerating=False), None, rx * mirror + shift),
            (one(7, moving=True, accelerating=False), tx * mirror + shift,
             rx + np.array([0.0, 0.0, -1.2])),
            (one(4, moving=True, accelerating=False), None, None)]
    joined = synthesize_if_sets(sets, cfg)
    apart = sum(synthesize_if_direct(sc, cfg, tx_positions_m=t, rx_positions_m=r)
                for sc, t, r in sets)
    err = np.max(np.abs(joined - apart)) / np.max(np.abs(apart))
    print(f"sets: one synthesis vs the sets' direct sums, max error {err:.2e} of the peak")
    assert err < 1e-4            # the moving-scatterer budget (MOTION_TOLERANCE_FLOOR)
    # Each set's antennas act: the same rows with the configuration's antennas differ.
    plain = sum(synthesize_if_direct(sc, cfg) for sc, _, _ in sets)
    assert np.max(np.abs(plain - apart)) > 0.1 * np.max(np.abs(apart))
    ghosts = [GhostSet(sc, 1, 0, tx_positions_m=t, rx_positions_m=r) for sc, t, r in sets]
    assert np.max(np.abs(synthesize_ghosts(ghosts, cfg) - apart)) < 1e-4 * np.max(np.abs(apart))
    empty = sets[1][0].subset(np.zeros(0, dtype=np.intp))
    assert not np.any(synthesize_if_sets([(empty, None, None)], cfg))


def test_ghost_label_sets_have_the_terms_of_one_call_per_set() -> None:
    """prepare_scatterer_sets: the sets with real antennas as one, those with their own
    (mirrored) antennas as another; every row has the terms (range, radial velocity,
    power, steering, object, Doppler) of prepare_scatterers on its own set, bit for bit."""
    from simcore.sensors.radar.labels import prepare_scatterer_sets, prepare_scatterers

    cfg = radar_config()
    rng = np.random.default_rng(5)

    def one(m: int, obj: int) -> Scatterers:
        return Scatterers(
            time_s=0.0, wavelength_m=cfg.wavelength_m,
            positions_m=np.column_stack([rng.uniform(-1, 1, m), rng.uniform(-0.5, 0.5, m),
                                         rng.uniform(1, 4, m)]),
            velocities_mps=rng.uniform(-2, 2, (m, 3)), rcs_m2=rng.uniform(0.1, 1, m),
            phase_rad=np.zeros(m), object_index=np.full(m, obj, np.int32),
            kind=np.zeros(m, np.int8))

    tx, rx = cfg.tx_positions_m(), cfg.rx_positions_m()
    shift = np.array([0.0, 1.6, 0.0])
    sets = [(one(4, 0), tx * np.array([1.0, -1.0, 1.0]) + shift, None),
            (one(3, 1), None, None),
            (one(5, 2), None, rx * np.array([-1.0, 1.0, 1.0]) + 2 * shift),
            (one(2, 3), tx + shift, rx - shift), (one(1, 4), None, None)]
    joined = prepare_scatterer_sets(sets, cfg)
    apart = [prepare_scatterers(sc, cfg, tx_positions_m=t, rx_positions_m=r) for sc, t, r in sets]

    def rows(prepared: list) -> list:
        return sorted((float(p.range_m[i]), float(p.velocity_mps[i]), float(p.power[i]),
                       int(p.object_index[i]), float(p.doppler_cycles[i]),
                       p.steering[i].tobytes()) for p in prepared for i in range(len(p)))

    assert len(joined) == 2
    assert rows(joined) == rows(apart)
    for p in joined:
        assert np.all(np.diff(p.range_m) >= 0)          # sorted by range, as each set


def test_simulator_adds_the_ghosts_on_the_plain_and_the_background_path() -> None:
    """The radar_multipath stage: both the plain path and the still-background
    accelerator add the same ghosts to the raw cube (a small box moves, the rest is still)."""
    from simcore.pipeline import Simulator

    project = scene(render_width=120, render_height=120)
    mover = SceneObject(id=9, name="mover", geometry=Box(size_m=(0.2, 0.2, 0.2)),
                        pose=Pose(position_m=(4.5, -1.0, Z)), material="concrete",
                        motion=Motion(velocity_mps=(0.0, 0.5, 0.0)))
    project = project.model_copy(update={"objects": [*project.objects, mover]})
    off = project.model_copy(deep=True)
    off.rig.radar.multipath_order = 0
    cubes, stages = {}, {}
    for name, proj, reuse in (("plain", project, False), ("background", project, True),
                              ("off", off, True)):
        with Simulator(proj, reuse_static=reuse) as sim:
            sim.frame(0)
            f1 = sim.frame(1)
            cubes[name], stages[name] = f1.outputs["radar"].raw.adc, set(f1.timings_ms)
    assert "radar_multipath" in stages["plain"] and "radar_multipath" in stages["background"]
    assert "radar_scatterers" in stages["plain"]
    assert "radar_scatterers" not in stages["background"]      # the accelerator ran
    assert "radar_multipath" not in stages["off"]
    scale = np.max(np.abs(cubes["plain"]))
    assert np.max(np.abs(cubes["background"] - cubes["plain"])) < 1e-6 * scale
    assert np.max(np.abs(cubes["off"] - cubes["plain"])) > 1e-3 * scale


def test_the_background_path_hands_the_ghosts_every_scatterer_of_the_frame() -> None:
    """Over the still background the ghosts' scatterers are the background's facets outside
    the changed cells plus the frame's own in them: the same set as the full frame's."""
    from simcore.pipeline import Simulator

    project = scene(render_width=120, render_height=120)
    mover = SceneObject(id=9, name="mover", geometry=Box(size_m=(0.2, 0.2, 0.2)),
                        pose=Pose(position_m=(4.5, -1.0, Z)), material="concrete",
                        motion=Motion(velocity_mps=(0.0, 0.5, 0.0)))
    project = project.model_copy(update={"objects": [*project.objects, mover]})
    with Simulator(project, reuse_static=True) as sim:
        sim.frame(0)
        frame = sim.frame(1)
        entries = sim.engine.cache._entries["radar_synthesis"]
        built = next(reversed(entries.values())).value[4]
    full = radar_scatterers(RadarScene.from_project(sim.engine.project, frame.snapshot),
                            frame.buffers["radar"],
                            seed=project.seed, see_through=frame.see_through.get("radar"),
                            config=sim.engine.project.rig.radar)
    assert isinstance(built, Scatterers) and len(built) == len(full)
    assert np.count_nonzero(built.object_index == 0) > 0     # the still objects are there
    order_b = np.lexsort((built.positions_m[:, 2], built.positions_m[:, 1],
                          built.positions_m[:, 0], built.object_index))
    order_f = np.lexsort((full.positions_m[:, 2], full.positions_m[:, 1],
                          full.positions_m[:, 0], full.object_index))
    for name in ("positions_m", "velocities_mps", "rcs_m2", "phase_rad", "object_index",
                 "kind"):
        np.testing.assert_array_equal(getattr(built, name)[order_b],
                                      getattr(full, name)[order_f], err_msg=name)


def test_detections_of_ghosts_are_labelled_ghost_of_the_object_they_mirror() -> None:
    """Labels: the detections at R (direct), (R+R_m)/2 (order 1) and R_m (order 2, at the
    image's azimuth) carry the corner's id; only the last two are ghosts. Without
    multipath nothing is detected at (R+R_m)/2."""
    from simcore.pipeline import Simulator

    r_m, az, _ = image_geometry()
    expected = ((R, 0.0, False), (0.5 * (R + r_m), None, True), (r_m, az, True))
    for order in (2, 0):
        project = scene(render_width=120, render_height=120, multipath_order=order,
                        point=True)
        with Simulator(project) as sim:
            out = sim.frame(0).outputs["radar"]
        det, labels = out.dsp.detections, out.labels
        cfg = project.rig.radar
        for r_exp, az_exp, is_ghost in expected:
            near = np.abs(det.range_m - r_exp) <= 0.5 * cfg.range_resolution_m
            if az_exp is not None:
                near &= np.abs(det.azimuth_deg - az_exp) <= 3.0
            if order == 0 and is_ghost:
                assert not near.any(), (r_exp, det.range_m[near])
                continue
            assert near.any(), (r_exp, det.range_m)
            i = np.flatnonzero(near)[np.argmax(det.power_db[near])]
            assert labels.object_id[i] == 1 and bool(labels.ghost[i]) is is_ghost, (
                r_exp, labels.object_id[i], labels.ghost[i])
            assert labels.power_fraction[i] > 0.5


def test_bistatic_label_terms_reduce_to_the_monostatic_ones_and_follow_the_image() -> None:
    """prepare_scatterers with antenna overrides: with the real antennas it gives the
    monostatic range, radial velocity, power and beam response; with the Tx mirrored in the
    plane y = H the range is half the unfolded path (|p − Tx'| + |p|)/2."""
    from simcore.sensors.radar.labels import prepare_scatterers

    cfg = radar_config()
    rng = np.random.default_rng(5)
    m = 12
    pos = np.column_stack([rng.uniform(-1, 1, m), rng.uniform(-0.5, 0.5, m),
                           rng.uniform(2, 6, m)])
    sc = Scatterers(time_s=0.0, wavelength_m=cfg.wavelength_m, positions_m=pos,
                    velocities_mps=rng.uniform(-2, 2, (m, 3)), rcs_m2=rng.uniform(0.1, 1, m),
                    phase_rad=np.zeros(m), object_index=np.zeros(m, np.int32),
                    kind=np.zeros(m, np.int8))
    mono = prepare_scatterers(sc, cfg)
    bi = prepare_scatterers(sc, cfg, tx_positions_m=cfg.tx_positions_m(),
                            rx_positions_m=cfg.rx_positions_m())
    # The bistatic ranges are from the antennas' centroids, the monostatic from the origin.
    offset = 0.5 * sum(float(np.linalg.norm(p.mean(axis=0)))
                       for p in (cfg.tx_positions_m(), cfg.rx_positions_m()))
    np.testing.assert_allclose(bi.range_m, mono.range_m, atol=offset + 1e-9)
    np.testing.assert_allclose(bi.velocity_mps, mono.velocity_mps, atol=0.02)
    np.testing.assert_allclose(bi.power, mono.power, rtol=4 * offset / 2.0)
    n_ch = mono.steering.shape[1]
    match = np.abs(np.sum(np.conj(bi.steering) * mono.steering, axis=1)) / n_ch
    assert np.all(match > 0.99), match
    # Tx mirrored in a plane y = H: the unfolded path of any such image.
    tx = cfg.tx_positions_m()
    tx_img = tx.copy()
    tx_img[:, 1] = 2 * H - tx_img[:, 1]
    ghost = prepare_scatterers(sc, cfg, tx_positions_m=tx_img)
    c_tx, c_rx = tx_img.mean(axis=0), cfg.rx_positions_m().mean(axis=0)
    unfolded = 0.5 * (np.linalg.norm(pos - c_tx, axis=1) + np.linalg.norm(pos - c_rx, axis=1))
    np.testing.assert_allclose(ghost.range_m, np.sort(unfolded), rtol=1e-12)


def test_report_section_marks_the_ghost_where_the_map_shows_it(tmp_path) -> None:
    """multipath_section on the bundled corridor: the figure is written, and the map's power
    at the corner's order-2 ghost (its image in the metal wall) rises by more than 20 dB
    when multipath is on (a trihedral has no order-1 ghost worth the name: it returns a
    wave only towards where it came from)."""
    from simcore.report.multipath import multipath_section

    figures, numbers = multipath_section(tmp_path, quick=True)
    assert (tmp_path / figures[0][0]).stat().st_size > 10_000
    # Every smooth face reflects now (concrete end walls too); the metal wall's are the
    # ghosts that must stand out.
    ghosts = [m for m in numbers["marks"] if m["order"] == 2 and "metal_wall" in m["label"]]
    assert len(ghosts) == 1
    for m in ghosts:
        assert m["power_on_db"] - m["power_off_db"] > 20.0, m
    target = [m for m in numbers["marks"] if m["order"] == 0][0]
    assert abs(target["power_on_db"] - target["power_off_db"]) < 1.0


def test_compiled_leg_test_equals_the_numpy_reference() -> None:
    from simcore.sensors.radar.multipath import (
        _segments_hit_triangles,
        _segments_hit_triangles_numpy,
    )

    rng = np.random.default_rng(0)
    tri = rng.normal(size=(300, 3, 3))
    a, b = 2 * rng.normal(size=(2000, 3)), 2 * rng.normal(size=(2000, 3))
    hit = _segments_hit_triangles(a, b, tri)
    np.testing.assert_array_equal(hit, _segments_hit_triangles_numpy(a, b, tri))
    assert 0 < hit.sum() < len(hit)


def test_one_pass_leg_test_equals_the_per_object_numpy_tests() -> None:
    """legs_blocked (every leg, every blocking object, one compiled pass) clears exactly the
    legs that the per-object numpy slab test and triangle test find blocked, objects in
    order, with the legs each object skips; segments parallel to a slab included."""
    from simcore.sensors.radar.leg_kernel import legs_blocked
    from simcore.sensors.radar.multipath import _segments_hit_box, _segments_hit_triangles_numpy

    rng = np.random.default_rng(4)
    n_legs, n_obj = 600, 5
    a, b = 2 * rng.normal(size=(n_legs, 3)), 2 * rng.normal(size=(n_legs, 3))
    b[::7, 0] = a[::7, 0]                     # parallel to the x slabs
    b[::11, 1:] = a[::11, 1:]                 # along x only
    tris = [rng.normal(size=(int(rng.integers(4, 60)), 3, 3)) * 0.8 for _ in range(n_obj)]
    boxes = np.stack([np.array([t.reshape(-1, 3).min(0), t.reshape(-1, 3).max(0)]) for t in tris])
    mats = [np.linalg.qr(rng.normal(size=(3, 3)))[0] for _ in range(n_obj)]
    la = np.stack([a @ m.T for m in mats])
    lb = np.stack([b @ m.T for m in mats])
    skip = rng.random((n_obj, n_legs)) < 0.2
    expected = np.ones(n_legs, dtype=bool)
    for o in range(n_obj):
        idx = np.flatnonzero(expected & ~skip[o])
        near = _segments_hit_box(la[o, idx], lb[o, idx], boxes[o])
        expected[idx[near]] = ~_segments_hit_triangles_numpy(la[o, idx[near]], lb[o, idx[near]],
                                                              tris[o])
    clear = np.ones(n_legs, dtype=bool)
    legs_blocked(la, lb, skip, boxes, np.concatenate(tris),
                 np.concatenate([[0], np.cumsum([len(t) for t in tris])]).astype(np.int64),
                 clear)
    np.testing.assert_array_equal(clear, expected)
    assert 0 < expected.sum() < n_legs
