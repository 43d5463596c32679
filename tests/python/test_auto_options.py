"""`auto` is the default kind of mbrt.Accel, as of the command line and the
C and C++ APIs; its two options take effect and bad values are refused."""
import numpy as np
import pytest

import mbrt
from conftest import assert_agrees, random_rays


def rigid_scene(rng, wobble=0.0, triangles=300):
    """Random triangles moving together by one translation over 3 steps;
    `wobble` moves one vertex of the last step off that motion."""
    base = rng.uniform(-2, 2, (3 * triangles, 3)).astype(np.float32)
    steps = np.stack([base + np.array([2.0 * k, 1.0 * k, 0], dtype=np.float32) for k in range(3)])
    steps[2, 0, 0] += wobble
    scene = mbrt.Scene()
    scene.add_triangle_mesh(np.arange(3 * triangles, dtype=np.uint32).reshape(-1, 3), steps)
    return scene


def test_default_kind_is_auto_and_agrees_with_brute():
    rng = np.random.default_rng(21)
    scene = rigid_scene(rng)
    accel = mbrt.Accel(scene)
    assert accel.stats()["kind"] == "auto"
    rays = random_rays(rng, 5000, scene.bounds())
    assert assert_agrees(mbrt.Accel(scene, "brute"), accel, rays, 1e-5, "auto") > 500


def test_leaf_kind_and_tolerance_take_effect():
    rng = np.random.default_rng(22)
    rigid = rigid_scene(rng)
    by_cost = mbrt.Accel(rigid).stats()
    # Brute below the top level leaves no tree over the rigid mesh's rest pose.
    by_brute = mbrt.Accel(rigid, auto_leaf_kind="brute").stats()
    assert by_brute["inner_nodes"] + by_brute["leaf_nodes"] < by_cost["inner_nodes"] + by_cost["leaf_nodes"]
    assert by_brute["bytes"] < by_cost["bytes"]
    # A wobble of 1e-2 keeps the mesh in world space at tolerance 0 and
    # makes it an instance at 0.5 (leaf kind forced, so that the cheaper
    # flat tree of so small a scene is not chosen instead).
    wobbly = rigid_scene(rng, wobble=1e-2)
    strict = mbrt.Accel(wobbly, auto_fit_tolerance=0.0, auto_leaf_kind="bvh-interp")
    loose = mbrt.Accel(wobbly, auto_fit_tolerance=0.5, auto_leaf_kind="bvh-interp")
    assert strict.stats()["references"] != loose.stats()["references"]
    rays = random_rays(rng, 5000, wobbly.bounds())
    assert_agrees(mbrt.Accel(wobbly, "brute"), strict, rays, 1e-5, "auto, tolerance 0")


@pytest.mark.parametrize("options, message", [
    (dict(auto_fit_tolerance=-1.0), "tolerance must be in"),
    (dict(auto_fit_tolerance=float("nan")), "tolerance must be in"),
    (dict(auto_fit_tolerance=1.0), "tolerance must be in"),
    (dict(auto_leaf_kind="no-such-kind"), r"unknown auto_leaf_kind 'no-such-kind' \(available: brute"),
    (dict(auto_leaf_kind="auto"), "cannot be auto"),
])
def test_bad_auto_options(options, message):
    with pytest.raises(mbrt.Error, match=message):
        mbrt.Accel(rigid_scene(np.random.default_rng(23), triangles=20), **options)
