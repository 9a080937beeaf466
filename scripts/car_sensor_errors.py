#!/usr/bin/env python3
"""Where the nuScenes ATE comes from, per source: the forward distance and the heading of the radar
match, the Doppler motion, the car's wheels and its gyro, each against the ground truth.

Usage: scripts/car_sensor_errors.py DATAROOT STEPS_DIR
  STEPS_DIR holds <scene>.csv written by
  radar_odometry --format nuscenes --dataroot DATAROOT --scene <scene> --steps STEPS_DIR/<scene>.csv
Reads DATAROOT/can_bus/<scene>_{ms_imu,zoe_veh_info}.json (wheel radius 0.305 m).
"""
import csv, json, os, sys
import numpy as np


def integral(t, x, a, b):
    ts = np.concatenate([[a], t[(t > a) & (t < b)], [b]])
    xs = np.interp(ts, t, x)
    return float(np.sum(0.5 * (xs[1:] + xs[:-1]) * np.diff(ts)))


def arc(d, th):
    return np.array([d, 0.0, th]) if abs(th) < 1e-12 else np.array([d * np.sin(th) / th, d * (1 - np.cos(th)) / th, th])


def chain(motions):
    p = [np.zeros(3)]
    for m in motions:
        c, s = np.cos(p[-1][2]), np.sin(p[-1][2])
        p.append(p[-1] + np.array([c * m[0] - s * m[1], s * m[0] + c * m[1], m[2]]))
    return np.array(p)


def ate(est, gt):  # RMSE after the least-squares SE(2) alignment, as radar_eval --metric ate
    a, b = est[:, :2], gt[:, :2]
    ma, mb = a.mean(0), b.mean(0)
    u, _, vt = np.linalg.svd((a - ma).T @ (b - mb))
    r = vt.T @ np.diag([1, np.sign(np.linalg.det(vt.T @ u.T))]) @ u.T
    return float(np.sqrt(np.mean(np.sum(((r @ (a - ma).T).T + mb - b) ** 2, 1))))


def main(root, steps_dir):
    print("| scene | ATE, only the forward distance from: ours / Doppler / wheels | distance / ground truth: "
          "Doppler / match / wheels | yaw error std per cycle (rad): gyro / match |")
    print("|---|---|---|---|")
    for name in sorted(f[:-4] for f in os.listdir(steps_dir) if f.endswith(".csv")):
        rows = list(csv.DictReader(open(os.path.join(steps_dir, name + ".csv"))))[1:]
        t = np.array([int(r["timestamp_us"]) for r in list(csv.DictReader(open(os.path.join(steps_dir, name + ".csv"))))]) * 1e-6
        get = lambda p: np.array([[float(r[p + "dx"]), float(r[p + "dy"]), float(r[p + "dyaw"])] for r in rows])
        gt, ours, dop, match = get("gt_"), get(""), get("doppler_"), get("match_")
        can = os.path.join(root, "can_bus", name)
        imu = json.load(open(can + "_ms_imu.json"))
        veh = json.load(open(can + "_zoe_veh_info.json"))
        ti = np.array([m["utime"] for m in imu]) * 1e-6
        wz = np.array([m["rotation_rate"][2] for m in imu])
        tv = np.array([m["utime"] for m in veh]) * 1e-6
        v = np.array([(m["RL_wheel_speed"] + m["RR_wheel_speed"]) / 2 for m in veh]) * 2 * np.pi * 0.305 / 60
        yaw = np.array([integral(ti, wz, t[k - 1], t[k]) for k in range(1, len(t))])
        dist = np.array([integral(tv, v, t[k - 1], t[k]) for k in range(1, len(t))])
        wheels = np.array([arc(d, th) for d, th in zip(dist, yaw)])
        truth = chain(gt)
        forward = lambda x: ate(chain(np.stack([x, gt[:, 1], gt[:, 2]], 1)), truth)
        along = gt[:, 0].sum()
        matched = np.array([r["status"] in ("matched", "retried") for r in rows])
        print("| %s | %.3f / %.3f / %.3f | %.4f / %.4f / %.4f | %.5f / %.5f |" % (
            name, forward(ours[:, 0]), forward(dop[:, 0]), forward(wheels[:, 0]), dop[:, 0].sum() / along,
            match[matched, 0].sum() / gt[matched, 0].sum(), dist.sum() / along, np.std(yaw - gt[:, 2]),
            np.std(match[matched, 2] - gt[matched, 2])))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
