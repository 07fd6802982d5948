"""Per-pixel geometry buffers produced by one band's render pass."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.jit import kernel
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
    gt_range = np.empty((hs, ws), dtype=np.float32)
    gt_id = np.empty((hs, ws), dtype=np.int32)
    _downsample(np.ascontiguousarray(buffers.object_id, dtype=np.int32),
                np.ascontiguousarray(buffers.range_m, dtype=np.float32), factor, gt_range,
                gt_id)
    return gt_range, gt_id


def downsample_labels(buffers: RenderBuffers, per_object: NDArray[np.integer], factor: int
                      ) -> NDArray[np.int32]:
    """A per-object label (e.g. body-part id) at sensor resolution, voted as object ids are.

    Parameters
    ----------
    buffers : RenderBuffers
        The supersampled pass.
    per_object : ndarray, shape (objects,), int
        Label of each object (by ``object_index``); background is −1.
    factor : int
        Supersampling factor.

    Returns
    -------
    ndarray, shape (H // factor, W // factor), int32
    """
    table = np.append(np.asarray(per_object, dtype=np.int32), np.int32(-1))
    labels = np.ascontiguousarray(table[buffers.object_index], dtype=np.int32)
    h, w = buffers.shape
    out_range = np.empty((h // factor, w // factor), dtype=np.float32)
    out = np.empty((h // factor, w // factor), dtype=np.int32)
    _downsample(labels, np.ascontiguousarray(buffers.range_m, dtype=np.float32), factor,
                out_range, out)
    return out


@kernel
def _downsample(ids: NDArray[np.int32], rng: NDArray[np.float32], factor: int,
                out_range: NDArray[np.float32], out_id: NDArray[np.int32]) -> None:
    """:func:`downsample_ground_truth` per sensor pixel.

    The vote of a mixed pixel: the sub-pixel whose id is the most frequent, ties to the
    nearer surface (background, NaN range, as 1e5 m) and then to the first in row-major
    order; its range is the mean of the finite ranges of that id's sub-pixels over their
    count. Sums in float64.
    """
    n = factor * factor
    sub_id = np.empty(n, dtype=np.int32)
    sub_rng = np.empty(n, dtype=np.float32)
    for r in range(out_id.shape[0]):
        for c in range(out_id.shape[1]):
            k = 0
            for i in range(factor):
                for j in range(factor):
                    sub_id[k] = ids[r * factor + i, c * factor + j]
                    sub_rng[k] = rng[r * factor + i, c * factor + j]
                    k += 1
            best = sub_id[0]
            uniform = True
            for k in range(1, n):
                if sub_id[k] != best:
                    uniform = False
                    break
            if not uniform:
                best_key = -np.inf
                for k in range(n):
                    count = 0
                    for m in range(n):
                        if sub_id[m] == sub_id[k]:
                            count += 1
                    dist = 1e5 if np.isnan(sub_rng[k]) else float(sub_rng[k])
                    key = count * 1e6 - dist
                    if key > best_key:
                        best_key = key
                        best = sub_id[k]
            total = 0.0
            count = 0
            for k in range(n):
                if sub_id[k] == best:
                    count += 1
                    if not np.isnan(sub_rng[k]):
                        total += sub_rng[k]
            out_id[r, c] = best
            out_range[r, c] = total / count if best >= 0 else np.nan
