"""RadarNDT: radar odometry with the weighted probabilistic NDT, from Python.

Numpy in and out: points are (N, 3) x, y, power arrays (or (N, 2), or (N, 11) with the columns
of POINT_FIELDS), poses 3x3 SE(2) or 4x4 matrices or (x, y, yaw), trajectories Trajectory objects
with (N, 4, 4) poses and (N,) stamps in seconds. Options are keyword arguments named as the C++
options structs' fields; nested structs take dicts (odometry={"keyframes": {"distance": 0}}). A value out of range
raises ValueError naming the field, an unknown name TypeError, a file that cannot be read
radar_ndt.IoError (an OSError naming the file). docs/python.md has the whole API.
"""

from ._radar_ndt import *  # noqa: F401,F403
from ._radar_ndt import IoError, POINT_FIELDS, __doc__ as _native_doc  # noqa: F401

__version__ = "0.2.0"
