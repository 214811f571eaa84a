#!/usr/bin/env python3
"""How many of a wall camera's point correspondences are right, against the truth: descriptor
matching (what `sparse` did before 2026-12-04), the same matches refined by Lucas-Kanade (what
it does since), and pyramidal Lucas-Kanade alone (what `ekf` does), by the frames between the
two images (docs/conditions.md, "Not done, and why"; docs/sparse_vo.md, "Matches refined by
Lucas-Kanade").

A re-creation of the front ends with OpenCV (not the product's code): each frame divided by the
gain mask (and blurred by `--blur` px), Harris corners by cv.goodFeaturesToTrack (600, 8 px
apart, 5 px block), then either SIFT descriptors at the corners (keypoint size 4 px, as
SiftDescriptionOptions) matched by Lowe's ratio 0.8 with a mutual check, or Lucas-Kanade from
the first image into the second and back (`--window` px, 3 levels, round trip within 0.5 px).
The refined matches: Lucas-Kanade from the first image's corner started at the matched one
(21 px window, full resolution only), those whose way back misses by more than 0.5 px dropped.
Both go through five-point RANSAC (cv.findEssentialMat, 1 px). Each corner is cast onto the
scene's cylinder (along z through the origin) from the first image's true pose and projected
into the second: where it should be. An inlier within 1 px of that is right. A wrong
correspondence can pass RANSAC when it errs along its epipolar line, which is the direction of
travel in a wall view: such errors are what bias the scale.
Prints per gap the medians over the sampled pairs: the true median flow (px), and per front
end the inliers, right inliers, the inliers' median error (px) and their flow bias (the mean
of the track's displacement along the true flow over the true flow, less 1).
Needs a `pinhole-radtan` camera and a straight scene along z (the wall6 and wall16 set-ups of
bench/conditions.sh), numpy, OpenCV and PyYAML (Debian: python3-numpy python3-opencv
python3-yaml).
Usage: bench/sparse_track_truth.py DATASET [--gaps 1,4,11] [--window 41] [--blur 0] [--pairs 12]
"""
import argparse
import os
import sys
import warnings

import cv2
import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fisheye_track_truth import rotation_from_quaternion  # noqa: E402


class WallDataset:
    def __init__(self, d):
        self.d = d
        camera = yaml.safe_load(open(f"{d}/camera.yaml"))
        if camera["model"] != "pinhole-radtan":
            sys.exit(f"{d}/camera.yaml: model {camera['model']}, this needs pinhole-radtan")
        fx, fy, cx, cy, k1, k2, p1, p2, k3 = camera["params"]
        self.focal = fx
        self.K = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1.0]])
        self.D = np.array([k1, k2, p1, p2, k3])
        self.radius = float(yaml.safe_load(open(f"{d}/scene.yaml"))["radius"])
        self.truth = np.loadtxt(f"{d}/groundtruth.tum")
        gain = cv2.imread(f"{d}/gain_mask.png", cv2.IMREAD_UNCHANGED).astype(np.float32)
        self.gain = np.maximum(gain / gain.max(), 0.01)

    def image(self, i, blur):
        grey = cv2.imread(f"{self.d}/images/{i:06d}.png", cv2.IMREAD_GRAYSCALE)
        if grey is None:
            sys.exit(f"{self.d}/images/{i:06d}.png: cannot be read")
        grey = grey.astype(np.float32) / self.gain
        if blur > 0:
            grey = cv2.GaussianBlur(grey, (0, 0), blur)
        return np.clip(grey, 0, 255).astype(np.uint8)

    def normalised(self, pixels):
        return cv2.undistortPoints(pixels.reshape(-1, 1, 2).astype(np.float64), self.K,
                                   self.D).reshape(-1, 2)

    def true_pixels(self, pixels, i, j):
        """Where the wall points that frame i's pixels see lie in frame j."""
        if len(pixels) == 0:
            return np.zeros((0, 2))
        rays = np.hstack([self.normalised(pixels), np.ones((len(pixels), 1))])
        rotation_i, origin = rotation_from_quaternion(*self.truth[i, 4:8]), self.truth[i, 1:4]
        direction = rays @ rotation_i.T
        a = direction[:, 0]**2 + direction[:, 1]**2
        b = 2 * (origin[0] * direction[:, 0] + origin[1] * direction[:, 1])
        c = origin[0]**2 + origin[1]**2 - self.radius**2
        wall = origin + direction * ((-b + np.sqrt(b * b - 4 * a * c)) / (2 * a))[:, None]
        rotation_j, origin_j = rotation_from_quaternion(*self.truth[j, 4:8]), self.truth[j, 1:4]
        in_j = (wall - origin_j) @ rotation_j
        projected, _ = cv2.projectPoints(in_j.reshape(-1, 1, 3), np.zeros(3), np.zeros(3),
                                         self.K, self.D)
        return projected.reshape(-1, 2)

    def ransac_inliers(self, first, second):
        if len(first) < 6:
            return np.zeros(len(first), bool)
        _, mask = cv2.findEssentialMat(self.normalised(first), self.normalised(second), np.eye(3),
                                       cv2.RANSAC, 0.999, 1.0 / self.focal)
        return mask.ravel().astype(bool) if mask is not None else np.zeros(len(first), bool)


def corners(grey):
    found = cv2.goodFeaturesToTrack(grey, 600, 0.01, 8, blockSize=5, useHarrisDetector=True)
    return np.zeros((0, 2), np.float32) if found is None else found.reshape(-1, 2)


def sift_matches(sift, first_image, second_image, first, second):
    def described(image, points):
        keypoints = [cv2.KeyPoint(float(x), float(y), 4.0) for x, y in points]
        return sift.compute(image, keypoints)

    first_keys, first_descriptors = described(first_image, first)
    second_keys, second_descriptors = described(second_image, second)
    if first_descriptors is None or second_descriptors is None or len(second_keys) < 2:
        return np.zeros((0, 2)), np.zeros((0, 2))
    matcher = cv2.BFMatcher(cv2.NORM_L2)
    forward = matcher.knnMatch(first_descriptors, second_descriptors, k=2)
    backward = matcher.knnMatch(second_descriptors, first_descriptors, k=1)
    pairs = [(m[0].queryIdx, m[0].trainIdx) for m in forward
             if len(m) == 2 and m[0].distance < 0.8 * m[1].distance
             and backward[m[0].trainIdx][0].trainIdx == m[0].queryIdx]
    return (np.array([first_keys[a].pt for a, _ in pairs]).reshape(-1, 2),
            np.array([second_keys[b].pt for _, b in pairs]).reshape(-1, 2))


def lucas_kanade(first_image, second_image, first, window, levels=3, starts=None):
    """Where Lucas-Kanade takes the first image's patches in the second (from `starts` when given,
    else from the points themselves), kept if the way back returns within 0.5 px."""
    if len(first) == 0:
        return first, first
    first = first.astype(np.float32)
    size = (window, window)
    flags = 0 if starts is None else cv2.OPTFLOW_USE_INITIAL_FLOW
    start = None if starts is None else starts.astype(np.float32).copy()
    tracked, forward, _ = cv2.calcOpticalFlowPyrLK(first_image, second_image, first, start,
                                                   winSize=size, maxLevel=levels, flags=flags)
    back, backward, _ = cv2.calcOpticalFlowPyrLK(second_image, first_image, tracked, first.copy(),
                                                 winSize=size, maxLevel=levels,
                                                 flags=cv2.OPTFLOW_USE_INITIAL_FLOW)
    kept = (forward.ravel() == 1) & (backward.ravel() == 1) & (
        np.linalg.norm(back - first, axis=1) < 0.5)
    return first[kept], tracked[kept]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--gaps", default="1,4,11", help="frames between the two images")
    parser.add_argument("--window", type=int, default=41, help="Lucas-Kanade window (px)")
    parser.add_argument("--blur", type=float, default=0.0, help="Gaussian blur sigma (px)")
    parser.add_argument("--pairs", type=int, default=12, help="image pairs per gap")
    args = parser.parse_args()
    warnings.filterwarnings("ignore", "All-NaN slice")  # a gap where nothing matched
    data = WallDataset(args.dataset)
    sift = cv2.SIFT_create()
    gaps = [int(g) for g in args.gaps.split(",")]
    # The first leg only, away from the start and the turnaround.
    last = len(data.truth) // 2 - max(gaps) - 10
    starts = np.linspace(10, last, args.pairs).astype(int)
    print(f"{args.dataset}: blur {args.blur} px, Lucas-Kanade window {args.window} px, "
          f"{args.pairs} pairs a gap; medians over the pairs")
    for gap in gaps:
        rows = []
        for i in starts:
            j = i + gap
            first_image, second_image = data.image(i, args.blur), data.image(j, args.blur)
            first = corners(first_image)
            row = [np.median(np.linalg.norm(data.true_pixels(first, i, j) - first, axis=1))]
            matched = sift_matches(sift, first_image, second_image, first, corners(second_image))
            # The refinement: from each matched corner, on the full-resolution level alone.
            refined = lucas_kanade(first_image, second_image, matched[0], 21, 0, matched[1])
            for a, b in (matched, refined,
                         lucas_kanade(first_image, second_image, first, args.window)):
                inlier = data.ransac_inliers(a, b)
                truth = data.true_pixels(a, i, j)
                error = np.linalg.norm(b - truth, axis=1)
                flow = truth - a
                # Along the true flow, over it: 1 is right, below 1 a track that fell short.
                ratio = np.sum((b - a) * flow, 1) / np.maximum(np.sum(flow * flow, 1), 1e-9)
                row += [inlier.sum(), (inlier & (error < 1.0)).sum(),
                        np.median(error[inlier]) if inlier.any() else np.nan,
                        np.mean(ratio[inlier]) - 1 if inlier.any() else np.nan]
            rows.append(row)
        m = np.nanmedian(np.array(rows, dtype=float), axis=0)
        print(f"  gap {gap:2d} (flow {m[0]:5.1f} px):")
        for k, name in enumerate(("SIFT", "SIFT refined by Lucas-Kanade", "Lucas-Kanade")):
            c = m[1 + 4 * k: 5 + 4 * k]
            print(f"    {name:<29} {c[0]:4.0f} inliers, {c[1]:4.0f} right, error {c[2]:5.2f} px, "
                  f"flow bias {100 * c[3]:+6.2f} %")


if __name__ == "__main__":
    main()
