"""RGB camera model: colour images of the visible band, from the same snapshot.

Per pixel the camera sees the surface's visible-band response ``f(θ)``
(:func:`simcore.scene.materials.band_response`, evaluated by the renderer) tinted by the
material's ``color_rgb``, lit by ambient light and by a lamp at the camera::

    L = color_rgb · (ambient · reflectance + lamp · f(θ) · g(R))

with ``g(R) = 1/R²`` (R in m) when the lamp falls off, else 1. ``L`` is linear RGB
relative to the camera's full exposure; it is clipped to [0, 1] and encoded as 8-bit sRGB.
Pixels where no surface is seen get the configured background colour. The model is a
convenience for fusion datasets (colour beside depth and radar), not a radiometric camera:
no noise, blur, exposure control or lens effects.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.materials import DualBandMaterial
from simcore.scene.model import SceneObject
from simcore.scene.rgb_config import RgbCameraConfig

BAND = "visible"


@dataclass(frozen=True)
class RgbOutput:
    """One colour image.

    Attributes
    ----------
    image : ndarray, shape (H, W, 3), uint8
        8-bit sRGB image, row 0 at the top.
    gt_object_id : ndarray, shape (H, W), int32
        Project id of the object seen in each pixel, −1 where none.
    gt_body_part : ndarray, shape (H, W), int32, or None
        Body part (segment index of :data:`simcore.scene.people.SEGMENTS`) where a person
        is seen, −1 elsewhere; None in scenes without people.
    """

    image: NDArray[np.uint8]
    gt_object_id: NDArray[np.int32]
    gt_body_part: NDArray[np.int32] | None = None

    def hdf5_items(self) -> dict[str, tuple[NDArray[np.generic], str]]:
        """Per-frame datasets: ``/rgb/image`` (H, W, 3) uint8, ``/rgb/gt_object_id``."""
        items: dict[str, tuple[NDArray[np.generic], str]] = {
            "/rgb/image": (self.image, "sRGB"),
            "/rgb/gt_object_id": (self.gt_object_id, "1"),
        }
        if self.gt_body_part is not None:
            items["/rgb/gt_body_part"] = (self.gt_body_part, "1")
        return items


def srgb_encode(linear: NDArray[np.floating]) -> NDArray[np.uint8]:
    """Linear RGB in [0, 1] → 8-bit sRGB (IEC 61966-2-1 transfer function).

    Examples
    --------
    >>> srgb_encode(np.array([0.0, 0.002, 0.5, 1.0])).tolist()  # 255·12.92·0.002 = 6.6
    [0, 7, 188, 255]
    """
    x = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    encoded = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    return np.asarray(np.rint(encoded * 255.0), dtype=np.uint8)


def object_colors(objects: Sequence[SceneObject], materials: Mapping[str, DualBandMaterial]
                  ) -> NDArray[np.float64]:
    """Linear RGB albedo and visible reflectance per object, shape (objects + 1, 4).

    Row ``i`` is object ``objects[i]``'s ``(r, g, b, reflectance)`` from its material in
    ``materials``; the extra last row (index −1) is zeros, for pixels with no object.

    Examples
    --------
    >>> from simcore.scene import Box, Project, SceneObject
    >>> from simcore.scene.project_io import material_table
    >>> project = Project(objects=[SceneObject(id=1, name="wall", geometry=Box(),
    ...                                        material="white_paint")])
    >>> object_colors(project.objects, material_table(project)).tolist()
    [[0.9, 0.9, 0.88, 1.0], [0.0, 0.0, 0.0, 0.0]]
    """
    rows = []
    for obj in objects:
        mat = materials[obj.material]
        rows.append((*mat.color_rgb, mat.band(BAND).reflectance))
    rows.append((0.0, 0.0, 0.0, 0.0))
    return np.asarray(rows, dtype=np.float64)


def simulate_rgb(buffers: RenderBuffers, config: RgbCameraConfig, colors: NDArray[np.float64]
                 ) -> RgbOutput:
    """Colour image of a visible-band render.

    Parameters
    ----------
    buffers : RenderBuffers
        Visible-band render on ``config.render_intrinsics()``, shape (H, W); uses
        ``object_index``, ``intensity`` (f(θ)) and ``range_m`` (m).
    config : RgbCameraConfig
        Camera parameters (ambient light, lamp, background colour).
    colors : ndarray, shape (objects + 1, 4)
        From :func:`object_colors`.

    Returns
    -------
    RgbOutput
    """
    expected = (config.height, config.width)
    if buffers.shape != expected:
        raise ValueError(f"RGB render is {buffers.shape[1]}×{buffers.shape[0]} px; the camera "
                         f"needs {expected[1]}×{expected[0]}")
    table = colors[buffers.object_index]
    lamp = config.lamp * buffers.intensity.astype(np.float64)
    if config.lamp_falloff:
        with np.errstate(divide="ignore", invalid="ignore"):
            lamp = np.where(buffers.valid, lamp / np.square(buffers.range_m, dtype=np.float64),
                            0.0)
    light = config.ambient * table[..., 3] + lamp
    linear = table[..., :3] * light[..., None]
    linear[~buffers.valid] = config.background_rgb
    return RgbOutput(image=srgb_encode(linear),
                     gt_object_id=np.ascontiguousarray(buffers.object_id, dtype=np.int32))
