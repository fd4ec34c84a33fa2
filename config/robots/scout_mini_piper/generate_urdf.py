#!/usr/bin/env python3
"""Writes scout_mini_piper.urdf beside this script.

Run:  python3 config/robots/scout_mini_piper/generate_urdf.py
The URDF is committed; this script records how its numbers were obtained.

Arm kinematics: the Agilex Piper's published modified-DH table (Craig's convention,
piper_sdk kinematics, with the 2-degree J2/J3 offset firmware default):
    a     = [0, 0, 285.03, -21.98, 0, 0] mm
    alpha = [0, -pi/2, 0, pi/2, -pi/2, pi/2]
    d     = [123, 0, 0, 250.75, 0, 91] mm
    theta offset = [0, -172.22, -102.78, 0, 0, 0] deg
Link i's transform is RotX(alpha_i) TransX(a_i) RotZ(q_i + offset_i) TransZ(d_i). RotZ and TransZ
commute, so the URDF joint origin is RotX(alpha) TransX(a) TransZ(d) RotZ(offset) and the joint
rotates about its local +z: URDF joint angle == SDK joint angle exactly. Values are printed with
17 significant digits so the URDF reproduces the DH chain to ~1e-15 m.

Joint limits: piper_sdk's parameter manager (J4 +-100 deg and J6 +-120 deg, tighter than the
vendor URDF). Velocity limits are conservative planning limits, not the motors' maxima.

Collision geometry: primitives sized to the real parts' envelopes (Scout Mini body
0.612 x 0.58 x 0.245 m overall; Piper tubes ~60-70 mm; wrist housings ~70 mm).
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))

A = [0.0, 0.0, 0.28503, -0.02198, 0.0, 0.0]
ALPHA = [0.0, -math.pi / 2, 0.0, math.pi / 2, -math.pi / 2, math.pi / 2]
D = [0.123, 0.0, 0.0, 0.25075, 0.0, 0.091]
OFFSET = [0.0, math.radians(-172.22), math.radians(-102.78), 0.0, 0.0, 0.0]
LOWER = [-2.6179, 0.0, -2.967, -1.745, -1.22, -2.09439]
UPPER = [2.6179, 3.14, 0.0, 1.745, 1.22, 2.09439]
VELOCITY = [1.5, 1.5, 1.5, 2.0, 2.0, 2.0]   # rad/s
EFFORT = [100.0, 100.0, 100.0, 30.0, 30.0, 30.0]

ARM_MOUNT_XYZ = (0.15, 0.0, 0.245)  # on the top plate, ahead of the base centre


def f(x):
    return repr(0.0 if abs(x) < 1e-300 else float(x))


def vec(v):
    return " ".join(f(x) for x in v)


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rot_x(t):
    c, s = math.cos(t), math.sin(t)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_z(t):
    c, s = math.cos(t), math.sin(t)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def rpy_from_matrix(R):
    """URDF convention R = Rz(yaw) Ry(pitch) Rx(roll)."""
    pitch = math.atan2(-R[2][0], math.hypot(R[0][0], R[1][0]))
    if abs(math.cos(pitch)) > 1e-9:
        roll = math.atan2(R[2][1], R[2][2])
        yaw = math.atan2(R[1][0], R[0][0])
    else:  # gimbal lock: put everything in yaw
        roll = 0.0
        yaw = math.atan2(-R[0][1], R[1][1])
    return roll, pitch, yaw


def dh_origin(i):
    xyz = (A[i], -D[i] * math.sin(ALPHA[i]), D[i] * math.cos(ALPHA[i]))
    rpy = rpy_from_matrix(matmul(rot_x(ALPHA[i]), rot_z(OFFSET[i])))
    return xyz, rpy


def origin(xyz=(0, 0, 0), rpy=(0, 0, 0)):
    return f'<origin xyz="{vec(xyz)}" rpy="{vec(rpy)}"/>'


def box(size, xyz=(0, 0, 0), rpy=(0, 0, 0)):
    return f'    <collision>{origin(xyz, rpy)}<geometry><box size="{vec(size)}"/></geometry></collision>'


def cyl(radius, length, xyz=(0, 0, 0), rpy=(0, 0, 0)):
    return (f'    <collision>{origin(xyz, rpy)}<geometry><cylinder radius="{f(radius)}" '
            f'length="{f(length)}"/></geometry></collision>')


def link(name, collisions):
    body = "\n".join(collisions)
    return f'  <link name="{name}">\n{body}\n  </link>' if body else f'  <link name="{name}"/>'


HALF_PI = math.pi / 2
Y_AXIS = (HALF_PI, 0, 0)   # rpy turning a z-axis cylinder onto the y axis
X_AXIS = (0, HALF_PI, 0)   # ... onto the x axis

# Geometry per link, in that link's frame (the frame of the joint that moves it).
GEOMETRY = {
    # Scout Mini: chassis between the wheels, four wheels, top plate at z = 0.245.
    "base_link": [
        box((0.612, 0.42, 0.155), (0, 0, 0.1675)),
        *[cyl(0.0875, 0.08, (sx * 0.232, sy * 0.25, 0.0875), Y_AXIS)
          for sx in (1, -1) for sy in (1, -1)],
    ],
    # LiDAR mast at the rear of the top plate and the MID-360 on it.
    "lidar_mast": [cyl(0.02, 0.255, (0, 0, 0.1275)), cyl(0.0325, 0.065, (0, 0, 0.2875))],
    # Piper base casing (fixed on the plate).
    "arm_base": [cyl(0.05, 0.07, (0, 0, 0.035))],
    # link1: turret above the casing and the joint-2 housing (axis = link1 y).
    "link1": [cyl(0.045, 0.055, (0, 0, -0.0275)), cyl(0.05, 0.11, (0, 0, 0), Y_AXIS)],
    # link2: upper arm along +x (285 mm) and the joint-3 housing (axis = link2 z).
    "link2": [box((0.25, 0.06, 0.07), (0.1425, 0, 0)), cyl(0.045, 0.09, (0.28503, 0, 0))],
    # link3: forearm from the elbow along -y to the wrist, 22 mm offset in -x.
    # (ends where the wrist-roll housing of link4 begins, so links 3 and 5 never overlap)
    "link3": [box((0.06, 0.175, 0.06), (-0.011, -0.1075, 0)), cyl(0.04, 0.08, (0, 0, 0))],
    # link4: wrist roll housing around the forearm axis (link4 z), joint-5 housing on y.
    "link4": [cyl(0.035, 0.07, (0, 0, -0.02)), cyl(0.035, 0.07, (0, 0, 0), Y_AXIS)],
    # link5: wrist pitch body reaching to the flange along -y.
    "link5": [cyl(0.035, 0.07, (0, 0, 0)), box((0.06, 0.07, 0.06), (0, -0.045, 0))],
    # link6: flange disc.
    "link6": [cyl(0.035, 0.02, (0, 0, -0.01))],
    # gripper: body on the flange, two fingers along the approach axis (+z), opened to 76 mm.
    "gripper_base": [box((0.12, 0.06, 0.085), (0, 0, 0.0425)),
                     box((0.012, 0.02, 0.06), (0.044, 0, 0.115)),
                     box((0.012, 0.02, 0.06), (-0.044, 0, 0.115))],
    "grasp_frame": [],
}


def main():
    out = ['<?xml version="1.0"?>',
           '<!-- Generated by generate_urdf.py; edit the script, not this file. -->',
           '<robot name="scout_mini_piper">']
    out.append(link("base_link", GEOMETRY["base_link"]))
    out.append(link("lidar_mast", GEOMETRY["lidar_mast"]))
    out.append('  <joint name="mast_mount" type="fixed"><parent link="base_link"/>'
               f'<child link="lidar_mast"/>{origin((-0.22, 0, 0.245))}</joint>')
    out.append(link("arm_base", GEOMETRY["arm_base"]))
    out.append('  <joint name="arm_mount" type="fixed"><parent link="base_link"/>'
               f'<child link="arm_base"/>{origin(ARM_MOUNT_XYZ)}</joint>')
    parent = "arm_base"
    for i in range(6):
        name = f"link{i + 1}"
        out.append(link(name, GEOMETRY[name]))
        xyz, rpy = dh_origin(i)
        out.append(f'  <joint name="joint{i + 1}" type="revolute"><parent link="{parent}"/>'
                   f'<child link="{name}"/>{origin(xyz, rpy)}<axis xyz="0 0 1"/>'
                   f'<limit lower="{f(LOWER[i])}" upper="{f(UPPER[i])}" '
                   f'velocity="{f(VELOCITY[i])}" effort="{f(EFFORT[i])}"/></joint>')
        parent = name
    out.append(link("gripper_base", GEOMETRY["gripper_base"]))
    out.append('  <joint name="gripper_mount" type="fixed"><parent link="link6"/>'
               f'<child link="gripper_base"/>{origin()}</joint>')
    out.append(link("grasp_frame", GEOMETRY["grasp_frame"]))
    out.append('  <joint name="grasp_point" type="fixed"><parent link="gripper_base"/>'
               f'<child link="grasp_frame"/>{origin((0, 0, 0.135))}</joint>')
    out.append('</robot>')
    path = os.path.join(HERE, "scout_mini_piper.urdf")
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")
    print(path)


if __name__ == "__main__":
    main()
