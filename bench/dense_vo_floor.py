#!/usr/bin/env python3
"""The distance error a planar dense method gets from what it cannot observe (docs/dense_vo.md).

A wall-looking camera converts image shift to metres with one reference scale (000 eq. 19), set
for the nominal wall distance d_nom = f / zeta. From ground truth:
  - drift floor: every frame's travel scaled by d_nom / d, d the true distance along the optical
    axis to the wall, as the robot drifts across the pipe;
  - tilt term: the camera's turn about its axis across the pipe from the first frame of a leg to
    its last moves the image like travel does, by d_nom times that angle (image x along the
    pipe).
One-way runs: both in % of the travel, and their sum. Out-and-back runs (the turnaround is the
frame farthest from the start): each leg's sum, the whole path's, and the return floor, a signed
eq. 51 ((forward - reverse) / 2 of the legs' errors): what the return error of a method that
followed the image motion exactly would be.
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


def turn_across(q0, q1):
    """The camera's turn about its own y axis (across the pipe) from q0 to q1, radians."""
    x, y, z, w = quaternion_product((-q0[0], -q0[1], -q0[2], q0[3]), tuple(q1))
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    sine = math.sqrt(x * x + y * y + z * z)
    return 2 * math.atan2(sine, w) * y / sine if sine > 1e-12 else 0.0


def floor_terms(dataset):
    """A dict: d_nominal, d_min, d_max (m); drift_floor (%, the whole run); for one-way runs
    tilt_term (%) and together (%); for out-and-back runs forward and reverse (% each leg, drift
    floor + tilt term), together (% of the whole path) and return_floor (signed %,
    (forward - reverse) / 2)."""
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

    def drift_floor(first, last):
        travel = seen = 0.0
        for i in range(first + 1, last + 1):
            step = abs(rows[i][3] - rows[i - 1][3])
            travel += step
            seen += step * d_nominal / (0.5 * (distances[i] + distances[i - 1]))
        return 100 * (seen / travel - 1), travel

    def tilt_term(first, last, travel):
        return 100 * d_nominal * turn_across(rows[first][4:8], rows[last][4:8]) / travel

    last = len(rows) - 1
    terms = {"d_nominal": d_nominal, "d_min": min(distances), "d_max": max(distances)}
    terms["drift_floor"], travel = drift_floor(0, last)
    turnaround = max(range(len(rows)), key=lambda i: abs(rows[i][3] - rows[0][3]))
    reach = abs(rows[turnaround][3] - rows[0][3])
    if abs(rows[last][3] - rows[0][3]) > 0.5 * reach:  # one way
        terms["tilt_term"] = tilt_term(0, last, travel)
        terms["together"] = terms["drift_floor"] + terms["tilt_term"]
        return terms
    # A turn that moves the image the way travel out does lengthens the way out and shortens
    # the way back.
    forward_floor, forward_travel = drift_floor(0, turnaround)
    reverse_floor, reverse_travel = drift_floor(turnaround, last)
    terms["forward"] = forward_floor + tilt_term(0, turnaround, forward_travel)
    terms["reverse"] = reverse_floor - tilt_term(turnaround, last, reverse_travel)
    terms["return_floor"] = 0.5 * (terms["forward"] - terms["reverse"])
    terms["together"] = ((terms["forward"] * forward_travel + terms["reverse"] * reverse_travel) /
                         (forward_travel + reverse_travel))
    return terms


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    dataset = sys.argv[1]
    terms = floor_terms(dataset)
    text = (f"{dataset}: d_nominal {1000 * terms['d_nominal']:.2f} mm, d "
            f"{1000 * terms['d_min']:.2f}..{1000 * terms['d_max']:.2f} mm; drift floor "
            f"{terms['drift_floor']:+.3f} %")
    if "tilt_term" in terms:
        text += (f", tilt term {terms['tilt_term']:+.3f} %, together {terms['together']:+.3f} %")
    else:
        text += (f"; with the tilt terms, forward {terms['forward']:+.4f} %, reverse "
                 f"{terms['reverse']:+.4f} %, together {terms['together']:+.4f} %, return floor "
                 f"{terms['return_floor']:+.4f} %")
    print(text)


if __name__ == "__main__":
    main()
