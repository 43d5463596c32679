"""Which libembree3 file the running process has mapped.

Shared by open3d/raycast.py (Debian's Python) and cycles/scene.py (Blender's
Python), so that each run states which library it really traced with."""

import os


def mapped_embree():
    """The real path of the mapped libembree3, or "(none)"."""
    with open("/proc/self/maps") as maps:
        for line in maps:
            path = line.split()[-1]
            if "libembree3.so" in path:
                return os.path.realpath(path)
    return "(none)"
