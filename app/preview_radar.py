"""A small preview radar chain, used only while the pipeline's frames carry no DSP products.

It is not the simulator's radar model (``simcore.sensors`` / ``simcore.dsp`` are): it maps
each valid radar-render pixel to a scatterer (amplitude from the radar equation,
``sqrt(σ⁰ dA) / R²``), accumulates the scatterers straight into range bins with the phase of
every Rx channel (far-field path difference) and chirp (Doppler), adds a noise floor, and runs
a Doppler FFT, Bartlett azimuth beamforming and a cell-averaging CFAR. The panels label its
output "preview" so it is never mistaken for the simulator's.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.ndimage import maximum_filter, uniform_filter1d

from app.frame_view import Detections, RadarView, radar_to_world
from simcore.scene import Project

NOISE_POWER = 1e-7
PIXEL_STRIDE = 2


def _cfar_ca(power: np.ndarray, *, train: tuple[int, int], guard: tuple[int, int],
             pfa: float) -> tuple[np.ndarray, np.ndarray]:
    """2-D cell-averaging CFAR over the last two axes; returns (threshold, noise)."""
    def window_mean(x: np.ndarray, half: tuple[int, int]) -> np.ndarray:
        out = x
        for axis, h in zip((-2, -1), half, strict=True):
            mode = "wrap" if axis == -2 else "reflect"
            out = uniform_filter1d(out, 2 * h + 1, axis=axis, mode=mode)
        return out * np.prod([2 * h + 1 for h in half])

    outer = window_mean(power, (train[0] + guard[0], train[1] + guard[1]))
    inner = window_mean(power, guard)
    n_outer = np.prod([2 * (t + g) + 1 for t, g in zip(train, guard, strict=True)])
    n_inner = np.prod([2 * g + 1 for g in guard])
    n = n_outer - n_inner
    noise = np.maximum((outer - inner) / n, 1e-30)
    alpha = n * (pfa ** (-1.0 / n) - 1.0)
    return alpha * noise, noise


def preview_radar_view(frame: Any, project: Project) -> RadarView:
    """Compute a :class:`RadarView` from the frame's radar render (see module docstring)."""
    cfg = project.rig.radar
    buf = frame.radar_buffers
    rng = np.random.default_rng([project.seed, frame.index, 7])
    lam = cfg.wavelength_m
    n_fft = 1 << int(np.ceil(np.log2(cfg.samples_per_chirp)))
    n_range = n_fft if cfg.complex_iq else n_fft // 2
    res = cfg.range_resolution_m * cfg.samples_per_chirp / n_fft
    range_axis = np.arange(n_range) * res

    s = PIXEL_STRIDE
    valid = buf.valid[::s, ::s]
    r = buf.range_m[::s, ::s][valid].astype(np.float64)
    pts = buf.points_m[::s, ::s][valid].astype(np.float64)
    cos_i = np.clip(buf.cos_incidence[::s, ::s][valid].astype(np.float64), 0.05, 1.0)
    sigma0 = buf.intensity[::s, ::s][valid].astype(np.float64)
    omega = buf.intrinsics.pixel_solid_angle()[::s, ::s][valid] * s * s
    vr = buf.radial_velocity_mps[::s, ::s][valid].astype(np.float64)
    amp = np.sqrt(sigma0 * r**2 * omega / cos_i) / np.maximum(r, 0.05) ** 2
    # Point targets (no surface) and visible corner reflectors (analytic RCS) are added as
    # single scatterers at their origin.
    visible_ids = set(np.unique(buf.object_id).tolist())
    extra = []
    for o, st in zip(project.objects, frame.snapshot.objects, strict=True):
        if o.geometry.kind == "point_target":
            extra.append((o.geometry.rcs_m2, st))
        elif o.geometry.kind == "corner_reflector" and o.id in visible_ids:
            extra.append((o.geometry.rcs_m2(lam), st))
    if extra:
        inv = np.linalg.inv(buf.sensor.transform)
        p = np.array([(inv @ np.append(st.origin, 1.0))[:3] for _, st in extra])
        rr = np.linalg.norm(p, axis=1)
        keep = p[:, 2] > 0
        pts = np.vstack([pts, p[keep]])
        r = np.concatenate([r, rr[keep]])
        amp = np.concatenate([amp, np.sqrt([rcs for rcs, _ in extra])[keep] / rr[keep] ** 2])
        vr = np.concatenate([vr, np.zeros(int(keep.sum()))])
    u = pts / np.maximum(r, 1e-6)[:, None]

    rx = np.array([a.position_mm for a in cfg.rx], dtype=np.float64) * 1e-3
    tx = np.array([a.position_mm for a in cfg.tx], dtype=np.float64) * 1e-3
    virt = (tx[:, None, :] + rx[None, :, :]).reshape(-1, 2)  # (tx*rx, 2)
    n_ch, n_chirp = len(virt), cfg.chirps_per_frame
    t_chirp = np.arange(n_chirp) * cfg.chirp_repetition_time_s * len(cfg.tx)

    pos = r / res
    i0 = np.floor(pos).astype(np.int64)
    frac = pos - i0
    ok = (i0 >= 0) & (i0 < n_range - 1)
    i0, frac, amp, u, r, vr = i0[ok], frac[ok], amp[ok], u[ok], r[ok], vr[ok]
    base = amp * np.exp(1j * 4 * np.pi * r / lam)
    path = u[:, :2] @ virt.T  # (k, channels): far-field path shortening
    spectrum = np.zeros((n_chirp, n_ch, n_range), dtype=np.complex128)
    for c in range(n_chirp):
        dop = np.exp(1j * 4 * np.pi * vr * t_chirp[c] / lam)
        for ch in range(n_ch):
            w = base * dop * np.exp(-1j * 2 * np.pi * path[:, ch] / lam)
            for idx, wt in ((i0, 1 - frac), (i0 + 1, frac)):
                spectrum[c, ch] += np.bincount(idx, weights=(w * wt).real, minlength=n_range)
                spectrum[c, ch] += 1j * np.bincount(idx, weights=(w * wt).imag,
                                                    minlength=n_range)
    # Window main lobe (Hann) along range, then the receiver noise floor.
    spectrum = 0.25 * np.roll(spectrum, 1, -1) + 0.5 * spectrum + 0.25 * np.roll(spectrum, -1, -1)
    spectrum += np.sqrt(NOISE_POWER / 2) * (rng.standard_normal(spectrum.shape)
                                            + 1j * rng.standard_normal(spectrum.shape))
    spectrum[..., :2] *= 1e-2  # IF high-pass
    profile_db = 10 * np.log10(np.mean(np.abs(spectrum) ** 2, axis=0))

    n_dop = 2 * (1 << int(np.ceil(np.log2(n_chirp))))
    win = np.hanning(n_chirp + 2)[1:-1]
    rd_c = np.fft.fftshift(np.fft.fft(spectrum * win[:, None, None], n=n_dop, axis=0), axes=0)
    rd_power = np.mean(np.abs(rd_c) ** 2, axis=1)  # (D, R)
    v_max = lam / (4 * cfg.chirp_repetition_time_s * len(cfg.tx))
    velocity_axis = (np.arange(n_dop) - n_dop // 2) / n_dop * 2 * v_max

    az = np.deg2rad(np.arange(-80.0, 80.01, 1.0))
    steer = np.exp(-1j * 2 * np.pi * np.outer(np.sin(az), virt[:, 0]) / lam) / np.sqrt(n_ch)
    beams = np.einsum("ac,dcr->adr", steer.conj(), rd_c)  # (A, D, R)
    ra_power = np.mean(np.abs(beams) ** 2, axis=1)

    threshold, noise = _cfar_ca(rd_power, train=(4, 8), guard=(1, 2), pfa=1e-5)
    peaks = (rd_power > threshold) & (rd_power == maximum_filter(rd_power, size=(3, 3),
                                                                 mode="wrap"))
    peaks[:, range_axis < 0.2] = False
    d_idx, r_idx = np.nonzero(peaks)
    order = np.argsort(-rd_power[d_idx, r_idx])[:64]
    d_idx, r_idx = d_idx[order], r_idx[order]
    a_idx = np.argmax(np.abs(beams[:, d_idx, r_idx]) ** 2, axis=0) if len(d_idx) else d_idx
    det_r = range_axis[r_idx]
    det_az = np.rad2deg(az[a_idx]) if len(d_idx) else np.zeros(0)
    a = np.deg2rad(det_az)
    xyz = np.stack([det_r * np.sin(a), np.zeros_like(det_r), det_r * np.cos(a)], axis=1)
    det = Detections(det_r, velocity_axis[d_idx], det_az, np.zeros_like(det_r),
                     10 * np.log10(rd_power[d_idx, r_idx] / noise[d_idx, r_idx]), xyz,
                     radar_to_world(xyz, buf.sensor.transform))
    prof_power = np.mean(10 ** (profile_db / 10), axis=0)
    thr_1d, _ = _cfar_ca(prof_power[None, :], train=(0, 12), guard=(0, 2), pfa=1e-5)
    return RadarView(
        range_axis_m=range_axis,
        profile_db=profile_db.astype(np.float32),
        threshold_db=(10 * np.log10(thr_1d[0])).astype(np.float32),
        velocity_axis_mps=velocity_axis,
        range_doppler_db=(10 * np.log10(rd_power)).astype(np.float32),
        azimuth_axis_deg=np.rad2deg(az),
        range_azimuth_db=(10 * np.log10(ra_power)).astype(np.float32),
        detections=det,
        channel_names=[
            f"{t.name or 'tx'}→{x.name or 'rx'}" if len(cfg.tx) > 1 else (x.name or f"rx{i + 1}")
            for t in cfg.tx for i, x in enumerate(cfg.rx)],
        source="preview",
    )
