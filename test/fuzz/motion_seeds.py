#!/usr/bin/env python3
"""Seeds for fuzz_view_of_delft and fuzz_motion_sensors, each behind its target's selector byte.

View-of-Delft (tudelft-iv/view-of-delft-dataset, docs/SENSORS_AND_DATA.md): a radar .bin of float32
rows x y z RCS v_r v_r_compensated time, a pose file of three JSON lines, a KITTI calibration whose
Tr_velo_to_cam is the radar-to-camera transform. Boreas (pyboreas DATA_REFERENCE.md): applanix/imu.csv
with the header GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx, times in ns.
"""
import math
import os
import struct
import sys


def write(path, selector, payload):
    with open(path, "wb") as f:
        f.write(bytes([selector]) + payload)


def main(seeds):
    vod = os.path.join(seeds, "fuzz_view_of_delft")
    motion = os.path.join(seeds, "fuzz_motion_sensors")
    os.makedirs(vod, exist_ok=True)
    os.makedirs(motion, exist_ok=True)
    rows = b"".join(struct.pack("<7f", 5.0 + i, 0.3 * i - 2.0, 0.1 * (i % 5), -8.0 + i, -3.1, 0.05 * i, -(i % 3))
                    for i in range(12))
    write(os.path.join(vod, "radar.bin"), 0, rows)
    pose = ('{"odomToCamera": [0, 0, 1, 12.5, -1, 0, 0, 0.2, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n'
            '{"mapToCamera": [0, 0, 1, 1012.5, -1, 0, 0, 3.2, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n'
            '{"UTMToCamera": [0, 0, 1, 594012.5, -1, 0, 0, 5761003.2, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n').encode()
    for k, key in enumerate(["odom", "map", "utm"]):
        write(os.path.join(vod, "pose_%s.json" % key), k + 1, pose)
    calib = ("P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 0 0 1 0 0 0 0 1 0\nP2: 1495.5 0 961.3 0 0 1495.5 624.9 0 0 0 1 0\n"
             "P3: 1 0 0 0 0 1 0 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n"
             "Tr_velo_to_cam: -0.0131 -0.9999 0.0026 0.0516 0.2215 -0.0004 -0.9752 0.9116 0.9751 -0.0128 0.2215 2.4825\n"
             "Tr_imu_to_velo: 1 0 0 0 0 1 0 0 0 0 1 0\n").encode()
    write(os.path.join(vod, "calib.txt"), 4, calib)
    lines = ["GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx"]
    for i in range(20):
        t = 1628184845000000000 + i * 5000000
        lines.append("%d,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f" % (t, 0.01 * math.sin(i / 3.0), 0.002, -0.001,
                                                         9.81, 0.3 * math.cos(i / 4.0), 0.02))
    write(os.path.join(motion, "boreas_imu.csv"), 0, ("\n".join(lines) + "\n").encode())


if __name__ == "__main__":
    main(sys.argv[1])
