#!/usr/bin/env python3
"""How wrong a network map's key-frame steps are, against the truth: what the loop closure's
pose graph should take as each step's standard deviations (docs/fisheye_mapping.md, "Where a
closure bends the path"). For consecutive key frames of a `pipescope map` run (keyframes.tum, or
KEYFRAMES_TUM, e.g. the run's keyframes_before_loop_closure.tum) the estimated relative pose is
compared with the true one (the dataset's groundtruth.tum at the same timestamps): the translation
error in the earlier camera's frame, split along the true step and across it, and the rotation
error, as RMS and percentiles; for the steps inside straight sections and those into or inside a
T section apart. Then, within straight sections, the same errors of the relative pose over n
steps: growing as the square root of n, the steps' errors are independent; much slower, they
cancel; as n, they drift together. Relative poses need no alignment of the two frames.
Needs numpy and scipy.
Usage: bench/fisheye_step_errors.py RUN_DIR GROUNDTRUTH_TUM [KEYFRAMES_TUM]
"""
import json
import sys

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from pose_graph_replay import read_tum  # noqa: E402


def read_poses(path):
    """world_from_cam as 4x4 matrices, by timestamp rounded to the microsecond."""
    stamps, positions, rotations = read_tum(path)
    poses = {}
    for stamp, position, rotation in zip(stamps, positions, rotations.as_matrix()):
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = rotation, position
        poses[round(stamp, 6)] = pose
    return poses


def relative_errors(estimated, truth, pairs):
    """Per pair (i, j): translation error along and across the true step (m), rotation (deg)."""
    along, across, rotation = [], [], []
    for i, j in pairs:
        e = np.linalg.inv(estimated[i]) @ estimated[j]
        g = np.linalg.inv(truth[i]) @ truth[j]
        direction = g[:3, 3] / np.linalg.norm(g[:3, 3])
        error = e[:3, 3] - g[:3, 3]
        along.append(error @ direction)
        across.append(np.linalg.norm(error - (error @ direction) * direction))
        rotation.append(np.degrees(Rotation.from_matrix(g[:3, :3].T @ e[:3, :3]).magnitude()))
    return np.array(along), np.array(across), np.array(rotation)


def summary(name, along, across, rotation):
    rms = lambda a: np.sqrt(np.mean(np.square(a)))  # noqa: E731
    p = lambda a: "/".join(f"{v:.3f}" for v in np.percentile(np.abs(a), [50, 90, 99]))  # noqa: E731
    print(f"{name}: {len(along)} steps; along rms {rms(along) * 1000:.3f} mm (|.| p50/p90/p99 "
          f"{p(along * 1000)}), across rms {rms(across) * 1000:.3f} mm ({p(across * 1000)}), "
          f"rotation rms {rms(rotation):.3f} deg ({p(rotation)})")


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    run, groundtruth = sys.argv[1:3]
    estimated = read_poses(sys.argv[3] if len(sys.argv) == 4 else f"{run}/keyframes.tum")
    truth_by_stamp = read_poses(groundtruth)
    stamps = sorted(estimated)
    missing = [s for s in stamps if s not in truth_by_stamp]
    if missing:
        sys.exit(f"{groundtruth}: no pose at key frame time {missing[0]}")
    est = [estimated[s] for s in stamps]
    truth = [truth_by_stamp[s] for s in stamps]
    straight = np.zeros(len(stamps), bool)
    for section in json.load(open(f"{run}/run.json"))["sections"]:
        if section["class"] == "straight":
            straight[section["first_keyframe"]:section["last_keyframe"] + 1] = True
    steps = [(k, k + 1) for k in range(len(stamps) - 1)]
    summary("straight", *relative_errors(est, truth, [(i, j) for i, j in steps if straight[j]]))
    summary("into or inside a T", *relative_errors(est, truth,
                                                   [(i, j) for i, j in steps if not straight[j]]))
    for n in (1, 5, 20, 100, 400):
        pairs = [(k, k + n) for k in range(len(stamps) - n) if straight[k:k + n + 1].all()]
        if not pairs:
            continue
        along, across, rotation = relative_errors(est, truth, pairs)
        print(f"over {n} straight steps: along rms {np.sqrt(np.mean(along ** 2)) * 1000:.3f} mm, "
              f"across rms {np.sqrt(np.mean(across ** 2)) * 1000:.3f} mm, rotation rms "
              f"{np.sqrt(np.mean(rotation ** 2)):.3f} deg")


if __name__ == "__main__":
    main()
