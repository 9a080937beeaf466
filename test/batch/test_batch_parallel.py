"""radar_batch with GNU parallel on the real data: the five nuScenes scenes x two methods and the
real Oxford scans; summary.csv equals each task run alone; report is byte-stable; a second run
skips finished tasks, a lost result reruns alone, a failing task keeps its log and stops nothing;
a killed run leaves no partial result."""

import json
import os
import pathlib
import shutil
import signal
import subprocess
import time

import pytest

from conftest import (APP_DIR, BATCH, METRICS, NUSCENES, ODOMETRY, OXFORD, SHARED, SIM, alone_figures, fmt, need,
                      read_csv, sh, tasks_of)


@pytest.fixture(scope="module")
def nuscenes_run(tmp_path_factory):
    need(NUSCENES)
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed (bash .ci/deps --test installs it)")
    run = tmp_path_factory.mktemp("batch") / "nuscenes run"  # a space: paths are quoted
    sh(BATCH, "plan", "--format", "nuscenes", "--root", NUSCENES, "--method", "pw-ndt,doppler", "--out", run)
    out = sh(BATCH, "run", run, "--engine", "parallel", "-j", "2").stdout
    assert "10 to run with parallel" in out and "10 complete, 0 failed" in out
    sh(BATCH, "report", run)
    return run


def test_every_scene_and_method_is_reported_with_the_figures_of_running_it_alone(nuscenes_run, tmp_path):
    rows = read_csv(nuscenes_run / "summary.csv")
    assert len(rows) == 10 and all(r["status"] == "complete" for r in rows)
    assert sorted({r["sequence"] for r in rows}) == ["scene-0061", "scene-0103", "scene-0655", "scene-0796",
                                                     "scene-1077"]
    commands = tasks_of(nuscenes_run)
    for r in rows:
        alone = alone_figures(commands[r["id"]], tmp_path)
        for m in METRICS:
            assert r[m] == fmt(alone[m]), (r["sequence"], r["method"], m)
    md = (nuscenes_run / "summary.md").read_text()
    assert "| pw-ndt | default | 5/5 |" in md and "lowest mean 1m_pct" in md
    assert (nuscenes_run / "summary.svg").read_text().startswith("<svg")


def test_report_writes_the_same_bytes_again(nuscenes_run):
    before = {f: (nuscenes_run / f).read_bytes() for f in ("summary.csv", "summary.md", "summary.svg")}
    sh(BATCH, "report", nuscenes_run)
    assert before == {f: (nuscenes_run / f).read_bytes() for f in before}


def test_a_second_run_skips_finished_tasks_and_reruns_only_a_lost_one(nuscenes_run):
    results = sorted((nuscenes_run / "tasks").glob("*/result.json"))
    stamps = {p: p.stat().st_mtime_ns for p in results}
    out = sh(BATCH, "run", nuscenes_run).stdout
    assert "10 complete (skipped), 0 to run" in out
    assert stamps == {p: p.stat().st_mtime_ns for p in results}
    lost = results[3]
    lost.unlink()  # a lost node: the task never finished
    out = sh(BATCH, "run", nuscenes_run, "--engine", "parallel").stdout
    assert "9 complete (skipped), 1 to run" in out
    assert lost.exists()
    assert all(p.stat().st_mtime_ns == stamps[p] for p in results if p != lost)


def test_bags_of_the_scenes_report_the_scenes_figures(nuscenes_run, tmp_path):
    to_bag = APP_DIR / "radar_nuscenes_to_bag"
    if not to_bag.exists():
        pytest.skip("this build has no ROS 1 support (bash .ci/deps installs Debian's ROS 1)")
    bags = tmp_path / "my bags"  # a space: paths are quoted
    for scene in ("scene-0061", "scene-0655"):
        sh(to_bag, "--dataroot", NUSCENES, "--scene", scene, "--out", bags)
    run = tmp_path / "bag run"
    sh(BATCH, "plan", "--format", "rosbag", "--root", bags, "--sensors", "preset:nuscenes_ars408", "--method",
       "pw-ndt,doppler", "--out", run)
    out = sh(BATCH, "run", run, "--engine", "parallel", "-j", "2").stdout
    assert "4 complete, 0 failed" in out
    sh(BATCH, "report", run)
    scenes = {(r["sequence"], r["method"]): r for r in read_csv(nuscenes_run / "summary.csv")}
    rows = read_csv(run / "summary.csv")
    assert len(rows) == 4
    for r in rows:  # a bag of a scene is the scene: the same figures to the last printed digit
        assert all(r[m] == scenes[(r["sequence"], r["method"])][m] for m in METRICS), r
    assert "--sensors preset:nuscenes_ars408" in (run / "tasks.tsv").read_text()


def test_a_4d_radars_bags_run_six_dof_with_the_imu_switched_off_and_on(tmp_path):
    """A 6-DoF plan: simulated 4D radar bags (the TI preset carried along the shared hand-held
    walks), `--set imu=off,on` as the switch it is, the rows equal to each task run alone."""
    walks = need(SHARED / "handheld-6dof")
    if not (APP_DIR / "radar_nuscenes_to_bag").exists():
        pytest.skip("this build has no ROS 1 support (bash .ci/deps installs Debian's ROS 1)")
    bags = tmp_path / "4d bags"
    bags.mkdir()
    for walk in ("carried_1", "carried_4"):
        sh(SIM, "--type", "4d", "--preset", "ti_iwr6843_rio", "--trajectory", walks / f"{walk}.txt", "--imu", "mems",
           "--out", tmp_path / walk)
        (tmp_path / walk / "radar.bag").rename(bags / f"{walk}.bag")
    sensors = tmp_path / "carried_1" / "sensors.yaml"
    run = tmp_path / "six dof"
    sh(BATCH, "plan", "--format", "rosbag", "--root", bags, "--sensors", sensors, "--method", "pw-ndt-3d",
       "--set", "imu=off,on", "--out", run)
    out = sh(BATCH, "run", run, "--engine", "parallel", "-j", "2").stdout
    assert "4 complete, 0 failed" in out, out
    sh(BATCH, "report", run)
    commands = tasks_of(run)
    rows = read_csv(run / "summary.csv")
    assert sorted((r["sequence"], r["settings"]) for r in rows) == [
        ("carried_1", "imu=off"), ("carried_1", "imu=on"), ("carried_4", "imu=off"), ("carried_4", "imu=on")]
    for r in rows:
        assert ("--imu" in commands[r["id"]]) == (r["settings"] == "imu=on")
        argv = list(commands[r["id"]])
        argv[argv.index("--out") + 1] = str(tmp_path / "alone.txt")
        alone = json.loads(sh(*argv).stdout)["metrics"]
        assert r["ate_posyaw_m"] == fmt(alone["ate6"]["posyaw"]["rmse_m"]), r
        assert r["final_pct"] == fmt(alone["final"]["final_pct"]), r
    assert "lowest mean ate_posyaw_m" in (run / "summary.md").read_text()
    # 6-DoF and planar methods run different pipelines: one plan takes one kind.
    done = sh(BATCH, "plan", "--format", "rosbag", "--root", bags, "--sensors", sensors, "--method",
              "pw-ndt-3d,pw-ndt", "--out", tmp_path / "mixed", check=False)
    assert done.returncode == 1 and "plan them in separate runs" in done.stderr, done.stderr
    done = sh(BATCH, "plan", "--format", "rosbag", "--root", bags, "--sensors", sensors, "--method", "pw-ndt-3d",
              "--set", "imu=yes", "--out", tmp_path / "bad switch", check=False)
    assert done.returncode == 1 and "on and off" in done.stderr, done.stderr


def test_the_real_oxford_scans_and_a_failing_setting(tmp_path):
    need(OXFORD)
    run = tmp_path / "oxford"
    # threshold 0.99 keeps no point: radar_odometry says the run was mostly unmatched and exits 1.
    sh(BATCH, "plan", "--format", "oxford", "--root", OXFORD, "--method", "pw-ndt,pcl-ndt", "--set",
       "threshold=0.333,0.99", "--out", run)
    done = sh(BATCH, "run", run, "--engine", "parallel", check=False)
    assert done.returncode == 1 and "2 complete, 2 failed" in done.stdout
    sh(BATCH, "report", run)
    rows = read_csv(run / "summary.csv")
    commands = tasks_of(run)
    for r in rows:
        if r["settings"] == "threshold=0.333":
            assert r["status"] == "complete"
            alone = alone_figures(commands[r["id"]], tmp_path)
            assert all(r[m] == fmt(alone[m]) for m in METRICS)
        else:
            assert r["status"] == "failed" and r["exit_code"] == "1"
            assert "mostly" in (run / r["log"]).read_text()
    md = (run / "summary.md").read_text()
    assert "## Failed tasks" in md and "threshold=0.99" in md
    assert sh(BATCH, "run", run, check=False).stdout.startswith("4 tasks: 2 complete (skipped), 2 to run")


def test_a_killed_run_resumes_without_partial_results(tmp_path):
    need(NUSCENES)
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed")
    run = tmp_path / "killed"
    sh(BATCH, "plan", "--format", "nuscenes", "--root", NUSCENES, "--method", "pw-ndt,pcl-icp", "--out", run)
    p = subprocess.Popen([str(BATCH), "run", str(run), "-j", "1"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.time() + 120
    while time.time() < deadline and len(list((run / "tasks").glob("*/result.json"))) < 2:
        time.sleep(0.05)
    kill_session(p.pid)  # the whole run: radar_batch, parallel, the tasks running (their own groups)
    p.wait()
    finished = {r.parent.name: r.stat().st_mtime_ns for r in (run / "tasks").glob("*/result.json")}
    assert 2 <= len(finished) < 10
    time.sleep(0.5)
    assert finished == {r.parent.name: r.stat().st_mtime_ns for r in (run / "tasks").glob("*/result.json")}
    out = sh(BATCH, "run", run, "-j", "2").stdout
    assert f"{len(finished)} complete (skipped), {10 - len(finished)} to run" in out
    assert all((run / "tasks" / i / "result.json").stat().st_mtime_ns == t for i, t in finished.items())
    sh(BATCH, "report", run)
    assert all(r["status"] == "complete" for r in read_csv(run / "summary.csv"))


def kill_session(sid):
    """SIGKILL to every process of session `sid` (GNU parallel puts each job in a group of its own),
    again until none is left: a job forked while the first round ran is caught by the next."""
    for _ in range(200):
        alive = []
        for stat in pathlib.Path("/proc").glob("[0-9]*/stat"):
            try:
                fields = stat.read_text().rsplit(")", 1)[1].split()
                if int(fields[3]) == sid and fields[0] != "Z":
                    alive.append(int(stat.parent.name))
            except (OSError, ValueError, IndexError):
                pass
        if not alive:
            return
        for pid in alive:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        time.sleep(0.02)
    raise AssertionError(f"session {sid} still has processes")


def test_plans_refuse_bad_settings_and_name_what_is_wrong(tmp_path):
    need(NUSCENES)
    for args, message in [(["--set", "gird=3"], "gird"), (["--set", "grid=-1"], "grid"),
                          (["--method", "gicp"], "gicp"), (["--sequences", "scene-9999"], "scene-9999")]:
        done = sh(BATCH, "plan", "--format", "nuscenes", "--root", NUSCENES, "--out", tmp_path / "bad", *args,
                  check=False)
        assert done.returncode == 1 and message in done.stderr, done.stderr
    assert ODOMETRY.exists()
