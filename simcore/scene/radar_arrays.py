"""Antenna array layouts on the radar board: ULA, URA, L-shape, circular, custom.

Every helper returns a list of :class:`~simcore.scene.radar_config.Antenna` with
positions in millimetres on the board (x right, y down, as seen from behind the board
looking along the boresight). ``origin_mm`` shifts the whole layout.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from simcore.scene.radar_config import Antenna


def custom_array(positions_mm: Sequence[tuple[float, float]], *, prefix: str = "rx"
                 ) -> list[Antenna]:
    """Antennas at arbitrary board positions, named ``{prefix}1``, ``{prefix}2``, and so on.

    Parameters
    ----------
    positions_mm : sequence of (x, y)
        Board positions (mm).
    prefix : str
        Name prefix.

    Examples
    --------
    >>> [(a.name, a.position_mm) for a in custom_array([(0, 0), (2.5, -1)], prefix="tx")]
    [('tx1', (0.0, 0.0)), ('tx2', (2.5, -1.0))]
    """
    return [Antenna(name=f"{prefix}{i + 1}", position_mm=(float(x), float(y)))
            for i, (x, y) in enumerate(positions_mm)]


def ula(n: int, spacing_mm: float, *, axis: str = "x", origin_mm: tuple[float, float] = (0, 0),
        prefix: str = "rx") -> list[Antenna]:
    """Uniform linear array of ``n`` elements along board ``axis`` ("x" or "y").

    Element ``i`` sits at ``origin + i * spacing`` along the axis (use a negative spacing to
    grow towards −x or upwards, −y).

    Examples
    --------
    >>> [a.position_mm for a in ula(3, 2.5)]
    [(0.0, 0.0), (2.5, 0.0), (5.0, 0.0)]
    >>> [a.position_mm for a in ula(2, -2.5, axis="y", origin_mm=(1, 0))]
    [(1.0, 0.0), (1.0, -2.5)]
    """
    if n < 1:
        raise ValueError(f"ula: n must be at least 1, got {n}")
    if axis not in ("x", "y"):
        raise ValueError(f"ula: axis must be 'x' or 'y', got {axis!r}")
    steps = np.arange(n) * spacing_mm
    pts = [(origin_mm[0] + s, origin_mm[1]) if axis == "x" else (origin_mm[0], origin_mm[1] + s)
           for s in steps]
    return custom_array(pts, prefix=prefix)


def ura(nx: int, ny: int, spacing_x_mm: float, spacing_y_mm: float | None = None, *,
        origin_mm: tuple[float, float] = (0, 0), prefix: str = "rx") -> list[Antenna]:
    """Uniform rectangular array, ``nx`` columns × ``ny`` rows, row by row (x fastest).

    Examples
    --------
    >>> [a.position_mm for a in ura(2, 2, 2.5)]
    [(0.0, 0.0), (2.5, 0.0), (0.0, 2.5), (2.5, 2.5)]
    """
    if nx < 1 or ny < 1:
        raise ValueError(f"ura: nx and ny must be at least 1, got {nx}, {ny}")
    sy = spacing_x_mm if spacing_y_mm is None else spacing_y_mm
    pts = [(origin_mm[0] + i * spacing_x_mm, origin_mm[1] + j * sy)
           for j in range(ny) for i in range(nx)]
    return custom_array(pts, prefix=prefix)


def l_shape(n_horizontal: int, n_vertical: int, spacing_mm: float, *,
            origin_mm: tuple[float, float] = (0, 0), prefix: str = "rx") -> list[Antenna]:
    """L-shaped array sharing its corner element: a horizontal arm and a vertical arm.

    The horizontal arm runs from the corner towards +x, the vertical arm upwards (−y). With
    ``n_horizontal = n_vertical = 2`` and λ/2 spacing this is the BGT60TR13C's 3-Rx L:
    ``[(d, 0), (0, 0), (0, -d)]`` (the corner is the second element).

    Examples
    --------
    >>> [a.position_mm for a in l_shape(2, 2, 2.5)]
    [(2.5, 0.0), (0.0, 0.0), (0.0, -2.5)]
    """
    if n_horizontal < 1 or n_vertical < 1:
        raise ValueError("l_shape: both arms need at least one element (the shared corner)")
    ox, oy = origin_mm
    horizontal = [(ox + i * spacing_mm, oy) for i in range(n_horizontal - 1, 0, -1)]
    vertical = [(ox, oy - j * spacing_mm) for j in range(1, n_vertical)]
    return custom_array([*horizontal, (ox, oy), *vertical], prefix=prefix)


def circular(n: int, radius_mm: float, *, start_deg: float = 0.0,
             origin_mm: tuple[float, float] = (0, 0), prefix: str = "rx") -> list[Antenna]:
    """Uniform circular array of ``n`` elements; element 0 at ``start_deg`` from board +x.

    Examples
    --------
    >>> [tuple(round(v, 6) + 0.0 for v in a.position_mm) for a in circular(4, 2.0)]
    [(2.0, 0.0), (0.0, 2.0), (-2.0, 0.0), (0.0, -2.0)]
    """
    if n < 1:
        raise ValueError(f"circular: n must be at least 1, got {n}")
    if radius_mm <= 0:
        raise ValueError(f"circular: radius_mm must be positive, got {radius_mm}")
    ang = np.deg2rad(start_deg) + 2 * np.pi * np.arange(n) / n
    pts = [(origin_mm[0] + radius_mm * np.cos(a), origin_mm[1] + radius_mm * np.sin(a))
           for a in ang]
    return custom_array(pts, prefix=prefix)
