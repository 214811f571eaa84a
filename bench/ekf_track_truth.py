#!/usr/bin/env python3
"""How well the tubular EKF's tracker follows the wall of a fisheye tube-bend dataset, against
the truth, by the angle off the optical axis (docs/ekf.md, "Wide fisheyes").

A re-creation of the tracker's steps with OpenCV (not the product's code): the frame divided by
the gain mask, then by its Gaussian blur (`--flat-field`, a share of the width), corners by
cv.goodFeaturesToTrack inside the lit view (the model's field of view where the gain mask is at
least 5 % of its brightest) shrunk by `--margin` px, pyramidal Lucas-Kanade (21 px window, 3
levels) into the next frame and back, kept when the round trip returns within 0.5 px. Each
corner is cast onto the first straight's cylinder (along z, through the origin) from the frame's
true pose and projected into the next frame: that is where it should go. Only wall points on the
straight leg (z < 0.95 m) count. Prints per band of angles: the tracks kept, the median and mean
flow ratio (the track's displacement along the true flow over the true flow; 1 is right) and the
median and 90th percentile of the distance from the truth.
Needs numpy, OpenCV and PyYAML (Debian: python3-numpy python3-opencv python3-yaml).
`--warp-truth`: the next frame is this one warped by the truth instead of the rendered one (each
pixel of the next frame takes this frame's grey value where its wall point lies here), so the
shading moves with the wall: what Lucas-Kanade itself does, without the shading that stays put.
Usage: bench/ekf_track_truth.py DATASET [--margin 33] [--frames 250] [--flat-field 0.023]
       [--warp-truth]
"""
import argparse
import os
import sys

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fisheye_track_truth import cylinder_wall_and_next_pixels, load_fisheye_dataset  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--margin", type=int, default=22, help="px inside the lit view's edge")
    parser.add_argument("--frames", type=int, default=250)
    parser.add_argument("--flat-field", type=float, default=0.05)
    parser.add_argument("--warp-truth", action="store_true",
                        help="track into this frame warped by the truth, not the next rendered one")
    args = parser.parse_args()
    d = args.dataset
    camera, radius, truth, width, height = load_fisheye_dataset(d)
    gain = cv2.imread(f"{d}/gain_mask.png", cv2.IMREAD_UNCHANGED).astype(np.float32)
    gain /= gain.max()
    ys, xs = np.mgrid[0:height, 0:width]
    grid = np.stack([xs.ravel(), ys.ravel()], 1).astype(np.float64)
    _, theta = camera.unproject(grid)
    view = ((theta.reshape(height, width) < np.radians(95)) & (gain >= 0.05)).astype(np.uint8)
    size = 2 * args.margin + 1
    inner = cv2.erode(view * 255, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size)))
    sigma = args.flat_field * width

    def corrected(i):
        grey = cv2.imread(f"{d}/images/{i:06d}.png", cv2.IMREAD_GRAYSCALE).astype(np.float32)
        return np.clip(grey / np.maximum(gain, 0.01), 0, 255).astype(np.uint8)

    def followed(grey8):
        grey = grey8.astype(np.float32)
        if sigma <= 0:
            return grey8
        shading = cv2.GaussianBlur(grey, (0, 0), sigma)
        return np.clip(128 * grey / np.maximum(shading, 4), 0, 255).astype(np.uint8)

    bands = [0, 40, 60, 70, 80, 85, 90, 95]
    found = {k: [] for k in range(len(bands) - 1)}
    window = (21, 21)
    for i in range(5, min(args.frames, len(truth) - 1), 10):
        a, b = corrected(i), corrected(i + 1)
        if args.warp_truth:
            _, source = cylinder_wall_and_next_pixels(camera, truth, radius, grid, i + 1, i)
            source = np.nan_to_num(source.astype(np.float32), nan=-1.0)
            b = cv2.remap(a, source[:, 0].reshape(height, width),
                          source[:, 1].reshape(height, width), cv2.INTER_CUBIC)
        p = cv2.goodFeaturesToTrack(a, 600, 0.01, 10, mask=inner)
        if p is None:
            continue
        p = p.reshape(-1, 2).astype(np.float32)
        fa, fb = followed(a), followed(b)
        q, forward, _ = cv2.calcOpticalFlowPyrLK(fa, fb, p, None, winSize=window, maxLevel=3)
        back, backward, _ = cv2.calcOpticalFlowPyrLK(fb, fa, q, p.copy(), winSize=window,
                                                     maxLevel=3,
                                                     flags=cv2.OPTFLOW_USE_INITIAL_FLOW)
        ok = (forward.ravel() == 1) & (backward.ravel() == 1) & (
            np.linalg.norm(back - p, axis=1) < 0.5)
        wall, truth_j = cylinder_wall_and_next_pixels(camera, truth, radius,
                                                      p.astype(np.float64), i, i + 1)
        ok &= wall[:, 2] < 0.95
        _, angle = camera.unproject(p.astype(np.float64))
        angle = np.degrees(angle)
        flow = truth_j - p
        moving = np.linalg.norm(flow, axis=1) > 0.3
        ratio = np.sum((q - p) * flow, 1) / np.maximum(np.sum(flow * flow, 1), 1e-9)
        error = np.linalg.norm(q - truth_j, axis=1)
        for k in range(len(bands) - 1):
            chosen = ok & moving & (angle >= bands[k]) & (angle < bands[k + 1])
            found[k] += list(zip(ratio[chosen], error[chosen]))
    print(f"{d}: margin {args.margin} px, flat field {args.flat_field} of the width"
          + (", the next frame warped by the truth" if args.warp_truth else ""))
    for k in range(len(bands) - 1):
        rows = np.array(found[k])
        label = f"{bands[k]:3d}-{bands[k + 1]:3d} deg"
        if len(rows) == 0:
            print(f"  {label}: none kept")
            continue
        print(f"  {label}: {len(rows):5d} kept, flow ratio median {np.median(rows[:, 0]):.3f} "
              f"mean {np.mean(rows[:, 0]):.3f}, error median {np.median(rows[:, 1]):.3f} px "
              f"90th percentile {np.percentile(rows[:, 1], 90):.3f} px")


if __name__ == "__main__":
    main()
