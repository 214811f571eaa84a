#!/usr/bin/env python3
"""Where a network map's heading goes wrong: at the turns or along the straight sections
(docs/fisheye_mapping.md, "Route A's diagonals: where the heading goes"). For each straight
section of a `pipescope map` run (run.json `sections`, class straight), a line is fitted to its
key frames' estimated positions (keyframes.tum) and to the true positions at the same timestamps
(the dataset's groundtruth.tum); printed per section: its true length and its bend, the angle
between the lines through its first and its last two fifths, estimated beside true (a straight
pipe's true bend is the camera's wander, a few hundredths of a degree); then, between consecutive
straight sections, the angle between their lines, estimated beside true, and the difference.
Angles between lines need no alignment of the two frames. Needs numpy.
KEYFRAMES_TUM (default RUN_DIR/keyframes.tum) may name the run's
keyframes_before_loop_closure.tum instead, to see the turns before the closure moved them.
Usage: bench/fisheye_section_turns.py RUN_DIR GROUNDTRUTH_TUM [KEYFRAMES_TUM]
"""
import json
import sys

import numpy as np


def read_positions(path):
    positions = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        values = [float(v) for v in line.split()]
        positions[values[0]] = np.array(values[1:4])
    return positions


def line_direction(points):
    """Unit direction of the least-squares line through `points`, pointing along the travel."""
    _, _, vt = np.linalg.svd(points - points.mean(axis=0))
    direction = vt[0]
    return direction if np.dot(points[-1] - points[0], direction) >= 0 else -direction


def angle_deg(a, b):
    return float(np.degrees(np.arccos(np.clip(np.dot(a, b), -1.0, 1.0))))


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    run, groundtruth = sys.argv[1:3]
    estimated = read_positions(sys.argv[3] if len(sys.argv) == 4 else f"{run}/keyframes.tum")
    truth = read_positions(groundtruth)
    truth_stamps = np.array(sorted(truth))
    stamps = sorted(estimated)

    def true_at(stamp):
        nearest = truth_stamps[np.argmin(np.abs(truth_stamps - stamp))]
        if abs(nearest - stamp) > 1e-3:
            sys.exit(f"{groundtruth}: no pose at key frame time {stamp}")
        return truth[nearest]

    sections = json.load(open(f"{run}/run.json"))["sections"]
    lines = []
    for section in sections:
        if section["class"] != "straight" or section["last_keyframe"] - section["first_keyframe"] < 2:
            continue  # a line needs three key frames
        keyframes = range(section["first_keyframe"], section["last_keyframe"] + 1)
        est = np.array([estimated[stamps[k]] for k in keyframes])
        gt = np.array([true_at(stamps[k]) for k in keyframes])
        fifth = len(est) // 5
        bends = ["-", "-"]
        if fifth >= 5:
            bends = [f"{angle_deg(line_direction(p[:2 * fifth]), line_direction(p[-2 * fifth:])):.3f}"
                     for p in (est, gt)]
        print(f"section {section['index']}: key frames {section['first_keyframe']}-"
              f"{section['last_keyframe']}, {np.linalg.norm(gt[-1] - gt[0]):.2f} m, bend "
              f"{bends[0]} deg (true {bends[1]})")
        lines.append((section["index"], line_direction(est), line_direction(gt)))
    for (first, est_a, gt_a), (second, est_b, gt_b) in zip(lines, lines[1:]):
        est_turn, true_turn = angle_deg(est_a, est_b), angle_deg(gt_a, gt_b)
        print(f"turn from section {first} to {second}: {est_turn:.3f} deg (true {true_turn:.3f}, "
              f"error {est_turn - true_turn:+.3f})")


if __name__ == "__main__":
    main()
