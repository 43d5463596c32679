"""Tracing from many Python threads at once (the GIL released, each call on
every core) gives the answers of one thread; rebuilds between traces wait
for them (the module's scene lock)."""
import threading

import numpy as np

import mbrt
from conftest import mixed_scene, random_rays


def test_many_threads_trace_one_accel():
    rng = np.random.default_rng(5)
    scene = mixed_scene(rng)
    accel = mbrt.Accel(scene, "stbvh")
    rays = random_rays(rng, 20000, scene.bounds())
    expected = accel.intersect(rays)
    expected_any = accel.occluded(rays)
    failures, barrier = [], threading.Barrier(8)

    def worker(k):
        barrier.wait()
        for _ in range(4):
            part = slice(k * 1000, k * 1000 + 5000)
            hits = accel.intersect(rays[part])
            if not (np.array_equal(hits.t, expected.t[part]) and np.array_equal(hits.prim_id, expected.prim_id[part])):
                failures.append(f"thread {k}: closest hits differ")
            if not np.array_equal(accel.occluded(rays[part]), expected_any[part]):
                failures.append(f"thread {k}: occluded differs")

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures


def test_rebuild_while_other_threads_trace():
    rng = np.random.default_rng(6)
    scene = mixed_scene(rng)
    accels = [mbrt.Accel(scene, kind) for kind in ("stbvh", "msbvh", "mbkd")]
    rays = random_rays(rng, 4000, scene.bounds())
    expected = accels[0].intersect(rays).t
    failures, stop = [], threading.Event()

    def tracer(accel):
        while not stop.is_set():
            t = accel.intersect(rays).t
            if not np.allclose(t, expected, rtol=2e-4):
                failures.append(accel.kind)

    def rebuilder():
        for _ in range(5):
            for a in accels:
                a.rebuild()
                a.refit()
        stop.set()

    threads = [threading.Thread(target=tracer, args=(a,)) for a in accels] + [threading.Thread(target=rebuilder)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures
