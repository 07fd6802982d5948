"""Independent reference for tofradar's radar multipath: Sionna RT in its own environment.

Not part of the package. Set up once (the venv is git-ignored)::

    python3 -m venv tools/references/sionna/.venv
    tools/references/sionna/.venv/bin/pip install -r tools/references/sionna/requirements.txt
    tools/references/sionna/.venv/bin/python tools/references/sionna/room_paths.py

It traces, with Sionna RT's polarimetric image-method path solver (specular reflections
only, ITU-R P.2040 concrete and metal at 60 GHz, isotropic V-polarised antennas), every
path from a radar back to itself in a 6 × 4 × 3 m concrete room (the radar 1 m above the
floor, 2.5 m from the front wall, facing it), with and without a metal wall on its left,
and writes each path's length (m), complex coefficient ``a`` (Sionna's, V → V) and
number of bounces to ``resources/references/sionna_room_paths.npz`` (shipped: the
validation report reads it too, :mod:`simcore.report.sionna`). The test
``tests/test_radar_sionna_reference.py`` reads that file: the room's own returns of
tofradar (:func:`simcore.sensors.radar.room.room_returns`) must match them.

The Rx sits 1 mm beside the Tx (a monostatic radar; Sionna's line-of-sight path is
dropped).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOM = (6.0, 4.0, 3.0)
RADAR = (3.5, 2.0, 1.0)          # 2.5 m from the front wall (x = 6), 1 m above the floor
FREQUENCY_HZ = 60e9
OUT = Path(__file__).resolve().parents[3] / "resources" / "references" / "sionna_room_paths.npz"

_XML = """<scene version="2.1.0">
  <bsdf type="itu-radio-material" id="concrete">
    <string name="type" value="concrete"/><float name="thickness" value="0.3"/>
  </bsdf>
  <bsdf type="itu-radio-material" id="metal">
    <string name="type" value="metal"/><float name="thickness" value="0.01"/>
  </bsdf>
{shapes}
</scene>
"""


def _rect(name: str, material: str, center: tuple[float, float, float],
          half: tuple[float, float], rotate: tuple[tuple[float, float, float, float], ...]
          ) -> str:
    """A mitsuba rectangle (2 × 2 in its xy plane, normal +z) scaled, rotated, moved."""
    rots = "".join(f'<rotate x="{x}" y="{y}" z="{z}" angle="{a}"/>' for x, y, z, a in rotate)
    return (f'  <shape type="rectangle" id="{name}"><transform name="to_world">'
            f'<scale x="{half[0]}" y="{half[1]}" z="1"/>{rots}'
            f'<translate x="{center[0]}" y="{center[1]}" z="{center[2]}"/></transform>'
            f'<ref id="{material}"/></shape>')


def room_xml(*, metal_left: bool) -> str:
    """The room's six faces (one-sided rectangles facing inwards), and a metal left wall."""
    lx, ly, lz = ROOM
    shapes = [
        _rect("floor", "concrete", (lx / 2, ly / 2, 0.0), (lx / 2, ly / 2), ()),
        _rect("ceiling", "concrete", (lx / 2, ly / 2, lz), (lx / 2, ly / 2), ((1, 0, 0, 180),)),
        _rect("front", "concrete", (lx, ly / 2, lz / 2), (lz / 2, ly / 2), ((0, 1, 0, -90),)),
        _rect("back", "concrete", (0.0, ly / 2, lz / 2), (lz / 2, ly / 2), ((0, 1, 0, 90),)),
        _rect("left", "metal" if metal_left else "concrete", (lx / 2, ly, lz / 2),
              (lx / 2, lz / 2), ((1, 0, 0, 90),)),
        _rect("right", "concrete", (lx / 2, 0.0, lz / 2), (lx / 2, lz / 2), ((1, 0, 0, -90),)),
    ]
    return _XML.format(shapes="\n".join(shapes))


def trace(*, metal_left: bool, max_depth: int = 3) -> dict[str, np.ndarray]:
    """Sionna's paths radar → room → radar: length (m), coefficient a, bounces."""
    import tempfile

    import sionna.rt as rt

    with tempfile.TemporaryDirectory() as tmp:
        xml = Path(tmp) / "room.xml"
        xml.write_text(room_xml(metal_left=metal_left))
        scene = rt.load_scene(str(xml), merge_shapes=False)
    scene.frequency = FREQUENCY_HZ
    scene.tx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization="V")
    scene.rx_array = rt.PlanarArray(num_rows=1, num_cols=1, pattern="iso", polarization="V")
    scene.add(rt.Transmitter("tx", position=list(RADAR)))
    scene.add(rt.Receiver("rx", position=[RADAR[0], RADAR[1] + 1e-3, RADAR[2]]))
    paths = rt.PathSolver()(scene, max_depth=max_depth, los=False, specular_reflection=True,
                            diffuse_reflection=False, refraction=False, synthetic_array=True,
                            samples_per_src=10**6)
    a_re, a_im = paths.a
    a = (np.asarray(a_re) + 1j * np.asarray(a_im)).reshape(-1)
    tau = np.asarray(paths.tau).reshape(-1)
    inter = np.asarray(paths.interactions)
    depth = np.count_nonzero(inter.reshape(inter.shape[0], -1) if inter.ndim == 1
                             else inter.reshape(inter.shape[0], -1, tau.size) != 0, axis=0)
    keep = tau > 0
    return {"length_m": 299_792_458.0 * tau[keep], "a": a[keep],
            "bounces": np.asarray(depth).reshape(-1)[keep]}


def main() -> int:
    """Trace both rooms and write the cached arrays."""
    out: dict[str, np.ndarray] = {}
    for metal in (False, True):
        res = trace(metal_left=metal)
        key = "metal_left" if metal else "concrete"
        for k, v in res.items():
            out[f"{key}_{k}"] = v
        order = np.argsort(res["length_m"])
        print(key, len(order), "paths")
        for i in order[:40]:
            print(f"  L = {res['length_m'][i]:.4f} m  bounces {res['bounces'][i]}  "
                  f"|a| = {20 * np.log10(abs(res['a'][i])):.1f} dB")
    out["radar_m"] = np.array(RADAR)
    out["room_m"] = np.array(ROOM)
    out["frequency_hz"] = np.array(FREQUENCY_HZ)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(OUT, **out)
    print("wrote", OUT)
    return 0


if __name__ == "__main__":
    sys.exit(main())
