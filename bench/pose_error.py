#!/usr/bin/env python3
"""Compare a run's loop-closure transforms with ground-truth camera poses.

Usage: bench/pose_error.py RUN.csv POSES [--every N --offset K]

RUN.csv is `memloop run --out`; its rel_* columns give, for each accepted loop closure,
x_match = R x_query + t (query camera to matched camera). POSES gives each image's camera pose
in a world frame: a CSV with a row per image, file,...,tx,ty,tz,qx,qy,qz,qw (tum_fr1_rpy's
poses.csv), or a TUM trajectory, 'time tx ty tz qx qy qz qw' lines, matched to the run's time
stamps (a generated TUM folder's groundtruth.txt). The true relative pose is inverse(T_match) * T_query. Prints the share of loop
closures with a metric pose and the median and 95th percentile of the rotation (degrees) and
translation (metres) errors; --every/--offset keep only the loop closures whose query image
index is offset modulo every (to check on frames not tuned on). Exits 1 when there is none.
"""
import argparse
import csv
import math
import os
import sys


def quat_to_matrix(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
    return [
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
    ]


def transpose(m):
    return [[m[j][i] for j in range(3)] for i in range(3)]


def multiply(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def rotation_angle_degrees(m):
    cosine = max(-1.0, min(1.0, (m[0][0] + m[1][1] + m[2][2] - 1) / 2))
    return math.degrees(math.acos(cosine))


def percentile(values, fraction):
    ordered = sorted(values)
    position = fraction * (len(ordered) - 1)
    low = int(math.floor(position))
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (position - low)


def load_trajectory(path):
    poses = {}
    with open(path) as handle:
        for line in handle:
            fields = line.split()
            if not fields or fields[0].startswith("#"):
                continue
            values = [float(v) for v in fields]
            poses[round(values[0], 3)] = (quat_to_matrix(*values[4:8]), values[1:4])
    return poses


def load_poses(path):
    poses = {}
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            rotation = quat_to_matrix(*(float(row[k]) for k in ("qx", "qy", "qz", "qw")))
            translation = [float(row[k]) for k in ("tx", "ty", "tz")]
            poses[os.path.basename(row["file"])] = (rotation, translation)
    return poses


def true_relative(pose_query, pose_match):
    """inverse(T_match) * T_query: maps query-camera points to matched-camera points."""
    r_q, t_q = pose_query
    r_m, t_m = pose_match
    r_m_inv = transpose(r_m)
    rotation = multiply(r_m_inv, r_q)
    translation = apply(r_m_inv, [t_q[i] - t_m[i] for i in range(3)])
    return rotation, translation


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_csv")
    parser.add_argument("poses")
    parser.add_argument("--every", type=int, default=1)
    parser.add_argument("--offset", type=int, default=0)
    args = parser.parse_args()

    with open(args.run_csv, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if args.poses.endswith(".csv"):
        poses = load_poses(args.poses)
        names = {row["image"]: os.path.basename(row["name"]) for row in rows}
    else:  # by time stamp, to the millisecond
        poses = load_trajectory(args.poses)
        names = {row["image"]: round(float(row["timestamp"]), 3) for row in rows}
    loops = [r for r in rows if r["matched_image"] not in ("", "-1")
             and int(r["image"]) % args.every == args.offset]
    metric = [r for r in loops if r["rel_metric"] == "1"]
    rotation_errors, translation_errors = [], []
    for row in metric:
        query, match = names[row["image"]], names[row["matched_image"]]
        if query not in poses or match not in poses:
            continue
        true_rotation, true_translation = true_relative(poses[query], poses[match])
        rotation = quat_to_matrix(*(float(row["rel_" + k]) for k in ("qx", "qy", "qz", "qw")))
        translation = [float(row["rel_" + k]) for k in ("tx", "ty", "tz")]
        rotation_errors.append(rotation_angle_degrees(multiply(transpose(true_rotation), rotation)))
        translation_errors.append(math.dist(translation, true_translation))

    print(f"loop closures: {len(loops)}; with a metric pose: {len(metric)} "
          f"({100.0 * len(metric) / max(1, len(loops)):.1f}%); compared: {len(rotation_errors)}")
    if not rotation_errors:
        return 1
    print(f"rotation error (deg): median {percentile(rotation_errors, 0.5):.2f}, "
          f"95th {percentile(rotation_errors, 0.95):.2f}, max {max(rotation_errors):.2f}")
    print(f"translation error (m): median {percentile(translation_errors, 0.5):.4f}, "
          f"95th {percentile(translation_errors, 0.95):.4f}, max {max(translation_errors):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
