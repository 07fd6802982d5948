"""Regenerate the bundled example projects in canonical form: .venv/bin/python tools/make_examples.py."""
import numpy as np

from simcore.scene import *
from simcore.scene.model import SensorRig
from simcore.scene.rgb_config import RgbCameraConfig
from simcore.scene.project_io import save_project
from simcore.scene.radar_presets import bgt60tr13c
from simcore.scene.tof_config import pmd_pico_flexx


def rig(height=1.0):
    tof = pmd_pico_flexx()
    tof.pose_on_rig = Pose(position_m=(0, 0.03, 0))
    return SensorRig(pose=Pose(position_m=(0, 0, height)), tof=tof,
                     radar=bgt60tr13c(pose_on_rig=Pose(position_m=(0, -0.03, 0))))

# wall.json
wall = Project(name="wall", description="A flat concrete wall 2.0 m in front of the rig, normal to the boresight, larger than both fields of view.",
    timeline=Timeline(frame_rate_hz=10, duration_s=0.5),
    objects=[SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 12.0, 8.0)), pose=Pose(position_m=(2.1, 0, 1.0)), material="concrete")],
    rig=rig(1.0))
save_project(wall, "resources/examples/wall.json")

# point_targets.json
objs = []
radar_y = -0.03
for i, (r, az) in enumerate([(1.5, -20.0), (3.0, 0.0), (4.5, 25.0)]):
    a = np.deg2rad(az)
    pos = (round(r*np.cos(a), 6), round(radar_y - r*np.sin(a), 6), 1.0)
    motion = Motion(velocity_mps=(1.0, 0.0, 0.0)) if az == 0.0 else Motion()
    objs.append(SceneObject(id=i+1, name=f"corner_{i+1}", geometry=CornerReflector(edge_m=0.06),
        pose=Pose(position_m=pos, rotation_deg=(0.0, -90.0, -az)), material="radar_retroreflector", motion=motion))
pt = Project(name="point_targets", description="Three radar corner reflectors (edge 6 cm) at 1.5/3.0/4.5 m and -20/0/+25 deg azimuth from the radar boresight at its height; the middle one moves radially away at 1.0 m/s.",
    timeline=Timeline(frame_rate_hz=10, duration_s=1.0), objects=objs, rig=rig(1.0))
save_project(pt, "resources/examples/point_targets.json")

# office.json
O = []
def add(name, geom, pos, mat, rot=(0,0,0), motion=None):
    O.append(SceneObject(id=len(O)+1, name=name, geometry=geom, pose=Pose(position_m=pos, rotation_deg=rot), material=mat, motion=motion or Motion()))
add("floor", Box(size_m=(6.0, 5.0, 0.1)), (2.5, 0, -0.05), "concrete")
add("ceiling", Box(size_m=(6.0, 5.0, 0.1)), (2.5, 0, 3.05), "white_paint")
add("back_wall", Box(size_m=(0.2, 5.0, 3.0)), (5.6, 0, 1.5), "white_paint")
add("left_wall", Box(size_m=(6.0, 0.2, 3.0)), (2.5, 2.6, 1.5), "white_paint")
add("right_wall", Box(size_m=(6.0, 0.2, 3.0)), (2.5, -2.6, 1.5), "white_paint")
# desk 1 (left) and desk 2 (right)
for k, y in ((1, 1.3), (2, -1.4)):
    x = 3.2
    add(f"desk{k}_top", Box(size_m=(0.8, 1.4, 0.04)), (x, y, 0.74), "wood")
    for j, (dx, dy) in enumerate(((-0.35, -0.65), (-0.35, 0.65), (0.35, -0.65), (0.35, 0.65))):
        add(f"desk{k}_leg{j+1}", Box(size_m=(0.05, 0.05, 0.72)), (x+dx, y+dy, 0.36), "aluminium")
add("chair_seat", Box(size_m=(0.45, 0.45, 0.06)), (2.4, 0.9, 0.46), "fabric")
add("chair_backrest", Box(size_m=(0.05, 0.45, 0.5)), (2.65, 0.9, 0.78), "black_plastic")
add("chair_post", Cylinder(radius_m=0.025, height_m=0.43), (2.4, 0.9, 0.215), "aluminium")
add("metal_plate", Box(size_m=(0.01, 0.5, 0.4)), (5.49, 0.6, 1.3), "aluminium")
add("book", Box(size_m=(0.22, 0.16, 0.04)), (3.0, 1.2, 0.78), "paper", rot=(0, 0, 15))
add("ir_retroreflector", Box(size_m=(0.01, 0.12, 0.12)), (3.3, -1.0, 0.82), "ir_retroreflector_tape")
add("corner_reflector", CornerReflector(edge_m=0.08), (3.4, -1.6, 0.85), "radar_retroreflector", rot=(0, -90, -25))
add("paper_box", Box(size_m=(0.3, 0.4, 0.3)), (3.0, -1.55, 0.91), "paper")
add("person", Cylinder(radius_m=0.18, height_m=1.7), (4.2, 0.2, 0.85), "skin", motion=Motion(keyframes=[Keyframe(time_s=0.0), Keyframe(time_s=2.0, position_m=(-1.0, -0.6, 0.0))], repeat="back_and_forth"))
office = Project(name="office", description="An office: desks, chair, metal plate, a book, a near-IR retroreflector on a desk, a radar corner reflector hidden behind a radar-transparent paper box, a walking person; the sensor rig looks in from the door.",
    timeline=Timeline(frame_rate_hz=10, duration_s=4.0), objects=O, rig=rig(1.2))
save_project(office, "resources/examples/office.json")
# office_rgb.json: the same office with a colour camera 3 cm beside the ToF camera.
office_rgb = office.model_copy(deep=True)
office_rgb.name = "office_rgb"
office_rgb.description = ("The office scene with an RGB camera (640x480, 69 x 42 deg) 3 cm to the "
                          "left of the ToF camera, for fusion datasets: colour, depth and radar "
                          "from one snapshot per frame.")
office_rgb.rig.rgb = RgbCameraConfig(pose_on_rig=Pose(position_m=(0, 0.06, 0)))
save_project(office_rgb, "resources/examples/office_rgb.json")
# office_walkthrough.json: the rig carried through the office on a keyframed path with turns.
walk = office.model_copy(deep=True)
walk.name = "office_walkthrough"
walk.description = ("The office with the sensor rig carried through it at walking speed on a "
                    "keyframed path with turns (about 1 m/s, up to 30 deg/s) while the person "
                    "walks: every frame is seen from a new pose (the moving-rig case).")
walk.rig.motion = Motion(keyframes=[
    Keyframe(time_s=0.0, position_m=(0.3, 0.0, 0.0)),
    Keyframe(time_s=1.5, position_m=(1.8, 0.0, 0.0)),
    Keyframe(time_s=2.5, position_m=(2.6, 0.4, 0.0), rotation_deg=(0.0, 0.0, 30.0)),
    Keyframe(time_s=3.5, position_m=(3.1, 1.0, 0.0), rotation_deg=(0.0, 0.0, 60.0)),
    Keyframe(time_s=4.0, position_m=(3.2, 1.3, 0.0), rotation_deg=(0.0, 0.0, 75.0)),
], repeat="hold")
save_project(walk, "resources/examples/office_walkthrough.json")
print(len(O))

# doppler_back_and_forth.json: the rig moves back and forth (sinusoidally, 0.5 m peak to
# peak, 4 s period) towards a corner reflector 3 m ahead, as in the reference simulator's
# velocity experiment; 16 chirps per frame, 20 frames/s.
period, amplitude = 4.0, 0.5
times = np.round(np.arange(0.0, period + 1e-9, 0.1), 6)
kf = [Keyframe(time_s=float(t), position_m=(round(amplitude * 0.5 * (1 - np.cos(2 * np.pi * t / period)), 6), 0.0, 0.0)) for t in times]
r = rig(1.0)
r.motion = Motion(keyframes=kf, repeat="loop")
doppler = Project(name="doppler_back_and_forth",
    description="The sensor rig moves back and forth (0.5 m peak to peak, 4 s period, up to 0.39 m/s) in front of one radar corner reflector 3 m ahead; 16 chirps per frame, as in the reference simulator's velocity experiment.",
    timeline=Timeline(frame_rate_hz=20, duration_s=8.0),
    objects=[SceneObject(id=1, name="corner", geometry=CornerReflector(edge_m=0.08), pose=Pose(position_m=(3.0, -0.03, 1.0), rotation_deg=(0.0, -90.0, 0.0)), material="radar_retroreflector")],
    rig=r)
save_project(doppler, "resources/examples/doppler_back_and_forth.json")
