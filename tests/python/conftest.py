"""Shared helpers of the Python tests: scenes, random rays, the brute oracle
check (the rule of tests/oracle.h: same primitive, or a tie at the same t;
a missed hit is never a tie)."""
import os
import pathlib

import numpy as np
import pytest

import mbrt

ROOT = pathlib.Path(__file__).resolve().parents[2]


def moving_quad(steps=3, offset=2.0):
    """Two triangles (a unit quad in z = 0) moving by `offset` along x over
    `steps` vertex steps: (indices, steps) arrays."""
    quad = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
    shifts = np.linspace(0.0, offset, steps, dtype=np.float32)
    vertices = np.stack([quad + np.array([s, 0, 0], dtype=np.float32) for s in shifts])
    indices = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
    return indices, vertices


def random_mesh(rng, triangles=200, steps=3, scale=1.0):
    """Random small triangles in [-1, 1]^3 moving randomly: (indices, (S, N, 3) steps)."""
    centers = rng.uniform(-1, 1, (triangles, 1, 3))
    corners = centers + rng.normal(0, 0.15, (triangles, 3, 3))
    base = corners.reshape(-1, 3)
    motion = rng.normal(0, 0.2, (triangles, 1, 3)).repeat(3, axis=1).reshape(-1, 3)
    vertices = np.stack([base + motion * k for k in range(steps)]).astype(np.float32) * scale
    indices = np.arange(triangles * 3, dtype=np.uint32).reshape(-1, 3)
    return indices, vertices


def mixed_scene(rng):
    """Moving triangles (one with its own time range), moving segments, a
    matrix instance and an SRT instance of a small moving mesh."""
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*random_mesh(rng, 150, 3))
    indices, vertices = random_mesh(rng, 60, 2)
    scene.add_triangle_mesh(indices, vertices, time_range=(0.25, 0.75))
    points = rng.uniform(-1, 1, (40, 3))
    segment_steps = np.stack([points, points + rng.normal(0, 0.1, points.shape)]).astype(np.float32)
    segments = np.array([[2 * i, 2 * i + 1] for i in range(20)], dtype=np.uint32)
    scene.add_segments(segments, segment_steps, np.full(40, 0.03, dtype=np.float32))
    child = mbrt.Scene()
    child.add_triangle_mesh(*random_mesh(rng, 40, 2, scale=0.3))
    keys = np.zeros((2, 3, 4), dtype=np.float32)
    keys[:, :, :3] = np.eye(3)
    keys[0, :, 3] = [0.5, 0.5, 0.5]
    keys[1, :, 3] = [0.8, 0.4, 0.5]
    scene.add_instance(child, keys)
    c, s = np.cos(0.6), np.sin(0.6)
    scene.add_instance_srt(child, scale=[[1, 1, 1], [1.2, 1.2, 1.2]], rotation=[[1, 0, 0, 0], [c, 0, s, 0]],
                           translation=[[-0.6, -0.5, 0.2], [-0.4, -0.5, 0.3]])
    return scene


def random_rays(rng, n, bounds, special_times=(0.0, 0.25, 0.5, 0.75, 1.0)):
    """(N, 9) rays from a sphere around the bounds towards points inside it;
    a quarter of them at the step and range times, the rest uniform in [0, 1]."""
    lo, hi = bounds
    center, radius = (lo + hi) / 2, np.linalg.norm(hi - lo)
    d = rng.normal(size=(n, 3))
    org = center + radius * d / np.linalg.norm(d, axis=1, keepdims=True)
    target = rng.uniform(lo, hi, (n, 3))
    time = rng.uniform(0, 1, n)
    special = rng.random(n) < 0.25
    time[special] = rng.choice(np.array(special_times), special.sum())
    rays = np.empty((n, 9), dtype=np.float32)
    rays[:, 0:3], rays[:, 3:6] = org, target - org
    rays[:, 6], rays[:, 7], rays[:, 8] = 0.0, np.inf, time
    return rays


def assert_agrees(oracle, tested, rays, tolerance=1e-5, label=""):
    """tested's closest hits and any-hits equal the oracle's on every ray."""
    a, b = oracle.intersect(rays), tested.intersect(rays)
    assert np.array_equal(a.hit, b.hit), f"{label}: {np.sum(a.hit != b.hit)} rays hit in one and miss in the other"
    h = a.hit
    scale = np.maximum(1.0, np.abs(a.t[h]))
    close = np.abs(a.t[h] - b.t[h]) <= tolerance * scale
    same = (a.geom_id[h] == b.geom_id[h]) & (a.prim_id[h] == b.prim_id[h]) & (a.inst_id[h] == b.inst_id[h])
    tie = np.abs(a.t[h] - b.t[h]) <= max(1e-4, tolerance) * scale
    wrong = ~np.where(same, close, tie)
    assert not wrong.any(), f"{label}: {wrong.sum()} of {h.sum()} hits differ from brute"
    assert np.array_equal(oracle.occluded(rays), tested.occluded(rays)), f"{label}: occluded() differs"
    return int(h.sum())


@pytest.fixture
def rng():
    return np.random.default_rng(7)


@pytest.fixture
def cli():
    path = os.environ.get("MBRT_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("the mbrt command is not built (MBRT_CLI unset)")
    return path
