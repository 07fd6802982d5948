"""Radar–radar interference in simulated frames: two rigs, each with a radar, no objects.

The victim is ``rig.radar`` (rig at the origin, looking along +x); the aggressor a radar
on a second rig. The known answers are computed here from the two radars' parameters,
poses and trigger offsets (closed forms: the frequencies' crossing, the one-way Friis
link with the cosine element pattern, the ghost range of equal slopes, a tone's power),
never from the module under test. Geometries differ from the bundled examples: other
distances, an aggressor turned off the line of sight, other slopes and offsets.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.pipeline import Simulator
from simcore.scene.model import NamedRadar, Project, Rig, SensorRig, Timeline
from simcore.scene.motion import Pose
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c
from simcore.sensors.radar.interference import (
    INR_NOISE_FREE_DB,
    INR_NONE_DB,
    AggressorTiming,
    interference_if,
)

QUIET = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
         "chirps_per_frame": 4}


def project(victim: RadarConfig, aggressor: RadarConfig, *, distance_m: float,
            yaw_deg: float = 180.0, offset_y_m: float = 0.0) -> Project:
    """Victim rig at the origin (radar 1 m up, along +x); aggressor rig ``distance_m``
    ahead, turned ``yaw_deg``."""
    named = NamedRadar.model_validate(aggressor.model_dump())
    return Project(
        timeline=Timeline(frame_rate_hz=10.0, duration_s=0.8),
        rig=SensorRig(pose=Pose(position_m=(0, 0, 1)), radar=victim),
        rigs=[Rig(name="other", pose=Pose(position_m=(distance_m, offset_y_m, 1),
                                          rotation_deg=(0, 0, yaw_deg)),
                  sensors={"aggressor": named})])


def frame_adc(p: Project, index: int = 0) -> tuple[np.ndarray, float | None, np.ndarray]:
    with Simulator(p) as sim:
        raw = sim.frame(index).outputs["radar"].raw
    return np.asarray(raw.adc), raw.inr_db, raw.chirp_start_s


def board_delay_s(victim: RadarConfig, aggressor: RadarConfig, distance_m: float,
                  yaw_deg: float = 180.0) -> float:
    """Aggressor Tx1 → victim Rx1 in the horizontal plane (body x forward, y left).

    Board x is body −y; the aggressor's board is turned by ``yaw_deg`` about z.
    """
    rx = np.array([0.0, -victim.rx[0].position_mm[0] * 1e-3])
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    tx_local = np.array([0.0, -aggressor.tx[0].position_mm[0] * 1e-3])
    tx = np.array([distance_m, 0.0]) + np.array([[c, -s], [s, c]]) @ tx_local
    return float(np.linalg.norm(tx - rx)) / SPEED_OF_LIGHT


def friis_fs(victim: RadarConfig, aggressor: RadarConfig, d: float, gain: float = 1.0) -> float:
    p_r = (1e-3 * 10 ** (aggressor.tx_power_dbm / 10)
           * 10 ** ((aggressor.tx_gain_dbi + victim.rx_gain_dbi) / 10) * gain
           * (aggressor.wavelength_m / (4 * np.pi * d)) ** 2)
    return float(np.sqrt(100.0 * p_r) * 10 ** (victim.if_gain_db / 20) / victim.adc_full_scale_v)


def group_delay_s(victim: RadarConfig) -> float:
    n = victim.if_lowpass_order
    poles = np.exp(1j * np.pi * (2 * np.arange(1, n + 1) + n - 1) / (2 * n))
    return float(np.sum(-poles.real)) / (2 * np.pi * victim.if_lowpass_hz)


def optical_pose(position: tuple[float, float, float], yaw_deg: float) -> np.ndarray:
    """Optical frame (x right, y down, z boresight) → world of a radar on a level rig
    turned ``yaw_deg`` about z: boresight (cos ψ, sin ψ, 0), right = body −y turned."""
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    pose = np.eye(4)
    pose[:3, 0] = (s, -c, 0.0)
    pose[:3, 1] = (0.0, 0.0, -1.0)
    pose[:3, 2] = (c, s, 0.0)
    pose[:3, 3] = position
    return pose


@pytest.mark.parametrize(("distance_m", "yaw_deg"), [(2.2, 180.0), (4.0, 200.0)])
def test_burst_in_the_frame_at_the_crossing_with_the_link_budget(distance_m: float,
                                                                  yaw_deg: float) -> None:
    """The frame's ADC holds the aggressor's burst: the same signal as the direct-path
    function for these poses and the trigger offset, its centre and duration where the
    formulas put them and its level from one-way Friis with the aggressor's pattern."""
    victim = bgt60tr13c(**QUIET, if_highpass_hz=0.0)
    d_slope = 1e11
    k_a = victim.slope_hz_per_s - d_slope
    offset = 2e-6                                  # aggressor frame trigger offset
    aggressor = bgt60tr13c(**QUIET, start_frequency_hz=60e9 + d_slope * 128e-6 + k_a * 2e-6,
                           bandwidth_hz=k_a * 256e-6, trigger_offset_s=offset)
    adc, inr, _ = frame_adc(project(victim, aggressor, distance_m=distance_m, yaw_deg=yaw_deg))
    cube = interference_if(victim, optical_pose((0, 0, 1), 0.0), aggressor,
                           optical_pose((distance_m, 0, 1), yaw_deg),
                           timing=AggressorTiming(offset))
    assert np.allclose(adc, cube.real, atol=1e-6)
    assert inr == INR_NOISE_FREE_DB                      # noise-free victim
    tau = board_delay_s(victim, aggressor, distance_m, yaw_deg)
    t_cross = (aggressor.start_frequency_hz - victim.start_frequency_hz
               - k_a * (offset + tau)) / d_slope + group_delay_s(victim)
    duration = 2 * victim.if_lowpass_hz / d_slope
    # Element patterns: the aggressor's boresight is off the line of sight by the yaw's
    # excess over 180° (azimuth), the victim looks straight at it: g = cos^2.6.
    off = np.radians(yaw_deg - 180.0)
    gain = np.cos(off) ** aggressor.element_pattern.exponent_az   # type: ignore[union-attr]
    friis = friis_fs(victim, aggressor, tau * SPEED_OF_LIGHT, gain)
    env = np.abs(cube[0, 0])
    t = np.arange(env.size) / victim.sample_rate_hz
    inside = np.flatnonzero(env > friis / np.sqrt(2))
    centre = 0.5 * (t[inside[0]] + t[inside[-1]])
    width = (inside[-1] - inside[0] + 1) / victim.sample_rate_hz
    level_db = 20 * np.log10(np.abs(adc[0, 0]).max() / friis)
    print(f"centre {centre * 1e6:.2f} µs (formula {t_cross * 1e6:.2f}), width "
          f"{width * 1e6:.2f} µs (formula {duration * 1e6:.2f}), level {level_db:+.2f} dB")
    # Within 1.5 samples: the half-power edges lie at ±f_AAF, where the Butterworth's
    # group delay exceeds its DC value (the one added to t×) by a few tenths of a µs.
    assert abs(centre - t_cross) < 1.5 / victim.sample_rate_hz
    assert abs(width - duration) < 0.05 * duration + 1.0 / victim.sample_rate_hz
    assert abs(level_db) < 1.0
    # Every chirp of the victim sees the same burst (equal repetition times).
    assert np.allclose(adc[-1, 0], adc[0, 0], atol=0.02 * np.abs(adc).max())


def ghost_range(adc: np.ndarray, cfg: RadarConfig, chirp: int = 0) -> float:
    pad = 16
    x = adc[chirp, 0].real
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size), pad * x.size))
    return float(np.argmax(spec) * SPEED_OF_LIGHT * cfg.sample_rate_hz
                 / (2 * cfg.slope_hz_per_s * pad * x.size))


@pytest.mark.parametrize(("distance_m", "offset_s"), [(2.0, 3e-9), (5.0, 0.0)])
def test_equal_slopes_give_a_ghost_at_the_range_of_the_start_offset(distance_m: float,
                                                                    offset_s: float) -> None:
    victim = bgt60tr13c(**QUIET)
    aggressor = bgt60tr13c(**QUIET, trigger_offset_s=offset_s)
    adc, _, _ = frame_adc(project(victim, aggressor, distance_m=distance_m))
    expect = SPEED_OF_LIGHT * (offset_s + board_delay_s(victim, aggressor, distance_m)) / 2
    est = ghost_range(adc, victim)
    print(f"ghost at {est:.4f} m, formula {expect:.4f} m")
    assert abs(est - expect) < 0.25 * victim.range_resolution_m


def test_interference_to_noise_ratio_of_an_equal_slope_tone() -> None:
    """A ghost tone of amplitude A·|H(f_b)| on a real IF: mean power A²|H|²/2 over σ²."""
    sigma2 = 1e-6
    victim = bgt60tr13c(**{**QUIET, "noise_variance_adc": sigma2})
    aggressor = bgt60tr13c(**QUIET, trigger_offset_s=3e-9)
    d = 2.0
    _, inr, _ = frame_adc(project(victim, aggressor, distance_m=d))
    tau = board_delay_s(victim, aggressor, d)
    f_b = victim.slope_hz_per_s * (3e-9 + tau)
    h2 = (1 / (1 + (victim.if_highpass_hz / f_b) ** 2)
          / (1 + (f_b / victim.if_lowpass_hz) ** (2 * victim.if_lowpass_order)))
    expect = 10 * np.log10(friis_fs(victim, aggressor, tau * SPEED_OF_LIGHT) ** 2 * h2 / 2
                           / sigma2)
    print(f"INR {inr:.2f} dB, formula {expect:.2f} dB")
    assert inr is not None and abs(inr - expect) < 0.5


def test_chirp_jitter_moves_the_ghost_by_each_chirps_own_delay() -> None:
    """The victim's jitter, read from its recorded chirp start times, shifts the ghost of
    an equal-slope aggressor chirp by chirp: range c (offset + τ − δ_k) / 2."""
    victim = bgt60tr13c(**QUIET, chirp_jitter_s=10e-9, transmit_seed=7)
    aggressor = bgt60tr13c(**QUIET, trigger_offset_s=12e-9)
    d = 2.0
    adc, _, starts = frame_adc(project(victim, aggressor, distance_m=d))
    delays = starts[:, 0] - victim.chirp_start_times_s()[:, 0]
    assert np.all((delays >= 0) & (delays < 10e-9)) and np.ptp(delays) > 2e-9
    tau = board_delay_s(victim, aggressor, d)
    for k in range(victim.chirps_per_frame):
        expect = SPEED_OF_LIGHT * (12e-9 + tau - delays[k]) / 2
        assert abs(ghost_range(adc, victim, k) - expect) < 0.25 * victim.range_resolution_m


def test_frequency_hopping_silences_frames_on_different_channels() -> None:
    """Start frequencies 200 MHz apart beat far outside the IF passband: no interference;
    on the same channel the equal-slope ghost is there."""
    hop = {"hop_step_hz": 200e6, "hop_channels": 4}
    victim = bgt60tr13c(**{**QUIET, "noise_variance_adc": 1e-6}, **hop, transmit_seed=1)
    aggressor = bgt60tr13c(**QUIET, **hop, transmit_seed=2, trigger_offset_s=3e-9)
    p = project(victim, aggressor, distance_m=2.0)
    seen = []
    with Simulator(p) as sim:
        for i in range(8):
            frame = sim.frame(i)
            same = np.isclose(frame.outputs["radar"].raw.chirp_start_s[0, 0], i / 10.0)
            inr = frame.outputs["radar"].raw.inr_db
            seen.append(inr)
            assert same
    quiet = [x for x in seen if x == INR_NONE_DB]
    loud = [x for x in seen if x > 20]
    print("INR per frame", np.round(seen, 1))
    assert len(quiet) + len(loud) == 8 and quiet and loud


def test_chirp_jitter_lowers_the_equal_slope_ghost_by_10_db() -> None:
    """Microseconds of jitter put the beat of most chirp pairs (K·δ) far outside the IF
    passband: the ghost's energy in the frame drops by far more than 10 dB."""
    sigma2 = 1e-6
    base = {**QUIET, "noise_variance_adc": sigma2, "chirps_per_frame": 16}
    jitter = {"chirp_jitter_s": 5e-6, "chirp_repetition_time_s": 300e-6}
    plain = frame_adc(project(bgt60tr13c(**base), bgt60tr13c(**base, trigger_offset_s=3e-9),
                              distance_m=2.0))[1]
    mitigated = frame_adc(project(bgt60tr13c(**base, **jitter, transmit_seed=3),
                                  bgt60tr13c(**base, **jitter, transmit_seed=4,
                                             trigger_offset_s=3e-9), distance_m=2.0))[1]
    print(f"INR {plain:.1f} dB plain, {mitigated:.1f} dB with chirp jitter")
    assert plain is not None and mitigated is not None and plain - mitigated >= 10.0


def test_aggressor_reaches_the_victim_over_a_scatterer_with_multipath() -> None:
    """Side by side, both looking at a corner reflector: no line of sight between the
    boards (90° off both boresights: cos^2.6 = 0), so with multipath on the only
    interference is the bistatic path aggressor → reflector → victim, an equal-slope
    ghost at half its length (r_a + r_v) / 2; without multipath there is none."""
    from simcore.scene import SceneObject
    from simcore.scene.geometry import CornerReflector

    target = np.array([3.0, 0.2, 1.0])
    side = 0.6
    corner = SceneObject(id=1, name="corner", geometry=CornerReflector(edge_m=0.08),
                         pose=Pose(position_m=tuple(target), rotation_deg=(0, -90, 0)),
                         material="radar_retroreflector")
    out = {}
    for order in (0, 1):
        victim = bgt60tr13c(**QUIET, multipath_order=order)
        named = NamedRadar.model_validate(bgt60tr13c(**QUIET).model_dump())
        p = Project(objects=[corner], timeline=Timeline(frame_rate_hz=10.0, duration_s=0.5),
                    rig=SensorRig(pose=Pose(position_m=(0, 0, 1)), radar=victim),
                    rigs=[Rig(name="other", pose=Pose(position_m=(0, side, 1)),
                              sensors={"aggressor": named})])
        with Simulator(p) as sim:
            out[order] = sim.frame(0).outputs["radar"].raw
    assert out[0].inr_db == INR_NONE_DB
    assert out[1].inr_db == INR_NOISE_FREE_DB       # noise-free victim, interference present
    # The victim's own echo sits at r_v; the difference of the two cubes is the ghost
    # (the victim's multipath adds nothing for a lone reflector without planar faces).
    diff = np.asarray(out[1].adc, np.float64) - np.asarray(out[0].adc, np.float64)
    r_v = float(np.linalg.norm(target - [0, 0, 1]))
    r_a = float(np.linalg.norm(target - [0, side, 1]))
    expect = (r_a + r_v) / 2
    est = ghost_range(diff[None, 0], bgt60tr13c(**QUIET))
    print(f"bistatic ghost at {est:.4f} m, formula {expect:.4f} m (own echo at {r_v:.4f} m)")
    assert abs(est - expect) < 0.25 * bgt60tr13c(**QUIET).range_resolution_m


def test_dsp_mitigation_in_frames_lowers_the_floor_10_db_and_recovers_the_weak_target() -> None:
    """The report's scene: a 5 mm corner reflector at 2.5 m, found alone; an aggressor of
    another slope 0.7 m away buries it under its bursts; burst interpolation lowers the
    range profile's floor by ≥ 10 dB and the target is detected again."""
    from simcore.report.interference import _project, _run
    from simcore.scene.dsp_config import DspConfig

    victim = bgt60tr13c()
    aggressor = bgt60tr13c(bandwidth_hz=4.5e9, start_frequency_hz=60.75e9)
    clean = _run(_project(None, victim, DspConfig()))
    bursts = _run(_project(aggressor, victim, DspConfig()))
    fixed = _run(_project(aggressor, victim, DspConfig(interference_mitigation="interpolate")))
    print(f"floor {clean['floor_db']:.1f} clean, {bursts['floor_db']:.1f} bursts, "
          f"{fixed['floor_db']:.1f} interpolated")
    assert clean["target_found"] and not bursts["target_found"] and fixed["target_found"]
    assert bursts["floor_db"] - fixed["floor_db"] >= 10.0


def test_hopping_is_honoured_by_the_victims_own_echo() -> None:
    """A lone radar hopping its start frequency per frame: the echo of a reflector at R
    keeps its beat frequency (range) and its phase moves by 2π Δf₀ · 2R / c between
    frames on channels Δf₀ apart (the frame's own synthesis uses the hopped carrier)."""
    from simcore.scene import SceneObject
    from simcore.scene.geometry import CornerReflector
    from simcore.sensors.radar.transmit import transmit_draw

    r_m = 2.0
    radar = bgt60tr13c(**QUIET, complex_iq=True, hop_step_hz=10e6, hop_channels=4,
                       transmit_seed=3)
    corner = SceneObject(id=1, name="corner", geometry=CornerReflector(edge_m=0.08),
                         pose=Pose(position_m=(r_m, 0.0, 1.0), rotation_deg=(0, -90, 0)),
                         material="radar_retroreflector")
    p = Project(objects=[corner], timeline=Timeline(frame_rate_hz=10.0, duration_s=0.6),
                rig=SensorRig(pose=Pose(position_m=(0, 0, 1)), radar=radar))
    peaks, phases, channels = [], [], []
    with Simulator(p) as sim:
        for i in range(6):
            x = np.asarray(sim.frame(i).outputs["radar"].raw.adc[0, 0], np.complex128)
            spec = np.fft.fft(x * np.hanning(x.size))
            k = int(np.argmax(np.abs(spec[: x.size // 2])))
            peaks.append(k)
            phases.append(np.angle(spec[k]))
            channels.append(transmit_draw(radar, i)[0])
    assert len(set(peaks)) == 1 and len(set(channels)) > 1
    # The reflector's phase centre: the delay from the peak's phase slope is not needed;
    # R to within a centimetre gives the phase steps to 2π·10 MHz·2·0.01 m/c = 0.004 rad.
    for i in range(1, 6):
        expect = 2 * np.pi * (channels[i] - channels[0]) * 10e6 * 2 * r_m / SPEED_OF_LIGHT
        got = np.angle(np.exp(1j * (phases[i] - phases[0])))
        assert abs(np.angle(np.exp(1j * (got - expect)))) < 0.05, (i, got, expect)
