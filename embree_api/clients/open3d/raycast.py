#!/usr/bin/python3
"""Runs Open3D's RaycastingScene on a real mesh and saves every result.

    /usr/bin/python3 raycast.py OUT.npz [--rays N] [--repeat R]

The scene is the Stanford bunny (../shared/scenes/stanford_bunny, relative to
the repository root) standing on a box; without ../shared it says so and uses
two of Open3D's built-in primitives instead. A fixed set of rays (a camera
grid, rays from outside aimed into the bounding box, rays starting inside it)
goes through cast_rays, count_intersections and test_occlusions; OUT.npz holds
the rays, the geometry and every result, the timings (median of R runs) and
the libembree3 file this process mapped, so that compare.py can check two
runs against each other and settle disagreements in float64.
"""

import argparse
import os
import statistics
import sys
import time

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from mapped_library import mapped_embree  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
BUNNY = os.path.join(REPO, "..", "shared", "scenes", "stanford_bunny", "bun_zipper.ply")


def load_meshes():
    """Returns [(name, vertices float32 (n,3), triangles uint32 (m,3)), ...]."""
    meshes = []
    if os.path.exists(BUNNY):
        bunny = o3d.io.read_triangle_mesh(BUNNY)
        meshes.append(("stanford_bunny", bunny))
    else:
        print(f"raycast: {BUNNY} absent (no ../shared): using Open3D's torus "
              "instead of the bunny", file=sys.stderr)
        torus = o3d.geometry.TriangleMesh.create_torus(0.06, 0.025, 60, 40)
        torus.translate((-0.017, 0.11, 0.0))
        meshes.append(("torus", torus))
    lower = np.asarray(meshes[0][1].vertices).min(axis=0)
    upper = np.asarray(meshes[0][1].vertices).max(axis=0)
    size = upper - lower
    # A slab under the first mesh, touching its lowest point: a second
    # geometry (geometry_ids 1) that rays also hit around and below the mesh.
    ground = o3d.geometry.TriangleMesh.create_box(2.0 * size[0], 0.1 * size[1], 2.0 * size[2])
    ground.translate((lower[0] - 0.5 * size[0], lower[1] - 0.1 * size[1], lower[2] - 0.5 * size[2]))
    meshes.append(("ground_box", ground))
    return [(name, np.asarray(m.vertices, dtype=np.float32),
             np.asarray(m.triangles, dtype=np.uint32)) for name, m in meshes]


def make_rays(vertices, count):
    """A fixed (seeded) set of rays around and inside the box of `vertices`."""
    rng = np.random.default_rng(20240343)
    lower, upper = vertices.min(axis=0), vertices.max(axis=0)
    center, diag = 0.5 * (lower + upper), float(np.linalg.norm(upper - lower))
    n_grid_side = int(np.sqrt(count * 0.6))
    n_outside = (count - n_grid_side ** 2) // 2
    n_inside = count - n_grid_side ** 2 - n_outside

    # Pinhole camera in front of the mesh, slightly above, looking at it.
    eye = center + np.array([0.3, 0.25, 1.2]) * diag
    forward = (center - eye) / np.linalg.norm(center - eye)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    s = (np.arange(n_grid_side) + 0.5) / n_grid_side * 2.0 - 1.0
    sx, sy = np.meshgrid(0.45 * s, -0.45 * s)
    dirs = forward + sx[..., None] * right + sy[..., None] * up
    grid = np.concatenate([np.broadcast_to(eye, dirs.shape), dirs], axis=-1).reshape(-1, 6)

    # From a sphere around the mesh towards random points in its box.
    o = rng.normal(size=(n_outside, 3))
    o = center + 1.5 * diag * o / np.linalg.norm(o, axis=1, keepdims=True)
    target = lower + rng.random((n_outside, 3)) * (upper - lower)
    outside = np.concatenate([o, target - o], axis=1)

    # From random points inside the box, in random directions.
    p = lower + rng.random((n_inside, 3)) * (upper - lower)
    d = rng.normal(size=(n_inside, 3))
    inside = np.concatenate([p, d], axis=1)
    return np.concatenate([grid, outside, inside]).astype(np.float32)


def timed(repeat, fn):
    """(result of the last call, median wall seconds over `repeat` calls)."""
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return result, statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="output .npz")
    parser.add_argument("--rays", type=int, default=100000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    meshes = load_meshes()
    scene = o3d.t.geometry.RaycastingScene()
    ids = [scene.add_triangles(o3d.core.Tensor(v), o3d.core.Tensor(t)) for _, v, t in meshes]
    if ids != list(range(len(meshes))):
        sys.exit(f"raycast: add_triangles returned ids {ids}, expected 0..{len(meshes) - 1}")
    rays = make_rays(meshes[0][1], args.rays)
    rays_t = o3d.core.Tensor(rays)

    scene.cast_rays(rays_t[:1])  # commits the scene: not part of the timings
    hits, t_cast = timed(args.repeat, lambda: scene.cast_rays(rays_t))
    counts, t_count = timed(args.repeat, lambda: scene.count_intersections(rays_t))
    occluded, t_occl = timed(args.repeat, lambda: scene.test_occlusions(rays_t))

    result = {k: v.numpy() for k, v in hits.items()}
    np.savez(
        args.out,
        rays=rays,
        counts=counts.numpy(),
        occluded=occluded.numpy(),
        times=np.array([t_cast, t_count, t_occl]),
        embree_library=np.array(mapped_embree()),
        mesh_names=np.array([name for name, _, _ in meshes]),
        **{f"vertices_{i}": v for i, (_, v, _) in enumerate(meshes)},
        **{f"triangles_{i}": t for i, (_, _, t) in enumerate(meshes)},
        **result,
    )
    n_hit = int(np.count_nonzero(np.isfinite(result["t_hit"])))
    print(f"raycast: {len(rays)} rays on {', '.join(n for n, _, _ in meshes)} "
          f"({sum(len(t) for _, _, t in meshes)} triangles) via {mapped_embree()}: "
          f"{n_hit} hit, {int(counts.numpy().sum())} intersections counted, "
          f"{int(occluded.numpy().sum())} occluded; cast_rays {t_cast * 1e3:.1f} ms, "
          f"count_intersections {t_count * 1e3:.1f} ms, test_occlusions {t_occl * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
