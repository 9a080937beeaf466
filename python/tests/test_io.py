"""The readers from Python on the real data: Oxford, RADIATE and Boreas scans as arrays, sequences
with their ground truth, nuScenes tables, sweeps and cycles with Doppler, trajectory files and the
6-DoF metrics on them."""

import json

import numpy as np
import pytest

import radar_ndt
from conftest import BOREAS, NUSCENES, OXFORD, RADIATE, SOURCE, need


def test_oxford_scan_arrays():
    need(OXFORD)
    path = sorted((OXFORD / "radar").glob("*.png"))[0]
    scan = radar_ndt.read_oxford_scan(path)  # str or os.PathLike
    assert (scan.azimuths, scan.bins) == (400, 3768)
    power = scan.power
    assert power.shape == (400, 3768) and power.dtype == np.uint8 and power.max() > 100
    assert scan.stamp == int(path.stem) and scan.stamp_us[0] == scan.stamp
    assert np.all(np.diff(scan.stamp_us) >= 0) and scan.stamp_us.dtype == np.int64
    assert np.all(np.abs(scan.angle) <= np.pi) and scan.encoder.dtype == np.uint16
    assert scan.chirp_up.size == 0 and scan.range_resolution == pytest.approx(0.0438)
    assert scan.ranges[0] == pytest.approx(0.5 * 0.0438)
    del scan  # the arrays keep the scan's memory alive
    assert power.sum() > 0


def test_a_change_to_the_power_view_reaches_the_front_end():
    need(OXFORD)
    scan = radar_ndt.read_oxford_scan(str(sorted((OXFORD / "radar").glob("*.png"))[0]))
    front_end = radar_ndt.PowerThreshold()
    points = front_end.points(scan)
    assert points.shape[1] == len(radar_ndt.POINT_FIELDS) and len(points) > 1000
    assert np.all(points[:, 3] >= front_end.options.threshold)
    scan.power[:] = 0
    assert len(front_end.points(scan)) == 0
    image, metres = front_end.cartesian_image(radar_ndt.read_oxford_scan(
        str(sorted((OXFORD / "radar").glob("*.png"))[0])))
    assert image.ndim == 2 and image.shape[0] == image.shape[1] and metres == 0.125


def test_oxford_sequence_and_ground_truth():
    need(OXFORD)
    seq = radar_ndt.ScanningSequence(OXFORD, "oxford")
    assert len(seq) == len(list((OXFORD / "radar").glob("*.png"))) and seq.format == "oxford"
    assert np.all(np.diff(seq.stamps) > 0) and 0.2 < seq.period < 0.3
    gt = seq.ground_truth
    assert len(gt) >= len(seq) and gt.stamps[0] == pytest.approx(seq.stamps[0] * 1e-6)
    assert np.array_equal(gt.poses[0], np.eye(4))
    assert seq.load(2).stamp == seq.stamps[2]
    with pytest.raises(IndexError):
        seq.load(len(seq))


def test_radiate_and_boreas_scans():
    need(RADIATE)
    seq = radar_ndt.ScanningSequence(str(RADIATE), "radiate")
    scan = seq.load(0)
    assert scan.azimuths == 400 and scan.encoder.size == 0 and scan.range_resolution == pytest.approx(0.173611)
    need(BOREAS)
    pngs = sorted(BOREAS.glob("**/radar/*.png"))
    assert pngs, "the Boreas sample has radar scans"
    scans = [radar_ndt.read_boreas_scan(str(p)) for p in pngs]
    chirped = [s for s in scans if s.chirp_up.size]
    assert chirped, "the 2024 scan carries chirp types"
    s = chirped[0]
    assert set(np.unique(s.chirp_up)) == {0, 1} and s.range_resolution == pytest.approx(0.04381)
    assert s.stamp == s.stamp_us[s.azimuths // 2 - 1]  # named by its middle row (199 of 400), as pyboreas
    estimate = radar_ndt.correct_chirps(s)
    assert estimate["valid"] and np.hypot(*estimate["u"]) < 0.05  # the real scan's car stands


def test_nuscenes_tables_sweeps_and_cycles():
    need(NUSCENES)
    ds = radar_ndt.NuScenesDataset(str(NUSCENES))
    assert len(ds.radar_channels) == 5 and ds.scenes
    scene = ds.scenes[0]["name"]
    sweeps = ds.radar_sweeps(scene)
    assert sweeps[0]["sensor_to_ego"].shape == (4, 4)
    points = radar_ndt.read_nuscenes_pcd(sweeps[0]["path"], sweeps[0]["channel_index"])
    assert points.shape[1] == 11 and np.all(points[:, 10] == sweeps[0]["channel_index"])
    assert np.any(points[:, 8] != 0)  # Doppler
    seq = radar_ndt.NuScenesRadarSequence(ds, scene)
    cycle, problems = seq.load(5)
    assert problems == [] and cycle.timestamp_us == seq.timestamp(5)
    assert len(cycle.sweeps) >= 3 and cycle.sweeps[0].points.shape[1] == 11
    processed = radar_ndt.AutomotiveFrontEnd().process(cycle)
    assert processed.ego_velocity.valid and processed.points.shape[1] == 11
    assert np.all(processed.points[:, 2] == 0)  # planar, in the vehicle frame
    assert len(seq.ground_truth) == len(seq)


def test_trajectory_files_round_trip(work):
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 0.1, 0.01], [2.0, 0.3, 0.02]])
    t = radar_ndt.Trajectory(poses, stamps=[10.0, 10.25, 10.5])
    for fmt in ("tum", "kitti", "boreas"):
        path = str(work / f"t.{fmt}")
        radar_ndt.write_trajectory(path, t, fmt)
        back = radar_ndt.read_trajectory(path, fmt)
        assert np.allclose(back.xy_yaw, poses, atol=1e-6)
        assert back.projected_rotations == 0  # written with full precision: read as written
    # Rounded to 3 decimals, as other projects write them: projected onto rotations and counted.
    rounded = work / "rounded.kitti"
    rounded.write_text("1 0 0 0 0 1 0 0 0 0 1 0\n0.994 -0.100 0 1 0.100 0.994 0 0 0 0 1 0\n")
    back = radar_ndt.read_trajectory(str(rounded))
    assert back.projected_rotations == 1 and 1e-4 < back.max_rotation_deviation < 1e-2
    R = back.poses[1][:3, :3]
    assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.allclose(t.pose_at(10.125)[:2, 3], [0.5, 0.05])
    assert t.pose_at(11.0) is None


def test_nuscenes_can_bus_as_arrays(work):
    need(NUSCENES / "can_bus")
    can = radar_ndt.read_can_bus(str(NUSCENES), "scene-0061")
    yaw, wheels = can["yaw_rate"], can["rear_wheel_rpm"]
    assert yaw["stamps_us"].dtype == np.int64 and len(yaw["stamps_us"]) == len(yaw["values"]) > 1000
    assert np.all(np.diff(yaw["stamps_us"]) > 0) and np.all(np.diff(wheels["stamps_us"]) > 0)
    # scene-0061 turns left by about 98 degrees: the integrated z rate is positive.
    turn = np.trapz(yaw["values"], yaw["stamps_us"] * 1e-6)
    assert 1.5 < turn < 1.9
    assert radar_ndt.read_can_bus(str(work), "scene-0061") is None  # no can_bus folder: nothing


def test_six_dof_metrics_equal_rpg_trajectory_evaluations():
    """The 6-DoF metrics from Python as radar_eval gives them: on test/data/rpg_fixture, the values
    rpg_trajectory_evaluation's own functions computed (expected.json), to 1e-9."""
    fixture = SOURCE / "test" / "data" / "rpg_fixture"
    expected = json.loads((fixture / "expected.json").read_text())
    gt = radar_ndt.read_trajectory(str(fixture / "gt.txt"))
    est = radar_ndt.read_trajectory(str(fixture / "est.txt"))
    m = radar_ndt.evaluate(gt, est, "all", re_distances=[10.0, 20.0, 50.0, 100.0])
    for kind in ("se3", "posyaw"):
        for key in ("rmse_m", "rot_rmse_deg"):
            assert m["ate6"][kind][key] == pytest.approx(expected["ate_" + kind][key], abs=1e-9)
    for got, want in zip(m["re"], expected["re"]):
        assert got["samples"] == want["samples"]
        for key in ("trans_mean_m", "trans_median_m", "trans_rmse_m", "yaw_mean_deg", "gravity_mean_deg"):
            assert got[key] == pytest.approx(want[key], abs=1e-9), key
    assert m["final"]["final_m"] == pytest.approx(expected["final"]["final_m"], abs=1e-9)
