"""A metal sphere's ghosts and the antennas' polarisation against formulas.

* **The phase of a sphere's ghost.** A metal sphere (radius a) 2.5 m ahead and a metal
  wall 1 m to the side: the ghost radar → wall → sphere → radar is, by the image method,
  the sphere lit by the radar's image in the wall and seen by the radar, and by geometric
  optics it scatters from the one point of the sphere whose normal bisects the directions
  from that point to the image and to the radar, with a perfect conductor's mirror
  (``−M``) on E there. So, relative to the sphere's direct return (delay ``2(d − a)/c``),
  the ghost's complex amplitude is ``Γ · (e_rx · M e_in) · e^{jφ(τ)}``, its delay the
  exact length through that point, with the dechirped IF's phase
  ``φ(τ) = 2π f₀ τ − π K τ²`` (:mod:`simcore.sensors.radar.synthesis`). A sphere's facets
  merged at their centroid (8.9 mm inside a 0.2 m sphere at 2.5 m) gave its ghosts the
  centroid's phase while drawing them at the surface: 197° off.
* **The antennas' E off boresight** (:func:`~simcore.sensors.radar.reflectors.
  antenna_fields`): Ludwig's second definition about the board's vertical, 3GPP TR 38.901
  §7.3.2 (model 2, Sionna RT's ``"V"``/``"H"``): V along ``θ̂``, H along ``φ̂`` of the
  direction's spherical angles about board y.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.pipeline import Simulator
from simcore.report.sionna_targets import radar_config
from simcore.scene import Box, Pose, Project, SceneObject, Sphere
from simcore.scene.model import SensorRig
from simcore.scene.radar_config import SPEED_OF_LIGHT
from simcore.sensors.radar.reflectors import antenna_field, antenna_fields

A = 0.2                                   # sphere radius (m)
D = 2.5                                   # sphere centre ahead of the radar (m)
WALL_Y = 1.0                              # the wall's face, to the radar's left (m)
HEIGHT = 1.0                              # radar and sphere above the origin (m)


def _if(polarization: str, order: int) -> np.ndarray:
    """One chirp's complex IF of the ideal radar: the sphere and a metal wall (world)."""
    cfg = radar_config(polarization).model_copy(update={"multipath_order": order})
    objs = [SceneObject(id=1, name="sphere", geometry=Sphere(radius_m=A),
                        pose=Pose(position_m=(D, 0.0, HEIGHT)), material="aluminium"),
            SceneObject(id=2, name="wall", geometry=Box(size_m=(6.0, 0.2, 3.0)),
                        pose=Pose(position_m=(2.5, WALL_Y + 0.1, HEIGHT)),
                        material="aluminium")]
    rig = SensorRig(pose=Pose(position_m=(0.0, 0.0, HEIGHT)), radar=cfg)
    with Simulator(Project(objects=objs, rig=rig), reuse_static=False) as sim:
        adc = sim.frame(0).outputs["radar"].raw.adc
    return np.asarray(adc, dtype=np.complex128).reshape(-1)[:cfg.samples_per_chirp]


def _at_delay(iq: np.ndarray, tau: float, polarization: str) -> complex:
    """The windowed IF's spectrum at the beat frequency of delay ``tau`` over e^{jφ(τ)}."""
    cfg = radar_config(polarization)
    slope = cfg.bandwidth_hz / cfg.chirp_time_s
    t = np.arange(iq.size) / cfg.sample_rate_hz
    win = np.hanning(iq.size)
    x = np.sum(iq * win * np.exp(-2j * np.pi * slope * tau * t)) / win.sum()
    return complex(x * np.exp(-1j * (2 * np.pi * cfg.start_frequency_hz * tau
                                     - np.pi * slope * tau**2)))


def _specular(centre: np.ndarray, src: np.ndarray, rcv: np.ndarray
              ) -> tuple[np.ndarray, float]:
    """The sphere's normal where it bisects the directions to ``src`` and ``rcv``, and the
    length src → sphere → rcv through that point (fixed-point iteration, to 1e-12)."""
    n = src - centre + rcv - centre
    n /= np.linalg.norm(n)
    for _ in range(200):
        p = centre + A * n
        u = (src - p) / np.linalg.norm(src - p) + (rcv - p) / np.linalg.norm(rcv - p)
        n = u / np.linalg.norm(u)
    p = centre + A * n
    return n, float(np.linalg.norm(src - p) + np.linalg.norm(rcv - p))


def _dipole_e(p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """E of a short dipole ``p`` towards ``d`` (unnormalised: ``p − (p·d̂) d̂``)."""
    d = d / np.linalg.norm(d)
    return p - (p @ d) * d


@pytest.mark.parametrize("polarization", ["V", "H"])
def test_a_spheres_ghost_over_a_metal_wall_has_the_image_methods_phase(
        polarization: str) -> None:
    radar = np.array([0.0, 0.0, HEIGHT])
    centre = np.array([D, 0.0, HEIGHT])
    image = radar.copy()
    image[1] = 2 * WALL_Y - radar[1]                     # the radar mirrored in the wall
    normal, length = _specular(centre, image, radar)
    # The image method: the image of a dipole p in a perfect conductor is −M p (M: the
    # wall's mirror); the image lights the sphere, whose specular point mirrors E (−M_n);
    # received by the radar's own dipole (reciprocity). V (world z) is along the wall and
    # across the plane of the path; H (world y) across the wall and in that plane. Both in
    # the horizontal plane of the path, where every E is the dipole's.
    p = np.array([0.0, 0.0, 1.0]) if polarization == "V" else np.array([0.0, 1.0, 0.0])
    p_image = -(p - 2 * p[1] * np.array([0.0, 1.0, 0.0]))
    e_in = _dipole_e(p_image, centre - image)
    e_in /= np.linalg.norm(e_in)
    e_rx = _dipole_e(p, centre - radar)
    e_rx /= np.linalg.norm(e_rx)
    scattered = -(e_in - 2 * (e_in @ normal) * normal)
    factor = (e_rx @ scattered) / -1.0                   # over the monostatic −1
    tau_d = 2 * (D - A) / SPEED_OF_LIGHT
    tau_g = length / SPEED_OF_LIGHT
    plain = _if(polarization, 0)
    ghosts = _if(polarization, 1) - plain
    ratio = _at_delay(ghosts, tau_g, polarization) / _at_delay(plain, tau_d, polarization)
    assert abs(factor) == pytest.approx(1.0, abs=1e-3)    # GO: |σ| = πa² either way
    err = np.degrees(np.angle(ratio / factor))
    assert abs(err) < 10.0, (polarization, err, length)


def test_the_antennas_e_is_theta_and_phi_about_the_boards_vertical() -> None:
    """V = ±θ̂, H = ±φ̂ of the direction's spherical angles about board y (polar axis),
    the azimuth from boresight (z) towards x; +y and +x on boresight."""
    rng = np.random.default_rng(3)
    theta = rng.uniform(0.1, np.pi - 0.1, 200)           # from board y
    phi = rng.uniform(-np.pi, np.pi, 200)                # about it, from boresight
    # Spherical frame with polar axis y: (x, y, z) = (sinθ sinφ, cosθ, sinθ cosφ).
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta),
                  np.sin(theta) * np.cos(phi)], axis=1)
    theta_hat = np.stack([np.cos(theta) * np.sin(phi), -np.sin(theta),
                          np.cos(theta) * np.cos(phi)], axis=1)
    phi_hat = np.stack([np.cos(phi), np.zeros_like(phi), -np.sin(phi)], axis=1)
    v = antenna_fields(np.array([0.0, 1.0, 0.0]), d)
    h = antenna_fields(np.array([1.0, 0.0, 0.0]), d)
    np.testing.assert_allclose(np.abs(np.einsum("kd,kd->k", v, theta_hat)), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.einsum("kd,kd->k", h, phi_hat), 1.0, atol=1e-12)
    # The one-direction form (the room's paths) on the same directions.
    np.testing.assert_allclose([antenna_field(np.array([1.0, 0.0, 0.0]), x) @ ph
                                for x, ph in zip(d, phi_hat, strict=True)], 1.0, atol=1e-12)
    np.testing.assert_allclose([abs(antenna_field(np.array([0.0, 1.0, 0.0]), x) @ th)
                                for x, th in zip(d, theta_hat, strict=True)], 1.0, atol=1e-12)
    boresight = np.array([[0.0, 0.0, 1.0]])
    np.testing.assert_allclose(antenna_fields(np.array([0.0, 1.0, 0.0]), boresight),
                               [[0.0, 1.0, 0.0]], atol=1e-15)
    np.testing.assert_allclose(antenna_fields(np.array([1.0, 0.0, 0.0]), boresight),
                               [[1.0, 0.0, 0.0]], atol=1e-15)
