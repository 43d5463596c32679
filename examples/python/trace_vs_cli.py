#!/usr/bin/env python3
"""The same ray file traced by `mbrt trace` and by Accel.intersect from
Python, in one run: both rays/s figures and their ratio, and a check that
the hits are the same.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/trace_vs_cli.py \
        --mbrt build/mbrt --scene crowd --size 0.1 --rays 1000000
"""
import argparse
import os
import re
import subprocess
import tempfile
import time

import numpy as np

import mbrt


def cli_pass(args, rays_path, hits_path):
    out = subprocess.run([args.mbrt, "trace", args.scene, "--size", str(args.size), "--accel", args.kind,
                          "--rays", rays_path, "--hits", hits_path], check=True, capture_output=True, text=True)
    match = re.search(r"time\s+([0-9.e+-]+) s", out.stdout)
    return float(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mbrt", default="build/mbrt", help="the mbrt command")
    parser.add_argument("--scene", default="crowd")
    parser.add_argument("--size", type=float, default=0.1)
    parser.add_argument("--kind", default="stbvh")
    parser.add_argument("--rays", type=int, default=1_000_000)
    parser.add_argument("--passes", type=int, default=3, help="alternating passes of each (the median counts)")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        rays_path, hits_path = os.path.join(tmp, "rays.bin"), os.path.join(tmp, "hits.bin")
        subprocess.run([args.mbrt, "trace", args.scene, "--size", str(args.size), "--rays", rays_path,
                        "--generate", str(args.rays)], check=True, capture_output=True)
        rays = mbrt.read_rays(rays_path)
        accel = mbrt.Accel(mbrt.load(args.scene, size=args.size), args.kind)
        cli_s, py_s, reuse_s = [], [], []
        for _ in range(args.passes):
            cli_s.append(cli_pass(args, rays_path, hits_path))
            start = time.perf_counter()
            hits = accel.intersect(rays)  # new result arrays
            py_s.append(time.perf_counter() - start)
            start = time.perf_counter()
            accel.intersect(rays, out=hits)  # into the arrays of the last call
            reuse_s.append(time.perf_counter() - start)
        records = np.fromfile(hits_path, dtype=[("t", "<f4"), ("geom", "<u4"), ("prim", "<u4")])
    same = np.array_equal(records["t"], hits.t) and np.array_equal(records["prim"], hits.prim_id)
    cli_rate, py_rate = len(rays) / np.median(cli_s) / 1e6, len(rays) / np.median(py_s) / 1e6
    print(f"{args.scene} size {args.size}, {args.kind}, {len(rays)} rays, {hits.hit.mean():.1%} hit, "
          f"{args.passes} alternating passes")
    print(f"mbrt trace          {cli_rate:8.3f} Mrays/s  (passes: {', '.join(f'{s:.4f}' for s in cli_s)} s)")
    print(f"Accel.intersect     {py_rate:8.3f} Mrays/s  (passes: {', '.join(f'{s:.4f}' for s in py_s)} s)")
    reuse_rate = len(rays) / np.median(reuse_s) / 1e6
    print(f"  with out=hits     {reuse_rate:8.3f} Mrays/s  (passes: {', '.join(f'{s:.4f}' for s in reuse_s)} s)")
    print(f"python / command    {py_rate / cli_rate:8.3f}x (with out=: {reuse_rate / cli_rate:.3f}x); same hits: {same}")
    if not same:
        raise SystemExit("the hits differ")


if __name__ == "__main__":
    main()
