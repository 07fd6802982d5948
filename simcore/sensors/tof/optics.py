"""Camera optics and electronics of the ToF camera: each a step where it happens physically.

* **Lens distortion** (Brown–Conrady, :func:`distort_buffers`): the lens bends the ray a
  pixel sees. A render pixel at distorted normalised coordinates ``(x_d, y_d)`` sees the
  undistorted ray ``(x, y)`` that the Brown–Conrady model maps onto it::

      r² = x² + y²,  g = 1 + k1 r² + k2 r⁴ + k3 r⁶
      x_d = x g + 2 p1 x y + p2 (r² + 2 x²),   y_d = y g + p1 (r² + 2 y²) + 2 p2 x y

  (OpenCV's and the camera SDKs' convention; coefficients ``(k1, k2, p1, p2, k3)``). The
  lens's focal length is chosen so that the edge centres of the image keep the configured
  field of view (:func:`lens_focal_px`); the render buffers are resampled (nearest render
  pixel) before anything else, so range, intensity and ground truth all follow the lens.
* **Vignetting** (:func:`vignetting`): the collected signal and ambient light fall off as
  ``cos⁴ θ`` of the pixel's off-axis angle (natural vignetting).
* **Wiggling** (:func:`wiggling_planes`): the modulation and correlation waveforms are not
  sinusoids; their correlation has odd harmonics ``c(φ) = cos φ + a3 cos 3φ + a5 cos 5φ``.
  With four samples ``φ + iπ/2`` the 3rd harmonic folds onto the phasor as ``a3 e^{−i3φ}``
  and the 5th as ``a5 e^{i5φ}``, so the measured phase is
  ``φ̂ ≈ φ + (a5 − a3) sin 4φ``: a cyclic depth error of amplitude
  ``|a5 − a3| c / (4π f)`` and period a quarter of the unambiguous range.
* **Stray light** (:func:`stray_light`): light scattered in the lens spreads each pixel's
  complex correlation (its offset and phasor) over the image with the point-spread function
  ``(1 − s) δ + s K``, ``K(r) = (1 + r²/r0²)^(−3/2) / (2π r0²)`` (a long tail, normalised to 1
  over the plane), applied by FFT convolution before read-out; a bright near object adds
  its phasor to dark far pixels and pulls their depth towards its own.
"""

from __future__ import annotations

import dataclasses
from typing import TypeVar, cast

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sp_fft

from simcore.jit import kernel
from simcore.render.buffers import RenderBuffers
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig

F32 = NDArray[np.float32]
G = TypeVar("G", bound=np.generic)
#: Fixed-point iterations of the Brown–Conrady inversion.
UNDISTORT_ITERATIONS = 20


def brown_conrady(x: NDArray[np.float64], y: NDArray[np.float64],
                  coefficients: tuple[float, float, float, float, float]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Distorted normalised coordinates of undistorted ones (module docstring).

    Parameters
    ----------
    x, y : ndarray
        Undistorted normalised image coordinates (``X/Z``, ``Y/Z``).
    coefficients : (k1, k2, p1, p2, k3)

    Returns
    -------
    (ndarray, ndarray)
        ``x_d, y_d``.
    """
    k1, k2, p1, p2, k3 = coefficients
    r2 = x * x + y * y
    g = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    return (x * g + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
            y * g + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y)


def undistort(xd: NDArray[np.float64], yd: NDArray[np.float64],
              coefficients: tuple[float, float, float, float, float]
              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Invert :func:`brown_conrady` by fixed-point iteration (as OpenCV's undistortPoints)."""
    k1, k2, p1, p2, k3 = coefficients
    x, y = xd.copy(), yd.copy()
    for _ in range(UNDISTORT_ITERATIONS):
        r2 = x * x + y * y
        g = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
        x = (xd - 2 * p1 * x * y - p2 * (r2 + 2 * x * x)) / g
        y = (yd - p1 * (r2 + 2 * y * y) - 2 * p2 * x * y) / g
    return x, y


def lens_focal_px(intrinsics: PinholeIntrinsics,
                  coefficients: tuple[float, float, float, float, float]) -> tuple[float, float]:
    """Focal lengths ``(fx, fy)`` of the distorting lens (pixels of ``intrinsics``).

    Chosen so that the middle of the image's right and bottom edges sees the same ray as
    the pinhole ``intrinsics`` (the configured field of view): ``x_d(tan(fov_h/2), 0)``
    lands on the edge.
    """
    tx = (intrinsics.width - intrinsics.cx) / intrinsics.fx
    ty = (intrinsics.height - intrinsics.cy) / intrinsics.fy
    xd, _ = brown_conrady(np.array([tx]), np.array([0.0]), coefficients)
    _, yd = brown_conrady(np.array([0.0]), np.array([ty]), coefficients)
    return (float(intrinsics.fx * tx / xd[0]), float(intrinsics.fy * ty / yd[0]))


_MAPS: dict[tuple[object, ...], NDArray[np.int64]] = {}


def distortion_map(intrinsics: PinholeIntrinsics,
                   coefficients: tuple[float, float, float, float, float]) -> NDArray[np.int64]:
    """Flat index of the render pixel each render pixel sees through the lens, shape (H, W).

    −1 where the undistorted ray falls outside the rendered field (seen as nothing).
    """
    key = (intrinsics, tuple(coefficients))
    if key in _MAPS:
        return _MAPS[key]
    fx, fy = lens_focal_px(intrinsics, coefficients)
    u = np.arange(intrinsics.width) + 0.5
    v = np.arange(intrinsics.height) + 0.5
    xd = np.broadcast_to((u - intrinsics.cx) / fx, (intrinsics.height, intrinsics.width))
    yd = np.broadcast_to(((v - intrinsics.cy) / fy)[:, None], xd.shape)
    x, y = undistort(np.array(xd), np.array(yd), coefficients)
    col = np.floor(x * intrinsics.fx + intrinsics.cx).astype(np.int64)
    row = np.floor(y * intrinsics.fy + intrinsics.cy).astype(np.int64)
    inside = ((col >= 0) & (col < intrinsics.width) & (row >= 0) & (row < intrinsics.height)
              & np.isfinite(x) & np.isfinite(y))
    index = np.where(inside, row * intrinsics.width + col, -1)
    if len(_MAPS) > 8:
        _MAPS.clear()
    _MAPS[key] = index
    return index


def distort_image(image: NDArray[G], intrinsics: PinholeIntrinsics,
                  coefficients: tuple[float, float, float, float, float],
                  fill: object = 0) -> NDArray[G]:
    """A per-render-pixel image (H, W, …) as seen through the distorting lens.

    Each pixel takes the value of the render pixel :func:`distortion_map` gives it;
    ``fill`` where the ray falls outside the rendered field.
    """
    index = distortion_map(intrinsics, coefficients)
    n = index.size
    src = np.ascontiguousarray(image).reshape(n, -1)
    pad = np.full(src.shape[1], fill, dtype=image.dtype)
    # The common widths with their own loops (a fixed inner width: ~3× faster).
    if src.shape[1] == 1:
        out = _gather_1(src.reshape(n), index.ravel(), pad)
    elif src.shape[1] == 3:
        out = _gather_3(src, index.ravel(), pad)
    else:
        out = _gather_rows(src, index.ravel(), pad)
    return cast("NDArray[G]", out.reshape(image.shape))


@kernel
def _gather_1(src: NDArray[np.generic], index: NDArray[np.int64],
              fill: NDArray[np.generic]) -> NDArray[np.generic]:
    """:func:`_gather_rows` of a single column, shape (N,)."""
    n = index.shape[0]
    out = np.empty(n, dtype=src.dtype)
    for i in range(n):
        j = index[i]
        out[i] = src[j] if j >= 0 else fill[0]
    return out


@kernel
def _gather_3(src: NDArray[np.generic], index: NDArray[np.int64],
              fill: NDArray[np.generic]) -> NDArray[np.generic]:
    """:func:`_gather_rows` of three columns, shape (N, 3)."""
    n = index.shape[0]
    out = np.empty((n, 3), dtype=src.dtype)
    for i in range(n):
        j = index[i]
        if j >= 0:
            out[i, 0], out[i, 1], out[i, 2] = src[j, 0], src[j, 1], src[j, 2]
        else:
            out[i, 0], out[i, 1], out[i, 2] = fill[0], fill[1], fill[2]
    return out


@kernel
def _gather_rows(src: NDArray[np.generic], index: NDArray[np.int64],
                 fill: NDArray[np.generic]) -> NDArray[np.generic]:
    """Row ``index[i]`` of ``src`` (N, C) for every ``i``, ``fill`` where ``index[i] < 0``."""
    n, c = index.shape[0], src.shape[1]
    out = np.empty((n, c), dtype=src.dtype)
    for i in range(n):
        j = index[i]
        if j >= 0:
            for m in range(c):
                out[i, m] = src[j, m]
        else:
            for m in range(c):
                out[i, m] = fill[m]
    return out


def distort_buffers(buffers: RenderBuffers, config: TofCameraConfig, *,
                    skip: tuple[str, ...] = ()) -> RenderBuffers:
    """The render as seen through the distorting lens (every per-pixel buffer resampled).

    ``skip``: buffers left as they are (not seen through the lens) — for a caller that never
    reads them (the camera model does not read ``cos_incidence`` or the radial velocity).
    """
    shape = buffers.range_m.shape
    background = {"object_index": -1, "object_id": -1, "range_m": np.nan}
    changes: dict[str, object] = {}
    for field in dataclasses.fields(buffers):
        value = getattr(buffers, field.name)
        if (field.name in skip or not isinstance(value, np.ndarray)
                or value.shape[:2] != shape):
            continue
        changes[field.name] = distort_image(value, buffers.intrinsics,
                                            config.distortion_coefficients,
                                            background.get(field.name, 0))
    return dataclasses.replace(buffers, **changes)  # type: ignore[arg-type]


_VIGNETTING: dict[PinholeIntrinsics, F32] = {}


def vignetting(intrinsics: PinholeIntrinsics) -> F32:
    """Natural vignetting ``cos⁴ θ`` of each pixel's off-axis angle, shape (H, W).

    Computed once per pixel grid (read-only).
    """
    if intrinsics not in _VIGNETTING:
        rays = intrinsics.ray_directions()
        cos_axis = 1.0 / np.linalg.norm(rays, axis=-1)
        falloff = (cos_axis**4).astype(np.float32)
        falloff.flags.writeable = False
        if len(_VIGNETTING) > 8:
            _VIGNETTING.clear()
        _VIGNETTING[intrinsics] = falloff
    return _VIGNETTING[intrinsics]


def wiggling_planes(m_signal: F32, phase: F32, harmonics: tuple[float, float]
                    ) -> tuple[F32, F32]:
    """Phasor of the 3rd and 5th correlation harmonics as seen by four samples (re, im).

    ``a3 m S e^{−i3φ} + a5 m S e^{i5φ}`` per sub-pixel (module docstring), to be added to
    the fundamental's phasor ``m S e^{iφ}``.
    """
    a3, a5 = (np.float32(a) for a in harmonics)
    re = m_signal * (a3 * np.cos(3 * phase) + a5 * np.cos(5 * phase))
    im = m_signal * (a5 * np.sin(5 * phase) - a3 * np.sin(3 * phase))
    return re.astype(np.float32), im.astype(np.float32)


def wiggling_error_m(depth_m: NDArray[np.float64], frequency_hz: float,
                     harmonics: tuple[float, float]) -> NDArray[np.float64]:
    """Exact depth error of the harmonic model for a pure return at ``depth_m`` (m).

    ``arg(e^{iφ} + a3 e^{−i3φ} + a5 e^{i5φ}) − φ`` converted to depth
    (``≈ (a5 − a3) sin 4φ · c/(4π f)``).
    """
    a3, a5 = harmonics
    phi = 4 * np.pi * frequency_hz * np.asarray(depth_m) / SPEED_OF_LIGHT
    z = 1 + a3 * np.exp(-4j * phi) + a5 * np.exp(4j * phi)
    return np.angle(z) * SPEED_OF_LIGHT / (4 * np.pi * frequency_hz)


def psf_kernel(shape: tuple[int, int], fraction: float, radius_px: float) -> F32:
    """The stray-light PSF on a ``(2H − 1, 2W − 1)`` grid centred on the middle pixel.

    ``(1 − s) δ + s K`` with ``K`` the long-tail kernel of the module docstring, sampled at
    pixel centres and normalised to sum 1 over the grid (so the scattered light is
    conserved within it).
    """
    h, w = shape
    y = np.arange(-(h - 1), h)[:, None]
    x = np.arange(-(w - 1), w)[None, :]
    tail = (1.0 + (x * x + y * y) / radius_px**2) ** -1.5
    tail /= tail.sum()
    kernel = fraction * tail
    kernel[h - 1, w - 1] += 1.0 - fraction
    return kernel.astype(np.float32)


_PSF_FFT: dict[tuple[object, ...], tuple[tuple[int, int], NDArray[np.complex64]]] = {}


def stray_light(planes: F32, fraction: float, radius_px: float) -> F32:
    """Convolve each plane (…, H, W) with :func:`psf_kernel` (FFT, same-size output).

    The kernel's transform is computed once per shape and parameters.
    """
    if fraction <= 0:
        return planes
    h, w = planes.shape[-2:]
    key = (h, w, float(fraction), float(radius_px))
    if key not in _PSF_FFT:
        # Circular size ≥ 2H − 1 keeps the wanted output rows free of wrap-around.
        size = (sp_fft.next_fast_len(2 * h - 1, real=True),
                sp_fft.next_fast_len(2 * w - 1, real=True))
        kernel = psf_kernel((h, w), fraction, radius_px)
        if len(_PSF_FFT) > 8:
            _PSF_FFT.clear()
        _PSF_FFT[key] = (size, sp_fft.rfft2(kernel, s=size).astype(np.complex64))
    size, kernel_ft = _PSF_FFT[key]
    # rfft2 / irfft2 one axis at a time, skipping the zero rows of the padding on the way
    # in and the rows outside the output on the way out (the same 1-D transforms).
    spectrum = sp_fft.fft(sp_fft.rfft(planes, n=size[1], axis=-1), n=size[0], axis=-2)
    spectrum *= kernel_ft
    # The kernel is centred on (h − 1, w − 1): the same-size output starts there.
    rows = sp_fft.ifft(spectrum, axis=-2, overwrite_x=True)[..., h - 1:2 * h - 1, :]
    full = sp_fft.irfft(rows, n=size[1], axis=-1)
    return np.ascontiguousarray(full[..., w - 1:2 * w - 1], dtype=np.float32)
