"""Whole runs and step-by-step odometry from Python give the apps' numbers: the real Oxford scans
through run_scanning and one real nuScenes scene through run_automotive write files byte-identical
to radar_odometry --out; the step-by-step classes give the runs' poses; the metrics equal --eval's."""

import json
import threading
import time

import numpy as np
import pytest

import radar_ndt
from conftest import NUSCENES, OXFORD, SHARED, app, need

SCENE = "scene-0103"


@pytest.fixture(scope="module")
def oxford_run():
    need(OXFORD)
    return radar_ndt.run_scanning(str(OXFORD), format="oxford")


@pytest.mark.parametrize("fmt", ["tum", "kitti"])
def test_run_scanning_writes_what_radar_odometry_writes(oxford_run, work, fmt):
    ours, theirs = work / f"python.{fmt}", work / f"app.{fmt}"
    radar_ndt.write_trajectory(str(ours), oxford_run.estimate, fmt)
    app("radar_odometry", "--format", "oxford", "--sequence", OXFORD, "--out", theirs, "--out-format", fmt, "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    assert len(oxford_run.estimate) == len(list((OXFORD / "radar").glob("*.png")))
    # The arrays say what the trajectory says: translations in the last column, rows (0, 0, 0, 1).
    poses = oxford_run.poses
    assert np.array_equal(poses[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (len(poses), 1)))
    assert np.allclose(poses[:, :2, 3], oxford_run.estimate.xy_yaw[:, :2], rtol=0, atol=1e-12)
    assert poses[-1, 0, 3] > 10  # 11 scans of a car driving forward


def test_run_scanning_with_pcl_ndt_and_options_matches_the_app(work):
    need(OXFORD)
    run = radar_ndt.run_scanning(str(OXFORD), method="pcl-ndt", threads=1, front_end={"threshold": 0.4},
                                 matcher={"grid": 4.0}, odometry={"keyframes": {"distance": 0.0}})
    assert run.method == "pcl-ndt"
    ours, theirs = work / "python.tum", work / "app.tum"
    radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
    app("radar_odometry", "--format", "oxford", "--sequence", OXFORD, "--method", "pcl-ndt", "--threads", "1",
        "--threshold", "0.4", "--grid", "4", "--keyframe-distance", "0", "--out", theirs, "-q")
    assert ours.read_bytes() == theirs.read_bytes()


def test_joint_compensation_through_run_scanning_matches_the_app(work):
    need(OXFORD)
    run = radar_ndt.run_scanning(OXFORD, threads=1, odometry={"compensation": {"mode": "joint"}})
    ours, theirs = work / "joint.tum", work / "joint-app.tum"
    radar_ndt.write_trajectory(ours, run.estimate, "tum")
    app("radar_odometry", "--format", "oxford", "--sequence", OXFORD, "--compensation", "joint", "--threads", "1",
        "--out", theirs, "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    with pytest.raises(ValueError, match="rounds, joint"):
        radar_ndt.run_scanning(OXFORD, odometry={"compensation": {"mode": "both"}})


def test_the_summary_and_metrics_equal_the_apps_json(oxford_run):
    expected = json.loads(app("radar_odometry", "--format", "oxford", "--sequence", OXFORD, "--eval", "--metric",
                              "frame,ate", "--json", "-q"))
    summary = oxford_run.summary(metrics="frame,ate")
    timing = {"ms_per_scan_median", "real_time_factor", "scans_per_second"}
    assert {k: v for k, v in summary.items() if k not in timing} == \
        {k: v for k, v in expected.items() if k not in timing}
    assert summary["metrics"]["frame"]["pairs"] == len(oxford_run.estimate) - 1
    assert summary["prior_frame"]["prior"] == "constant velocity"
    direct = radar_ndt.evaluate(oxford_run.ground_truth, oxford_run.estimate, "frame,ate")
    assert direct["frame"] == expected["metrics"]["frame"]
    assert radar_ndt.frame_error(oxford_run.ground_truth, oxford_run.estimate)["trans_err_m"] == \
        expected["metrics"]["frame"]["trans_err_m"]
    assert radar_ndt.absolute_trajectory_error(oxford_run.ground_truth, oxford_run.estimate)["rmse_m"] == \
        expected["metrics"]["ate"]["rmse_m"]


def test_scan_by_scan_gives_the_runs_poses(oxford_run):
    seq = radar_ndt.ScanningSequence(str(OXFORD))
    front_end = radar_ndt.PowerThreshold()
    odometry = radar_ndt.ScanningOdometry()
    for k in range(len(seq)):
        step = odometry.add_scan(int(seq.stamps[k]), front_end.points(seq.load(k)))
        assert step.status in ("first", "matched", "retried"), step
    assert np.array_equal(odometry.trajectory.poses, oxford_run.poses)
    assert np.array_equal(odometry.trajectory.stamps, oxford_run.stamps)
    assert odometry.counters["matched"] + odometry.counters["retried"] == len(seq) - 1


def test_run_automotive_writes_what_radar_odometry_writes(work):
    need(NUSCENES)
    run = radar_ndt.run_automotive(str(NUSCENES), SCENE)
    ours, theirs = work / "python.tum", work / "app.tum"
    radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
    app("radar_odometry", "--format", "nuscenes", "--dataroot", NUSCENES, "--scene", SCENE, "--out", theirs, "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    assert run.scene == SCENE and len(run.estimate) > 100
    # Cycle by cycle, with the run's fallback velocity, gives the same poses.
    seq = radar_ndt.NuScenesRadarSequence(radar_ndt.NuScenesDataset(str(NUSCENES)), SCENE)
    front_end, odometry, last = radar_ndt.AutomotiveFrontEnd(), radar_ndt.AutomotiveOdometry(), None
    for k in range(len(seq)):
        cycle, _ = seq.load(k)
        processed = front_end.process(cycle)
        if not processed.ego_velocity.valid and last is not None:
            processed = front_end.process(cycle, last)
        if processed.ego_velocity.valid:
            last = processed.ego_velocity
        odometry.add(processed)
    assert np.array_equal(odometry.trajectory.poses, run.poses)
    metrics = radar_ndt.evaluate(run.ground_truth, run.estimate, "1m,ate")
    assert metrics["1m"]["trans_err_pct"] < 10 and metrics["ate"]["rmse_m"] < 5


def test_the_doppler_method_and_rapp_through_run_automotive(work):
    need(NUSCENES)
    for method in ("doppler", "rapp-ndt"):
        run = radar_ndt.run_automotive(str(NUSCENES), SCENE, method=method, max_cycles=60)
        ours, theirs = work / f"{method}.py.tum", work / f"{method}.app.tum"
        radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
        app("radar_odometry", "--format", "nuscenes", "--dataroot", NUSCENES, "--scene", SCENE, "--method", method,
            "--max-cycles", "60", "--out", theirs, "-q")
        assert ours.read_bytes() == theirs.read_bytes(), method


def test_options_are_checked_before_a_run():
    need(OXFORD)
    with pytest.raises(ValueError, match="grid"):
        radar_ndt.run_scanning(str(OXFORD), matcher={"grid": -1.0})
    with pytest.raises(ValueError, match="threshold"):
        radar_ndt.run_scanning(str(OXFORD), front_end={"threshold": 2.0})
    with pytest.raises(ValueError, match="doppler"):
        radar_ndt.run_scanning(str(OXFORD), method="doppler")
    with pytest.raises(TypeError, match="gridd"):
        radar_ndt.run_scanning(str(OXFORD), matcher={"gridd": 4.0})
    with pytest.raises(TypeError, match="matcher.grid"):
        radar_ndt.run_scanning(str(OXFORD), matcher={"grid": "four"})
    with pytest.raises(ValueError, match="format"):
        radar_ndt.run_scanning(str(OXFORD), format="navtech")


def test_the_gil_is_released_while_a_run_works():
    need(OXFORD)
    done = threading.Event()
    result = {}

    def worker():
        result["run"] = radar_ndt.run_scanning(str(OXFORD), threads=1)
        done.set()

    ticks = 0
    t = threading.Thread(target=worker)
    start = time.perf_counter()
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    # The run takes hundreds of milliseconds; holding the GIL, this thread would not tick at all.
    assert time.perf_counter() - start > 0.05 and ticks > 10
    assert len(result["run"].estimate) == len(list((OXFORD / "radar").glob("*.png")))


def test_the_cars_sensors_through_run_automotive(work):
    """The car's own dead reckoning and the fused run, from Python as from the app."""
    need(NUSCENES / "can_bus")
    runs = [("wheel-gyro", {}, []), ("pw-ndt", {"odometry": {"car": {"gyro": True, "wheels": True}}},
                                     ["--imu", "--wheels"])]
    for method, kw, flags in runs:
        run = radar_ndt.run_automotive(str(NUSCENES), SCENE, method=method, max_cycles=60, **kw)
        ours, theirs = work / f"{method}.py.tum", work / f"{method}.app.tum"
        radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
        app("radar_odometry", "--format", "nuscenes", "--dataroot", NUSCENES, "--scene", SCENE, "--method", method,
            *flags, "--max-cycles", "60", "--out", theirs, "-q")
        assert ours.read_bytes() == theirs.read_bytes(), method


def test_the_scanning_gyro_through_run_scanning(work):
    """A simulated Boreas drive with a gyro: run_scanning with the gyro on equals radar_odometry --imu."""
    seq = work / "boreas-gyro"
    app("radar_sim", "--layout", "boreas", "--frames", "12", "--start", "80", "--imu", "navigation", "--out", seq,
        "-q")
    run = radar_ndt.run_scanning(str(seq), format="boreas", threads=1, odometry={"gyro": {"enabled": True}})
    assert run.prior == "constant velocity, gyro yaw"
    ours, theirs = work / "gyro.py.tum", work / "gyro.app.tum"
    radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
    app("radar_odometry", "--format", "boreas", "--sequence", seq, "--imu", "--threads", "1", "--out", theirs, "-q")
    assert ours.read_bytes() == theirs.read_bytes()


def test_run_rosbag_gives_the_scenes_trajectory(work):
    need(NUSCENES)
    try:
        app("radar_nuscenes_to_bag", "--dataroot", NUSCENES, "--scene", SCENE, "--out", work)
    except FileNotFoundError:
        pytest.skip("this build has no ROS support (no radar_nuscenes_to_bag)")
    run = radar_ndt.run_rosbag(str(work / f"{SCENE}.bag"), "preset:nuscenes_ars408")
    scene = radar_ndt.run_automotive(str(NUSCENES), SCENE)
    assert run.scene == SCENE and np.array_equal(run.poses, scene.poses)
    with pytest.raises(Exception, match="no_such.yaml"):
        radar_ndt.run_rosbag(str(work / f"{SCENE}.bag"), str(work / "no_such.yaml"))


def test_run_rosbag_runs_a_scanning_radars_bag_as_the_app(work):
    """A scanning radar's bag (the real Oxford scans in CFEAR's layout) runs the scanning odometry,
    with run_scanning's keywords, and writes what radar_odometry --format rosbag writes."""
    need(OXFORD)
    bag = work / "oxford.bag"
    try:
        app("radar_scans_to_bag", "--format", "oxford", "--sequence", OXFORD, "--out", bag)
    except FileNotFoundError:
        pytest.skip("this build has no ROS support (no radar_scans_to_bag)")
    run = radar_ndt.run_rosbag(str(bag), "preset:navtech_oxford", threads=1)
    assert isinstance(run, radar_ndt.ScanningRun) and run.format == "rosbag"
    ours, theirs = work / "bag.py.tum", work / "bag.app.tum"
    radar_ndt.write_trajectory(str(ours), run.estimate, "tum")
    app("radar_odometry", "--format", "rosbag", "--bag", bag, "--sensors", "preset:navtech_oxford", "--out", theirs,
        "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    with pytest.raises(Exception, match="rapp-ndt"):  # a method that needs Doppler, refused as run_scanning does
        radar_ndt.run_rosbag(str(bag), "preset:navtech_oxford", method="rapp-ndt")


def test_the_rio_presets_mounting_and_doppler_sign_see_the_rig_walk_forward():
    """The TI preset's mounting and Doppler sign on the real rio bag: a handheld rig carried
    forward, so the Doppler ego-motion in the base frame points forward (+x) more than sideways.
    rio's reader swaps the driver's axes (x = -y, y = x) before its calibration applies; a
    mounting taken from the calibration alone turns the motion sideways, a wrong sign backwards."""
    bag = SHARED / "ros-rio-ti-mmwave" / "ti_mmwave_rospkg_demo.bag"
    need(bag)
    try:
        run = radar_ndt.run_rosbag(str(bag), "preset:ti_iwr6843_rio")
    except RuntimeError as e:
        if "no ROS support" in str(e):
            pytest.skip(str(e))
        raise
    import csv
    import io
    rows = [r for r in csv.DictReader(io.StringIO(run.steps_csv())) if r["velocity_valid"] == "1"]
    assert len(rows) > 300
    dx = np.mean([float(r["doppler_dx"]) for r in rows])
    dy = np.mean([float(r["doppler_dy"]) for r in rows])
    assert dx > 0.02 and dx > abs(dy), (dx, dy)  # m a cycle (10 Hz): a walk, forward
