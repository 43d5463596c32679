#!/usr/bin/env python3
"""Three structures on one suite scene, the same rays: rays/s and memory
side by side, as a bar chart (PNG).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/compare.py \
        --scene crowd --size 0.1 --kinds stbvh msbvh mbkd --out compare.png
"""
import argparse
import time

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mbrt  # noqa: E402


def scene_rays(scene, count, seed):
    """Rays from a sphere around the scene towards random points of its
    bounds, at random shutter times: (N, 9) float32 as in a ray file."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds()
    center, radius = (lo + hi) / 2, np.linalg.norm(hi - lo)
    d = rng.normal(size=(count, 3))
    org = center + radius * d / np.linalg.norm(d, axis=1, keepdims=True)
    rays = np.zeros((count, 9), dtype=np.float32)
    rays[:, 0:3] = org
    rays[:, 3:6] = rng.uniform(lo, hi, (count, 3)) - org
    rays[:, 7] = np.inf
    rays[:, 8] = rng.uniform(0, 1, count)
    return rays


def measure(scene, kind, rays, repeats):
    accel = mbrt.Accel(scene, kind)
    hits = accel.intersect(rays)  # warm-up, and the hits to compare
    best = min(timed(accel, rays) for _ in range(repeats))
    stats = accel.stats()
    return {"kind": kind, "mrays": len(rays) / best / 1e6, "mib": stats["bytes"] / 2**20,
            "build_s": stats["build_seconds"], "hits": hits}


def timed(accel, rays):
    start = time.perf_counter()
    accel.intersect(rays)
    return time.perf_counter() - start


def plot(rows, title, path):
    kinds = [r["kind"] for r in rows]
    colors = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3"][: len(rows)]
    fig, (left, right) = plt.subplots(1, 2, figsize=(7.5, 3.0), dpi=80)
    for axis, key, label in ((left, "mrays", "Mrays/s (all threads)"), (right, "mib", "structure memory (MiB)")):
        bars = axis.bar(kinds, [r[key] for r in rows], color=colors)
        axis.bar_label(bars, fmt="%.2f")
        axis.set_title(label, fontsize=10)
        axis.margins(y=0.2)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="crowd", help="a built-in scene (mbrt.scenes.names())")
    parser.add_argument("--size", type=float, default=0.1, help="the suite's size knob")
    parser.add_argument("--kinds", nargs="+", default=["stbvh", "msbvh", "mbkd"], help="accel kinds")
    parser.add_argument("--rays", type=int, default=500_000)
    parser.add_argument("--repeats", type=int, default=3, help="timed passes per kind (the best counts)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default="compare.png")
    args = parser.parse_args()

    scene = mbrt.scenes.make(args.scene, size=args.size)
    rays = scene_rays(scene, args.rays, args.seed)
    rows = [measure(scene, kind, rays, args.repeats) for kind in args.kinds]
    reference = rows[0]["hits"]
    for r in rows[1:]:  # the same rays give the same hits (ties aside)
        if not np.array_equal(r["hits"].hit, reference.hit):
            raise SystemExit(f"{r['kind']} and {rows[0]['kind']} disagree on which rays hit")
    print(f"{scene.name} (size {args.size}): {scene.num_primitives} primitives at the top level, "
          f"{len(rays)} rays, {reference.hit.mean():.1%} hit")
    for r in rows:
        print(f"  {r['kind']:<12} {r['mrays']:7.2f} Mrays/s  {r['mib']:8.2f} MiB  built in {r['build_s']:.3f} s")
    plot(rows, f"{scene.name}, size {args.size}: {len(rays)} rays at random times", args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
