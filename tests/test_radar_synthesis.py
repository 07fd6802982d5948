"""IF synthesis and receiver chain against the direct sum and analytic answers (no render)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.scene.radar_arrays import custom_array
from simcore.scene.radar_config import SPEED_OF_LIGHT, CosinePattern, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c, tdm_mimo_2tx4rx
from simcore.sensors.radar import RadarOutput, simulate_radar
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.synthesis import (
    highpass_response,
    synthesize_if,
    synthesize_if_direct,
)

IDEAL = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
         "if_highpass_hz": 0.0, "if_lowpass_hz": 0.0}


def relative_error_db(fast: np.ndarray, ref: np.ndarray) -> float:
    return float(20 * np.log10(np.linalg.norm(fast - ref) / np.linalg.norm(ref)))


def random_scene(n: int, seed: int) -> Scatterers:
    """Scatterers over the field of view, 0.2–7 m (some beyond 6.4 m alias), half moving."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.2, 7.0, n)
    az = rng.uniform(-1.2, 1.2, n)
    el = rng.uniform(-0.5, 0.5, n)
    pos = np.stack([r * np.sin(az) * np.cos(el), -r * np.sin(el), r * np.cos(az) * np.cos(el)],
                   axis=1)
    vel = np.where(rng.uniform(size=(n, 1)) < 0.5, rng.uniform(-3, 3, (n, 3)), 0.0)
    return Scatterers.from_arrays(pos, rng.lognormal(-4, 2, n), velocities_mps=vel,
                                  phase_rad=rng.uniform(0, 2 * np.pi, n))


def point(r: float, az_deg: float, el_deg: float = 0.0, rcs: float = 1.0,
          v_radial: float = 0.0) -> Scatterers:
    az, el = np.deg2rad(az_deg), np.deg2rad(el_deg)
    u = np.array([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)])
    return Scatterers.from_arrays(r * u[None], [rcs], velocities_mps=v_radial * u[None])


class front_end:  # noqa: N801 - reads as a call: front_end(cfg).synthesize(...)
    """The synthesis + receiver of one radar configuration."""

    def __init__(self, config: RadarConfig):
        self.config = config

    def synthesize(self, scatterers: Scatterers, *, rng: np.random.Generator) -> RadarOutput:
        return simulate_radar(scatterers, self.config, rng=rng)

    def ideal_if(self, scatterers: Scatterers) -> np.ndarray:
        return synthesize_if(scatterers, self.config)


def peak_spectrum(x: np.ndarray, pad: int = 16) -> tuple[np.ndarray, int]:
    """Hann-windowed, zero-padded FFT over the last axis, scaled so a real tone of
    amplitude A peaks at A; and the peak bin of the first row."""
    n = x.shape[-1]
    w = np.hanning(n)
    spec = np.fft.fft(x * w, n=pad * n, axis=-1) / (w.sum() / 2)
    first = spec.reshape(-1, pad * n)[0]
    k = int(np.argmax(np.abs(first[: pad * n // 2])))
    return spec, k


@pytest.mark.parametrize("preset", ["bgt60tr13c", "tdm_mimo_2tx4rx"])
def test_fast_synthesis_matches_the_direct_sum(preset: str) -> None:
    """Acceptance: ≤ −60 dB relative error on ≥ 2000 scatterers, half of them moving."""
    cfg = (bgt60tr13c() if preset == "bgt60tr13c"
           else tdm_mimo_2tx4rx(chirps_per_frame=8))
    scene = random_scene(2400, seed=3)
    fast = synthesize_if(scene, cfg)
    ref = synthesize_if_direct(scene, cfg)
    part = (lambda z: z) if cfg.complex_iq else np.real
    err = relative_error_db(part(fast), part(ref))
    print(f"{preset}: fast vs direct {err:.1f} dB")
    assert err <= -60.0
    # Moving scatterers alone (the per-chirp path) also agree.
    moving = scene.subset(np.any(scene.velocities_mps != 0, axis=1))
    err_moving = relative_error_db(synthesize_if(moving, cfg), synthesize_if_direct(moving, cfg))
    assert err_moving <= -60.0


def test_negated_scatterers_remove_what_they_add_in_one_synthesis() -> None:
    """IF(concat(a negated, b)) = IF(b) − IF(a): the still background's change in one call."""
    cfg = bgt60tr13c(chirps_per_frame=8)
    a, b = random_scene(300, seed=5), random_scene(200, seed=6)
    assert_allclose(np.cos(a.negated().phase_rad), -np.cos(a.phase_rad), atol=1e-12)
    assert np.all(np.abs(a.negated().phase_rad) <= np.pi)
    both = Scatterers.concatenate([a.negated(), b])
    assert len(both) == len(a) + len(b)
    ref = synthesize_if_direct(b, cfg) - synthesize_if_direct(a, cfg)
    assert relative_error_db(synthesize_if(both, cfg), ref) <= -60.0
    # a − a cancels to the transforms' rounding, far below either part.
    gone = synthesize_if(Scatterers.concatenate([a.negated(), a]), cfg)
    assert np.linalg.norm(gone) < 1e-5 * np.linalg.norm(synthesize_if(a, cfg))
    with pytest.raises(ValueError, match="at least one"):
        Scatterers.concatenate([])


def test_direct_sum_matches_a_single_tone_by_hand() -> None:
    """The reference itself: one static scatterer is the IF model of DESIGN.md, by hand."""
    cfg = bgt60tr13c(**IDEAL, element_pattern=CosinePattern(exponent_az=0, exponent_el=0))
    r = 2.0
    y = synthesize_if_direct(point(r, 0.0, rcs=2.0), cfg)
    tau = (r + np.hypot(r, cfg.rx_positions_m()[0, 0])) / SPEED_OF_LIGHT
    t = cfg.sample_times_s()
    k = cfg.slope_hz_per_s
    lam = cfg.wavelength_m
    p_r = (1e-3 * 10 ** (cfg.tx_power_dbm / 10) * 10 ** ((cfg.tx_gain_dbi + cfg.rx_gain_dbi) / 10)
           * lam**2 * 2.0 / ((4 * np.pi) ** 3 * r**2 * (r**2 + cfg.rx_positions_m()[0, 0] ** 2)))
    amp = np.sqrt(2 * 50.0 * p_r) * 10 ** (cfg.if_gain_db / 20) / cfg.adc_full_scale_v
    expected = amp * np.cos(2 * np.pi * cfg.start_frequency_hz * tau + 2 * np.pi * k * tau * t
                            - np.pi * k * tau**2)
    assert_allclose(y[3, 0].real, expected, rtol=1e-9, atol=1e-12 * amp)


def test_rx_phase_difference_is_pi_sin_azimuth() -> None:
    """Acceptance: two Rx λ/2 apart (λ at the chirp centre) see π·sin(az) at ±30°."""
    half = 0.5 * bgt60tr13c().wavelength_m * 1e3
    cfg = bgt60tr13c(**IDEAL, rx=custom_array([(0.0, 0.0), (half, 0.0)]))
    fe = front_end(cfg)
    for az in (30.0, -30.0):
        out = fe.synthesize(point(2.0, az), rng=np.random.default_rng(0))
        spec, k = peak_spectrum(out.adc[0].astype(np.float64))
        measured = np.angle(spec[0, k] * np.conj(spec[1, k]))
        expected = np.pi * np.sin(np.deg2rad(az))
        print(f"az {az:+.0f}°: Δφ = {measured:.5f} rad, π sin(az) = {expected:.5f} rad")
        assert abs(measured - expected) < 0.01


def test_doppler_phase_per_chirp_matches_radial_velocity() -> None:
    cfg = bgt60tr13c(**IDEAL)
    v = 1.3
    y = synthesize_if(point(2.5, 10.0, v_radial=v), cfg)
    spec, k = peak_spectrum(y[:, 1].real)
    steps = np.angle(spec[1:, k] * np.conj(spec[:-1, k]))
    expected = 4 * np.pi * v * cfg.chirp_repetition_time_s / cfg.wavelength_m
    print(f"Doppler step error {np.abs(steps - expected).max():.2e} rad")
    assert_allclose(steps, expected, atol=0.01)


def test_tdm_mimo_virtual_channels_and_timing() -> None:
    cfg = tdm_mimo_2tx4rx(**IDEAL, chirps_per_frame=4)
    az = 20.0
    out = front_end(cfg).synthesize(point(3.0, az), rng=np.random.default_rng(0))
    assert out.adc.shape == (4, 8, 256) and out.adc.dtype == np.complex64
    assert_allclose(out.chirp_start_s[1], [2e-4, 3e-4])
    spec, k = peak_spectrum(out.adc[0].astype(np.complex128))
    assert k < 16 * 256 // 2  # IQ: a positive beat frequency
    # Each channel's phase is that of its exact bistatic delay at the window centre.
    x = point(3.0, az).positions_m[0]
    p_tx, p_rx = out.tx_positions_m, out.rx_positions_m
    tau = ((np.linalg.norm(x - p_tx, axis=1)[:, None] + np.linalg.norm(x - p_rx, axis=1)[None])
           / SPEED_OF_LIGHT).ravel()
    t_c = (cfg.samples_per_chirp - 1) / (2 * cfg.sample_rate_hz)
    f_eff = cfg.start_frequency_hz + cfg.slope_hz_per_s * t_c
    expected = 2 * np.pi * f_eff * tau - np.pi * cfg.slope_hz_per_s * tau**2
    measured = np.angle(spec[:, k] * np.conj(spec[0, k]))
    resid = np.angle(np.exp(1j * (measured - expected + expected[0])))
    print(f"MIMO channel phase error max {np.abs(resid).max():.2e} rad")
    assert_allclose(resid, 0, atol=5e-3)
    # In the far field that is a linear phase over the virtual ULA: slope −2π sin(az)/λ.
    phases = np.unwrap(np.angle(spec[:, k]))
    virt_x = out.virtual_positions_m[:, 0]
    order = np.argsort(virt_x)
    slope = np.polyfit(virt_x[order], phases[order], 1)[0]
    assert_allclose(slope, -2 * np.pi / cfg.wavelength_m * np.sin(np.deg2rad(az)), rtol=1e-2)


def test_static_scatterers_give_identical_chirps_moving_ones_do_not() -> None:
    cfg = bgt60tr13c(**IDEAL)
    static = synthesize_if(point(1.0, 0.0), cfg)
    assert_array_equal(static[0], static[-1])
    moving = synthesize_if(point(1.0, 0.0, v_radial=0.5), cfg)
    assert not np.allclose(moving[0], moving[-1])


def test_receiver_noise_follows_the_noise_figure() -> None:
    cfg = bgt60tr13c(leakage_dbc=None, if_highpass_hz=0.0, adc_bits=None, if_lowpass_hz=0.0)
    out = front_end(cfg).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                    rng=np.random.default_rng(1))
    k_t0 = 1.380649e-23 * 290.0
    # Thermal noise (k T0 F f_s/2 R G² / V_fs², no IF filter here) plus the white noise
    # added after the IF filters (adc_noise_fs, issue #35).
    sigma2 = (k_t0 * 10 ** (cfg.noise_figure_db / 10) * cfg.sample_rate_hz / 2 * 50.0
              * 10 ** (cfg.if_gain_db / 10) / cfg.adc_full_scale_v**2) + cfg.adc_noise_fs**2
    print(f"noise variance / noise-figure formula = {np.var(out.adc) / sigma2:.4f}")
    assert_allclose(np.var(out.adc.astype(np.float64)), sigma2, rtol=0.03)
    explicit = cfg.model_copy(update={"noise_variance_adc": 1e-4})
    out = front_end(explicit).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                         rng=np.random.default_rng(1))
    assert_allclose(np.var(out.adc.astype(np.float64)), 1e-4, rtol=0.03)
    iq = explicit.model_copy(update={"complex_iq": True})
    out = front_end(iq).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                   rng=np.random.default_rng(1))
    assert_allclose(np.var(out.adc.real), 1e-4, rtol=0.03)
    assert_allclose(np.var(out.adc.imag), 1e-4, rtol=0.03)


def test_noise_is_seeded_and_reproducible() -> None:
    fe = front_end(bgt60tr13c())
    scene = point(1.5, 5.0)
    a = fe.synthesize(scene, rng=np.random.default_rng(7)).adc
    b = fe.synthesize(scene, rng=np.random.default_rng(7)).adc
    c = fe.synthesize(scene, rng=np.random.default_rng(8)).adc
    assert_array_equal(a, b)
    assert not np.array_equal(a, c)


@pytest.mark.parametrize("order", [1, 3])
def test_highpass_attenuates_a_tone_by_its_response(order: int) -> None:
    base = bgt60tr13c(**IDEAL)
    filt = base.model_copy(update={"if_highpass_hz": 80e3, "if_highpass_order": order})
    scene = point(0.6, 0.0)  # beat ≈ 94 kHz, near the cutoff
    raw = synthesize_if(scene, base)[0, 1].real
    hp = synthesize_if(scene, filt)[0, 1].real
    spec_raw, k = peak_spectrum(raw)
    spec_hp, _ = peak_spectrum(hp)
    f_beat = base.slope_hz_per_s * 2 * 0.6 / SPEED_OF_LIGHT
    expected = highpass_response(f_beat, 80e3, order)
    ratio = spec_hp[k] / spec_raw[k]
    print(f"high-pass order {order}: |H| error {abs(ratio) / abs(expected) - 1:.2e}, "
          f"phase error {np.angle(ratio / expected):.2e} rad")
    assert_allclose(abs(spec_hp[k]) / abs(spec_raw[k]), abs(expected), rtol=2e-3)
    assert_allclose(np.angle(spec_hp[k] / spec_raw[k]), np.angle(expected), atol=2e-3)


def test_high_pass_shapes_the_noise_spectrum() -> None:
    cfg = bgt60tr13c(leakage_dbc=None, adc_bits=None, noise_variance_adc=1.0,
                     chirps_per_frame=256, if_highpass_hz=100e3, if_highpass_order=2,
                     if_lowpass_hz=0.0)
    out = front_end(cfg).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                    rng=np.random.default_rng(2))
    psd = np.mean(np.abs(np.fft.rfft(out.adc.astype(np.float64), axis=-1)) ** 2, axis=(0, 1))
    f = np.fft.rfftfreq(512, 1 / cfg.sample_rate_hz)
    level = psd[f > 400e3].mean()
    for f0 in (50e3, 100e3):
        i = int(np.argmin(np.abs(f - f0)))
        expected = np.abs(highpass_response(f[i], 100e3, 2)) ** 2
        assert_allclose(psd[i - 1: i + 2].mean() / level, expected, rtol=0.15)


def test_leakage_is_a_tone_at_the_board_path_delay() -> None:
    spacing = 20.0  # mm between Tx and Rx: τ = 67 ps, beat ≈ 1.6 kHz
    cfg = bgt60tr13c(noise_variance_adc=0.0, adc_bits=None, if_highpass_hz=0.0,
                     leakage_dbc=-60.0, if_gain_db=40.0, leakage_path_mm=None,
                     leakage_echoes=[],
                     tx=custom_array([(0.0, 0.0)], prefix="tx"),
                     rx=custom_array([(spacing, 0.0)]), if_lowpass_hz=0.0)
    out = front_end(cfg).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                    rng=np.random.default_rng(0))
    p = 1e-3 * 10 ** ((cfg.tx_power_dbm - 60.0) / 10)
    amp = np.sqrt(2 * 50.0 * p) * 10 ** (40.0 / 20)
    tau = spacing * 1e-3 / SPEED_OF_LIGHT
    k = cfg.slope_hz_per_s
    t = cfg.sample_times_s()
    expected = amp * np.cos(2 * np.pi * cfg.start_frequency_hz * tau + 2 * np.pi * k * tau * t
                            - np.pi * k * tau**2)
    assert_allclose(out.adc[5, 0], expected, rtol=1e-5, atol=1e-7)
    with_hp = cfg.model_copy(update={"if_highpass_hz": 80e3})
    out_hp = front_end(with_hp).synthesize(Scatterers.from_arrays(np.zeros((0, 3)), []),
                                           rng=np.random.default_rng(0))
    gain = abs(highpass_response(k * tau, 80e3, 1))
    assert np.abs(out_hp.adc).max() <= 1.01 * gain * amp


def test_adc_quantizes_to_its_grid_and_clips_at_full_scale() -> None:
    cfg = bgt60tr13c(noise_variance_adc=0.0, leakage_dbc=None, if_highpass_hz=0.0, adc_bits=8)
    fe = front_end(cfg)
    lsb = 2.0 / 2**8
    small = fe.synthesize(point(3.0, 0.0, rcs=0.05), rng=np.random.default_rng(0))
    codes = small.adc.astype(np.float64) / lsb
    assert_allclose(codes, np.round(codes), atol=1e-6)
    exact = fe.ideal_if(point(3.0, 0.0, rcs=0.05)).real
    assert np.abs(small.adc - exact).max() <= lsb / 2 + 1e-7
    assert small.clipped_samples == 0
    loud = fe.synthesize(point(0.5, 0.0, rcs=100.0), rng=np.random.default_rng(0))
    assert loud.clipped_samples > 0
    assert loud.adc.max() == pytest.approx(1 - lsb) and loud.adc.min() == pytest.approx(-1)


def test_output_dtypes_and_hdf5_items() -> None:
    real = front_end(bgt60tr13c()).synthesize(point(2.0, 0.0), rng=np.random.default_rng(0))
    assert real.adc.dtype == np.float32 and real.adc.shape == (16, 3, 512)
    items = real.hdf5_items()
    assert items["/radar/adc"][0] is real.adc and items["/radar/adc"][1] == "FS"
    assert items["/radar/chirp_start_time"][0].shape == (16, 1)
    iq = front_end(bgt60tr13c(complex_iq=True)).synthesize(point(2.0, 0.0),
                                                           rng=np.random.default_rng(0))
    assert iq.adc.dtype == np.complex64


def test_scatterers_for_another_wavelength_are_refused() -> None:
    scene = Scatterers.from_arrays(np.array([[0, 0, 2.0]]), [1.0], wavelength_m=4e-3)
    with pytest.raises(ValueError, match="compute them again"):
        synthesize_if(scene, bgt60tr13c())
