#!/usr/bin/env python3
"""A single-node Slurm on this machine, in a folder of its own: munged with its own key and socket,
slurmctld and slurmd on loopback ports of their own, proctrack/linuxproc and task/none (no cgroups),
select/cons_tres over this machine's CPUs. For radar_batch's Slurm test and benchmark; needs root
(a container) and Debian's munge, slurmctld, slurmd and slurm-client.

    python3 test/batch/local_slurm.py start DIR   # prints: export SLURM_CONF=DIR/slurm.conf
    python3 test/batch/local_slurm.py stop DIR
"""

import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import time

PROGRAMS = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo"]


def missing():
    """Why a local Slurm cannot start here ("" when it can)."""
    absent = [p for p in PROGRAMS if shutil.which(p) is None and not os.path.exists(f"/usr/sbin/{p}")]
    if absent:
        return "not installed: " + ", ".join(absent) + " (bash .ci/deps --test installs munge, slurmctld, slurmd, " \
               "slurm-client)"
    if os.geteuid() != 0:
        return "the daemons start as root (a container); this user is not root"
    return ""


def program(name):
    return shutil.which(name) or f"/usr/sbin/{name}"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def node_line(host):
    """This machine as slurmd sees it (CPUs, sockets, memory), named `host`."""
    line = subprocess.run([program("slurmd"), "-C"], capture_output=True, text=True, check=True).stdout.splitlines()[0]
    fields = [f for f in line.split() if not f.startswith(("NodeName=", "UpTime="))]
    return f"NodeName={host} NodeAddr=127.0.0.1 " + " ".join(fields) + " State=UNKNOWN"


def start(folder):
    """Starts munged, slurmctld and slurmd in `folder`; the environment clients need (SLURM_CONF)."""
    d = pathlib.Path(folder).resolve()
    (d / "state").mkdir(parents=True, exist_ok=True)
    (d / "spool").mkdir(exist_ok=True)
    key = d / "munge.key"
    key.write_bytes(os.urandom(1024))
    key.chmod(0o600)
    host = socket.gethostname().split(".")[0]
    conf = d / "slurm.conf"
    conf.write_text("\n".join([
        "ClusterName=radarndt", f"SlurmctldHost={host}(127.0.0.1)", f"SlurmctldPort={free_port()}",
        f"SlurmdPort={free_port()}", "SlurmUser=root", "SlurmdUser=root", "AuthType=auth/munge",
        "CredType=cred/munge", f"AuthInfo=socket={d}/munge.sock", f"StateSaveLocation={d}/state",
        f"SlurmdSpoolDir={d}/spool", f"SlurmctldPidFile={d}/slurmctld.pid", f"SlurmdPidFile={d}/slurmd.pid",
        f"SlurmctldLogFile={d}/slurmctld.log", f"SlurmdLogFile={d}/slurmd.log",
        "ProctrackType=proctrack/linuxproc", "TaskPlugin=task/none", "SelectType=select/cons_tres",
        "SelectTypeParameters=CR_Core", "JobAcctGatherType=jobacct_gather/none",
        "AccountingStorageType=accounting_storage/none", "JobCompType=jobcomp/none", "MpiDefault=none",
        "ReturnToService=2", "MailProg=/bin/true", "SchedulerParameters=sched_min_interval=100000",
        node_line(host), f"PartitionName=batch Nodes={host} Default=YES MaxTime=INFINITE State=UP", ""]))
    env = dict(os.environ, SLURM_CONF=str(conf))
    log = open(d / "daemons.out", "ab")
    pids = []
    munged = subprocess.Popen([program("munged"), "-F", "--force", f"--socket={d}/munge.sock", f"--key-file={key}",
                               f"--pid-file={d}/munged.pid", f"--log-file={d}/munged.log",
                               f"--seed-file={d}/munged.seed"], stdout=log, stderr=log, start_new_session=True)
    pids.append(munged.pid)
    wait_for(lambda: (d / "munge.sock").exists(), 20, "munged's socket", d)
    ctld = subprocess.Popen([program("slurmctld"), "-D", "-i", "-f", str(conf)], stdout=log, stderr=log, env=env,
                            start_new_session=True)
    pids.append(ctld.pid)
    slurmd = subprocess.Popen([program("slurmd"), "-D", "-f", str(conf), "-N", host], stdout=log, stderr=log,
                              env=env, start_new_session=True)
    pids.append(slurmd.pid)
    (d / "pids").write_text(" ".join(map(str, pids)))
    wait_for(lambda: "idle" in subprocess.run([program("sinfo"), "-h", "-o", "%T"], capture_output=True, text=True,
                                              env=env).stdout, 60, "the node to be idle", d)
    return env


def wait_for(ready, seconds, what, d):
    deadline = time.time() + seconds
    while time.time() < deadline:
        if ready():
            return
        time.sleep(0.2)
    stop(d)
    raise RuntimeError(f"local Slurm: no {what} after {seconds} s; logs in {d}")


def stop(folder):
    """Stops the daemons `start` started in `folder`."""
    d = pathlib.Path(folder)
    pids = [int(p) for p in (d / "pids").read_text().split()] if (d / "pids").exists() else []
    for pid in reversed(pids):
        try:
            os.kill(pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    deadline = time.time() + 15
    for pid in reversed(pids):
        while time.time() < deadline:
            try:
                os.kill(pid, 0)
                os.waitpid(pid, os.WNOHANG)
                time.sleep(0.1)
            except (ProcessLookupError, ChildProcessError):
                break
        else:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("start", "stop"):
        sys.exit(__doc__)
    if sys.argv[1] == "start":
        why = missing()
        if why:
            sys.exit("local Slurm: " + why)
        print(f"export SLURM_CONF={start(sys.argv[2])['SLURM_CONF']}")
    else:
        stop(sys.argv[2])
