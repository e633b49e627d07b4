"""rove: a toolkit for mobile robots, from Python.

Poses and Lie groups (SE2, SE3, SO3), point clouds and occupancy grids whose
arrays are numpy views of rove's own storage (no copies), file formats
(PCD, PLY, ROS map.yaml, rawlogs), registration (align), pose graphs and the
SLAM and localization pipelines of the `rove` command line. See
docs/python.md.
"""

from ._rove import *  # noqa: F401,F403

__all__ = [name for name in dir() if not name.startswith("_")]

# For tests and diagnostics: the address of the points C++ reads for an
# argument (equal to a float32 array's own data pointer: no copy).
from ._rove import _points_address  # noqa: E402,F401
