#!/usr/bin/env python3
"""The distance error a planar dense method gets from what it cannot observe (docs/dense_vo.md).

A wall-looking camera converts image shift to metres with one reference scale (000 eq. 19), set
for the nominal wall distance d_nom = f / zeta. From ground truth:
  - drift floor: every frame's travel scaled by d_nom / d, d the true distance along the optical
    axis to the wall, as the robot drifts across the pipe;
  - tilt term (one-way runs): the camera's turn about its axis across the pipe from the first
    frame to the last moves the image like travel does, by d_nom times that angle (image x
    along the pipe).
Prints both in % of the travel, and their sum.
Usage: bench/dense_vo_floor.py DATASET
"""
import math
import re
import sys


def quaternion_product(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def optical_axis(q):
    x, y, z, w = q
    return (2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y))


def yaml_number(text, key, path):
    match = re.search(key + r":\s*\[?\s*([\d.eE+-]+)", text)
    if not match:
        sys.exit(f"{path}: no {key}")
    return float(match.group(1))


def floor_terms(dataset):
    """(drift floor %, tilt term % or None for an out-and-back run, d_nominal, d_min, d_max)."""
    manifest = open(f"{dataset}/dataset.yaml").read()
    radius = yaml_number(manifest, "inner_radius_m", "dataset.yaml")
    zeta = yaml_number(manifest, "reference_scale_px_per_m", "dataset.yaml")
    focal = yaml_number(open(f"{dataset}/camera.yaml").read(), "params", "camera.yaml")
    d_nominal = focal / zeta
    rows = [list(map(float, line.split())) for line in open(f"{dataset}/groundtruth.tum")
            if line.strip() and not line.startswith("#")]
    distances = []
    for row in rows:
        t, v = row[1:4], optical_axis(row[4:8])  # the ray from the camera meets the cylinder
        a = v[0] ** 2 + v[1] ** 2
        b = 2 * (t[0] * v[0] + t[1] * v[1])
        c = t[0] ** 2 + t[1] ** 2 - radius ** 2
        distances.append((-b + math.sqrt(b * b - 4 * a * c)) / (2 * a))
    travel = seen = 0.0
    for i in range(1, len(rows)):
        step = abs(rows[i][3] - rows[i - 1][3])
        travel += step
        seen += step * d_nominal / (0.5 * (distances[i] + distances[i - 1]))
    q0, q1 = rows[0][4:8], rows[-1][4:8]
    x, y, z, w = quaternion_product((-q0[0], -q0[1], -q0[2], q0[3]), tuple(q1))
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    sine = math.sqrt(x * x + y * y + z * z)
    tilt = 2 * math.atan2(sine, w) * y / sine if sine > 1e-12 else 0.0
    floor = 100 * (seen / travel - 1)
    reach = max(abs(row[3] - rows[0][3]) for row in rows)
    tilt_term = None
    if abs(rows[-1][3] - rows[0][3]) > 0.5 * reach:  # one way (an out-and-back run turns round)
        tilt_term = 100 * d_nominal * tilt / travel
    return floor, tilt_term, d_nominal, min(distances), max(distances)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    dataset = sys.argv[1]
    floor, tilt_term, d_nominal, d_min, d_max = floor_terms(dataset)
    text = (f"{dataset}: d_nominal {1000 * d_nominal:.2f} mm, d {1000 * d_min:.2f}.."
            f"{1000 * d_max:.2f} mm; drift floor {floor:+.3f} %")
    if tilt_term is not None:
        text += f", tilt term {tilt_term:+.3f} %, together {floor + tilt_term:+.3f} %"
    print(text)


if __name__ == "__main__":
    main()
