#!/usr/bin/python3
"""Secondary ray set of docs/performance.md from a camera ray file and its
hit file (`mbrt trace --generate N --rays cam.rays --hits cam.hits`): from
each camera hit a ray in a uniformly random direction (tnear = 1e-4 of the
hits' bounds diagonal), plus as many rays from a sphere around the hits'
bounds (radius = the diagonal) towards uniformly random points inside them;
random times. Writes the mbrt trace ray format (float32 x9 per ray).

Usage: secondary_rays.py cam.rays cam.hits out.rays [copies]
"""
import sys

import numpy as np


def main():
    rays = np.fromfile(sys.argv[1], dtype='<f4').reshape(-1, 9)
    raw = np.fromfile(sys.argv[2], dtype='<u4').reshape(-1, 3)
    t = raw[:, 0].view('<f4')
    hit = np.isfinite(t)
    points = rays[hit, 0:3] + rays[hit, 3:6] * t[hit, None]
    n = len(points)
    rng = np.random.default_rng(7)

    def sphere(k):
        v = rng.normal(size=(k, 3))
        return v / np.linalg.norm(v, axis=1)[:, None]

    lo, hi = points.min(0), points.max(0)
    diagonal = np.linalg.norm(hi - lo)
    bounces = np.zeros((n, 9), np.float32)
    bounces[:, 0:3] = points
    bounces[:, 3:6] = sphere(n)
    bounces[:, 6] = 1e-4 * diagonal
    bounces[:, 7] = np.inf
    bounces[:, 8] = rng.random(n)
    origins = (lo + hi) / 2 + sphere(n) * diagonal
    targets = lo + rng.random((n, 3)) * (hi - lo)
    inward = np.zeros((n, 9), np.float32)
    inward[:, 0:3] = origins
    inward[:, 3:6] = targets - origins
    inward[:, 7] = np.inf
    inward[:, 8] = rng.random(n)
    out = np.concatenate([bounces, inward])
    if len(sys.argv) > 4:
        out = np.tile(out, (int(sys.argv[4]), 1))
    out.astype('<f4').tofile(sys.argv[3])
    print(n, 'hits,', len(out), 'secondary rays')


if __name__ == '__main__':
    main()
