"""What the Python module's tests share: the data folders, the apps they are compared with and a
scratch folder. Tests that need ../shared/data skip with a message saying so when it is absent."""

import os
import pathlib
import subprocess

import pytest

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = pathlib.Path(os.environ.get("RADAR_NDT_SOURCE_DIR", HERE.parents[1]))
SHARED = pathlib.Path(os.environ.get("RADAR_NDT_SHARED_DATA", SOURCE.parent / "shared" / "data"))
APP_DIR = pathlib.Path(os.environ.get("RADAR_NDT_APP_DIR", SOURCE / "build" / "apps"))
OXFORD = SHARED / "oxford-radar-real"
NUSCENES = SHARED / "nuscenes-mini-radar"
BOREAS = SHARED / "boreas-sample"
RADIATE = SHARED / "radiate-tiny-foggy"


def need(path):
    """Skips the test, saying what is missing, when `path` does not exist."""
    if not path.exists():
        pytest.skip(f"{path} is absent: the shared data (../shared/data beside the checkout) is not here")
    return path


def app(name, *args):
    """Runs one of the project's apps; its stdout (a failure shows its stderr)."""
    cmd = [str(APP_DIR / name), *map(str, args)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(cmd)} failed:\n{done.stderr}"
    return done.stdout


@pytest.fixture
def work(tmp_path):
    return tmp_path
