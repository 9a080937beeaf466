"""Python's keywords against the command line, every field of both run options' tables: the same value
given as a keyword (its own Python type) and as radar_odometry's option (its text) builds the same
options, or is refused by both. The test walks the tables (radar_ndt.option_fields), so a field added
later is covered without editing it."""
import json
import math
import os
import subprocess

import pytest

import radar_ndt

BIN = os.environ.get("RADAR_NDT_APP_DIR", "build/apps")


def nested(path, value):
    """{"odometry": {"gyro": {"bias_walk": v}}} for "odometry.gyro.bias_walk"."""
    head, _, rest = path.partition(".")
    return {head: nested(rest, value) if rest else value}


def inside(f, v):
    lo, hi = f["low"], f["high"]
    return (v > lo if f["low_open"] else v >= lo) and (v < hi if f["high_open"] else v <= hi)


def probes(f, default):
    """Values other than the default: a switch both ways, 1e-7 and larger numbers where the bounds
    allow, an integer above the default, each name of a choice, a one-item list."""
    kind = f["kind"]
    if kind == "bool":
        return [True, False]
    if kind == "int":
        return [default + 1 if inside(f, default + 1) else default - 1]
    if kind == "float":
        return [v for v in (1e-7, 2 * default + 0.5, default + 0.125) if inside(f, v) and v != default]
    if kind == "str":
        if f["path"] == "matcher.method":
            return [m["name"] for m in radar_ndt.matchers()]
        return list(f["names"]) or ["RADAR_FRONT"]
    item = {"str": "RADAR_FRONT", "float": 3.5}.get(f["item_kind"], 3)
    return [[item]]


def cli_text(f, v):
    if f["spelled"] and isinstance(v, bool):
        return f["spelled"][1] if v else f["spelled"][0]
    if isinstance(v, list):
        return ",".join(cli_text(f, x) for x in v)
    if isinstance(v, float):
        return repr(v)  # every digit the double needs
    return str(v)


def python_values(fmt, path, value):
    try:
        return radar_ndt.option_values(radar_ndt.run_options(fmt, **nested(path, value)))
    except (TypeError, ValueError):
        return "refused"


def cli_values(fmt, args):
    done = subprocess.run([f"{BIN}/radar_odometry", "--format", fmt, *args, "--show-options"], capture_output=True,
                          text=True)
    return json.loads(done.stdout) if done.returncode == 0 else "refused"


def same(a, b):
    if a == "refused" or b == "refused":
        return a == b
    return a.keys() == b.keys() and all(
        x == y or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y))
        for x, y in ((a[k], b[k]) for k in a))


@pytest.mark.parametrize("pipeline,fmt", [("automotive", "nuscenes"), ("scanning", "oxford")])
def test_every_field_as_a_keyword_gives_the_command_lines_options(pipeline, fmt):
    if not os.path.exists(f"{BIN}/radar_odometry"):
        pytest.skip(f"no {BIN}/radar_odometry (RADAR_NDT_APP_DIR)")
    fields = radar_ndt.option_fields(pipeline)
    defaults = radar_ndt.option_values(radar_ndt.run_options(fmt))
    assert [f["path"] for f in fields] == list(defaults), "option_fields and option_values in one order"
    compared = via_cli = 0
    for f in fields:
        layout = f["layout"] or fmt
        for v in probes(f, defaults[f["path"]]):
            ours = python_values(layout, f["path"], v)
            if f["option"] and (f["switch_sets"] is None or v == f["switch_sets"]):
                args = [f"--{f['option']}"] + ([] if f["switch_sets"] is not None else [cli_text(f, v)])
                theirs = cli_values(layout, args)
                via_cli += 1
            else:  # the command line cannot say it: the value must reach the field as given
                theirs = ours if ours == "refused" or ours[f["path"]] == v else "not set"
            assert same(ours, theirs), f"{f['path']} = {v!r}"
            compared += 1
    assert compared >= len(fields) > 20 and via_cli > 20


def test_a_double_stays_a_double_and_a_switch_takes_its_value():
    o = radar_ndt.run_options("boreas", odometry={"gyro": {"bias_walk": 1e-7}})
    assert o.odometry.gyro.bias_walk == 1e-7
    for on in (True, False):
        assert radar_ndt.run_options("nuscenes", odometry={"fuse_doppler": on}).odometry.fuse_doppler is on
    with pytest.raises(TypeError, match="front_end.threshold.*scanning"):
        radar_ndt.run_options("nuscenes", front_end={"threshold": 0.3})
    with pytest.raises(TypeError, match="sequence.boreas"):
        radar_ndt.run_options("oxford", sequence={"boreas": {"range_resolution": 0.05}})
    with pytest.raises(TypeError, match="true or false"):
        radar_ndt.run_options("nuscenes", odometry={"fuse_doppler": "yes"})
