#!/usr/bin/env python3
"""Writes the demo trajectory pair (TUM format) that README's first command evaluates.

demo_gt.txt: a 4 Hz, ~1.7 km urban drive (straights, turns, a stop), made up, no dataset needed.
demo_est.txt: the same drive as an odometry would estimate it: each frame-to-frame motion with a
1.5 % scale error, a small yaw bias and seeded noise. Deterministic (fixed seed); standard library only.
Run from this folder: python3 make_demo_trajectories.py
"""
import math
import random

random.seed(42)
dt = 0.25
# (duration s, speed m/s, yaw rate rad/s)
plan = [(60, 10.0, 0.0), (8, 6.0, math.pi / 2 / 8), (40, 11.0, 0.0), (10, 0.0, 0.0), (30, 9.0, 0.0),
        (8, 6.0, -math.pi / 2 / 8), (50, 12.0, 0.01), (12, 5.0, math.pi / 12), (30, 10.0, 0.0)]


def quat(yaw):
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def write(path, poses):
    with open(path, "w") as f:
        f.write("# t x y z qx qy qz qw\n")
        for t, x, y, yaw in poses:
            qx, qy, qz, qw = quat(yaw)
            f.write(f"{t:.6f} {x:.6f} {y:.6f} 0 {qx:.9f} {qy:.9f} {qz:.9f} {qw:.9f}\n")


gt, est = [], []
t = 1600000000.0
g = [0.0, 0.0, 0.0]
e = [0.0, 0.0, 0.0]
for duration, v, w in plan:
    for _ in range(int(duration / dt)):
        gt.append((t, g[0], g[1], g[2]))
        est.append((t, e[0], e[1], e[2]))
        ds, dyaw = v * dt, w * dt
        g = [g[0] + ds * math.cos(g[2] + dyaw / 2), g[1] + ds * math.sin(g[2] + dyaw / 2), g[2] + dyaw]
        ds_e = ds * 1.015 + random.gauss(0, 0.01)
        dyaw_e = dyaw + 0.00005 + random.gauss(0, 0.0005)
        e = [e[0] + ds_e * math.cos(e[2] + dyaw_e / 2), e[1] + ds_e * math.sin(e[2] + dyaw_e / 2), e[2] + dyaw_e]
        t += dt
write("demo_gt.txt", gt)
write("demo_est.txt", est)
