#!/usr/bin/env python3
"""Which nuScenes detections to keep: the reader's ambig_state keep lists as separate choices for the
map and the match (sequence.filter.ambig_states) and for the Doppler fit and the moving-detection test
(sequence.filter.doppler_ambig_states), on every scene of a dataroot, for ours (with and without the
car's CAN bus), PCL's NDT and ICP, Rapp's NDT and the Doppler integration. Prints a markdown table:
ATE (m) per scene, its mean, and the mean of the paper's 1 m metric (%).

    PYTHONPATH=build/python python3 scripts/nuscenes_keep_lists.py ../shared/data/nuscenes-mini-radar
"""
import sys

import radar_ndt

CHOICES = [
    ("all ambig_states (the default)", {"ambig_states": [], "doppler_ambig_states": []}),
    ("ambig_state 3 (the devkit's)", {"ambig_states": [3], "doppler_ambig_states": []}),
    ("all for the match, 3 for the Doppler", {"ambig_states": [], "doppler_ambig_states": [3]}),
]
METHODS = [("pw-ndt", {}), ("pw-ndt --imu --wheels", {"odometry": {"car": {"gyro": True, "wheels": True}}}),
           ("pcl-ndt", {}), ("pcl-icp", {}), ("rapp-ndt", {}), ("doppler", {})]


def main(dataroot):
    scenes = [s["name"] for s in radar_ndt.NuScenesDataset(dataroot).scenes]
    print("| keep lists | method | " + " | ".join(scenes) + " | mean ATE (m) | mean 1 m (%) |")
    print("|---|---|" + "---|" * len(scenes) + "---|---|")
    for label, lists in CHOICES:
        for method, kw in METHODS:
            ates, one_m = [], []
            for scene in scenes:
                run = radar_ndt.run_automotive(dataroot, scene, method=method.split()[0],
                                               sequence={"filter": dict(lists)}, **kw)
                m = radar_ndt.evaluate(run.ground_truth, run.estimate, "ate,1m")
                ates.append(m["ate"]["rmse_m"])
                one_m.append(m["1m"]["trans_err_pct"])
            cells = " | ".join(f"{a:.3f}" for a in ates)
            print(f"| {label} | {method} | {cells} | {sum(ates) / len(ates):.3f} | "
                  f"{sum(one_m) / len(one_m):.2f} |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "../shared/data/nuscenes-mini-radar")
