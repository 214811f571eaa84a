#!/usr/bin/env python3
"""The loop closure's pose graph solved again, offline, with other standard deviations, to see
where a closure puts its correction without mapping the frames again (docs/fisheye_mapping.md,
"Where a closure bends the path"). An independent implementation of `map`'s graph
(pipeline/loop_closure_pass.cc OdometryGraphEdges, estimation/pose_graph.cc): its vertices are
the key frames as the T pass left them (RUN/keyframes_before_loop_closure.tum), its edges the
consecutive steps (a straight step no applied window spans gets --unconfirmed-factor times both
sigmas, a step into or inside a T section --t-step-r), optionally each T's turn from its P_r to its
P_b (--t-turn above 0, Huber's loss beyond --t-turn-huber sigmas, by reweighting), and the loop
edges run.json accepted (their relative pose: translation_m, rotation_vector_deg). The error is
[t_est - t_meas in the earlier frame; rotation vector of R_meas^T R_est], as `map`'s. The first
key frame is held. Solved by Levenberg-Marquardt, the Jacobian by finite differences over its
sparsity, each step by a sparse solve.

Printed: the graph's cost before and after (Ceres's convention, half the sum of squares), how far
the replay's key frames lie from RUN/keyframes.tum (the run's own closure: with the run's
settings this checks the replay), the turns between straight sections against the truth, each
adjusted T's distance to every other against scene.yaml (the T matched to the tee its red key
frame truly lies nearest), and the gap between the passages of each tee passed twice.
Needs numpy, scipy and PyYAML. Usage:
  bench/pose_graph_replay.py RUN_DIR DATASET_DIR [--step-t M] [--step-r DEG] [--t-step-r DEG]
      [--t-turn DEG] [--t-turn-huber K] [--unconfirmed-factor F] [--loop-t M] [--loop-r DEG]
      [--out TUM]
The defaults are `map`'s (loop_step_translation_sigma_m, loop_step_rotation_sigma_deg,
loop_t_step_rotation_sigma_deg, loop_t_turn_sigma_deg, loop_t_turn_huber_sigmas in a --config);
the graph before the twenty-sixth session: --step-r 0.05 --t-step-r 0.5 --t-turn 0.
"""
import argparse
import json
import sys

import numpy as np
import yaml
from scipy.optimize._numdiff import approx_derivative
from scipy.sparse import csr_matrix, diags, lil_matrix
from scipy.sparse.linalg import spsolve
from scipy.spatial.transform import Rotation

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from fisheye_section_turns import angle_deg, line_direction  # noqa: E402


def read_tum(path):
    rows = [[float(v) for v in line.split()] for line in open(path)
            if line.strip() and not line.startswith("#")]
    rows = np.array(rows)
    return rows[:, 0], rows[:, 1:4], Rotation.from_quat(rows[:, 4:8])


def build_edges(run, positions, rotations, args):
    """Edges as (from, to, translation, rotation, translation sigma, rotation sigma (rad), huber)."""
    count = len(positions)
    section_of = np.zeros(count, int)
    straight_sections = set()
    for section in run["sections"]:
        section_of[section["first_keyframe"]:section["last_keyframe"] + 1] = section["index"]
        if section["class"] == "straight":
            straight_sections.add(section["index"])
    confirmed = np.zeros(count, bool)
    for window in run["windows"]:
        if window["straight"] and not window["rejected"]:
            confirmed[window["first_keyframe"] + 1:window["last_keyframe"] + 1] = True
    deg = np.pi / 180.0
    edges = []

    def relative(i, j):
        return (rotations[i].inv().apply(positions[j] - positions[i]),
                rotations[i].inv() * rotations[j])

    for k in range(count - 1):
        t, r = relative(k, k + 1)
        if section_of[k + 1] not in straight_sections:
            sigmas = (args.step_t, args.t_step_r * deg)
        elif not confirmed[k + 1]:
            sigmas = (args.unconfirmed_factor * args.step_t,
                      args.unconfirmed_factor * args.step_r * deg)
        else:
            sigmas = (args.step_t, args.step_r * deg)
        edges.append((k, k + 1, t, r, *sigmas, 0.0))
    if args.t_turn > 0:
        for record in run["t_intersections"]:
            i, j = record.get("red_keyframe", -1), record.get("blue_keyframe", -1)
            if record["rejection"] or i < 0 or i >= j or j >= count:
                continue
            t, r = relative(i, j)
            edges.append((i, j, t, r, 1.0, args.t_turn * deg, args.t_turn_huber))
    loops = [e for e in run["loop_closure"]["edges"] if e["accepted"]]
    for edge in loops:
        if "rotation_vector_deg" not in edge:
            sys.exit("run.json's loop edges have no rotation_vector_deg (a run from before it was "
                     "recorded)")
        edges.append((edge["earlier_keyframe"], edge["later_keyframe"],
                      np.array(edge["translation_m"]),
                      Rotation.from_rotvec(np.array(edge["rotation_vector_deg"]) * deg),
                      args.loop_t, args.loop_r * deg, 0.0))
    return edges, len(loops)


def solve(positions, rotations, edges):
    count = len(positions)
    src = np.array([e[0] for e in edges])
    dst = np.array([e[1] for e in edges])
    t_meas = np.array([e[2] for e in edges])
    r_meas_inv = Rotation.concatenate([e[3] for e in edges]).inv()
    sigma = np.array([[e[4]] * 3 + [e[5]] * 3 for e in edges])
    huber = np.array([e[6] for e in edges])
    weights = np.ones(len(edges))

    def poses(x):
        x = x.reshape(count - 1, 6)
        p = positions.copy()
        p[1:] += x[:, :3]
        r = rotations[1:] * Rotation.from_rotvec(x[:, 3:])
        return p, Rotation.concatenate([rotations[:1], r])

    def whitened(x):
        p, r = poses(x)
        inv_from = r[src].inv()
        error = np.hstack([inv_from.apply(p[dst] - p[src]) - t_meas,
                           (r_meas_inv * inv_from * r[dst]).as_rotvec()])
        return error / sigma

    def residuals(x):
        return (whitened(x) * np.sqrt(weights)[:, None]).ravel()

    sparsity = lil_matrix((6 * len(edges), 6 * (count - 1)), dtype=int)
    for e, (a, b) in enumerate(zip(src, dst)):
        for v in (a, b):
            if v > 0:
                sparsity[6 * e:6 * e + 6, 6 * (v - 1):6 * v] = 1

    def cost(x):
        norms = np.linalg.norm(whitened(x), axis=1)
        rho = np.where((huber > 0) & (norms > huber), 2 * huber * norms - huber ** 2, norms ** 2)
        return 0.5 * rho.sum()

    x = np.zeros(6 * (count - 1))
    initial = cost(x)
    # Levenberg-Marquardt with a sparse solve (the chain's normal equations are banded but for
    # the loop edges); Huber's loss as reweighted squares, the weights renewed each iteration.
    damping = 1e-4
    for _ in range(100):
        norms = np.linalg.norm(whitened(x), axis=1)
        weights = np.where((huber > 0) & (norms > huber), huber / np.maximum(norms, 1e-12), 1.0)
        r0 = residuals(x)
        jacobian = csr_matrix(approx_derivative(residuals, x, method="2-point", f0=r0,
                                                sparsity=sparsity))
        normal = (jacobian.T @ jacobian).tocsc()
        gradient = jacobian.T @ r0
        diagonal = normal.diagonal()
        old = cost(x)
        while True:
            step = spsolve(normal + damping * diags(diagonal), -gradient)
            if cost(x + step) < old:
                x = x + step
                damping = max(damping / 10, 1e-12)
                break
            damping *= 10
            if damping > 1e8:
                break
        if damping > 1e8 or old - cost(x) < 1e-10 * old:
            break
    p, r = poses(x)
    return p, r, initial, cost(x)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run")
    parser.add_argument("dataset")
    parser.add_argument("--step-t", type=float, default=0.001)
    parser.add_argument("--step-r", type=float, default=0.01)
    parser.add_argument("--t-step-r", type=float, default=1.0)
    parser.add_argument("--t-turn", type=float, default=0.5)
    parser.add_argument("--t-turn-huber", type=float, default=0.5)
    parser.add_argument("--unconfirmed-factor", type=float, default=20.0)
    parser.add_argument("--loop-t", type=float, default=0.005)
    parser.add_argument("--loop-r", type=float, default=0.5)
    parser.add_argument("--out")
    args = parser.parse_args()

    run = json.load(open(f"{args.run}/run.json"))
    stamps, positions, rotations = read_tum(f"{args.run}/keyframes_before_loop_closure.tum")
    _, run_positions, run_rotations = read_tum(f"{args.run}/keyframes.tum")
    edges, loop_count = build_edges(run, positions, rotations, args)
    p, r, initial, final = solve(positions, rotations, edges)
    print(f"{len(positions)} key frames, {len(edges)} edges ({loop_count} loop); cost "
          f"{initial:.2f} -> {final:.2f}")
    print(f"replay against the run's own closure: positions {np.abs(p - run_positions).max() * 1000:.2f}"
          f" mm apart at most, rotations "
          f"{np.degrees((r.inv() * run_rotations).magnitude()).max():.3f} deg")
    if args.out:
        with open(args.out, "w") as out:
            out.write("# timestamp tx ty tz qx qy qz qw (world_from_cam, metres, seconds)\n")
            for s, pos, q in zip(stamps, p, r.as_quat()):
                out.write(f"{s:.9f} {' '.join(f'{v:.12g}' for v in (*pos, *q))}\n")

    truth_stamps, truth_positions, _ = read_tum(f"{args.dataset}/groundtruth.tum")
    row_of = {round(s, 6): i for i, s in enumerate(truth_stamps)}
    true_positions = truth_positions[[row_of[round(s, 6)] for s in stamps]]
    lines = []
    for section in run["sections"]:
        first, last = section["first_keyframe"], section["last_keyframe"]
        if section["class"] == "straight" and last - first >= 2:
            lines.append((section["index"], line_direction(p[first:last + 1]),
                          line_direction(true_positions[first:last + 1])))
    print("turn errors:", ", ".join(
        f"{a}->{b} {angle_deg(ea, eb) - angle_deg(ga, gb):+.3f} deg"
        for (a, ea, ga), (b, eb, gb) in zip(lines, lines[1:])))

    # Each adjusted T's centre moves with its P_r (as in `map`): back to before the run's
    # closure, then with the replay's correction.
    scene = yaml.safe_load(open(f"{args.dataset}/scene.yaml"))
    tees = {s["name"]: np.array(s["center"]) for s in scene["sections"] if s["type"] == "tee"}
    centres = []
    for record in run["t_intersections"]:
        if record["rejection"] or "center" not in record:
            continue
        k = record["red_keyframe"]
        before = rotations[k] * run_rotations[k].inv()  # R_before R_run^-1
        centre = positions[k] + before.apply(np.array(record["center"]) - run_positions[k])
        centre = p[k] + (r[k] * rotations[k].inv()).apply(centre - positions[k])
        name = min(tees, key=lambda n: np.linalg.norm(tees[n] - true_positions[k]))
        centres.append((name, record["section"], centre))
    for i, (name_a, section_a, a) in enumerate(centres):
        for name_b, section_b, b in centres[i + 1:]:
            if name_a == name_b:
                print(f"{name_a} (sections {section_a}, {section_b}): passages "
                      f"{np.linalg.norm(a - b) * 1000:.1f} mm apart")
                continue
            true = np.linalg.norm(tees[name_a] - tees[name_b])
            print(f"{name_a}-{name_b} (sections {section_a}, {section_b}): "
                  f"{(np.linalg.norm(a - b) - true) / true * 100:+.3f} % of {true:.4f} m")


if __name__ == "__main__":
    main()
