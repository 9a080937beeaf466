"""The example script runs the real Oxford scans and writes its plot."""

import subprocess
import sys

from conftest import OXFORD, SOURCE, need


def test_the_oxford_example_writes_its_png(work):
    need(OXFORD)
    out = work / "oxford_trajectory.png"
    done = subprocess.run([sys.executable, str(SOURCE / "examples" / "oxford_trajectory.py"), "--sequence",
                           str(OXFORD), "--out", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "frame error" in done.stdout and "ATE" in done.stdout
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_the_type_stubs_check_the_example(tmp_path):
    """The stubs written beside the module (make_stubs.py) are valid and type the example's use of it."""
    import os
    import importlib.util
    import pathlib

    import pytest

    import radar_ndt

    stub = pathlib.Path(radar_ndt.__file__).parent / "_radar_ndt.pyi"
    if not stub.exists() or importlib.util.find_spec("mypy") is None:
        pytest.skip("no type stubs or no mypy (Debian's mypy writes and checks them; bash .ci/deps installs it)")
    env = dict(os.environ, MYPYPATH=str(stub.parent.parent))
    typed = tmp_path / "typed_use.py"  # calls whose argument types the stubs must accept
    typed.write_text(
        "import pathlib\nimport numpy as np\nimport radar_ndt\n"
        "scan: radar_ndt.PolarScan = radar_ndt.read_oxford_scan('a.png')\n"
        "scan = radar_ndt.read_oxford_scan(pathlib.Path('a.png'))\n"
        "points: np.ndarray = radar_ndt.PowerThreshold().points(scan)\n"
        "r: radar_ndt.WeightedNDT2DResult = radar_ndt.WeightedNDT2D(resolution=3.0).align(points, points)\n"
        "ok: bool = r.converged\n"
        "run: radar_ndt.ScanningRun = radar_ndt.run_scanning('seq', format='oxford')\n"
        "m: dict = radar_ndt.evaluate(run.ground_truth, run.estimate, 'frame')\n")
    for script in (SOURCE / "examples" / "oxford_trajectory.py", typed):
        done = subprocess.run([sys.executable, "-m", "mypy", "--check-untyped-defs", "--ignore-missing-imports",
                               "--no-incremental", "--cache-dir", str(tmp_path / "cache"), str(script)],
                              capture_output=True, text=True, env=env)
        assert done.returncode == 0, done.stdout + done.stderr
    bad = tmp_path / "bad_use.py"  # and refuse a wrong one
    bad.write_text("import radar_ndt\nradar_ndt.read_oxford_scan(3)\n")
    done = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
                           str(bad)], capture_output=True, text=True, env=env)
    assert done.returncode == 1 and "read_oxford_scan" in done.stdout
