"""radar_batch on a real Slurm: a single-node Slurm started here (local_slurm.py) runs a plan of six
tasks as a job array; its report equals the GNU-parallel run's; a task cancelled mid-run (scancel)
leaves no result, and a second run reruns that task alone."""

import os
import re
import shutil
import subprocess
import time

import pytest

import local_slurm
from conftest import BATCH, METRICS, OXFORD, SIM, need, read_csv, sh


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    why = local_slurm.missing()
    if why:
        if os.environ.get("RADAR_NDT_REQUIRE_SLURM"):
            pytest.fail("a local Slurm is required here (CI) but " + why)
        pytest.skip("no local Slurm: " + why)
    folder = tmp_path_factory.mktemp("slurm")
    env = local_slurm.start(folder)
    yield env
    local_slurm.stop(folder)


@pytest.fixture(scope="module")
def sequences(tmp_path_factory):
    """The real Oxford scans and two simulated Oxford sequences, one long enough to cancel mid-run."""
    need(OXFORD)
    root = tmp_path_factory.mktemp("sequences")
    os.symlink(OXFORD, root / "oxford-real")
    gt = OXFORD.parent / "oxford-radar-gt" / "2019-01-10-11-46-21.txt"
    need(gt)
    for name, frames in (("sim-short", 30), ("sim-long", 200)):
        sh(SIM, "--type", "scanning", "--trajectory", gt, "--start", "3000", "--frames", frames, "--seed", "5",
           "--out", root / name, "-q")
    return root


def plan(root, out):
    sh(BATCH, "plan", "--format", "oxford", "--root", root, "--method", "pw-ndt,pcl-ndt", "--out", out)
    return out


def array_states(env, job):
    """{array index: state} of the job's array tasks still queued or running."""
    out = subprocess.run(["squeue", "-h", "-r", "-j", job, "-o", "%K %T"], capture_output=True, text=True,
                         env=env).stdout
    return {int(k): s for k, s in (line.split() for line in out.splitlines() if line.strip())}


def wait_until(done, seconds, what):
    deadline = time.time() + seconds
    while time.time() < deadline:
        if done():
            return
        time.sleep(0.1)
    raise AssertionError(f"no {what} after {seconds} s")


def without_timing(rows):
    return [{k: v for k, v in r.items() if k != "ms_per_scan"} for r in rows]


def test_a_job_array_runs_the_plan_and_a_cancelled_task_alone_reruns(slurm, sequences, tmp_path):
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed (bash .ci/deps --test installs it)")
    reference = plan(sequences, tmp_path / "parallel")
    sh(BATCH, "run", reference, "--engine", "parallel", "-j", "2")
    sh(BATCH, "report", reference)

    run = plan(sequences, tmp_path / "slurm")
    ids = [line.split("\t")[0] for line in (run / "tasks.tsv").read_text().splitlines()[1:]]
    assert len(ids) == 6
    out = sh(BATCH, "run", run, "--engine", "slurm", "--throttle", "1", "--mem", "1G", env=slurm).stdout
    job = re.search(r"Submitted batch job (\d+)", out).group(1)
    # The long sequence's pcl-ndt task: cancelled while it runs.
    rows = read_csv(reference / "summary.csv")
    target = next(r["id"] for r in rows if r["sequence"] == "sim-long" and r["method"] == "pcl-ndt")
    index = (run / "slurm" / "pending-1.txt").read_text().split().index(target) + 1
    wait_until(lambda: array_states(slurm, job).get(index) == "RUNNING", 300, f"array task {index} running")
    time.sleep(1.0)
    sh("scancel", f"{job}_{index}", env=slurm)
    wait_until(lambda: not array_states(slurm, job), 300, "end of the job array")

    sh(BATCH, "report", run)
    after_first = {r["id"]: r for r in read_csv(run / "summary.csv")}
    assert after_first[target]["status"] == "missing"
    assert not (run / "tasks" / target / "result.json").exists()
    assert sum(r["status"] == "complete" for r in after_first.values()) == 5
    assert target in (run / "summary.md").read_text()
    results = {i: (run / "tasks" / i / "result.json").stat().st_mtime_ns for i in ids if i != target}

    out = sh(BATCH, "run", run, "--engine", "slurm", "--wait", "--throttle", "2", "--mem", "1G", env=slurm).stdout
    assert "5 complete (skipped), 1 to run with slurm" in out and "6 complete, 0 failed" in out
    assert (run / "slurm" / "pending-2.txt").read_text().split() == [target]
    assert results == {i: (run / "tasks" / i / "result.json").stat().st_mtime_ns for i in results}
    sh(BATCH, "report", run)
    assert without_timing(read_csv(run / "summary.csv")) == without_timing(read_csv(reference / "summary.csv"))
    logs = list((run / "slurm" / "logs").glob("*.out"))
    assert len(logs) == 7  # six array tasks, then the one rerun
    assert all(r[m] != "" for r in read_csv(run / "summary.csv") for m in ("frame_m", "ate_m"))
    assert set(METRICS) <= set(read_csv(run / "summary.csv")[0])
