"""What radar_batch's integration tests share: the apps, the shared data, running a command."""

import json
import os
import pathlib
import shlex
import subprocess

import pytest

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parents[1]
SHARED = pathlib.Path(os.environ.get("RADAR_NDT_SHARED_DATA", SOURCE.parent / "shared" / "data"))
APP_DIR = pathlib.Path(os.environ.get("RADAR_NDT_APP_DIR", SOURCE / "build" / "apps"))
BATCH = APP_DIR / "radar_batch"
ODOMETRY = APP_DIR / "radar_odometry"
SIM = APP_DIR / "radar_sim"
OXFORD = SHARED / "oxford-radar-real"
NUSCENES = SHARED / "nuscenes-mini-radar"
METRICS = ["kitti_pct", "kitti_deg_per_m", "1m_pct", "1m_deg_per_m", "frame_m", "frame_deg", "ate_m"]


def need(path):
    if not path.exists():
        pytest.skip(f"{path} is absent: the shared data (../shared/data beside the checkout) is not here")
    return path


def sh(*args, check=True, env=None, timeout=900):
    """Runs a command; its completed process (stdout, stderr as text)."""
    done = subprocess.run([str(a) for a in args], capture_output=True, text=True, env=env, timeout=timeout)
    if check and done.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, args))} exited {done.returncode}:\n{done.stdout}\n{done.stderr}")
    return done


def read_csv(path):
    lines = pathlib.Path(path).read_text().splitlines()
    header = lines[0].split(",")
    return [dict(zip(header, line.split(","))) for line in lines[1:]]


def fmt(v):
    """A number as the report writes it (%.9g; "" for none)."""
    return "" if v is None else "%.9g" % v


def metric(metrics, name, key):
    """metrics[name][key] when it is a number, else None (undefined, or not computed)."""
    value = metrics.get(name, {}).get(key)
    return value if isinstance(value, (int, float)) else None


def alone_figures(command, work):
    """The metrics of running a task's radar_odometry command alone (its own output file)."""
    argv = list(command)
    argv[argv.index("--out") + 1] = str(work / "alone.txt")
    m = json.loads(sh(*argv, "--threads", "1").stdout).get("metrics", {})
    return {"kitti_pct": metric(m, "kitti", "trans_err_pct"), "kitti_deg_per_m": metric(m, "kitti", "rot_err_deg_per_m"),
            "1m_pct": metric(m, "1m", "trans_err_pct"), "1m_deg_per_m": metric(m, "1m", "rot_err_deg_per_m"),
            "frame_m": metric(m, "frame", "trans_err_m"), "frame_deg": metric(m, "frame", "rot_err_deg"),
            "ate_m": metric(m, "ate", "rmse_m")}


def tasks_of(run):
    """id -> command (argv) from a run folder's tasks.tsv, read with the shell's own splitting."""
    out = {}
    for line in (pathlib.Path(run) / "tasks.tsv").read_text().splitlines():
        if line.startswith("#"):
            continue
        cols = line.split("\t")
        out[cols[0]] = shlex.split(cols[4])
    return out
