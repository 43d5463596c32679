"""mbrt: ray tracing with motion blur over numpy arrays.

The structures of the mbrt library (STBVH, MSBVH, MBKD, fuzzy kd-trees,
BVHs with linear bounds, Embree as a peer) behind one class, ``Accel``::

    import mbrt, numpy as np
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)   # (M, 3) uint32, (S, N, 3) float32
    accel = mbrt.Accel(scene)                  # kind="auto"; or any kind of mbrt.kinds()
    hits = accel.intersect(rays)               # rays: (N, 9) float32, as a ray file
    hits.t, hits.geom_id, hits.prim_id, hits.u, hits.v, hits.ng

An input over its timeline, frame by frame, each frame's scene updated in
place and an accel refitted or rebuilt to follow it::

    doc = mbrt.load("CesiumMan.glb")           # read once; a Scene over one shutter
    for frame in doc.frames(fps=24, accel="bvh-interp", update="auto"):
        image = mbrt.render(frame.scene, frame.accel)

Tracing releases the GIL and uses every core (TBB). Errors raise
``mbrt.Error`` with the library's message. See docs/python.md.
"""
from __future__ import annotations

import numpy as _np

from ._mbrt import (Accel, Document, Error, Frame, Frames, Hits, Scene, Timeline, __version__, bench, kinds, load,
                    render)
from . import scenes

__all__ = [
    "Accel", "Document", "Error", "Frame", "Frames", "Hits", "Scene", "Timeline", "__version__", "bench", "kinds",
    "load", "render", "scenes", "read_rays", "write_rays", "RAY_FIELDS",
]

#: The columns of an (N, 9) ray array, as in a ray file (include/mbrt/io/ray_file.h).
RAY_FIELDS = ("org_x", "org_y", "org_z", "dir_x", "dir_y", "dir_z", "tnear", "tfar", "time")


def read_rays(path: str) -> _np.ndarray:
    """Reads a ray file (`mbrt trace --rays`) as an (N, 9) float32 array."""
    data = _np.fromfile(path, dtype="<f4")
    if data.size % 9:
        raise Error(f"{path}: {data.size * 4} bytes is not a whole number of 36-byte rays")
    return data.reshape(-1, 9)


def write_rays(path: str, rays: _np.ndarray) -> None:
    """Writes an (N, 9) array of rays as a ray file that `mbrt trace` reads."""
    rays = _np.asarray(rays)
    if rays.ndim != 2 or rays.shape[1] != 9:
        raise Error(f"rays must have shape (N, 9), got {rays.shape}")
    _np.ascontiguousarray(rays, dtype="<f4").tofile(path)
