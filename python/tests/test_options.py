"""Every field of the C++ options structs is a keyword in Python: the headers are read and each
field looked up on its bound class, so a field added in C++ and not bound fails here."""

import copy
import re

import pytest

import radar_ndt
from conftest import SOURCE

STRUCTS = {
    "WeightedNDT2DSettings": "registration/include/radar_ndt/registration/weighted_ndt_2d_settings.h",
    "MatcherOptions": "radar_ndt/include/radar_ndt/odometry/matcher.h",
    "PolarConvention": "io/include/radar_ndt/io/polar_scan.h",
    "OxfordPolarOptions": "io/include/radar_ndt/io/oxford_scan.h",
    "RadiatePolarOptions": "io/include/radar_ndt/io/radiate_scan.h",
    "BoreasPolarOptions": "io/include/radar_ndt/io/boreas_scan.h",
    "ScanningSequenceOptions": "io/include/radar_ndt/io/scanning_sequence.h",
    "PowerThresholdOptions": "radar_ndt/include/radar_ndt/frontend/power_threshold.h",
    "ChirpCorrectionOptions": "radar_ndt/include/radar_ndt/frontend/chirp_correction.h",
    "ScanningMotionGateOptions": "radar_ndt/include/radar_ndt/odometry/motion_gate.h",
    "MotionCompensationOptions": "radar_ndt/include/radar_ndt/odometry/motion_compensation.h",
    "KeyframeOptions": "radar_ndt/include/radar_ndt/odometry/keyframe_policy.h",
    "FitCheckOptions": "radar_ndt/include/radar_ndt/odometry/fit_history.h",
    "ScanningOdometryOptions": "radar_ndt/include/radar_ndt/odometry/scanning_odometry.h",
    "ScanningRunOptions": "radar_ndt/include/radar_ndt/pipeline/scanning_run.h",
    "NuScenesRadarFilter": "io/include/radar_ndt/io/nuscenes.h",
    "NuScenesSequenceOptions": "io/include/radar_ndt/io/nuscenes_sequence.h",
    "PolarAccuracy": "radar_ndt/include/radar_ndt/frontend/point_covariance.h",
    "EgoVelocityOptions": "radar_ndt/include/radar_ndt/frontend/ego_velocity.h",
    "AutomotiveFrontEndOptions": "radar_ndt/include/radar_ndt/frontend/automotive_front_end.h",
    "MotionFusionOptions": "radar_ndt/include/radar_ndt/odometry/motion_fusion.h",
    "AutomotiveMotionGateOptions": "radar_ndt/include/radar_ndt/odometry/motion_gate.h",
    "AutomotiveOdometryOptions": "radar_ndt/include/radar_ndt/odometry/automotive_odometry.h",
    "AutomotiveRunOptions": "radar_ndt/include/radar_ndt/pipeline/automotive_run.h",
    "EvaluationOptions": "radar_ndt/include/radar_ndt/evaluation/report.h",
}


def header_fields(name, header):
    """The data members of `struct name` in `header`: declarations at the struct's top level."""
    text = (SOURCE / header).read_text()
    start = re.search(r"^struct " + name + r" \{", text, re.M)
    assert start, f"struct {name} not in {header}"
    body, depth, fields = [], 1, []
    for line in text[start.end():].splitlines():
        depth_before = depth
        depth += line.count("{") - line.count("}")
        if depth <= 0:
            break
        if depth_before == 1:
            body.append(line)
    for line in body:
        code = line.split("//")[0].strip()
        if not code.endswith(";") or "(" in code.split("=")[0] or code.startswith(("static", "using", "void")):
            continue
        decl = code[:-1]
        # "double a = 0, b = 0" declares several; "T name{...}" and "T name = v" one each.
        for part in re.split(r",(?![^{(]*[})])", decl):
            m = re.search(r"([A-Za-z_]\w*)\s*(?:=.*|\{.*\})?$", part.strip())
            if m:
                fields.append(m.group(1))
    return fields


@pytest.mark.parametrize("name", sorted(STRUCTS))
def test_every_field_is_bound(name):
    fields = header_fields(name, STRUCTS[name])
    assert fields, name
    options = getattr(radar_ndt, name)()
    missing = [f for f in fields if not hasattr(options, f)]
    assert not missing, f"{name}: {missing} not reachable from Python"


def test_keywords_reach_nested_structs_and_copies_are_independent():
    run = radar_ndt.ScanningRunOptions()
    run.odometry.keyframes.distance = 0.0  # nested structs are references into the parent
    assert run.odometry.keyframes.distance == 0.0
    other = copy.deepcopy(run)
    other.matcher.grid = 9.0
    assert run.matcher.grid == 3.75
    run.matcher.method = "pcl-icp"
    assert run.matcher.method == "pcl-icp"
    run.matcher.method = "gicp"  # a name the registry of matchers lacks: validate() says so
    with pytest.raises(ValueError, match="gicp"):
        run.validate()
    assert [m["name"] for m in radar_ndt.matchers()][:5] == ["pw-ndt", "pcl-ndt", "pcl-icp", "doppler", "rapp-ndt"]
    assert "KeyframeOptions" in radar_ndt.KeyframeOptions.__doc__
    assert "0: scan to scan" in radar_ndt.KeyframeOptions.distance.__doc__, "the field table's help"
    with pytest.raises(ValueError):
        radar_ndt.with_method(radar_ndt.AutomotiveRunOptions(), "gicp")
    rapp = radar_ndt.with_method(radar_ndt.AutomotiveRunOptions(), "rapp-ndt")
    assert rapp.odometry.doppler_weights and not rapp.front_end.remove_moving
    rapp.validate()
    rapp.front_end.remove_moving = True
    with pytest.raises(ValueError, match="remove_moving"):
        rapp.validate()
    paper = radar_ndt.AutomotiveOdometryOptions().paper(5)
    assert paper.mode == "submap-to-submap" and paper.submap_size == 5 and not paper.fuse_doppler
