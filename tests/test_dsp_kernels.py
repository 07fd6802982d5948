"""The compiled and cached fast paths of the DSP chain against plain numpy references.

Each reference is the straightforward formula (the previous implementation): OS-CFAR by
:func:`numpy.partition` of every CUT's training cells, the Bartlett angle search by the full
``|a^H x|^2`` grid and :func:`numpy.argmax`, the Bartlett spectrum as ``a^H (R a)``, the
bird's-eye image by :func:`scipy.ndimage.map_coordinates`. Inputs include ties, negative values and
infinities where they change the code path.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.ndimage as ndi
from numpy.testing import assert_allclose, assert_array_equal

from simcore.dsp import (
    array_layout,
    bartlett_spectrum,
    bird_eye_axes,
    bird_eye_image,
    cfar_2d,
    estimate_angles,
    range_azimuth_power,
    spatial_covariance,
    steering_vectors,
)
from simcore.dsp.angle import direction_vectors
from simcore.dsp.cfar import _pad, cfar_threshold_factor, os_rank

# --------------------------------------------------------------------------------------
# OS-CFAR
# --------------------------------------------------------------------------------------


def os_statistic_reference(power: np.ndarray, train: tuple[int, int], guard: tuple[int, int],
                           k: int, circular: tuple[bool, bool]) -> np.ndarray:
    """k-th smallest (1-based) float32 training cell of every CUT, by np.partition."""
    h0, h1 = train[0] + guard[0], train[1] + guard[1]
    padded = _pad(power, (h0, h1), circular).astype(np.float32)
    ring = np.ones((2 * h0 + 1, 2 * h1 + 1), dtype=bool)
    ring[h0 - guard[0]:h0 + guard[0] + 1, h1 - guard[1]:h1 + guard[1] + 1] = False
    out = np.empty(power.shape, dtype=np.float32)
    for i in range(power.shape[0]):
        for j in range(power.shape[1]):
            cells = padded[i:i + 2 * h0 + 1, j:j + 2 * h1 + 1][ring]
            out[i, j] = np.partition(cells, k - 1)[k - 1]
    return out


def _maps() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(11)
    expo = rng.exponential(size=(32, 256))
    expo[5, 40:60] *= 1e4                     # a strong target line: ranks jump
    special = rng.exponential(size=(16, 64))
    special[3, 3], special[4, 4], special[5, 5] = np.inf, 0.0, -0.0
    special[9, 30] = -np.inf
    return {
        "exponential": expo,
        "ties": np.round(rng.exponential(size=(32, 128)) * 2) / 2,
        "constant": np.ones((8, 40)),
        "negative": rng.standard_normal((16, 64)),
        "special": special,
        "small": rng.exponential(size=(3, 25)),
    }


WINDOWS = {"preset": ((4, 8), (1, 2)), "no_guard": ((2, 3), (0, 0)),
           "doppler_only": ((3, 0), (1, 0)), "range_only": ((0, 6), (0, 1))}


@pytest.mark.parametrize("name", list(_maps()))
@pytest.mark.parametrize("rank", [0.0, 0.5, 0.75, 1.0])
@pytest.mark.parametrize("window", list(WINDOWS))
def test_os_cfar_statistic_equals_the_partition_reference(name: str, rank: float,
                                                          window: str) -> None:
    power = _maps()[name]
    train, guard = WINDOWS[window]
    res = cfar_2d(power, method="os", train=train, guard=guard, pfa=1e-6, rank=rank,
                  n_integrated=3)
    k = os_rank(res.n_training, rank)
    _, mean = cfar_threshold_factor("os", n_training=res.n_training, pfa=1e-6, k=k,
                                    n_integrated=3)
    stat = os_statistic_reference(power, train, guard, k, (True, False)).astype(np.float64)
    assert_array_equal(res.noise, (stat / mean).astype(np.float32))
    assert_array_equal(res.threshold, (res.alpha * stat).astype(np.float32))
    assert_array_equal(res.detections, power > res.alpha * stat)


# --------------------------------------------------------------------------------------
# Bartlett angle search
# --------------------------------------------------------------------------------------


def bartlett_reference(x: np.ndarray, positions: np.ndarray, lam: float, az: np.ndarray,
                       el: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Full grid power, argmax and parabolic refinement in dB on both cuts."""
    steer = steering_vectors(positions, wavelength_m=lam, azimuth_rad=az[None, :],
                             elevation_rad=el[:, None]).reshape(-1, positions.shape[0])
    power = np.abs(x @ steer.conj().T) ** 2
    power = power.reshape(len(x), el.size, az.size)
    i_el, i_az = np.unravel_index(np.argmax(power.reshape(len(x), -1), axis=1),
                                  (el.size, az.size))
    rows = np.arange(len(x))

    def refine(cut: np.ndarray, idx: np.ndarray, grid: np.ndarray) -> np.ndarray:
        db = 10 * np.log10(np.maximum(cut, 1e-300))
        n = grid.size
        if n < 3:
            return grid[idx]
        left, mid, right = (db[rows, np.clip(idx + s, 0, n - 1)] for s in (-1, 0, 1))
        denom = left - 2 * mid + right
        with np.errstate(divide="ignore", invalid="ignore"):
            off = np.clip(np.nan_to_num(np.where(denom < 0, 0.5 * (left - right) / denom, 0)),
                          -0.5, 0.5)
        off = np.where((idx > 0) & (idx < n - 1), off, 0.0)
        return grid[idx] + off * (grid[1] - grid[0])

    return refine(power[rows, i_el, :], i_az, az), refine(power[rows, :, i_az], i_el, el)


@pytest.mark.parametrize("array", ["l_shape", "ula", "planar"])
def test_bartlett_search_equals_the_full_grid_reference(array: str) -> None:
    lam = 5e-3
    h = lam / 2
    positions = {
        "l_shape": np.array([[h, 0, 0], [0, 0, 0], [0, -h, 0]]),
        "ula": np.array([[i * h, 0, 0] for i in range(4)]),
        "planar": np.array([[i * h, -j * h, 0] for j in range(2) for i in range(4)]),
    }[array]
    layout = array_layout(positions)
    rng = np.random.default_rng(3)
    n = 40
    az_true = rng.uniform(-1.3, 1.3, n)
    el_true = rng.uniform(-1.0, 1.0, n)
    u = direction_vectors(az_true, el_true)
    x = np.exp(-2j * np.pi * (u @ positions.T) / lam)
    x += 0.3 * (rng.standard_normal(x.shape) + 1j * rng.standard_normal(x.shape))
    x[0] = 0.0                                   # flat spectrum: the first grid point
    x[1] = x[2]                                  # equal snapshots, equal answers
    az = np.deg2rad(np.arange(-80.0, 80.5, 1.0))
    el = np.deg2rad(np.arange(-60.0, 60.5, 1.0))
    got_az, got_el = estimate_angles(x, layout, wavelength_m=lam, method="bartlett",
                                     azimuth_grid_rad=az, elevation_grid_rad=el)
    ref_az, ref_el = bartlett_reference(
        x, positions, lam, az, el if layout.has_vertical_extent else np.zeros(1))
    assert_allclose(got_az, ref_az, rtol=0, atol=1e-9)
    assert_allclose(got_el, ref_el, rtol=0, atol=1e-9)
    assert got_az[0] == az[0] and got_el[0] == (el[0] if layout.has_vertical_extent else 0.0)


def test_bartlett_spectrum_equals_a_h_r_a() -> None:
    rng = np.random.default_rng(5)
    positions = np.array([[2.5e-3, 0, 0], [0, 0, 0], [0, -2.5e-3, 0], [5e-3, 0, 0]])
    x = rng.standard_normal((32, 4, 50)) + 1j * rng.standard_normal((32, 4, 50))
    r = spatial_covariance(x)                                  # (50, 4, 4)
    a = steering_vectors(positions, wavelength_m=5e-3,
                         azimuth_rad=np.deg2rad(np.arange(-80.0, 81.0)))
    reference = np.real(np.einsum("di,rij,dj->rd", np.conj(a), r, a)) / 16
    assert_allclose(bartlett_spectrum(r, a), reference, rtol=1e-12, atol=0)
    assert bartlett_spectrum(r[:0], a).shape == (0, a.shape[0])


@pytest.mark.parametrize("dtype", [np.complex64, np.complex128])
def test_bartlett_range_azimuth_map_equals_covariance_then_spectrum(dtype: type) -> None:
    rng = np.random.default_rng(6)
    positions = np.array([[2.5e-3, 0, 0], [0, 0, 0], [0, -2.5e-3, 0]])
    rd = (rng.standard_normal((32, 3, 40)) + 1j * rng.standard_normal((32, 3, 40))).astype(dtype)
    az = np.deg2rad(np.arange(-80.0, 81.0))
    a = steering_vectors(positions, wavelength_m=5e-3, azimuth_rad=az)
    reference = np.maximum(bartlett_spectrum(spatial_covariance(rd), a), 0.0).T
    got = range_azimuth_power(rd, array_layout(positions), wavelength_m=5e-3, azimuth_rad=az)
    assert got.dtype == np.float32 and got.shape == (az.size, 40)
    assert_allclose(got, reference.astype(np.float32), rtol=1e-6, atol=1e-7)


# --------------------------------------------------------------------------------------
# Bird's-eye image
# --------------------------------------------------------------------------------------


def bird_eye_reference(m: np.ndarray, r_ax: np.ndarray, a_ax: np.ndarray, x_ax: np.ndarray,
                       z_ax: np.ndarray) -> np.ndarray:
    """Bilinear resampling by scipy's map_coordinates (the previous implementation)."""
    xx, zz = np.meshgrid(x_ax, z_ax)
    ir = (np.hypot(xx, zz) - r_ax[0]) / (r_ax[1] - r_ax[0])
    ia = (np.arctan2(xx, zz) - a_ax[0]) / (a_ax[1] - a_ax[0])
    inside = (ir >= 0) & (ir <= r_ax.size - 1) & (ia >= 0) & (ia <= a_ax.size - 1)
    out = ndi.map_coordinates(m, [ia.ravel(), ir.ravel()], order=1, mode="nearest")
    out = out.reshape(xx.shape)
    out[~inside] = np.nan
    return out.astype(np.float32)


@pytest.mark.parametrize("seed", [0, 1])
def test_bird_eye_image_equals_map_coordinates(seed: int) -> None:
    rng = np.random.default_rng(seed)
    r_ax = 0.3 + np.arange(200) * 0.025
    a_ax = np.deg2rad(np.arange(-80.0, 80.5, 1.0))
    x_ax, z_ax = bird_eye_axes(max_range_m=float(r_ax[-1]), max_azimuth_rad=1.4,
                               resolution_m=0.05)
    z_ax = np.append(z_ax, r_ax[-1])                     # a row on the far edge
    m = (rng.standard_normal((a_ax.size, r_ax.size)) * 20).astype(np.float32)
    got = bird_eye_image(m, range_axis_m=r_ax, azimuth_axis_rad=a_ax, x_axis_m=x_ax,
                         z_axis_m=z_ax)
    want = bird_eye_reference(m.astype(np.float64), r_ax, a_ax, x_ax, z_ax)
    assert_array_equal(got, want)
    assert np.isnan(got).any() and np.isfinite(got).any()


# --------------------------------------------------------------------------------------
# CFAR edge padding
# --------------------------------------------------------------------------------------


def pad_reference(x: np.ndarray, widths: tuple[int, int],
                  circular: tuple[bool, bool]) -> np.ndarray:
    """np.pad per axis: wrap where circular, else reflect (edge for a single line)."""
    out = x
    for axis in (0, 1):
        if widths[axis] == 0:
            continue
        pad = [(0, 0), (0, 0)]
        pad[axis] = (widths[axis], widths[axis])
        if circular[axis]:
            out = np.pad(out, pad, mode="wrap")
        else:
            out = np.pad(out, pad, mode="reflect" if out.shape[axis] > 1 else "edge")
    return out


@pytest.mark.parametrize("shape", [(1, 1), (1, 4), (2, 2), (5, 30), (32, 256)])
@pytest.mark.parametrize("widths", [(0, 0), (1, 1), (2, 3), (5, 10)])
@pytest.mark.parametrize("circular", [(True, False), (False, True), (True, True),
                                      (False, False)])
def test_cfar_padding_equals_np_pad(shape: tuple[int, int], widths: tuple[int, int],
                                    circular: tuple[bool, bool]) -> None:
    x = np.random.default_rng(2).standard_normal(shape)
    assert_array_equal(_pad(x, widths, circular), pad_reference(x, widths, circular))
