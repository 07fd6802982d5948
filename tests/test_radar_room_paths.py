"""The room's multiple-bounce returns against formulas: dihedral, trihedral, two surfaces.

* A 90° dihedral of two metal plates a × b seen along its bisector in the far field has
  the geometric-optics RCS ``σ = 8π a² b² / λ²``, and a square trihedral seen along its
  symmetry axis ``σ = 12π a⁴ / λ²`` (Knott, Shaeffer & Tuley, *Radar Cross Section*, 2nd
  ed., Table 5.2 / §5.4); both at the range of their edge (apex).
* Near a large corner (room scale), the double bounce is the radar's double image: at
  the distance ``D`` of the edge, ``√σ = |Γ_A Γ_B| √π D`` per order (an infinite plane's
  return, image theory of a 90° wedge): one image, the two orders of its faces together
  (each carries half; counting each order as a whole image doubled the edge, +6 dB, and
  a corner's six orders made it 15.6 dB too strong, against Sionna RT in
  tests/test_radar_sionna_targets.py).
* A target ghost over two different surfaces (Tx → wall → target → floor → Rx) has the
  length ``|p − Tx_wall| + |p − Rx_floor|`` and the amplitude Γ_wall Γ_floor.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.materials import BandMaterial
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.radar.multipath import (
    ImagePaths,
    Reflector,
    two_surface_ghosts,
)
from simcore.sensors.radar.room import room_returns
from simcore.sensors.radar.scatterers import Scatterers

METAL = BandMaterial(reflectance=0.0, specular=0.0, metallic=1.0)
CONFIG = RadarConfig(multipath_order=2)
LAM = CONFIG.wavelength_m
FREQ = 299_792_458.0 / LAM


def plate(obj: int, corner: np.ndarray, u: np.ndarray, v: np.ndarray, normal: np.ndarray,
          band: BandMaterial = METAL) -> Reflector:
    """A one-sided rectangle with edges ``u``, ``v`` from ``corner`` (radar frame)."""
    a, b = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    return Reflector(object_index=obj, center_m=corner + 0.5 * (u + v),
                     axes=np.array([u / a, v / b]), half_size_m=0.5 * np.array([a, b]),
                     normal=normal / np.linalg.norm(normal), two_sided=False,
                     gamma=complex(band.coefficients(FREQ)[0]), height_rms_m=0.0,
                     normal_speed_mps=0.0, band=band, frequency_hz=FREQ)


def total_return(reflectors: list[Reflector], *, order: int = 2,
                 polarization: str = "V") -> tuple[complex, list[float]]:
    """Coherent sum of the room paths' √σ (all at one range here) and their ranges."""
    cfg = CONFIG.model_copy(update={"polarization": polarization})
    sets = room_returns(None, cfg, reflectors, buffers=None, order=order,  # type: ignore[arg-type]
                        time_s=0.0)
    amp = sum((np.sqrt(g.scatterers.rcs_m2[0]) * np.exp(1j * g.scatterers.phase_rad[0])
               for g in sets), 0j)
    return complex(amp), [float(np.linalg.norm(g.scatterers.positions_m[0])) for g in sets]


def dihedral(edge_at: float, a: float, b: float) -> list[Reflector]:
    """90° dihedral, edge along radar y at range ``edge_at``, opening towards the radar."""
    edge = np.array([0.0, -0.5 * b, edge_at])
    da = np.array([1.0, 0.0, -1.0]) / np.sqrt(2)
    db = np.array([-1.0, 0.0, -1.0]) / np.sqrt(2)
    y = np.array([0.0, b, 0.0])
    return [plate(0, edge, a * da, y, db), plate(1, edge, a * db, y, da)]


@pytest.mark.parametrize("polarization", ["V", "H"])
def test_far_field_dihedral_is_8pi_a2b2_over_lambda2(polarization: str) -> None:
    a, b, r = 0.1, 0.15, 12.0
    amp, ranges = total_return(dihedral(r, a, b), polarization=polarization)
    expected = 8 * np.pi * a**2 * b**2 / LAM**2
    assert len(ranges) == 2 and np.allclose(ranges, r, atol=1e-9)
    assert 10 * np.log10(abs(amp) ** 2 / expected) == pytest.approx(0.0, abs=0.05)


def trihedral(apex_at: float, a: float) -> list[Reflector]:
    """Square trihedral, its symmetry axis on boresight, apex at range ``apex_at``."""
    axis = np.ones(3) / np.sqrt(3)                    # local symmetry axis
    target = np.array([0.0, 0.0, -1.0])               # towards the radar
    v = np.cross(axis, target)
    c = float(axis @ target)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rot = np.eye(3) + vx + vx @ vx / (1 + c)          # axis → target (Rodrigues)
    apex = np.array([0.0, 0.0, apex_at])
    e = rot @ (a * np.eye(3))                         # the three edges
    return [plate(i, apex, e[:, (i + 1) % 3], e[:, (i + 2) % 3], e[:, i]) for i in range(3)]


def test_far_field_square_trihedral_is_12pi_a4_over_lambda2() -> None:
    a, r = 0.1, 20.0
    amp, ranges = total_return(trihedral(r, a))
    expected = 12 * np.pi * a**4 / LAM**2
    assert len(ranges) == 6 and np.allclose(ranges, r, atol=1e-9)
    assert 10 * np.log10(abs(amp) ** 2 / expected) == pytest.approx(0.0, abs=0.1)


def test_a_room_edge_is_the_double_image_of_the_radar() -> None:
    """Concrete floor and wall, radar 1 m above the floor and 3 m from the wall (V pol)."""
    concrete = BandMaterial(permittivity=5.24, loss_tangent=0.065)
    # Radar frame: y down, so the floor is at y = +1; the wall at z = 3.
    floor = plate(0, np.array([-3.0, 1.0, -1.0]), np.array([6.0, 0, 0]),
                  np.array([0, 0, 4.0]), np.array([0, -1.0, 0]), concrete)
    wall = plate(1, np.array([-3.0, 1.0, 3.0]), np.array([6.0, 0, 0]),
                 np.array([0, -3.0, 0]), np.array([0, 0, -1.0]), concrete)
    amp, ranges = total_return([floor, wall], order=1)
    d = np.hypot(1.0, 3.0)
    assert len(ranges) == 2 and np.allclose(ranges, d, atol=1e-9)
    # V lies in the plane across the edge, the plane of incidence on both faces: TM on the
    # floor and on the wall at the path's angles (image theory of the wedge), times an
    # infinite plane's √π D, once: both orders are the one double image.
    cos_floor = 1.0 / d                     # leg to the edge point: angle from the floor normal
    cos_wall = 3.0 / d
    _, tm_w = concrete.oblique_coefficients(FREQ, np.array([cos_wall]))
    _, tm_f = concrete.oblique_coefficients(FREQ, np.array([cos_floor]))
    expected = abs(tm_f[0] * tm_w[0]) * np.sqrt(np.pi) * d
    # H (along the edge) is TE on both.
    te_w, _ = concrete.oblique_coefficients(FREQ, np.array([cos_wall]))
    te_f, _ = concrete.oblique_coefficients(FREQ, np.array([cos_floor]))
    amp_h, _ = total_return([floor, wall], order=1, polarization="H")
    assert 20 * np.log10(abs(amp_h) / (abs(te_f[0] * te_w[0]) * np.sqrt(np.pi) * d)) \
        == pytest.approx(0.0, abs=0.1)
    assert 20 * np.log10(abs(amp) / expected) == pytest.approx(0.0, abs=0.1)


def test_a_ghost_over_two_surfaces_has_the_image_methods_length_and_level() -> None:
    """Tx → side wall → target → floor → Rx: mirrored Tx in the wall, Rx in the floor."""
    p = np.array([[0.2, 0.0, 3.0]])
    sc = Scatterers.from_arrays(p, np.array([1.0]))
    wall = plate(0, np.array([-1.0, 2.0, -1.0]), np.array([0, -4.0, 0]),
                 np.array([0, 0, 8.0]), np.array([1.0, 0, 0]))
    floor = plate(1, np.array([-3.0, 1.0, -1.0]), np.array([6.0, 0, 0]),
                  np.array([0, 0, 8.0]), np.array([0, -1.0, 0]))
    ga, gb = np.array([-0.5 + 0.1j]), np.array([0.3 - 0.2j])
    paths = [ImagePaths(wall, np.array([0]), wall.mirror(p), ga, np.zeros((1, 3))),
             ImagePaths(floor, np.array([0]), floor.mirror(p), gb, np.zeros((1, 3)))]
    tx, rx = CONFIG.tx_positions_m(), CONFIG.rx_positions_m()
    sets = two_surface_ghosts(sc, paths, tx, rx)
    assert len(sets) == 2                                  # wall → floor and floor → wall
    first = sets[0]
    assert first.tx_positions_m is not None and first.rx_positions_m is not None
    length = (np.linalg.norm(p[0] - first.tx_positions_m[0])
              + np.linalg.norm(p[0] - first.rx_positions_m[0]))
    tx_image = np.array([-2.0, 0.0, 0.0]) + tx[0] * [-1, 1, 1]     # Tx mirrored in x = −1
    rx_image = np.array([0.0, 2.0, 0.0]) + rx[0] * [1, -1, 1]      # Rx mirrored in y = +1
    assert length == pytest.approx(np.linalg.norm(p[0] - tx_image)
                                   + np.linalg.norm(p[0] - rx_image), abs=1e-12)
    assert first.scatterers.rcs_m2[0] == pytest.approx(abs(ga[0] * gb[0]) ** 2)
    assert first.scatterers.phase_rad[0] == pytest.approx(np.angle(ga[0] * gb[0]))


def test_a_ghost_over_two_faces_on_one_leg_is_the_double_image_of_the_tx() -> None:
    """Tx → side wall → front wall → target → Rx (metal, V across the faces: TE twice):
    length ``|p − Tx_AB| + |p − Rx|`` with the Tx mirrored in the side wall and then in the
    front wall, amplitude |Γ|² = 1; the reverse (Rx mirrored) the same."""
    from simcore.scene.radar_config import CosinePattern
    from simcore.sensors.radar.legs import one_leg_double_ghosts

    p = np.array([[0.5, 0.0, 2.0]])
    sc = Scatterers.from_arrays(p, np.array([1.0]))
    # Side wall at x = −1 (normal +x), front wall at z = 4 (normal −z), both 8 m × 8 m.
    side = plate(0, np.array([-1.0, -4.0, -4.0]), np.array([0, 8.0, 0]),
                 np.array([0, 0, 8.0]), np.array([1.0, 0, 0]))
    front = plate(1, np.array([-1.0, -4.0, 4.0]), np.array([8.0, 0, 0]),
                  np.array([0, 8.0, 0]), np.array([0, 0, -1.0]))
    tx, rx = CONFIG.tx_positions_m(), CONFIG.rx_positions_m()
    iso = CosinePattern(exponent_az=0.0, exponent_el=0.0)
    sets = one_leg_double_ghosts(sc, [side, front], polarization="V", wavelength_m=LAM,
                                 tx_positions_m=tx, rx_positions_m=rx, patterns=(iso, iso),
                                 buffers=None)
    # One order of the two perpendicular faces has a path (both have the same image; the
    # line from the target to it crosses one of them first), with the Tx and the Rx mirrored.
    assert len(sets) == 2
    tx_ab = tx[0] * [-1, 1, -1] + np.array([-2.0, 0.0, 8.0])   # x → −2 − x, z → 8 − z
    lengths = sorted(np.linalg.norm(p[0] - g.tx_positions_m[0]) + np.linalg.norm(p[0] - rx[0])
                     for g in sets if g.tx_positions_m is not None)
    assert lengths == pytest.approx([np.linalg.norm(p[0] - tx_ab)
                                     + np.linalg.norm(p[0] - rx[0])], abs=1e-12)
    for g in sets:
        assert g.scatterers.rcs_m2[0] == pytest.approx(1.0, abs=1e-6)


def test_no_ghost_where_no_geometric_path_exists() -> None:
    """A concrete front wall 3 m ahead and a metal side wall 1 m to the left (the issue's
    case): before, the front wall's facets mirrored in the metal wall made ghosts at
    5.42 m and 5.83 m. Every multipath return must now be a geometric path: the front
    wall–side wall edge (the double image at the edge's distance √10 m, both orders) and
    the rig front's image in the front wall (at twice its distance, 6 m; in the side wall
    it is edge-on)."""
    from simcore.render import RenderRequest, SceneRenderer
    from simcore.scene import Box, Pose, Project, SceneObject
    from simcore.scene.model import SensorRig
    from simcore.scene.snapshot import take_snapshot
    from simcore.sensors.radar import radar_scatterers
    from simcore.sensors.radar.multipath import ghost_scatterers
    from simcore.sensors.radar.scene import RadarScene

    cfg = RadarConfig(multipath_order=2, speckle=False)
    front = SceneObject(id=1, name="front", geometry=Box(size_m=(0.2, 6.0, 3.0)),
                        material="concrete", pose=Pose(position_m=(3.1, 0.0, 1.0)))
    side = SceneObject(id=2, name="side", geometry=Box(size_m=(8.0, 0.2, 3.0)),
                       material="aluminium", pose=Pose(position_m=(1.0, 1.1, 1.0)))
    project = Project(objects=[front, side],
                      rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0)), radar=cfg))
    snap = take_snapshot(project, 0.0)
    renderer = SceneRenderer(project)
    try:
        buf = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics(),
                                                  geometry_only=True))
    finally:
        renderer.close()
    scene = RadarScene.from_project(project, snap)
    sc = radar_scatterers(scene, buf, config=cfg)
    sets = ghost_scatterers(scene, sc, cfg, buffers=buf)
    ranges = []
    for g in sets:
        pos = g.scatterers.positions_m
        if g.tx_positions_m is None and g.rx_positions_m is None:
            ranges += list(np.linalg.norm(pos, axis=1))
        else:                                     # half the unfolded bistatic path
            tx = cfg.tx_positions_m() if g.tx_positions_m is None else g.tx_positions_m
            rx = cfg.rx_positions_m() if g.rx_positions_m is None else g.rx_positions_m
            ranges += list(0.5 * (np.linalg.norm(pos - tx[0], axis=1)
                                  + np.linalg.norm(pos - rx[0], axis=1)))
    assert ranges, "the edge and the rig-front images are there"
    geometric = np.array([np.sqrt(10.0), 6.0])
    off = [r for r in ranges if np.min(np.abs(geometric - r)) > 0.01]
    assert off == [], f"multipath returns without a geometric path at {off} m"
    assert np.sum(np.abs(np.array(ranges) - np.sqrt(10.0)) < 0.01) == 2


def test_a_spheres_ghost_scatters_from_its_bistatic_specular_point() -> None:
    """Lit from one point and seen from another, a sphere reflects where its normal bisects
    the two directions (law of reflection), ``a |û₁ + û₂|`` closer than its centre (GO)."""
    from simcore.scene import Pose, Project, SceneObject, Sphere
    from simcore.scene.model import SensorRig
    from simcore.scene.snapshot import take_snapshot
    from simcore.sensors.radar.legs import sphere_placement
    from simcore.sensors.radar.scatterers import KIND_POINT_TARGET
    from simcore.sensors.radar.scene import RadarScene

    a = 0.2
    project = Project(objects=[SceneObject(id=1, name="ball", geometry=Sphere(radius_m=a),
                                           pose=Pose(position_m=(3.0, 0.5, 1.3)),
                                           material="aluminium")],
                      rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0))))
    scene = RadarScene.from_project(project, take_snapshot(project, 0.0))
    centre = np.array([-0.5, -0.3, 3.0])                    # radar frame: right, down, ahead
    sc = Scatterers(time_s=0.0, wavelength_m=LAM, positions_m=centre[None] + [[0, 0, -a]],
                    velocities_mps=np.zeros((1, 3)), rcs_m2=np.array([np.pi * a * a]),
                    phase_rad=np.zeros(1), object_index=np.zeros(1, np.int32),
                    kind=np.array([KIND_POINT_TARGET], np.int8))
    src, rcv = np.array([[0.0, 2.0, 0.0]]), np.zeros((1, 3))  # the radar's floor image, radar
    s = sphere_placement(scene, sc)(np.array([0]), sc.positions_m, src, rcv)[0]
    assert np.linalg.norm(s - centre) == pytest.approx(a, abs=1e-12)
    n = (s - centre) / a
    u_in, u_out = (src[0] - s) / np.linalg.norm(src[0] - s), -s / np.linalg.norm(s)
    assert np.degrees(abs(np.arccos(u_in @ n) - np.arccos(u_out @ n))) < 0.5
    assert np.cross(n, u_in) @ u_out == pytest.approx(0.0, abs=1e-3)       # one plane
    u1, u2 = (src[0] - centre), -centre
    d1, d2 = np.linalg.norm(u1), np.linalg.norm(u2)
    go = d1 + d2 - a * np.linalg.norm(u1 / d1 + u2 / d2)
    assert np.linalg.norm(src[0] - s) + np.linalg.norm(s) == pytest.approx(go, abs=2e-3)


@pytest.mark.parametrize("edge", ["vertical", "horizontal"])
def test_a_metal_edges_double_bounce_has_the_image_methods_sign(edge: str) -> None:
    """The radar's double image in two perpendicular perfect conductors is its dipole
    mirrored twice, ``(−M_B)(−M_A) p``: a half turn about the edge, ``+p`` for E along the
    edge and ``−p`` across it, so a metal dihedral returns ``+√π D`` (a point target's
    sign) for E along its edge and ``−√π D`` across it (S = diag(1, −1), the dihedral's
    polarimetric signature; Knott, Shaeffer & Tuley §5.4). A vertical edge: V along it,
    H across; a horizontal one (floor and wall): the other way. H's E (``φ̂`` about board
    y) reverses with the direction, so the radar receives it by its field towards where
    the wave comes from, not along the wave (that gave H the plate's sign)."""
    front = plate(0, np.array([-3.0, 1.0, 3.0]), np.array([6.0, 0, 0]),
                  np.array([0, -3.0, 0]), np.array([0, 0, -1.0]))
    if edge == "vertical":                          # the right wall at x = 1
        other = plate(1, np.array([1.0, -2.0, -1.0]), np.array([0, 4.0, 0]),
                      np.array([0, 0, 4.0]), np.array([-1.0, 0, 0]))
    else:                                           # the floor at y = 1 (y down)
        other = plate(1, np.array([-3.0, 1.0, -1.0]), np.array([6.0, 0, 0]),
                      np.array([0, 0, 4.0]), np.array([0, -1.0, 0]))
    d = np.hypot(1.0, 3.0)
    along = "V" if edge == "vertical" else "H"
    across = "H" if edge == "vertical" else "V"
    amp_along, _ = total_return([front, other], order=1, polarization=along)
    amp_across, _ = total_return([front, other], order=1, polarization=across)
    assert amp_along == pytest.approx(np.sqrt(np.pi) * d, rel=1e-9, abs=1e-9)
    assert amp_across == pytest.approx(-np.sqrt(np.pi) * d, rel=1e-9, abs=1e-9)
