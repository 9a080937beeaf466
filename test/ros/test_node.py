"""The ROS node with a real master: a bag of a nuScenes scene (the automotive pipeline) or of a
scanning radar's sweeps (the scanning one) played with `rosbag play`, the published odometry
recorded with `rosbag record`, compared with the offline run of the same bag.

Environment: RADAR_NDT_BIN (the build's apps folder), RADAR_NDT_SHARED_DATA (../shared/data).
Skips when the data or Debian's ROS 1 tools are absent."""
import os
import shutil
import socket
import subprocess
import time

import numpy as np
import pytest

BIN = os.environ.get("RADAR_NDT_BIN", "build/apps")
DATA = os.environ.get("RADAR_NDT_SHARED_DATA", "../shared/data")
SCENE = "scene-0103"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def ros_env(tmp_path_factory):
    for tool in ("roscore", "rosbag"):
        if not shutil.which(tool):
            pytest.skip(f"{tool} not found (Debian's ROS 1: bash .ci/deps)")
    if not os.path.isdir(os.path.join(DATA, "nuscenes-mini-radar")):
        pytest.skip(f"no {DATA}/nuscenes-mini-radar (../shared/data is absent)")
    work = tmp_path_factory.mktemp("ros")
    env = dict(os.environ)
    port = free_port()
    env["ROS_MASTER_URI"] = f"http://127.0.0.1:{port}"
    env["ROS_HOSTNAME"] = "127.0.0.1"
    env["ROS_HOME"] = str(work / "ros_home")
    master = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):  # the master answers
            if subprocess.run(["rosparam", "list"], env=env, capture_output=True).returncode == 0:
                break
            time.sleep(0.2)
        else:
            pytest.fail("the ROS master did not start")
        yield env, work
    finally:
        master.terminate()
        master.wait(timeout=20)


def write_bag(work):
    subprocess.run([f"{BIN}/radar_nuscenes_to_bag", "--dataroot", f"{DATA}/nuscenes-mini-radar", "--scene", SCENE,
                    "--out", str(work)], check=True, capture_output=True)
    return str(work / f"{SCENE}.bag")


NUSCENES_TOPICS = ["/RADAR_FRONT", "/RADAR_FRONT_LEFT", "/RADAR_FRONT_RIGHT", "/RADAR_BACK_LEFT", "/RADAR_BACK_RIGHT",
                   "/tf", "/imu"]


def offline(bag, work, *extra, sensors="preset:nuscenes_ars408"):
    out = work / "offline.tum"
    subprocess.run([f"{BIN}/radar_odometry", "--format", "rosbag", "--bag", bag, "--sensors", sensors, "--out", str(out),
                    "-q", *extra], check=True, capture_output=True)
    return np.loadtxt(out)


def reference_period(bag, topic="/RADAR_FRONT"):
    """The offline run's interval: the median interval of the reference radar's sweeps (s)."""
    import rosbag
    with rosbag.Bag(bag) as b:
        t = [m.header.stamp.to_nsec() // 1000 for _, m, _ in b.read_messages(topics=[topic])]
    return float(np.median(np.diff(sorted(t)))) * 1e-6


def wait_subscribed(env, wanted, timeout=60):
    """Waits until, for each topic, a node whose name starts with the given prefix subscribes to
    it (the master's system state): a loaded machine can take seconds to start the recorder."""
    import rosgraph
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    master = rosgraph.Master("/test_node", master_uri=env["ROS_MASTER_URI"])
    deadline = time.time() + timeout
    while time.time() < deadline:
        try:
            subscribers = dict(master.getSystemState()[1])
        except Exception:  # the master is busy: ask again
            subscribers = {}
        if all(any(n.startswith(prefix) for n in subscribers.get(topic, [])) for topic, prefix in wanted.items()):
            return
        time.sleep(0.2)
    pytest.fail(f"not subscribed within {timeout} s: {wanted}")


def wait_closed(recorded, timeout=30):
    """Waits until `rosbag record` has closed its bag. `rosbag` is a Python wrapper: on SIGINT it passes
    the signal to its `record` process and returns at once, while `record` is still writing the
    index into NAME.bag.active; it renames that to NAME.bag when it is done."""
    active = recorded.with_name(recorded.name + ".active")
    deadline = time.time() + timeout
    while active.exists():
        if time.time() > deadline:
            pytest.fail(f"rosbag record did not close {active} within {timeout} s of SIGINT")
        time.sleep(0.1)


def run_node(env, work, bag, rate, name, *params, sensors="preset:nuscenes_ars408", topics=NUSCENES_TOPICS,
             period=None, plays=1, flush_after=1.0, connected=False):
    recorded = work / f"{name}.bag"
    # Private parameters outlive a node on the master: a previous run's would be read again.
    subprocess.run(["rosparam", "delete", "/radar_ndt"], env=env, capture_output=True)
    period = reference_period(bag) if period is None else period
    node = subprocess.Popen([f"{BIN}/radar_ndt_node", f"_sensors:={sensors}", f"_cycle_period:={period}",
                             f"_flush_after:={flush_after}", *params],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    record = subprocess.Popen(["rosbag", "record", "-O", str(recorded), "/radar_ndt/odometry", "/diagnostics"],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        wait_subscribed(env, {"/radar_ndt/odometry": "/record", topics[0]: "/radar_ndt"})
    except BaseException:  # pytest.fail's exception: the node's output says why
        node.kill()
        print("the node:", node.communicate()[0])
        raise
    # -d: a pause after advertising, so that the node's subscriptions are connected before the first
    # messages go out (a message published before its subscriber connects is lost: under load the
    # IMU's first samples were, and the gyro's integral to the second cycle with them).
    # connected: the node subscribes to every topic played; the player waits until each has a
    # connection (a gyro message lost before its connection changes every pose after it).
    wait = ["--wait-for-subscribers"] if connected else []
    for _ in range(plays):  # played again: the stream's time jumps back
        play = subprocess.run(["rosbag", "play", "-q", "-d", "2", *wait, "-r", str(rate), bag, "--topics", *topics],
                              env=env, capture_output=True, text=True)
        if play.returncode != 0:
            node.kill()
            pytest.fail(f"rosbag play exited {play.returncode}: {play.stderr}\nthe node:\n{node.communicate()[0]}")
    # The last cycles flushed (after ~flush_after of quiet) and recorded; a slow build (ASan) is still
    # working off its queue of cycles when a bag played at 10x ends.
    time.sleep(7 + flush_after)
    record.send_signal(2)
    record.wait(timeout=30)
    node.send_signal(2)
    try:
        out, _ = node.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        node.kill()
        pytest.fail(f"the node did not stop within 30 s of SIGINT:\n{node.communicate()[0]}")
    wait_closed(recorded)
    import rosbag
    if not recorded.exists():  # the recorder got nothing: the node's output says why
        pytest.fail(f"nothing recorded from the node ({name}):\n{out}")
    poses, diag = [], []
    with rosbag.Bag(str(recorded)) as b:
        for topic, m, _ in b.read_messages():
            if topic == "/radar_ndt/odometry":
                p, q = m.pose.pose.position, m.pose.pose.orientation
                poses.append([m.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w])
            else:
                diag.append(m)
    return np.array(poses), diag, out


def assert_same_poses(poses, expected, name, out):
    assert len(poses) == len(expected), f"{name}: {len(poses)} cycles published, {len(expected)} offline\n{out}"
    assert np.allclose(poses[:, 0], expected[:, 0], atol=1e-6), name
    d = np.abs(poses[:, 1:3] - expected[:, 1:3]).max(axis=1)
    assert d.max() < 1e-6, f"{name}: first difference at cycle {np.argmax(d > 1e-6)}\n{out}"
    yaw = lambda q: np.arctan2(2 * (q[:, 3] * q[:, 2] + q[:, 0] * q[:, 1]), 1 - 2 * (q[:, 1] ** 2 + q[:, 2] ** 2))
    assert np.abs(np.unwrap(yaw(poses[:, 4:])) - np.unwrap(yaw(expected[:, 4:]))).max() < 1e-6, name


def test_with_the_gyro_the_node_gives_the_offline_imu_poses(ros_env):
    env, work = ros_env
    bag = write_bag(work)
    expected = offline(bag, work, "--imu")
    plain = offline(bag, work)
    # The gyro changes the poses (else this test would not see it unused).
    assert np.abs(expected[:, 1:3] - plain[:, 1:3]).max() > 1e-3
    for rate, name in ((1.0, "gyro-normal"), (10.0, "gyro-fast")):
        poses, diag, out = run_node(env, work, bag, rate, name, "_odometry/car/gyro:=true")
        assert_same_poses(poses, expected, name, out)
        print(name, out.strip().splitlines()[-1])
        imu = [s for d in diag for s in d.status if s.name == "radar_ndt: /imu"]
        assert imu and int(dict((v.key, v.value) for v in imu[-1].values)["messages"]) > 1000


def test_played_bag_gives_the_offline_poses(ros_env):
    env, work = ros_env
    bag = write_bag(work)
    expected = offline(bag, work)
    for rate, name in ((1.0, "normal"), (10.0, "fast")):
        poses, diag, out = run_node(env, work, bag, rate, name)
        # The same poses: the node runs the offline run's front-end and odometry on the same cycles.
        assert_same_poses(poses, expected, name, out)
        assert "latency" in out, out
        print(name, out.strip().splitlines()[-1])
        assert any(s.name.startswith("radar_ndt") for d in diag for s in d.status), "diagnostics published"


def test_scanning_radar_node_gives_the_offline_poses(ros_env, tmp_path):
    """A scanning radar's sweeps (Boreas' layout, simulated with a navigation-grade gyro, written
    as CFEAR's bag layout): the node runs the scanning pipeline, without and with the gyro, and its
    poses are the offline run's."""
    env, work = ros_env
    seq, bag = tmp_path / "boreas", str(tmp_path / "boreas.bag")
    subprocess.run([f"{BIN}/radar_sim", "--layout", "boreas", "--imu", "navigation", "--start", "80", "--frames", "40",
                    "--out", str(seq), "-q"], check=True, capture_output=True)
    subprocess.run([f"{BIN}/radar_scans_to_bag", "--format", "boreas", "--sequence", str(seq), "--out", bag],
                   check=True, capture_output=True)
    sensors = "preset:navtech_boreas"
    plain = offline(bag, work, sensors=sensors)
    # A navigation-grade gyro's bias walk (docs/results/boreas_sim.md): a double of 1e-7, which the
    # node once turned into text with %f, that is 0.
    gyro = offline(bag, work, "--imu", "--imu-bias-walk", "1e-7", sensors=sensors)
    default_walk = offline(bag, work, "--imu", sensors=sensors)
    assert len(plain) == 40 and np.abs(gyro[:, 1:3] - plain[:, 1:3]).max() > 1e-3  # the gyro is seen used
    assert np.abs(gyro[:, 1:3] - default_walk[:, 1:3]).max() > 1e-4  # and so is its bias walk
    period = reference_period(bag, "/Navtech/Polar")
    # At 10x the bag is played twice: the second pass starts again and gives the same poses.
    for expected, rate, plays, name, params in ((plain, 1.0, 1, "scanning", []),
                                                (gyro, 10.0, 2, "scanning-gyro-fast",
                                                 ["_odometry/gyro/enabled:=true", "_odometry/gyro/bias_walk:=1e-7"])):
        poses, diag, out = run_node(env, work, bag, rate, name, *params, sensors=sensors,
                                    topics=["/Navtech/Polar", "/imu"], period=period, plays=plays,
                                    connected=bool(params))
        assert len(poses) == plays * len(expected), f"{name}: {len(poses)} poses\n{out}"
        for k in range(plays):
            assert_same_poses(poses[k * len(expected):(k + 1) * len(expected)], expected, f"{name} pass {k + 1}", out)
        print(name, out.strip().splitlines()[-1])
        radar = [s for d in diag for s in d.status if s.name == "radar_ndt: /Navtech/Polar"]
        assert radar and int(dict((v.key, v.value) for v in radar[-1].values)["messages"]) == 40 * plays


def add_speed_topic(bag, out):
    """`bag` with a speed topic added: nav_msgs/Odometry on /vehicle/odom at every ground-truth
    pose, twist.linear.x the speed between it and the next (the node reads either this type or
    geometry_msgs/TwistStamped, told by each message's type)."""
    import rosbag
    import rospy
    from nav_msgs.msg import Odometry
    shutil.copy(bag, out)
    poses = []
    with rosbag.Bag(bag) as b:
        for _, m, _ in b.read_messages(topics=["/tf"]):
            for t in m.transforms:
                if t.header.frame_id == "map" and t.child_frame_id == "base_link":
                    poses.append((t.header.stamp, t.transform.translation.x, t.transform.translation.y))
    written = 0
    with rosbag.Bag(out, "a") as b:
        for k, ((s0, x0, y0), (s1, x1, y1)) in enumerate(zip(poses, poses[1:])):
            if s1 <= s0:
                continue
            o = Odometry()
            o.header.stamp = s0
            o.twist.twist.linear.x = float(np.hypot(x1 - x0, y1 - y0) / (s1 - s0).to_sec())
            b.write("/vehicle/odom", o, s0)
            written += 1
            if k == 10:  # a speed that is not a number: left out by both, said by the node
                o.header.stamp = s0 + rospy.Duration(0.001)
                o.twist.twist.linear.x = float("nan")
                b.write("/vehicle/odom", o, o.header.stamp)
    return written


def test_with_the_speed_the_node_gives_the_offline_wheels_poses(ros_env, tmp_path):
    env, work = ros_env
    bag = str(tmp_path / "speed.bag")
    assert add_speed_topic(write_bag(work), bag) > 100
    sensors = tmp_path / "ars408_speed.yaml"
    preset = os.path.join(os.path.dirname(__file__), "..", "..", "config", "sensors", "nuscenes_ars408.yaml")
    sensors.write_text(open(preset).read() + "speed: /vehicle/odom\n")
    expected = offline(bag, work, "--imu", "--wheels", sensors=str(sensors))
    gyro_only = offline(bag, work, "--imu", sensors=str(sensors))
    assert np.abs(expected[:, 1:3] - gyro_only[:, 1:3]).max() > 1e-3  # the speed is seen used
    poses, diag, out = run_node(env, work, bag, 10.0, "speed-fast", "_odometry/car/gyro:=true",
                                "_odometry/car/wheels:=true", sensors=str(sensors),
                                topics=NUSCENES_TOPICS + ["/vehicle/odom"])
    assert_same_poses(poses, expected, "speed-fast", out)
    print("speed-fast", out.strip().splitlines()[-1])
    speed = [s for d in diag for s in d.status if s.name == "radar_ndt: /vehicle/odom"]
    counts = dict((v.key, v.value) for v in speed[-1].values) if speed else {}
    assert int(counts.get("messages", 0)) > 100 and counts["not a speed"] == "1", counts


def test_a_bag_played_again_starts_the_odometry_again(ros_env):
    """A bag played twice (as `rosbag play -l` does): the time jumps back, the node warns, says so
    in /diagnostics and starts again, and the second pass gives the offline poses again."""
    env, work = ros_env
    bag = write_bag(work)
    expected = offline(bag, work)
    # A quiet longer than the pause between the passes: the first pass's last cycles are not flushed
    # by the quiet but must be run when the time jumps back (a slow build is still working then).
    poses, diag, out = run_node(env, work, bag, 10.0, "again", plays=2, flush_after=10.0)
    passes = np.split(poses, np.flatnonzero(np.diff(poses[:, 0]) < 0) + 1) if len(poses) else []
    assert [len(p) for p in passes] == [len(expected)] * 2, \
        f"{[len(p) for p in passes]} poses in the passes, of {len(expected)} each\n{out}"
    assert_same_poses(poses[:len(expected)], expected, "first pass", out)
    assert_same_poses(poses[len(expected):], expected, "second pass", out)
    assert "time jumped back" in out and "starts again" in out, out
    said = [s.message for d in diag for s in d.status if "time jumped back" in s.message]
    assert said, "the jump is said in /diagnostics"


DRIVER_FIELDS = {"vx": "vrel_long", "vy": "vrel_lat", "x_rms": "dist_long_rms", "y_rms": "dist_lat_rms"}


def record_style_bag(src, out, chain=False):
    """`src` (a scene's bag in nuscenes2bag's layout) laid out as a radar driver and `rosbag record`
    lay one out: the mountings once, on /tf_static at the bag's start, its connection latched (the
    radars' edges left out of /tf, the ground truth's kept), and the clouds' fields under a driver's
    names (Continental's cluster list: VrelLong, DistLong_rms, ...). With `chain`, each radar is
    reached through a mount frame: base_link -> RADAR_X_mount (its position) -> RADAR_X (its
    rotation)."""
    import rosbag
    import rospy
    # The message classes the bag's own definitions give (no message package needed).
    mountings, start, tf_header = {}, None, None
    with rosbag.Bag(src) as b:
        start = b.get_start_time()
        for _, m, _, header in b.read_messages(topics=["/tf"], return_connection_header=True):
            TFMessage, TransformStamped, tf_header = type(m), type(m.transforms[0]), header
            for t in m.transforms:
                if t.header.frame_id == "base_link" and t.child_frame_id not in mountings:
                    mountings[t.child_frame_id] = t
    static = TFMessage()
    for child, t in sorted(mountings.items()):
        if not chain:
            static.transforms.append(t)
            continue
        mount = TransformStamped()
        mount.header = t.header
        mount.child_frame_id = child + "_mount"
        mount.transform.translation = t.transform.translation
        mount.transform.rotation.w = 1.0
        sensor = TransformStamped()
        sensor.header.stamp = t.header.stamp
        sensor.header.frame_id = child + "_mount"
        sensor.child_frame_id = child
        sensor.transform.rotation = t.transform.rotation
        static.transforms += [mount, sensor]
    header = {"topic": "/tf_static", "type": tf_header["type"], "md5sum": tf_header["md5sum"],
              "message_definition": tf_header["message_definition"], "callerid": "/static_transform_publisher",
              "latching": "1"}
    with rosbag.Bag(src) as b, rosbag.Bag(out, "w") as w:
        w.write("/tf_static", static, rospy.Time.from_sec(start), connection_header=header)
        for topic, m, t in b.read_messages():
            if topic == "/tf":
                m.transforms = [x for x in m.transforms if x.header.frame_id != "base_link"]
            elif topic.startswith("/RADAR_"):
                for f in m.fields:
                    f.name = DRIVER_FIELDS.get(f.name, f.name)
            w.write(topic, m, t)


def driver_description(path):
    """A description written from docs/ros.md alone: the driver's field names, no frame: keys (the
    messages name their frames), the mountings left to /tf_static."""
    radars = "\n".join(f"  - {{name: {r}, topic: /{r}, fields: *ars408}}" for r in
                       ("RADAR_FRONT_LEFT", "RADAR_FRONT_RIGHT", "RADAR_BACK_LEFT", "RADAR_BACK_RIGHT"))
    path.write_text(f"""name: "five radars as a driver records them"
base_frame: base_link
stamps: header
imu: /imu
ground_truth: {{topic: /tf, parent: map, child: base_link}}
radars:
  - name: RADAR_FRONT
    topic: /RADAR_FRONT
    fields: &ars408
      position: [x, y, z]
      doppler: {{vx: vrel_long, vy: vrel_lat}}
      rcs: rcs
      accuracy: {{ars408_rms: [dist_long_rms, dist_lat_rms]}}
      max_range: 150
      keep: {{invalid_state: [0, 4, 8, 9, 10, 11, 12, 15, 16, 17]}}
{radars}
""")
    return str(path)


def test_a_recording_with_its_mountings_on_tf_static_runs_live_as_offline(ros_env, tmp_path):
    """A bag laid out as `rosbag record` lays one out (the mountings once, latched, before any cloud
    names its frame) and a description without frame: keys: the node publishes every cycle, equal
    to the offline run; ~odometry/fuse_doppler:=true is the default run (a switch's parameter sets
    its field's value)."""
    env, work = ros_env
    bag = str(tmp_path / "recorded.bag")
    record_style_bag(write_bag(work), bag)
    sensors = driver_description(tmp_path / "driver.yaml")
    expected = offline(bag, work, sensors=sensors)
    assert len(expected) > 250
    topics = [t for t in NUSCENES_TOPICS] + ["/tf_static"]
    poses, diag, out = run_node(env, work, bag, 10.0, "recorded", "_odometry/fuse_doppler:=true", sensors=sensors,
                                topics=topics)
    assert_same_poses(poses, expected, "recorded", out)
    print("recorded", out.strip().splitlines()[-1])


def test_a_radar_behind_a_chain_of_frames_runs_live_as_offline(ros_env, tmp_path):
    """The same with each radar reached through a mount frame (base_link -> RADAR_X_mount ->
    RADAR_X), resolved by tf2 offline and live; ~odometry/fuse_doppler:=false is the offline
    --no-fusion run."""
    env, work = ros_env
    bag = str(tmp_path / "chain.bag")
    record_style_bag(write_bag(work), bag, chain=True)
    sensors = driver_description(tmp_path / "driver.yaml")
    expected = offline(bag, work, "--no-fusion", sensors=sensors)
    fused = offline(bag, work, sensors=sensors)
    assert np.abs(expected[:, 1:3] - fused[:, 1:3]).max() > 1e-3  # the switch is seen used
    topics = [t for t in NUSCENES_TOPICS] + ["/tf_static"]
    poses, diag, out = run_node(env, work, bag, 10.0, "chain", "_odometry/fuse_doppler:=false", sensors=sensors,
                                topics=topics)
    assert_same_poses(poses, expected, "chain", out)
    print("chain", out.strip().splitlines()[-1])


RIO = os.path.join(DATA, "ros-rio-ti-mmwave", "ti_mmwave_rospkg_demo.bag")
RIO_TOPICS = ["/ti_mmwave/radar_scan_pcl", "/sensor_platform/imu"]
PRESETS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "config", "sensors")


def header_stamped_rio(out):
    """The rio bag with each message's receive time written into its header: live, a zero or
    foreign header stamp becomes the message's arrival, which no replay reproduces to the
    microsecond; with the stamps in the headers, the node and the offline run read the same times."""
    import rosbag
    with rosbag.Bag(str(out), "w") as w, rosbag.Bag(RIO) as r:
        for topic, m, t in r.read_messages(topics=RIO_TOPICS):
            m.header.stamp = t
            w.write(topic, m, t)
    return str(out)


def test_a_4d_radar_with_its_imu_runs_live_as_offline(ros_env, tmp_path):
    """The real TI bag of the rio rig through the 6-DoF node (~matcher/method:=pw-ndt-3d, ~imu,
    ~radar_latency), played at 10x: each scan waits for the IMU to pass it, and every published pose
    (position, full rotation) equals the offline run's within 1e-6."""
    env, work = ros_env
    if not os.path.exists(RIO):
        pytest.skip(f"no {RIO} (../shared/data is absent)")
    bag = header_stamped_rio(tmp_path / "rio_stamped.bag")
    sensors = tmp_path / "rio.yaml"
    with open(os.path.join(PRESETS, "ti_iwr6843_rio.yaml")) as f:
        sensors.write_text(f.read().replace("stamps: receive", "stamps: header"))
    expected = offline(bag, work, "--method", "pw-ndt-3d", "--imu", "--radar-latency", "0.125", sensors=str(sensors))
    assert len(expected) > 400
    poses, diag, out = run_node(env, work, bag, 10.0, "rio", "_matcher/method:=pw-ndt-3d", "_imu:=true",
                                "_radar_latency:=0.125", sensors=str(sensors), topics=RIO_TOPICS, period=0.1)
    assert len(poses) == len(expected), f"{len(poses)} poses published, {len(expected)} offline\n{out}"
    assert np.abs(poses[:, 0] - expected[:, 0]).max() < 1e-6
    d = np.abs(poses[:, 1:4] - expected[:, 1:4]).max(axis=1)
    assert d.max() < 1e-6, f"first difference at scan {np.argmax(d > 1e-6)}: {d.max()} m\n{out}"
    sign = np.sign(np.einsum("ij,ij->i", poses[:, 4:8], expected[:, 4:8]))[:, None]  # q and -q: one rotation
    assert np.abs(poses[:, 4:8] - sign * expected[:, 4:8]).max() < 1e-6, out
    assert np.abs(poses[:, 3]).max() > 0  # 6-DoF: the height is published
    print("rio", out.strip().splitlines()[-1])


def tf_message_class():
    """tf2_msgs/TFMessage from its definition (Debian's ROS has no Python tf2_msgs): the same type and
    md5 as the C++ message's."""
    import genpy.dynamic
    from geometry_msgs.msg import TransformStamped
    text = ("geometry_msgs/TransformStamped[] transforms\n" + "=" * 80 + "\nMSG: geometry_msgs/TransformStamped\n" +
            TransformStamped._full_text)
    return genpy.dynamic.generate_dynamic("tf2_msgs/TFMessage", text)["tf2_msgs/TFMessage"]


def rio_placed_by_tf(out, preset):
    """The rio bag with header stamps (as header_stamped_rio), its clouds naming their frame
    (ti_radar), and the preset's mounting once on a latched /tf_static at the bag's start, through a
    mount frame as a rig's URDF gives it: base_link -> ti_mount (the position) -> ti_radar (the
    rotation, roll pitch yaw about x y z)."""
    import re
    import rosbag
    import rospy
    from geometry_msgs.msg import TransformStamped
    m = re.search(r"mounting: \{x: (\S+), y: (\S+), z: (\S+), roll: (\S+), pitch: (\S+), yaw: (\S+)\}", preset)
    x, y, z, roll, pitch, yaw = (float(v) for v in m.groups())
    cr, sr, cp, sp, cy, sy = (f(a / 2) for a in (roll, pitch, yaw) for f in (np.cos, np.sin))
    quaternion = (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
                  cr * cp * cy + sr * sp * sy)  # x y z w of Rz(yaw) Ry(pitch) Rx(roll)
    mount, sensor = TransformStamped(), TransformStamped()
    mount.header.frame_id, mount.child_frame_id = "base_link", "ti_mount"
    mount.transform.translation.x, mount.transform.translation.y, mount.transform.translation.z = x, y, z
    mount.transform.rotation.w = 1.0
    sensor.header.frame_id, sensor.child_frame_id = "ti_mount", "ti_radar"
    r = sensor.transform.rotation
    r.x, r.y, r.z, r.w = quaternion
    TFMessage = tf_message_class()
    header = {"topic": "/tf_static", "type": TFMessage._type, "md5sum": TFMessage._md5sum,
              "message_definition": TFMessage._full_text, "callerid": "/robot_state_publisher", "latching": "1"}
    with rosbag.Bag(str(out), "w") as w, rosbag.Bag(RIO) as b:
        start = rospy.Time.from_sec(b.get_start_time())
        mount.header.stamp = sensor.header.stamp = start
        w.write("/tf_static", TFMessage(transforms=[mount, sensor]), start, connection_header=header)
        for topic, msg, t in b.read_messages(topics=RIO_TOPICS):
            msg.header.stamp = t
            if topic == RIO_TOPICS[0]:
                msg.header.frame_id = "ti_radar"
            w.write(topic, msg, t)
    return str(out)


def test_a_4d_radar_placed_by_tf_static_runs_live_as_offline(ros_env, tmp_path):
    """The rio bag with the radar's mounting on /tf_static only (as `rosbag record` stores a rig's
    static transforms) and a description without `mounting:`: offline, the bag's tree places the
    radar where the preset's mounting does; live, the 6-DoF node holds the scans until the tree
    places the radar, then publishes every pose, equal to the offline run's."""
    env, work = ros_env
    if not os.path.exists(RIO):
        pytest.skip(f"no {RIO} (../shared/data is absent)")
    with open(os.path.join(PRESETS, "ti_iwr6843_rio.yaml")) as f:
        preset = f.read().replace("stamps: receive", "stamps: header")
    bag = rio_placed_by_tf(tmp_path / "rio_tf.bag", preset)
    described = tmp_path / "rio.yaml"
    described.write_text(preset)
    unplaced = tmp_path / "rio_tf.yaml"
    unplaced.write_text("\n".join(line for line in preset.splitlines() if "mounting:" not in line) + "\n")
    args = ("--method", "pw-ndt-3d", "--imu", "--radar-latency", "0.125")
    expected = offline(bag, work, *args, sensors=str(unplaced))
    by_description = offline(bag, work, *args, sensors=str(described))
    assert len(expected) == len(by_description) > 400
    # The same mounting (float64 both ways): the same poses.
    assert np.abs(expected[:, 1:4] - by_description[:, 1:4]).max() < 1e-9
    poses, diag, out = run_node(env, work, bag, 10.0, "rio_tf", "_matcher/method:=pw-ndt-3d", "_imu:=true",
                                "_radar_latency:=0.125", sensors=str(unplaced), topics=RIO_TOPICS + ["/tf_static"],
                                period=0.1)
    assert len(poses) == len(expected), f"{len(poses)} poses published, {len(expected)} offline\n{out}"
    d = np.abs(poses[:, 1:4] - expected[:, 1:4]).max(axis=1)
    assert d.max() < 1e-6, f"first difference at scan {np.argmax(d > 1e-6)}: {d.max()} m\n{out}"
    sign = np.sign(np.einsum("ij,ij->i", poses[:, 4:8], expected[:, 4:8]))[:, None]
    assert np.abs(poses[:, 4:8] - sign * expected[:, 4:8]).max() < 1e-6, out
    mountings = [v.value for d in diag for s in d.status for v in s.values if v.key == "mounting"]
    assert mountings and mountings[-1] == "known", mountings
    print("rio_tf", out.strip().splitlines()[-1])


def rio_with_a_second_radar(out, preset, offset):
    """The header-stamped rio bag with a second radar on /ti_back/radar_scan_pcl: the same clouds in
    a frame turned half a turn about the radar's z (x and y negated), stamped `offset` s later, and
    the description with that radar mounted where the first is, turned back (its yaw a half turn
    more, its own spherical accuracy): both see the same world, at their own times."""
    import re
    import rosbag
    import rospy
    m = re.search(r"mounting: \{x: (\S+), y: (\S+), z: (\S+), roll: (\S+), pitch: (\S+), yaw: (\S+)\}", preset)
    x, y, z, roll, pitch, yaw = (float(v) for v in m.groups())
    c, s = np.cos, np.sin
    rz = lambda a: np.array([[c(a), -s(a), 0], [s(a), c(a), 0], [0, 0, 1]])
    ry = lambda a: np.array([[c(a), 0, s(a)], [0, 1, 0], [-s(a), 0, c(a)]])
    rx = lambda a: np.array([[1, 0, 0], [0, c(a), -s(a)], [0, s(a), c(a)]])
    r = rz(yaw) @ ry(pitch) @ rx(roll) @ rz(np.pi)
    back = (f"{{x: {x!r}, y: {y!r}, z: {z!r}, roll: {float(np.arctan2(r[2, 1], r[2, 2]))!r}, "
            f"pitch: {float(-np.arcsin(r[2, 0]))!r}, yaw: {float(np.arctan2(r[1, 0], r[0, 0]))!r}}}")
    radar = preset[preset.index("  - name:"):]
    second = (radar.replace("IWR6843", "IWR6843_back").replace("/ti_mmwave/", "/ti_back/")
              .replace(m.group(0), "mounting: " + back)
              .replace("spherical_accuracy: {range: 0.05, azimuth_deg: 3, elevation_deg: 6}",
                       "spherical_accuracy: {range: 0.1, azimuth_deg: 5, elevation_deg: 10}"))
    assert second.count("IWR6843_back") == 1 and "elevation_deg: 10" in second
    with rosbag.Bag(str(out), "w") as w, rosbag.Bag(RIO) as b:
        for topic, msg, t in b.read_messages(topics=RIO_TOPICS):
            msg.header.stamp = t
            w.write(topic, msg, t)
            if topic == RIO_TOPICS[0]:
                xy = np.frombuffer(msg.data, dtype="<f4").reshape(-1, msg.point_step // 4).copy()
                xy[:, :2] = -xy[:, :2]
                msg.data = xy.tobytes()
                later = t + rospy.Duration.from_sec(offset)
                msg.header.stamp = later
                w.write("/ti_back/radar_scan_pcl", msg, later)
    return str(out), preset.rstrip("\n") + "\n" + second


def test_a_rig_of_two_4d_radars_runs_live_as_offline(ros_env, tmp_path):
    """Two 4D radars a rig through the 6-DoF node: the rio bag's radar and a second one turned back
    (rio_with_a_second_radar), 40 ms apart. Offline, every sweep of both runs, each with its mounting
    and its accuracy: merged into the reference's steps (the default), or a step each
    (--no-merge-sweeps); live, the node plans the same cycles and steps: every pose equal within 1e-6."""
    env, work = ros_env
    if not os.path.exists(RIO):
        pytest.skip(f"no {RIO} (../shared/data is absent)")
    with open(os.path.join(PRESETS, "ti_iwr6843_rio.yaml")) as f:
        preset = f.read().replace("stamps: receive", "stamps: header")
    bag, description = rio_with_a_second_radar(tmp_path / "rio_two.bag", preset, 0.04)
    sensors = tmp_path / "rio_two.yaml"
    sensors.write_text(description)
    single = tmp_path / "rio_one.yaml"
    single.write_text(preset)
    args = ("--method", "pw-ndt-3d", "--imu", "--radar-latency", "0.125")
    one = offline(bag, work, *args, sensors=str(single))
    topics = RIO_TOPICS + ["/ti_back/radar_scan_pcl"]
    period = reference_period(bag, RIO_TOPICS[0])
    for name, switch, parameter in (("rio_merged", (), ()), ("rio_each", ("--no-merge-sweeps",), ("_merge_sweeps:=false",))):
        expected = offline(bag, work, *args, *switch, sensors=str(sensors))
        if switch:  # a step for each sweep time: about twice the single radar's
            assert len(expected) > 1.5 * len(one), f"{len(expected)} poses with two radars, {len(one)} with one"
        else:  # a step a cycle: the reference radar's
            assert abs(len(expected) - len(one)) <= 2, f"{len(expected)} poses merged, {len(one)} with one radar"
        poses, diag, out = run_node(env, work, bag, 10.0, name, "_matcher/method:=pw-ndt-3d", "_imu:=true",
                                    "_radar_latency:=0.125", *parameter, sensors=str(sensors), topics=topics,
                                    period=period)
        assert len(poses) == len(expected), f"{name}: {len(poses)} poses published, {len(expected)} offline\n{out}"
        assert np.abs(poses[:, 0] - expected[:, 0]).max() < 1e-6
        d = np.abs(poses[:, 1:4] - expected[:, 1:4]).max(axis=1)
        assert d.max() < 1e-6, f"{name}: first difference at scan {np.argmax(d > 1e-6)}: {d.max()} m\n{out}"
        sign = np.sign(np.einsum("ij,ij->i", poses[:, 4:8], expected[:, 4:8]))[:, None]
        assert np.abs(poses[:, 4:8] - sign * expected[:, 4:8]).max() < 1e-6, out
        names = {s.hardware_id for d in diag for s in d.status}
        assert {"IWR6843", "IWR6843_back"} <= names, names
        print(name, len(expected), "poses;", out.strip().splitlines()[-1])


def test_the_launch_file_gives_the_node_its_settings_file(tmp_path):
    """launch/radar_ndt.launch loads a settings file under the node's namespace, keys as its
    parameters (nested or with slashes), each keeping its YAML type."""
    if not shutil.which("roslaunch"):
        pytest.skip("roslaunch not found (Debian's ROS 1: bash .ci/deps)")
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    settings = tmp_path / "settings.yaml"
    settings.write_text("odometry/car/gyro: true\nodometry:\n  fuse_doppler: false\nmatcher: {grid: 4.0}\n")
    env = dict(os.environ, ROS_PACKAGE_PATH=os.path.abspath(root))
    for extra, expected in (([], {}), ([f"settings:={settings}"], {"odometry/car/gyro": True,
                                                                      "odometry/fuse_doppler": False,
                                                                      "matcher/grid": 4.0})):
        done = subprocess.run(["roslaunch", "--dump-params", "radar_ndt", "radar_ndt.launch", "sensors:=my.yaml",
                               *extra], env=env, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        import yaml
        params = {k.replace("/radar_ndt/", "", 1): v for k, v in yaml.safe_load(done.stdout).items()}
        assert params.pop("sensors") == "my.yaml"
        assert set(params) - set(expected) == {"cycle_period", "flush_after", "odom_frame"}, params
        for k, v in expected.items():
            assert params[k] == v and type(params[k]) is type(v), (k, params[k])
