#!/usr/bin/env python3
"""Rotation error of a `pipescope map` run's key frames against the simulator's ground truth.

For each straight section (run.json `sections`), the relative rotation between key frames k and
k + span (cam_k_from_cam_k+span) is compared with the truth's over spans of 1, 10, 50 and 150 key
frames: median, 90th percentile and largest angle of the difference. The one-key-frame steps are
also split by where they lie: steps into a window's first key frame (run.json `windows`, applied
windows only) against all the others, because a window frees its first pose's rotation while the
key frame before it stays where it is.

Key frames are matched to ground-truth poses by timestamp (nearest). Standard library only.
Usage: bench/fisheye_rotation_error.py DATASET_DIR RUN_DIR
"""
import bisect
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dense_vo_floor import quaternion_product as q_mul  # noqa: E402  (x, y, z, w)


def load_tum(path):
    poses = []
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()]
            poses.append((v[0], tuple(v[4:8])))  # timestamp, quaternion x y z w
    return poses


def q_inv(q):
    return (-q[0], -q[1], -q[2], q[3])


def angle_deg(q):
    norm = math.sqrt(sum(c * c for c in q))
    return 2.0 * math.degrees(math.acos(min(1.0, abs(q[3]) / norm)))


def relative(a, b):  # cam_a_from_cam_b for world_from_cam quaternions
    return q_mul(q_inv(a), b)


def stats(values):
    if not values:
        return "-"
    v = sorted(values)
    return (f"median {v[len(v) // 2]:.3f}, p90 {v[min(len(v) - 1, int(len(v) * 0.9))]:.3f}, "
            f"max {v[-1]:.3f} deg (n {len(v)})")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    dataset, run = sys.argv[1], sys.argv[2]
    truth = load_tum(dataset + "/groundtruth.tum")
    truth_times = [t for t, _ in truth]
    keyframes = load_tum(run + "/keyframes.tum")
    report = json.load(open(run + "/run.json"))

    def truth_at(t):
        i = bisect.bisect_left(truth_times, t)
        best = min((j for j in (i - 1, i) if 0 <= j < len(truth)), key=lambda j: abs(truth_times[j] - t))
        return truth[best][1]

    true_rotation = [truth_at(t) for t, _ in keyframes]
    estimated = [q for _, q in keyframes]

    def error(k, span):
        return angle_deg(relative(relative(true_rotation[k], true_rotation[k + span]),
                                  relative(estimated[k], estimated[k + span])))

    window_starts = {w["first_keyframe"] for w in report.get("windows", [])
                     if w.get("straight") and not w.get("rejected")}
    for section in report["sections"]:
        if section["class"] != "straight":
            continue
        first, last = section["first_keyframe"], section["last_keyframe"]
        print(f"section {section['index']} (key frames {first}-{last})")
        for span in (1, 10, 50, 150):
            errors = [error(k, span) for k in range(first, last - span + 1)]
            truths = [angle_deg(relative(true_rotation[k], true_rotation[k + span]))
                      for k in range(first, last - span + 1)]
            if errors:
                print(f"  span {span:3d}: error {stats(errors)}; true rotation median "
                      f"{sorted(truths)[len(truths) // 2]:.3f} deg")
        into_start = [error(k, 1) for k in range(first, last) if k + 1 in window_starts]
        others = [error(k, 1) for k in range(first, last) if k + 1 not in window_starts]
        print(f"  steps into a window's first key frame: {stats(into_start)}")
        print(f"  all other steps:                       {stats(others)}")


if __name__ == "__main__":
    main()
