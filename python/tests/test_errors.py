"""Bad arrays and bad files raise the documented exceptions (ValueError, TypeError, radar_ndt.IoError,
an OSError naming the file) and never crash the interpreter."""

import shutil

import numpy as np
import pytest

import radar_ndt
from conftest import NUSCENES, OXFORD, need

GOOD = np.c_[np.random.default_rng(0).uniform(-20, 20, (500, 2)), np.ones(500)]


@pytest.mark.parametrize("points, message", [
    (np.zeros((0, 3)), "no points"),
    (np.zeros((10, 4)), "shape"),
    (np.zeros(30), "shape"),
    (np.zeros((2, 5, 3)), "shape"),
    (np.array([[0.0, 1.0, np.nan]] * 10), "column power is not finite"),
    (np.array([[np.inf, 1.0]] * 10), "column x is not finite"),
    ([["a", "b", "c"]], "not convertible"),
    (None, "None"),
], ids=["empty", "4 columns", "1-D", "3-D", "NaN power", "inf x", "strings", "None"])
@pytest.mark.parametrize("matcher", [radar_ndt.WeightedNDT2D, radar_ndt.NDT, radar_ndt.ICP])
@pytest.mark.parametrize("side", ["source", "target"])
def test_bad_point_arrays_raise_value_error(matcher, side, points, message):
    args = {"source": GOOD, "target": GOOD, side: points}
    with pytest.raises(ValueError, match=message) as e:
        matcher().align(args["source"], args["target"])
    assert side in str(e.value)


def test_bad_sensor_ids_and_guesses():
    full = np.zeros((10, len(radar_ndt.POINT_FIELDS)))
    full[:, 10] = 1.5
    with pytest.raises(ValueError, match="sensor_id"):
        radar_ndt.WeightedNDT2D().align(full, GOOD)
    for guess in [(1.0, 2.0), np.eye(2), np.full((3, 3), np.nan)]:
        with pytest.raises(ValueError, match="guess"):
            radar_ndt.WeightedNDT2D().align(GOOD, GOOD, guess)


def test_bad_trajectories():
    with pytest.raises(ValueError, match="poses"):
        radar_ndt.Trajectory(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="stamps"):
        radar_ndt.Trajectory(np.zeros((3, 3)), stamps=[0.0, 1.0])
    with pytest.raises(ValueError, match="increasing"):
        radar_ndt.Trajectory(np.zeros((3, 3)), stamps=[0.0, 2.0, 1.0])
    with pytest.raises(ValueError, match="not finite"):
        radar_ndt.Trajectory(np.array([[0.0, np.nan, 0.0]]))
    one = radar_ndt.Trajectory(np.zeros((1, 3)))
    with pytest.raises(ValueError):  # fewer than 2 pairs cannot be evaluated
        radar_ndt.evaluate(one, one)


def expect_io_error(call, path, match=None):
    with pytest.raises(radar_ndt.IoError, match=match) as e:
        call()
    assert isinstance(e.value, OSError)
    assert e.value.filename == str(path)
    assert str(path) in str(e.value)
    # What print(e) shows is the message, which names the problem too, not OSError's errno form.
    assert str(e.value) == e.value.args[0] == e.value.strerror
    assert "[Errno" not in str(e.value)
    return e.value


def test_missing_and_malformed_files_raise_io_error_naming_them(work):
    missing = work / "nothing.png"
    for read in (radar_ndt.read_oxford_scan, radar_ndt.read_radiate_scan, radar_ndt.read_boreas_scan):
        expect_io_error(lambda: read(str(missing)), missing)
    not_png = work / "1547131046353776.png"
    not_png.write_bytes(b"this is not a PNG at all" * 10)
    expect_io_error(lambda: radar_ndt.read_oxford_scan(str(not_png)), not_png)
    traj = work / "traj.txt"
    traj.write_text("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n")
    e = expect_io_error(lambda: radar_ndt.read_trajectory(str(traj)), traj)
    assert e.line == 2
    expect_io_error(lambda: radar_ndt.ScanningSequence(str(work / "no_sequence")),
                    work / "no_sequence" / "radar.timestamps")
    expect_io_error(lambda: radar_ndt.read_nuscenes_pcd(str(work / "x.pcd")), work / "x.pcd")


def test_a_truncated_real_scan_raises_io_error(work):
    need(OXFORD)
    scan = sorted((OXFORD / "radar").glob("*.png"))[0]
    for keep in (100, len(scan.read_bytes()) // 2, len(scan.read_bytes()) - 20):
        cut = work / scan.name
        cut.write_bytes(scan.read_bytes()[:keep])
        expect_io_error(lambda: radar_ndt.read_oxford_scan(str(cut)), cut)


def test_a_nuscenes_dataroot_without_a_table_raises_io_error(work):
    need(NUSCENES)
    root = work / "nuscenes"
    shutil.copytree(NUSCENES / "v1.0-mini", root / "v1.0-mini")
    (root / "v1.0-mini" / "ego_pose.json").unlink()
    with pytest.raises(radar_ndt.IoError, match="ego_pose.json"):
        radar_ndt.NuScenesDataset(str(root))
    with pytest.raises(ValueError, match="scene"):
        radar_ndt.NuScenesDataset(str(NUSCENES)).radar_sweeps("no-such-scene")


def test_a_bad_frame_in_a_run_is_reported_and_the_run_goes_on(work):
    need(OXFORD)
    seq = work / "oxford"
    shutil.copytree(OXFORD, seq)
    bad = sorted((seq / "radar").glob("*.png"))[5]
    bad.write_bytes(bad.read_bytes()[:1000])
    run = radar_ndt.run_scanning(str(seq), threads=1)
    assert any(bad.name in p for p in run.problems)
    assert [s.status for s in run.steps].count("bridged") == 1
    assert len(run.estimate) == len(list((seq / "radar").glob("*.png")))
