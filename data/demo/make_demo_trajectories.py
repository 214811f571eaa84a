#!/usr/bin/env python3
"""Writes the demo trajectory pair shipped in data/demo (deterministic; rerun to regenerate).

Ground truth: a camera driven 2 m down a straight pipe (pipe Z axis) and back at 0.1 m/s,
sampled at 10 Hz, with a small lateral wobble and roll. Estimate: the same run as a slightly
miscalibrated odometry would see it: forward leg 0.3 % long, reverse leg 0.2 % short, a 0.2 mm
random walk on each axis, timestamps 2 ms late.
"""
import math
import random

random.seed(7)
rate_hz, speed = 10.0, 0.1
leg_frames = int(2.0 / speed * rate_hz)


def axial_position(i):
    return speed * i / rate_hz if i <= leg_frames else speed * (2 * leg_frames - i) / rate_hz


def quaternion_about_z(angle):
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


with open("groundtruth.tum", "w") as gt, open("estimate.tum", "w") as est:
    for out in (gt, est):
        out.write("# timestamp tx ty tz qx qy qz qw (camera-to-world, metres)\n")
    walk = [0.0, 0.0, 0.0]
    est_z = 0.0
    for i in range(2 * leg_frames + 1):
        t = i / rate_hz
        z = axial_position(i)
        x = 0.004 * math.sin(0.7 * t)
        y = 0.003 * math.cos(0.5 * t)
        roll = 0.02 * math.sin(0.3 * t)
        if i > 0:
            step = z - axial_position(i - 1)
            est_z += step * (1.003 if step > 0 else 0.998)
        walk = [w + random.gauss(0.0, 0.0002) for w in walk]
        q = quaternion_about_z(roll)
        gt.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % ((t, x, y, z) + q))
        q_est = quaternion_about_z(roll + random.gauss(0.0, 0.002))
        est.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" %
                  ((t + 0.002, x + walk[0], y + walk[1], est_z + walk[2]) + q_est))
