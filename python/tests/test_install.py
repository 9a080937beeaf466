"""`cmake --install` puts the package where Debian's python3 finds it: the install folder under the
build's prefix is on this interpreter's sys.path, and the installed copy imports and works."""

import os
import pathlib
import re
import subprocess
import sys

import pytest


def test_the_installed_module_imports_from_where_python_looks(tmp_path):
    build = os.environ.get("RADAR_NDT_BUILD_DIR")
    folder = os.environ.get("RADAR_NDT_PYTHON_INSTALL_DIR")
    cmake = os.environ.get("RADAR_NDT_CMAKE", "cmake")
    if not build or not folder:
        pytest.skip("RADAR_NDT_BUILD_DIR / RADAR_NDT_PYTHON_INSTALL_DIR are not set (CTest sets them)")
    cache = (pathlib.Path(build) / "CMakeCache.txt").read_text()
    prefix = re.search(r"^CMAKE_INSTALL_PREFIX:PATH=(.*)$", cache, re.M).group(1)
    assert str(pathlib.Path(prefix) / folder) in sys.path, \
        f"{prefix}/{folder} is not on {sys.executable}'s sys.path: {sys.path}"

    stage = tmp_path / "prefix"
    subprocess.run([cmake, "--install", build, "--prefix", str(stage), "--component", "python"], check=True,
                   capture_output=True)
    site = stage / folder
    assert (site / "radar_ndt" / "__init__.py").exists()
    code = ("import radar_ndt, numpy as np; print(radar_ndt.__file__); "
            "p = np.c_[np.random.default_rng(0).uniform(-20, 20, (500, 2)), np.ones(500)]; "
            "print(radar_ndt.WeightedNDT2D().align(p, p).converged)")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    file, converged = done.stdout.split()
    assert file.startswith(str(site)) and converged == "True"
