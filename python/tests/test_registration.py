"""The matchers from Python: align on a real Oxford pair equals the C++ matcher's result bit for
bit; known motions are recovered by ours, PCL's NDT and PCL's ICP; every guess form means the same."""

import os
import subprocess

import numpy as np
import pytest

import radar_ndt
from conftest import OXFORD, need


def synthetic_pair(motion=(0.6, -0.3, 0.04), n=3000, seed=3):
    """A target of walls and posts, and the source seen from `motion` (x, y, yaw) in it."""
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 1, n)
    walls = np.c_[np.where(t < 0.5, -20 + 80 * t, 20 - 80 * (t - 0.5)), np.where(t < 0.5, 12.0, -15.0)]
    walls[: n // 4, 1] = rng.uniform(-15, 12, n // 4)
    walls[: n // 4, 0] = 25.0
    walls += rng.normal(0, 0.05, walls.shape)
    target = np.c_[walls, rng.uniform(0.4, 1.0, n)]
    x, y, yaw = motion
    c, s = np.cos(yaw), np.sin(yaw)
    source = target.copy()
    source[:, :2] = (target[:, :2] - [x, y]) @ np.array([[c, -s], [s, c]])
    return source, target


def reference(a, b, resolution, shift, guess_x):
    exe = os.environ.get("RADAR_NDT_ALIGN_REFERENCE")
    if not exe:
        pytest.skip("RADAR_NDT_ALIGN_REFERENCE is not set (CTest sets it)")
    out = subprocess.run([exe, a, b, str(resolution), str(shift), str(guess_x)], capture_output=True, text=True,
                         check=True).stdout
    fields = {}
    for line in out.splitlines():
        key, *values = line.split()
        fields[key] = values
    return fields


def test_align_on_a_real_oxford_pair_equals_the_cpp_matcher():
    need(OXFORD)
    scans = sorted((OXFORD / "radar").glob("*.png"))
    a, b = str(scans[3]), str(scans[4])
    ref = reference(a, b, 3.75, 0.333, 1.0)
    front_end = radar_ndt.PowerThreshold()
    target = front_end.points(radar_ndt.read_oxford_scan(a))
    source = front_end.points(radar_ndt.read_oxford_scan(b))
    assert len(source) == int(ref["source_points"][0]) and len(target) == int(ref["target_points"][0])
    ndt = radar_ndt.WeightedNDT2D(resolution=3.75, power_shift=0.333)
    r = ndt.align(source, target, (1.0, 0.0, 0.0))
    assert r.status == ref["status"][0] and r.converged == bool(int(ref["converged"][0]))
    assert r.iterations == int(ref["iterations"][0])
    assert r.final_cost == float.fromhex(ref["final_cost"][0])
    expected = np.array([float.fromhex(v) for v in ref["final_transformation"]], dtype=np.float32).reshape(4, 4)
    assert r.final_transformation.dtype == np.float32
    assert np.array_equal(r.final_transformation, expected)
    cov = np.array([float.fromhex(v) for v in ref["covariance"]]).reshape(3, 3)
    assert np.array_equal(r.covariance, cov)
    assert r.num_matched_points == int(ref["num_matched_points"][0])
    # A real pair at 4 Hz: the car moved forward by metres, not tens of them.
    assert r.converged and 0.1 < r.pose[0] < 5.0 and abs(r.pose[2]) < 0.1


@pytest.mark.parametrize("matcher", [
    lambda: radar_ndt.WeightedNDT2D(resolution=3.0),
    lambda: radar_ndt.WeightedNDT2D(resolutions=[6.0, 3.0], cell_lookup="overlapping-grids"),
    lambda: radar_ndt.NDT(resolution=3.0),
    lambda: radar_ndt.ICP(max_correspondence_distance=3.0),
], ids=["ours", "ours-coarse-to-fine", "pcl-ndt", "pcl-icp"])
def test_a_known_motion_is_recovered(matcher):
    motion = (0.6, -0.3, 0.04)
    source, target = synthetic_pair(motion)
    r = matcher().align(source, target)
    assert r.converged, r.status
    assert np.allclose(r.pose, motion, atol=[0.05, 0.05, 0.005]), r.pose
    assert np.allclose(r.transform[:2, 2], r.pose[:2])
    assert r.final_transformation.shape == (4, 4)


def test_every_guess_form_means_the_same():
    source, target = synthetic_pair()
    g = (0.5, -0.2, 0.03)
    c, s = np.cos(g[2]), np.sin(g[2])
    m3 = np.array([[c, -s, g[0]], [s, c, g[1]], [0, 0, 1]])
    m4 = np.eye(4)
    m4[:2, :2], m4[:2, 3] = m3[:2, :2], m3[:2, 2]
    ndt = radar_ndt.WeightedNDT2D()
    poses = [ndt.align(source, target, guess).final_transformation for guess in (g, m3, m4)]
    assert np.array_equal(poses[0], poses[1]) and np.array_equal(poses[1], poses[2])


def test_points_with_every_field_and_without_power():
    source, target = synthetic_pair()
    full = np.zeros((len(source), len(radar_ndt.POINT_FIELDS)))
    full[:, 0:2], full[:, 3] = source[:, :2], source[:, 2]
    ndt = radar_ndt.WeightedNDT2D()
    assert np.array_equal(ndt.align(full, target).final_transformation,
                          ndt.align(source, target).final_transformation)
    assert ndt.align(source[:, :2], target[:, :2]).converged


def test_settings_are_keywords_and_stay_validated():
    ndt = radar_ndt.WeightedNDT2D(resolution=2.5, power_shift=0.2, min_points_per_cell=1, source_voxel_size=0.0,
                                  max_iterations=12, transformation_epsilon=1e-6)
    s = ndt.settings
    assert s.resolutions == [2.5] and abs(s.power_shift - 0.2) < 1e-7 and s.min_points_per_cell == 1
    assert ndt.max_iterations == 12 and ndt.transformation_epsilon == 1e-6
    s.cell_lookup = "overlapping-grids"
    ndt.settings = s
    assert ndt.settings.cell_lookup == "overlapping-grids"
    with pytest.raises(ValueError, match="eigenvalue_ratio"):
        radar_ndt.WeightedNDT2D(eigenvalue_ratio=-1.0)
    with pytest.raises(ValueError, match="cell_lookup"):
        radar_ndt.WeightedNDT2D(cell_lookup="nearest")
    with pytest.raises(TypeError, match="resolutionz"):
        radar_ndt.WeightedNDT2D(resolutionz=2.0)
    bad = ndt.settings
    bad.armijo = 2.0
    with pytest.raises(ValueError, match="armijo"):
        ndt.settings = bad
    assert ndt.settings.armijo != 2.0  # a refused setting changes nothing
    with pytest.raises(TypeError, match="step_size"):
        radar_ndt.ICP(step_size=0.1)
    with pytest.raises(ValueError, match="resolution"):
        radar_ndt.NDT(resolution=0.0)
    with pytest.raises(TypeError, match="max_iterations"):
        radar_ndt.WeightedNDT2D(max_iterations="many")
    with pytest.raises(TypeError, match="resolution"):
        radar_ndt.NDT(resolution=[1, 2])


def test_a_skewed_sweep_is_recovered_with_its_time_offsets():
    """A source seen from a sensor moving at 12 m/s through its quarter-second sweep: with its time
    offsets and set_source_sweep the motion is recovered; rigidly it is not."""
    _, target = synthetic_pair(n=6000, seed=5)
    v, yaw_rate, dt = 12.0, 0.3, 0.25
    th = yaw_rate * dt
    motion = np.array([v * np.sin(th) / yaw_rate, v * (1 - np.cos(th)) / yaw_rate, th])  # exp of the velocity

    def pose_at(tau):  # the sensor's pose at time tau after the source's reference time, in the target frame
        a = th + yaw_rate * tau
        return np.array([v * np.sin(a) / yaw_rate, v * (1 - np.cos(a)) / yaw_rate, a])

    az = np.arctan2(target[:, 1] - motion[1], target[:, 0] - motion[0])
    tau = dt * (az + np.pi) / (2 * np.pi)
    poses = np.array([pose_at(t) for t in tau])
    d = target[:, :2] - poses[:, :2]
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    full = np.zeros((len(target), len(radar_ndt.POINT_FIELDS)))
    full[:, 0], full[:, 1] = c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]
    full[:, radar_ndt.POINT_FIELDS.index("power")] = target[:, 2]
    full[:, radar_ndt.POINT_FIELDS.index("time_offset")] = tau
    ndt = radar_ndt.WeightedNDT2D(resolutions=[6.0, 3.0])
    guess = motion * 0.9
    rigid = ndt.align(full, target, guess).pose
    ndt.set_source_sweep(dt)
    assert ndt.has_source_sweep
    r = ndt.align(full, target, guess)
    assert r.converged, r.status
    assert np.allclose(r.pose, motion, atol=[0.03, 0.03, 0.002]), (r.pose, motion)
    assert np.hypot(*(rigid[:2] - motion[:2])) > 0.3, rigid
    ndt.clear_source_sweep()
    assert np.array_equal(ndt.align(full, target, guess).pose, rigid)
    with pytest.raises(ValueError, match="interval"):
        ndt.set_source_sweep(0.0)
