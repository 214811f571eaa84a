#!/usr/bin/env python3
"""How well pyramidal Lucas-Kanade follows the wall in a straight fisheye dataset, against the
truth (docs/conditions.md, "Fisheye straight pipe").

A re-creation of the steps of `map`'s tracker with OpenCV (not the product's code): corners by
Harris in the image's four quarters (200 each, 7 px apart, 7 px window) within `--max-angle` of
the optical axis, both frames divided by their Gaussian blur (`--flat-field` px), followed into
the next frame and back, kept when the round trip returns within `--round-trip` px. Each corner
is cast onto the scene's cylinder from the frame's true pose (groundtruth.tum) and projected into
the next frame: that is where it should go. Prints, over frame pairs every 15 frames: the tracks
kept a frame, those within 2 px of the truth, and the quartiles of the flow ratio (the track's
displacement along the true flow over the true flow; 1 is right).
`--guess-scale S` starts each search at S times the true flow instead of at the corner (what a
perfect or a biased prediction would give), so one sees whether a search leaves its start.
Needs a `fisheye-poly` camera and a straight scene along z (the fisheye1 set-up of
bench/conditions.sh and bench/fisheye_texture_sweep.sh). Needs numpy, OpenCV and PyYAML
(Debian: python3-numpy python3-opencv python3-yaml).
Usage: bench/fisheye_track_truth.py DATASET [--window 21] [--levels 3] [--guess-scale S] [--blur B]
"""
import argparse
import sys

import cv2
import numpy as np
import yaml


def rotation_from_quaternion(qx, qy, qz, qw):
    return np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])


class FisheyePoly:
    """001 eq. 1: r(theta) = k1 theta + k2 theta^3 + k3 theta^4 + k4 theta^5."""

    def __init__(self, params):
        self.k1, self.k2, self.k3, self.k4, self.u0, self.v0 = params
        self.thetas = np.linspace(0.0, 1.65, 20000)
        self.radii = self.radius(self.thetas)

    def radius(self, theta):
        return self.k1 * theta + self.k2 * theta**3 + self.k3 * theta**4 + self.k4 * theta**5

    def project(self, points):
        rho = np.maximum(np.linalg.norm(points[:, :2], axis=1), 1e-12)
        r = self.radius(np.arctan2(rho, points[:, 2]))
        return np.stack([self.u0 + r * points[:, 0] / rho, self.v0 + r * points[:, 1] / rho], 1)

    def unproject(self, pixels):
        du, dv = pixels[:, 0] - self.u0, pixels[:, 1] - self.v0
        r = np.maximum(np.hypot(du, dv), 1e-12)
        theta = np.interp(r, self.radii, self.thetas)
        s = np.sin(theta)
        return np.stack([s * du / r, s * dv / r, np.cos(theta)], 1), theta


def load_fisheye_dataset(d):
    """A simulated dataset's fisheye-poly camera, scene radius, ground truth rows, image size."""
    camera_yaml = yaml.safe_load(open(f"{d}/camera.yaml"))
    if camera_yaml["model"] != "fisheye-poly":
        sys.exit(f"{d}/camera.yaml: model {camera_yaml['model']}, this needs fisheye-poly")
    camera = FisheyePoly(camera_yaml["params"])
    radius = float(yaml.safe_load(open(f"{d}/scene.yaml"))["radius"])
    truth = np.loadtxt(f"{d}/groundtruth.tum")
    return camera, radius, truth, camera_yaml["width"], camera_yaml["height"]


def cylinder_wall_and_next_pixels(camera, truth, radius, pixels, i, j):
    """The wall points the pixels of frame i see on the cylinder along z through the origin, from
    the true pose of frame i, and where they lie in frame j (groundtruth.tum rows)."""
    def pose(k):
        return rotation_from_quaternion(*truth[k, 4:8]), truth[k, 1:4]

    bearings, _ = camera.unproject(pixels)
    rotation, origin = pose(i)
    direction = bearings @ rotation.T
    a = direction[:, 0]**2 + direction[:, 1]**2
    b = 2 * (origin[0] * direction[:, 0] + origin[1] * direction[:, 1])
    c = origin[0]**2 + origin[1]**2 - radius**2
    wall = origin + ((-b + np.sqrt(b * b - 4 * a * c)) / (2 * a))[:, None] * direction
    rotation_j, origin_j = pose(j)
    return wall, camera.project((wall - origin_j) @ rotation_j)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--window", type=int, default=21)
    parser.add_argument("--levels", type=int, default=3)
    parser.add_argument("--round-trip", type=float, default=0.5)
    parser.add_argument("--flat-field", type=float, default=8.0)
    parser.add_argument("--max-angle", type=float, default=70.0)
    parser.add_argument("--blur", type=float, default=0.0, help="Gaussian blur after the flat field")
    parser.add_argument("--guess-scale", type=float, default=None)
    args = parser.parse_args()
    d = args.dataset
    camera, radius, truth, width, height = load_fisheye_dataset(d)

    def true_pixels(pixels, i, j):
        return cylinder_wall_and_next_pixels(camera, truth, radius, pixels, i, j)[1]

    def followed_image(grey):
        image = grey.astype(np.float32)
        blur = cv2.GaussianBlur(image, (0, 0), args.flat_field)
        image = np.clip(128 * image / np.maximum(blur, 1), 0, 255).astype(np.uint8)
        return cv2.GaussianBlur(image, (0, 0), args.blur) if args.blur > 0 else image

    ys, xs = np.mgrid[0:height, 0:width]
    _, theta = camera.unproject(np.stack([xs.ravel(), ys.ravel()], 1).astype(np.float64))
    mask = (theta.reshape(height, width) < np.radians(args.max_angle)).astype(np.uint8) * 255
    mask = cv2.erode(mask, np.ones((31, 31), np.uint8))
    window = (args.window, args.window)
    kept, near, ratios, pairs = 0, 0, [], 0
    for i in range(20, len(truth) - 1, 15):
        a = cv2.imread(f"{d}/images/{i:06d}.png", cv2.IMREAD_GRAYSCALE)
        b = cv2.imread(f"{d}/images/{i + 1:06d}.png", cv2.IMREAD_GRAYSCALE)
        corners = []
        for qy in range(2):
            for qx in range(2):
                quarter = np.zeros_like(mask)
                rows = slice(qy * height // 2, (qy + 1) * height // 2)
                cols = slice(qx * width // 2, (qx + 1) * width // 2)
                quarter[rows, cols] = mask[rows, cols]
                found = cv2.goodFeaturesToTrack(a, 200, 1e-6, 7, mask=quarter, blockSize=7,
                                                useHarrisDetector=True, k=0.04)
                if found is not None:
                    corners.append(found.reshape(-1, 2))
        p = np.concatenate(corners).astype(np.float32)
        fa, fb = followed_image(a), followed_image(b)
        truth_j = true_pixels(p.astype(np.float64), i, i + 1)
        if args.guess_scale is None:
            q, forward, _ = cv2.calcOpticalFlowPyrLK(fa, fb, p, None, winSize=window,
                                                     maxLevel=args.levels)
        else:
            guess = (p + args.guess_scale * (truth_j - p)).astype(np.float32)
            q, forward, _ = cv2.calcOpticalFlowPyrLK(fa, fb, p, guess, winSize=window,
                                                     maxLevel=args.levels,
                                                     flags=cv2.OPTFLOW_USE_INITIAL_FLOW)
        back, backward, _ = cv2.calcOpticalFlowPyrLK(fb, fa, q, p.copy(), winSize=window,
                                                     maxLevel=args.levels,
                                                     flags=cv2.OPTFLOW_USE_INITIAL_FLOW)
        ok = (forward.ravel() == 1) & (backward.ravel() == 1) & (
            np.linalg.norm(back - p, axis=1) < args.round_trip)
        flow = truth_j - p
        ratio = np.sum((q - p) * flow, 1) / np.sum(flow * flow, 1)
        kept += ok.sum()
        near += (ok & (np.linalg.norm(q - truth_j, axis=1) < 2.0)).sum()
        ratios += list(ratio[ok])
        pairs += 1
    quartiles = np.percentile(ratios, [25, 50, 75]) if ratios else [np.nan] * 3
    print(f"{d}: {pairs} frame pairs; tracks kept a frame {kept / pairs:.1f}, within 2 px of the "
          f"truth {near / pairs:.1f}; flow ratio quartiles {quartiles[0]:.3f} {quartiles[1]:.3f} "
          f"{quartiles[2]:.3f}")


if __name__ == "__main__":
    main()
