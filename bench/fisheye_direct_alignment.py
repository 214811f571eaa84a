#!/usr/bin/env python3
"""What a measurement that pools the whole wall gives on a straight fisheye dataset: each frame
aligned as a whole to a key frame on the pipe's known cylinder (docs/conditions.md, "Fisheye
straight pipe"). A research prototype, not the product's code.

Every STRIDE-th pixel of the key frame within the colatitude band (--min-angle, --max-angle) is
cast onto the cylinder (radius from dataset.yaml, the axis the scene's z axis) from the key
frame's pose, and projected into the current frame; the residual is the difference of the two
frames' flat-fielded grey values there (each frame divided by the gain mask, then by its Gaussian
blur of --flat-field px, less one, smoothed by --smooth px). Levenberg-Marquardt with a Huber
loss over the current frame's six degrees of freedom and the key frame's tilt and offset across
the pipe (its position along the axis and its roll fix the gauge), the latter held to their last
values by a prior (--prior-offset-mm, --prior-tilt-deg): one frame's tilt and offset are hardly
observable from two views of faint texture. A new key frame every --key-step frames. The first
pose is the truth's; the rest are chained. Prints, every 20 frames, the distance error along the
axis, the camera's offset error across it and the orientation error.
--bowl instead: at key frames 30, 60, 90, 120 and 150 and steps of 1 and 5 frames, both poses
the truth's but the current one moved along the axis by up to 15 % of the step, the mean squared
residual; prints where a parabola through it has its minimum (0 % is the truth) and how much
deeper the bowl is than its bottom at its edges.
Needs a `fisheye-poly` camera and a straight scene along z (the fisheye1 set-up of
bench/conditions.sh and bench/fisheye_texture_sweep.sh), numpy, SciPy, OpenCV and PyYAML
(Debian: python3-numpy python3-scipy python3-opencv python3-yaml).
Usage: bench/fisheye_direct_alignment.py DATASET [--frames N] [--key-step 3]
"""
import argparse

import cv2
import numpy as np
import yaml
from scipy.spatial.transform import Rotation


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--key-step", type=int, default=3)
    parser.add_argument("--stride", type=int, default=3, help="key-frame pixels sampled, px")
    parser.add_argument("--min-angle", type=float, default=45.0)
    parser.add_argument("--max-angle", type=float, default=85.0)
    parser.add_argument("--flat-field", type=float, default=6.0)
    parser.add_argument("--smooth", type=float, default=3.0)
    parser.add_argument("--prior-offset-mm", type=float, default=1.0)
    parser.add_argument("--prior-tilt-deg", type=float, default=0.3)
    parser.add_argument("--bowl", action="store_true")
    args = parser.parse_args()
    d = args.dataset
    manifest = yaml.safe_load(open(f"{d}/dataset.yaml"))
    camera = yaml.safe_load(open(f"{d}/{manifest['camera']}"))
    if camera["model"] != "fisheye-poly":
        raise SystemExit(f"{d}: camera model {camera['model']}, this needs fisheye-poly")
    k = np.array(camera["params"][:4], dtype=float)
    u0, v0 = camera["params"][4:6]
    width, height = camera["width"], camera["height"]
    radius = float(manifest["pipe"]["inner_radius_m"])
    truth = np.loadtxt(f"{d}/{manifest['groundtruth']}")
    gain = cv2.imread(f"{d}/{manifest['gain_mask']}", cv2.IMREAD_UNCHANGED).astype(np.float32)
    gain /= 65535.0 if gain.max() > 255 else 255.0
    sigma_offset = args.prior_offset_mm * 1e-3
    sigma_tilt = np.radians(args.prior_tilt_deg)
    band = (args.min_angle, args.max_angle)

    def pose(i):
        return Rotation.from_quat(truth[i, 4:8]).as_matrix(), truth[i, 1:4].copy()

    def r_of_theta(theta):  # 001 eq. 1
        return theta * (k[0] + theta**2 * (k[1] + theta * (k[2] + theta * k[3])))

    def project(points_cam):
        x, y, z = points_cam[:, 0], points_cam[:, 1], points_cam[:, 2]
        rho = np.sqrt(x * x + y * y) + 1e-12
        theta = np.arctan2(rho, z)
        scale = r_of_theta(theta) / rho
        return np.stack([scale * x + u0, scale * y + v0], -1), np.degrees(theta)

    # The key frame's sample pixels and their bearings, once: the grid is the same in every frame.
    ys, xs = np.mgrid[0:height:args.stride, 0:width:args.stride]
    xs, ys = xs.ravel().astype(float), ys.ravel().astype(float)
    radial = np.hypot(xs - u0, ys - v0)
    theta = radial / k[0]
    for _ in range(20):  # Newton on r(theta) = radial
        slope = k[0] + 3 * k[1] * theta**2 + 4 * k[2] * theta**3 + 5 * k[3] * theta**4
        theta -= (r_of_theta(theta) - radial) / slope
    keep = (np.degrees(theta) > band[0]) & (np.degrees(theta) < band[1])
    xs, ys, theta = xs[keep], ys[keep], theta[keep]
    azimuth = np.arctan2(ys - v0, xs - u0)
    bearings = np.stack([np.sin(theta) * np.cos(azimuth), np.sin(theta) * np.sin(azimuth),
                         np.cos(theta)], -1)
    pixels = np.stack([xs, ys], -1)

    def flat_fielded(i):
        image = cv2.imread(f"{d}/images/{i:06d}.png", cv2.IMREAD_UNCHANGED).astype(np.float32)
        corrected = image / np.maximum(gain, 0.05)
        low = cv2.GaussianBlur(corrected, (0, 0), args.flat_field)
        result = corrected / np.maximum(low, 1) - 1.0
        if args.smooth > 0:
            result = cv2.GaussianBlur(result, (0, 0), args.smooth)
        result[(gain < 0.12) | (image > 250)] = np.nan
        return result

    def sample(image, at):
        n = len(at)
        cols = 1024
        rows = (n + cols - 1) // cols
        grid = np.full((rows * cols, 2), -10.0, np.float32)
        grid[:n] = at
        grid = grid.reshape(rows, cols, 2)
        values = cv2.remap(image, grid[..., 0], grid[..., 1], cv2.INTER_LINEAR,
                           borderMode=cv2.BORDER_CONSTANT, borderValue=np.nan)
        return values.ravel()[:n]

    def wall_points(world_from_key, key_position, index):
        directions = bearings[index] @ world_from_key.T
        a = directions[:, 0]**2 + directions[:, 1]**2
        b = 2 * (key_position[0] * directions[:, 0] + key_position[1] * directions[:, 1])
        c = key_position[0]**2 + key_position[1]**2 - radius**2
        along = (-b + np.sqrt(np.maximum(b * b - 4 * a * c, 0))) / (2 * a)
        return key_position + along[:, None] * directions

    def moved(rotation, position, delta):  # delta: rotation vector (camera frame), translation
        return rotation @ Rotation.from_rotvec(delta[:3]).as_matrix(), position + delta[3:]

    class Key:
        def __init__(self, rotation, position, image):
            self.rotation, self.position = rotation, position
            self.prior_rotation, self.prior_position = rotation.copy(), position.copy()
            values = sample(image, pixels)
            self.index = np.where(np.isfinite(values))[0]
            self.values = values[self.index]

    def poses_of(key, current, x):  # x: key tilt (2), key offset (2), current (6)
        key_rotation, key_position = moved(key.rotation, key.position,
                                           np.array([x[0], x[1], 0, x[2], x[3], 0]))
        rotation, position = moved(current[0], current[1], x[4:10])
        return key_rotation, key_position, rotation, position

    def residuals(key, image, key_rotation, key_position, rotation, position):
        points = wall_points(key_rotation, key_position, key.index)
        at, angle = project((points - position) @ rotation)
        values = sample(image, at)
        values[(angle < band[0]) | (angle > band[1])] = np.nan
        return values - key.values

    def prior(key, key_rotation, key_position):
        tilt = Rotation.from_matrix(key.prior_rotation.T @ key_rotation).as_rotvec()
        offset = key_position - key.prior_position
        return np.array([tilt[0] / sigma_tilt, tilt[1] / sigma_tilt, offset[0] / sigma_offset,
                         offset[1] / sigma_offset])

    def huber(r, c):
        a = np.abs(r)
        return np.where(a < c, 0.5 * r * r, c * (a - 0.5 * c))

    def align(key, image, rotation, position, iterations=15, step=2e-4):
        current = (rotation.copy(), position.copy())
        damping, c = 1e-2, None

        def cost(x):
            poses = poses_of(key, current, x)
            r = residuals(key, image, *poses)
            r = r[np.isfinite(r)]
            return np.sum(huber(r, c)) / (c * c) + 0.5 * np.sum(prior(key, *poses[:2])**2)

        for _ in range(iterations):
            zero = np.zeros(10)
            poses = poses_of(key, current, zero)
            r0, p0 = residuals(key, image, *poses), prior(key, *poses[:2])
            jacobian, prior_jacobian = np.zeros((len(r0), 10)), np.zeros((4, 10))
            for j in range(10):
                delta = np.zeros(10)
                delta[j] = step
                plus, minus = poses_of(key, current, delta), poses_of(key, current, -delta)
                jacobian[:, j] = (residuals(key, image, *plus) -
                                  residuals(key, image, *minus)) / (2 * step)
                prior_jacobian[:, j] = (prior(key, *plus[:2]) - prior(key, *minus[:2])) / (2 * step)
            ok = np.isfinite(r0) & np.all(np.isfinite(jacobian), 1)
            r, jo = r0[ok], jacobian[ok]
            if c is None:
                c = 1.345 * 1.4826 * np.median(np.abs(r))
            w = np.where(np.abs(r) < c, 1.0, c / np.maximum(np.abs(r), 1e-12)) / (c * c)
            normal = jo.T @ (jo * w[:, None]) + prior_jacobian.T @ prior_jacobian
            gradient = jo.T @ (w * r) + prior_jacobian.T @ p0
            before = cost(zero)
            for _ in range(8):
                dx = -np.linalg.solve(normal + damping * np.diag(np.diag(normal)) +
                                      1e-12 * np.eye(10), gradient)
                if cost(dx) < before:
                    key_rotation, key_position, rotation, position = poses_of(key, current, dx)
                    key.rotation, key.position, current = key_rotation, key_position, (rotation,
                                                                                       position)
                    damping = max(damping / 3, 1e-5)
                    break
                damping *= 4
            else:
                break
            if np.abs(dx).max() < 1e-6:
                break
        return current

    if args.bowl:
        for step in (1, 5):
            for k0 in (30, 60, 90, 120, 150):
                key = Key(*pose(k0), flat_fielded(k0))
                image = flat_fielded(k0 + step)
                true_rotation, true_position = pose(k0 + step)
                length = true_position[2] - key.position[2]
                shifts = np.linspace(-0.15, 0.15, 13) * length
                costs = []
                for shift in shifts:
                    r = residuals(key, image, key.rotation, key.position, true_rotation,
                                  true_position + np.array([0, 0, shift]))
                    costs.append(np.mean(r[np.isfinite(r)]**2))
                costs = np.array(costs)
                a, b, _ = np.polyfit(shifts, costs, 2)
                print(f"key frame {k0}, step {step}: minimum at {100 * (-b / (2 * a)) / length:+.2f} % "
                      f"of the step, the bowl {100 * (costs.max() / costs.min() - 1):.1f} % deeper "
                      f"at its edges")
        return
    rotation, position = pose(0)
    start = position.copy()
    key = Key(rotation, position, flat_fielded(0))
    history = [position.copy()]
    last = min(args.frames, len(truth))
    for i in range(1, last):
        image = flat_fielded(i)
        velocity = history[-1] - history[-2] if len(history) > 1 else np.array([0, 0, 0.01])
        rotation, position = align(key, image, rotation, history[-1] + velocity)
        history.append(position.copy())
        if i % args.key_step == 0:
            key = Key(rotation, position, image)
        if i % 20 == 0 or i == last - 1:
            true_rotation, true_position = pose(i)
            error = 100 * ((position[2] - start[2]) / (true_position[2] - start[2]) - 1)
            offset = 1000 * (position[:2] - true_position[:2])
            turn = np.degrees(Rotation.from_matrix(rotation.T @ true_rotation).as_rotvec())
            print(f"frame {i}: distance {error:+.3f} %, offset error ({offset[0]:+.2f}, "
                  f"{offset[1]:+.2f}) mm, orientation error ({turn[0]:+.2f}, {turn[1]:+.2f}, "
                  f"{turn[2]:+.2f}) deg", flush=True)


if __name__ == "__main__":
    main()
