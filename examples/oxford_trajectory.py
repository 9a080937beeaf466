#!/usr/bin/env python3
"""Runs RadarNDT over a scanning-radar sequence from Python and plots the estimate against the
dataset's ground truth into a PNG.

    python3 examples/oxford_trajectory.py [--sequence ../shared/data/oxford-radar-real]
                                          [--format oxford] [--out oxford_trajectory.png]

Needs the radar_ndt module (cmake --install build, or PYTHONPATH=build/python) and matplotlib.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import radar_ndt  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sequence", default=str(HERE.parent.parent / "shared" / "data" / "oxford-radar-real"))
    parser.add_argument("--format", default="oxford", choices=["oxford", "radiate", "boreas"])
    parser.add_argument("--method", default="pw-ndt", choices=["pw-ndt", "pcl-ndt", "pcl-icp"])
    parser.add_argument("--out", default="oxford_trajectory.png")
    args = parser.parse_args()

    run = radar_ndt.run_scanning(args.sequence, format=args.format, method=args.method)
    estimate = run.estimate.xy_yaw
    print(f"{run.sequence}: {len(run.estimate)} scans, {run.method}, "
          f"{run.summary()['matched']} matched, {run.scans_per_second:.0f} scans/s")

    fig, ax = plt.subplots(figsize=(6, 6))
    title = f"{run.sequence}: {run.method}"
    if len(run.ground_truth) > 1:
        gt = run.ground_truth.xy_yaw
        metrics = run.summary(metrics="frame,ate")
        frame, prior = metrics["metrics"]["frame"], metrics.get("prior_frame", {})
        ate = metrics["metrics"]["ate"]["rmse_m"]
        print(f"frame error {frame['trans_err_m']:.3f} m / {frame['rot_err_deg']:.3f} deg "
              f"(constant-velocity prior {prior.get('trans_err_m', float('nan')):.3f} m / "
              f"{prior.get('rot_err_deg', float('nan')):.3f} deg), ATE {ate:.3f} m")
        ax.plot(gt[:, 1], gt[:, 0], "k-", lw=2, label="ground truth")
        title += f"\nframe {frame['trans_err_m']:.3f} m, ATE {ate:.3f} m"
    ax.plot(estimate[:, 1], estimate[:, 0], "r.-", label=f"RadarNDT ({run.method})")
    ax.set_xlabel("y, left (m)")
    ax.set_ylabel("x, forward (m)")
    ax.invert_xaxis()  # left is left, seen from above
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")
    return 0 if np.all(np.isfinite(estimate)) else 1


if __name__ == "__main__":
    raise SystemExit(main())
