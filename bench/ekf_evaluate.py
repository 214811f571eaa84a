#!/usr/bin/env python3
"""Scores an ekf run (004) against the simulator's scene: the distance travelled along the
tube's centreline, the bend angle (first to last section axis), each section's radius, plus
metrics.json's ATE and net distance error. Usage: ekf_evaluate.py DATASET RUN [LABEL]"""
import json
import math
import sys

import yaml


def centreline_samples(scene, step=0.0005):
    """Points along the true centreline with their arc length (straights and bends)."""
    points, arcs, arc = [], [], 0.0
    for section in scene["sections"]:
        start = section["start"]
        if section["type"] == "straight":
            end = section["end"]
            length = math.dist(start, end)
            n = max(1, int(length / step))
            for k in range(n + 1):
                f = k / n
                points.append([a + f * (b - a) for a, b in zip(start, end)])
                arcs.append(arc + f * length)
            arc += length
        else:
            centre, axis = section["center"], section["axis"]
            radius, angle = section["bend_radius"], math.radians(section["angle_deg"])
            u = [(s - c) / radius for s, c in zip(start, centre)]
            w = [axis[1] * u[2] - axis[2] * u[1], axis[2] * u[0] - axis[0] * u[2],
                 axis[0] * u[1] - axis[1] * u[0]]
            n = max(1, int(radius * angle / step))
            for k in range(n + 1):
                t = angle * k / n
                points.append([c + radius * (math.cos(t) * a + math.sin(t) * b)
                               for c, a, b in zip(centre, u, w)])
                arcs.append(arc + radius * t)
            arc += radius * angle
    return points, arcs


def arc_of(point, samples):
    points, arcs = samples
    best = min(range(len(points)), key=lambda i: math.dist(points[i], point))
    return arcs[best]


def positions(path):
    rows = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    return [(float(r[0]), [float(x) for x in r[1:4]]) for r in rows]


def main():
    dataset, run = sys.argv[1], sys.argv[2]
    label = sys.argv[3] if len(sys.argv) > 3 else run
    scene = yaml.safe_load(open(f"{dataset}/scene.yaml"))
    report = json.load(open(f"{run}/run.json"))
    metrics = json.load(open(f"{run}/metrics.json"))
    truth = positions(f"{dataset}/groundtruth.tum")
    estimate = positions(f"{run}/trajectory.tum")
    by_time = {round(t, 6): p for t, p in truth}
    matched = [by_time[round(t, 6)] for t, _ in estimate if round(t, 6) in by_time]
    samples = centreline_samples(scene)
    true_distance = arc_of(matched[-1], samples) - arc_of(matched[0], samples)
    est_distance = report["distance_along_centreline_m"]
    true_bend = sum(s.get("angle_deg", 0.0) for s in scene["sections"] if s["type"] == "bend")
    a = report["sections"][0]["axis"]
    b = report["sections"][-1].get("end_axis", report["sections"][-1]["axis"])
    est_bend = math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))))
    radius = scene["radius"]
    radius_errors = [100.0 * (s["radius_m"] - radius) / radius for s in report["sections"]]
    worst_radius = max(radius_errors, key=abs)
    frames = report["counts"]["frames"]
    fps = frames / report["timings_s"]["odometry"]
    print(f"{label:28s} along {100 * (est_distance - true_distance) / true_distance:+7.3f} % "
          f"({true_distance:.3f} m)  net {metrics['distance_error_pct']:6.3f} %  "
          f"ATE {1000 * metrics['ate_rmse_m']:6.1f} mm  rot {metrics['rot_rmse_deg']:5.2f} deg  "
          f"bend {est_bend:7.2f} ({true_bend:g}) deg  radius worst {worst_radius:+5.1f} %  "
          f"sections {len(report['sections']):2d}  {fps:5.1f} frames/s  "
          f"verdict {report['quality']['verdict']}, along the centreline "
          f"{report['quality'].get('along_pipe_verdict', '-')}")


if __name__ == "__main__":
    main()
