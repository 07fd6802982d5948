"""Per-pixel geometry buffers produced by one band's render pass."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.render.meshes import TriangleMesh
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.snapshot import SensorState


@dataclass(frozen=True)
class RenderBuffers:
    """Float geometry buffers of one band seen from one sensor at one instant.

    All images have shape (H, W) with row 0 at the top of the image; vectors are in the
    sensor's optical frame (x right, y down, z forward). Background pixels have
    ``range_m = NaN``, ``object_index = object_id = -1`` and zeros elsewhere.

    Attributes
    ----------
    band : str
        Material band of the pass (:data:`simcore.scene.materials.BANDS`).
    time_s : float
        Snapshot timestamp (s).
    intrinsics : PinholeIntrinsics
        Pixel grid of the pass.
    sensor : SensorState
        World pose and velocity of the sensor.
    range_m : ndarray, shape (H, W), float32
        Distance from the sensor origin to the surface along the pixel-centre ray (m).
    points_m : ndarray, shape (H, W, 3), float32
        Surface points in the optical frame (m).
    normals : ndarray, shape (H, W, 3), float32
        Unit surface normals facing the sensor, optical frame.
    cos_incidence : ndarray, shape (H, W), float32
        Cosine of the angle between the normal and the direction back to the sensor.
    object_index : ndarray, shape (H, W), int32
        Index of the object in ``project.objects``.
    object_id : ndarray, shape (H, W), int32
        The object's project ``id``.
    intensity : ndarray, shape (H, W), float32
        Band response of the material model (:func:`simcore.scene.materials.band_response`).
    velocity_mps : ndarray, shape (H, W, 3), float32
        Velocity of the surface point relative to the sensor origin, optical frame (m/s).
    radial_velocity_mps : ndarray, shape (H, W), float32
        Range rate d|X - p_sensor|/dt (m/s), positive when moving away.
    meshes : tuple of TriangleMesh or None
        Each object's triangles in its own frame (None: no surface), as rendered; empty
        when unknown.
    """

    band: str
    time_s: float
    intrinsics: PinholeIntrinsics
    sensor: SensorState
    range_m: NDArray[np.float32]
    points_m: NDArray[np.float32]
    normals: NDArray[np.float32]
    cos_incidence: NDArray[np.float32]
    object_index: NDArray[np.int32]
    object_id: NDArray[np.int32]
    intensity: NDArray[np.float32]
    velocity_mps: NDArray[np.float32]
    radial_velocity_mps: NDArray[np.float32]
    meshes: tuple[TriangleMesh | None, ...] = ()

    @property
    def valid(self) -> NDArray[np.bool_]:
        """Pixels that hit a surface, shape (H, W)."""
        return self.object_index >= 0

    @property
    def shape(self) -> tuple[int, int]:
        """Image shape (H, W)."""
        return (self.intrinsics.height, self.intrinsics.width)


def downsample_ground_truth(
    buffers: RenderBuffers, factor: int
) -> tuple[NDArray[np.float32], NDArray[np.int32]]:
    """Ground-truth range and object id at sensor resolution from a supersampled pass.

    Each sensor pixel covers ``factor × factor`` sub-pixels. Its object id is the most
    frequent sub-pixel id (background counts as an id, ties go to the nearer surface) and
    its range is the mean range of the sub-pixels that show that object (NaN if background).

    Returns
    -------
    gt_range : ndarray, shape (H // factor, W // factor), float32
    gt_object_id : ndarray, shape (H // factor, W // factor), int32
    """
    h, w = buffers.shape
    hs, ws = h // factor, w // factor
    ids = (buffers.object_id[: hs * factor, : ws * factor].reshape(hs, factor, ws, factor)
           .transpose(0, 2, 1, 3).reshape(hs, ws, -1))
    rng = (buffers.range_m[: hs * factor, : ws * factor].reshape(hs, factor, ws, factor)
           .transpose(0, 2, 1, 3).reshape(hs, ws, -1))
    # Most pixels see one object (or none) in all their sub-pixels: those need no vote.
    gt_id = ids[..., 0].copy()
    uniform = np.all(ids == gt_id[..., None], axis=-1)
    with np.errstate(invalid="ignore"):
        gt_range = np.nansum(rng, axis=-1) / np.float64(ids.shape[-1])
    mixed = np.flatnonzero(~uniform)
    if mixed.size:
        m_ids = ids.reshape(-1, ids.shape[-1])[mixed]
        m_rng = rng.reshape(-1, rng.shape[-1])[mixed]
        counts = (m_ids[..., :, None] == m_ids[..., None, :]).sum(axis=-1)
        # Prefer the most frequent id; among equals the nearest surface (background = +inf).
        key = counts * 1e6 - np.nan_to_num(m_rng, nan=1e5)
        best = np.argmax(key, axis=-1)
        m_id = np.take_along_axis(m_ids, best[..., None], axis=-1)[..., 0]
        same = m_ids == m_id[..., None]
        with np.errstate(invalid="ignore"):
            m_range = np.nansum(np.where(same, m_rng, 0.0), axis=-1) / same.sum(axis=-1)
        gt_id.reshape(-1)[mixed] = m_id
        gt_range.reshape(-1)[mixed] = m_range
    gt_range = np.where(gt_id >= 0, gt_range, np.nan).astype(np.float32)
    return gt_range, gt_id.astype(np.int32)
