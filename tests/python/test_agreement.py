"""Every kind agrees with brute on random rays at random times, at 0, 1 and
the step and range boundaries, through the Python API."""
import numpy as np
import pytest

import mbrt
from conftest import assert_agrees, mixed_scene, random_rays

# `frozen` traces the scene frozen at one time (checked below at that time).
KINDS = [k for k in mbrt.kinds() if k not in ("brute", "frozen", "embree")]


@pytest.fixture(scope="module")
def mixed():
    rng = np.random.default_rng(11)
    scene = mixed_scene(rng)
    rays = random_rays(rng, 20000, scene.bounds())
    return scene, mbrt.Accel(scene, "brute"), rays


@pytest.mark.parametrize("kind", KINDS)
def test_kind_agrees_with_brute_on_mixed_scene(mixed, kind):
    scene, brute, rays = mixed
    accel = mbrt.Accel(scene, kind)
    hits = assert_agrees(brute, accel, rays, 1e-5, kind)
    assert hits > 2000  # the rays reach the geometry
    assert accel.stats()["kind"] == kind


def test_frozen_agrees_with_brute_at_its_time(mixed):
    scene, brute, rays = mixed
    at = rays.copy()
    at[:, 8] = 0.25
    assert_agrees(brute, mbrt.Accel(scene, "frozen", frozen_time=0.25), at, 1e-5, "frozen")


@pytest.mark.skipif("embree" not in mbrt.kinds(), reason="mbrt was built without Embree")
def test_embree_agrees_with_brute(mixed):
    """Embree evaluates motion, segments and instances with its own
    arithmetic: rays grazing an edge may go either way, so up to 0.1% of the
    hits may differ (tests/test_embree_reference.cpp judges both structures
    against the float64 reference instead)."""
    scene, brute, rays = mixed
    a, b = brute.intersect(rays), mbrt.Accel(scene, "embree").intersect(rays)
    differ = (a.hit != b.hit) | (a.hit & (a.prim_id != b.prim_id) & ~np.isclose(a.t, b.t, rtol=2e-4))
    assert a.hit.sum() > 2000 and differ.sum() <= 1e-3 * a.hit.sum(), f"{differ.sum()} rays differ"


@pytest.mark.skipif("embree" not in mbrt.kinds(), reason="mbrt was built without Embree")
@pytest.mark.parametrize("mode", ["static", "static-robust"])
def test_embree_static_modes_are_the_scene_at_the_frozen_time(mixed, mode):
    """Embree's static BVH, default or robust flags, over the scene frozen
    at frozen_time: brute's hits at that time, whatever time a ray carries
    (up to 0.1% of the hits may differ, as above)."""
    scene, brute, rays = mixed
    at = rays.copy()
    at[:, 8] = 0.25
    a = brute.intersect(at)
    b = mbrt.Accel(scene, "embree", embree_mode=mode, frozen_time=0.25).intersect(rays)
    differ = (a.hit != b.hit) | (a.hit & (a.prim_id != b.prim_id) & ~np.isclose(a.t, b.t, rtol=2e-4))
    assert a.hit.sum() > 2000 and differ.sum() <= 1e-3 * a.hit.sum(), f"{differ.sum()} rays differ"


@pytest.mark.parametrize("kind", ["stbvh", "msbvh", "mbkd", "fuzzykd"])
def test_kind_agrees_with_brute_on_suite_scene(kind):
    scene = mbrt.scenes.make("crowd", size=0.005)
    rng = np.random.default_rng(3)
    rays = random_rays(rng, 5000, scene.bounds())
    assert_agrees(mbrt.Accel(scene, "brute"), mbrt.Accel(scene, kind), rays, 1e-5, kind)


def test_hits_carry_ids_barycentrics_and_normals():
    from conftest import moving_quad
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad(steps=2, offset=2.0))
    accel = mbrt.Accel(scene, "stbvh")
    # At time 1 the quad spans x in [1, 3]; the ray at x = 2.5, y = -0.5 hits triangle 0.
    hits = accel.intersect(org=[[2.5, -0.5, -5.0], [0.0, 0.0, -5.0]], dir=[[0, 0, 1], [0, 0, 1]], time=1.0)
    assert hits.geom_id.tolist() == [0, 0xFFFFFFFF]
    assert hits.prim_id[0] == 0 and hits.inst_id[0] == 0xFFFFFFFF
    assert hits.t[0] == pytest.approx(5.0) and np.isinf(hits.t[1])
    # v0 = (1,-1), v1 = (3,-1), v2 = (3,1): p = v0 + u (v1 - v0) + v (v2 - v0) gives u = 0.5, v = 0.25.
    assert hits.u[0] == pytest.approx(0.5) and hits.v[0] == pytest.approx(0.25)
    n = hits.ng[0]
    assert n[0] == pytest.approx(0) and n[1] == pytest.approx(0) and n[2] > 0
    assert hits.hit.tolist() == [True, False]
